//! `windrive shutdown --preset C`: the thesis's normal-operation and shutdown scenes of a drivetrain
//! through the co-simulation master, then the summary of [`crate::analysis::shutdown`] and the plots a
//! drivetrain engineer reads: shaft torques, speeds, mesh forces (reversals visible), the HSS-torque
//! spectrum while braking with the computed modes marked, the rainflow range–mean cloud.

use crate::analysis::fatigue::rainflow;
use crate::analysis::shutdown;
use crate::cosim::{Algorithm, Master, Options, Record, Scene, System, recorder::Recorder};
use crate::linear::modes::Boundary;
use crate::physics::drivetrain::Drivetrain;
use crate::plot::{self, Series};
use crate::reference::modes::lowest_mode;
use anyhow::{Context, bail};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct ShutdownArgs {
    /// Drivetrain: A, B, C or D (the scenes under scenes/<preset>-normal and scenes/<preset>-shutdown)
    #[arg(long, default_value = "C")]
    pub preset: String,
    /// Output folder [default: results/<preset>-shutdown]
    #[arg(long)]
    pub out_dir: Option<PathBuf>,
    /// Rotor aerodynamics for both scenes: scene (as the scene files say: the blade-element rotor, or the
    /// analytic C_p in the spring scenes), bem (blade-element momentum, trimmed start pitch: the parked
    /// rotor is damped by its blades) or analytic (Heier's C_p, fine start pitch)
    #[arg(long, default_value = "scene")]
    pub aerodynamics: String,
    /// Run the spring scenes (scenes/<preset>-{normal,shutdown}-spring, C and D): the thesis's electrical
    /// spring K_gen in place of the generator it simulated, and the analytic C_p; the scenes the
    /// modal comparisons and thesis-validation tests use
    #[arg(long)]
    pub spring: bool,
}

/// Runs one scene folder with Gauss–Seidel at its own step, every output recorded.
fn run_scene(dir: &Path, csv: &Path, overrides: &[(String, String, String)]) -> anyhow::Result<()> {
    let scene = Scene::open(dir)?;
    super::run::provide_own_fmus(&scene, false)?;
    let mut system = System::build(&scene, overrides, &Record::Outputs)?;
    let stop = scene.experiment.stop_time.context("the scene has no stop time")?;
    let step = scene.experiment.step_size.unwrap_or(1e-3);
    system.initialize(Some(stop))?;
    let mut recorder = Recorder::create(csv, &system, 1)?;
    let started = std::time::Instant::now();
    let mut master = Master::new(&mut system, Options::new(Algorithm::GaussSeidel, step, stop))?;
    master.run(|t, sys| recorder.observe(t, sys))?;
    let final_time = master.stats.final_time;
    recorder.finish(final_time, &mut system)?;
    let wall = started.elapsed().as_secs_f64();
    println!(
        "  {:<12} {stop} s in {wall:.2} s ({:.0}× real time) -> {}",
        scene.name,
        stop / wall,
        csv.display()
    );
    system.terminate();
    Ok(())
}

pub fn run(args: &ShutdownArgs) -> anyhow::Result<()> {
    let preset = args.preset.trim().to_ascii_uppercase();
    let drivetrain =
        Drivetrain::preset(&preset).with_context(|| format!("unknown preset {preset:?}: use A, B, C, D or P"))?;
    let root = crate::pack::workspace_root()?;
    let lower = preset.to_ascii_lowercase();
    let suffix = if args.spring { "-spring" } else { "" };
    let (normal_dir, shutdown_dir) = (
        root.join("scenes").join(format!("{lower}-normal{suffix}")),
        root.join("scenes").join(format!("{lower}-shutdown{suffix}")),
    );
    if !shutdown_dir.is_dir() || !normal_dir.is_dir() {
        bail!(
            "no scenes {} and {} (scenes exist for A, B, C and D; spring scenes for C and D)",
            normal_dir.display(),
            shutdown_dir.display()
        );
    }
    let rotor = |var: &str, value: &str| ("rotor".to_string(), var.to_string(), value.to_string());
    let overrides = match args.aerodynamics.trim() {
        "bem" => vec![rotor("aerodynamics", "bem"), rotor("initial_pitch", "-1")],
        "analytic" => vec![rotor("aerodynamics", "analytic"), rotor("initial_pitch", "0")],
        "scene" => vec![],
        other => bail!("--aerodynamics {other:?}: use bem, analytic or scene"),
    };
    let out = args
        .out_dir
        .clone()
        .unwrap_or_else(|| PathBuf::from("results").join(format!("{lower}-shutdown")));
    std::fs::create_dir_all(&out).with_context(|| out.display().to_string())?;
    println!("drivetrain {preset}: normal operation and shutdown through the co-simulation master");
    let (normal_csv, shutdown_csv) = (out.join("normal.csv"), out.join("shutdown.csv"));
    println!("rotor aerodynamics: {}", args.aerodynamics.trim());
    run_scene(&normal_dir, &normal_csv, &overrides)?;
    run_scene(&shutdown_dir, &shutdown_csv, &overrides)?;

    let free = lowest_mode(&preset, Boundary::Disconnected)?;
    let held_mode = lowest_mode(&preset, Boundary::HssLocked)?;
    let summary = shutdown::summarise(&preset, &drivetrain, &normal_csv, &shutdown_csv, free, held_mode)?;
    print!("\n{summary}");
    std::fs::write(out.join("summary.txt"), summary.to_string())?;
    let s = &summary.series;
    let (t, hss, full) = (&s.time, &s.hss_torque, summary.brake_applied_s);
    let shafts = &summary.shafts;
    let (sp, gp, last_label) = (&s.sun_planet, &s.last_mesh, summary.last_mesh_label);
    let slip = summary
        .slipping
        .as_ref()
        .map(|r| (r.frequency_hz, &r.frequencies, &r.amplitudes));

    // plots
    let pairs = |x: &[f64], scale: f64| -> Vec<(f64, f64)> { t.iter().zip(x).map(|(a, b)| (*a, b * scale)).collect() };
    let (lss_rated, hss_rated) = (shafts[0].rated_torque, shafts[shafts.len() - 1].rated_torque);
    let p_hss = pairs(hss, 1.0 / hss_rated);
    let p_lss = pairs(&s.lss_torque, 1.0 / lss_rated);
    let marks = vec![
        (shutdown::SHUTDOWN_TIME, "shutdown".to_string()),
        (full, "brake on".into()),
    ];
    let draw =
        |file: &str, title: &str, y: &str, series: Vec<Series>, markers: &[(f64, String)]| -> anyhow::Result<()> {
            let path = out.join(file);
            plot::lines(&path, title, "time [s]", y, &series, markers)?;
            println!("  {}", path.display());
            Ok(())
        };
    println!("\nplots:");
    draw(
        "shaft_torques.png",
        &format!("Drivetrain {preset} shutdown: shaft torques"),
        "torque / rated",
        vec![
            Series {
                label: "HSS".into(),
                points: &p_hss,
            },
            Series {
                label: "LSS".into(),
                points: &p_lss,
            },
        ],
        &marks,
    )?;
    let (wr, wg) = (&s.rotor_speed, &s.generator_speed);
    let rpm = 30.0 / std::f64::consts::PI;
    let (p_wr, p_wg) = (
        pairs(wr, rpm / (drivetrain.rated_rotor_speed * rpm)),
        pairs(wg, 1.0 / (drivetrain.rated_rotor_speed * drivetrain.gear_ratio())),
    );
    draw(
        "speeds.png",
        &format!("Drivetrain {preset} shutdown: speeds"),
        "speed / rated",
        vec![
            Series {
                label: "rotor".into(),
                points: &p_wr,
            },
            Series {
                label: "generator".into(),
                points: &p_wg,
            },
        ],
        &marks,
    )?;
    let (p_sp, p_gp) = (pairs(sp, 1e-3), pairs(gp, 1e-3));
    draw(
        "mesh_forces.png",
        &format!("Drivetrain {preset} shutdown: mesh forces (negative = flank reversal)"),
        "force along the line of action [kN]",
        vec![
            Series {
                label: "sun-planet 1".into(),
                points: &p_sp,
            },
            Series {
                label: last_label.into(),
                points: &p_gp,
            },
        ],
        &marks,
    )?;
    if let Some((d, f, a)) = slip {
        let pts: Vec<(f64, f64)> = f
            .iter()
            .zip(a)
            .take_while(|(f, _)| **f <= 10.0)
            .map(|(f, a)| (*f, *a))
            .collect();
        let path = out.join("hss_spectrum.png");
        plot::lines(
            &path,
            &format!("Drivetrain {preset}: HSS torque while the brake slips (peak {d:.3} Hz)"),
            "frequency [Hz]",
            "amplitude [N·m]",
            &[Series {
                label: "HSS torque".into(),
                points: &pts,
            }],
            &[
                (free, format!("free-free {free:.2} Hz")),
                (held_mode, format!("HSS locked {held_mode:.2} Hz")),
            ],
        )?;
        println!("  {}", path.display());
    }
    let cloud = |x: &[f64]| -> Vec<(f64, f64)> {
        rainflow::cycles(x)
            .iter()
            .map(|c| (c.mean / 1e3, c.range / 1e3))
            .collect()
    };
    let path = out.join("rainflow.png");
    plot::scatter(
        &path,
        &format!("Drivetrain {preset}: rainflow cycles of HSS torque"),
        "cycle mean [kN·m]",
        "cycle range [kN·m]",
        &[
            ("shutdown".into(), cloud(hss)),
            ("normal operation".into(), cloud(&s.normal_hss_torque)),
        ],
    )?;
    println!("  {}", path.display());
    Ok(())
}
