//! `windrive shutdown --preset C`: the thesis's normal-operation and shutdown scenes of a drivetrain
//! through the co-simulation master, with the plots and the summary a drivetrain engineer reads:
//! shaft torques, speeds, mesh forces (reversals visible), the HSS-torque spectrum while braking with
//! the computed modes marked, the rainflow range–mean cloud, and the torque ratios.

use super::plot::{self, Series};
use crate::analysis::{rainflow, series::read_channel, spectrum};
use crate::cosim::{Algorithm, Master, Options, Record, Scene, System, recorder::Recorder};
use crate::physics::drivetrain::Drivetrain;
use crate::physics::modes::{Boundary, modes};
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
}

/// Runs one scene folder with Gauss–Seidel at its own step, every output recorded.
fn run_scene(dir: &Path, csv: &Path) -> anyhow::Result<()> {
    let scene = Scene::open(dir)?;
    super::run::provide_own_fmus(&scene, false)?;
    let mut system = System::build(&scene, &[], &Record::Outputs)?;
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

struct Channels {
    t: Vec<f64>,
    csv: PathBuf,
}

impl Channels {
    fn get(&self, name: &str) -> anyhow::Result<Vec<f64>> {
        Ok(read_channel(&self.csv, name)?.1)
    }
}

/// Largest minus smallest value.
pub fn range(x: &[f64]) -> f64 {
    x.iter().cloned().fold(f64::MIN, f64::max) - x.iter().cloned().fold(f64::MAX, f64::min)
}

/// Lowest non-zero natural frequency of a preset at full fidelity under `boundary`, Hz.
pub fn lowest_mode(preset: &str, boundary: Boundary) -> anyhow::Result<f64> {
    let params = crate::slaves::torsional::Params {
        preset: preset.into(),
        fidelity: "full".into(),
        integrator: "implicit".into(),
        damping_scale: 1.0,
        contact_ratio: 1.6,
        ..Default::default()
    };
    let built = params.build().map_err(|e| anyhow::anyhow!("{e}"))?;
    let m = modes(&built.model, boundary, built.drivetrain.k_generator);
    m.frequencies_hz
        .into_iter()
        .find(|f| *f > 1e-6)
        .context("no non-zero mode")
}

/// Dominant frequency (above 0.3 Hz) of `x` over [a, b), with the spectrum it came from.
pub fn dominant(t: &[f64], x: &[f64], a: f64, b: f64) -> Option<(f64, Vec<f64>, Vec<f64>)> {
    let i0 = t.partition_point(|&v| v < a);
    let i1 = t.partition_point(|&v| v < b);
    if i1 <= i0 + 16 {
        return None;
    }
    let (f, amp) = spectrum::amplitude_spectrum(&x[i0..i1], t[1] - t[0]);
    spectrum::dominant_frequency(&f, &amp, 0.3).map(|d| (d, f, amp))
}

/// The first mesh of the last stage, as a torsional output name and a label: the last parallel
/// stage's gear–pinion mesh, or the second planetary stage's sun–planet 1 (drivetrain A).
fn last_stage_mesh(dt: &Drivetrain) -> (String, &'static str) {
    use crate::physics::drivetrain::Stage;
    let parallel = dt.stages.iter().filter(|s| matches!(s, Stage::Parallel(_))).count();
    match dt.stages.last() {
        Some(Stage::Parallel(_)) => (format!("mesh_force_gear_pinion_{parallel}"), "last gear-pinion"),
        _ => ("mesh_force_sun_planet2_1".into(), "2nd-stage sun-planet"),
    }
}

pub fn run(args: &ShutdownArgs) -> anyhow::Result<()> {
    let preset = args.preset.trim().to_ascii_uppercase();
    let drivetrain =
        Drivetrain::preset(&preset).with_context(|| format!("unknown preset {preset:?}: use A, B, C or D"))?;
    let root = crate::pack::workspace_root()?;
    let lower = preset.to_ascii_lowercase();
    let (normal_dir, shutdown_dir) = (
        root.join("scenes").join(format!("{lower}-normal")),
        root.join("scenes").join(format!("{lower}-shutdown")),
    );
    if !shutdown_dir.is_dir() || !normal_dir.is_dir() {
        bail!(
            "no scenes {} and {} (scenes exist for A, B, C and D)",
            normal_dir.display(),
            shutdown_dir.display()
        );
    }
    let out = args
        .out_dir
        .clone()
        .unwrap_or_else(|| PathBuf::from("results").join(format!("{lower}-shutdown")));
    std::fs::create_dir_all(&out).with_context(|| out.display().to_string())?;
    println!("drivetrain {preset}: normal operation and shutdown through the co-simulation master");
    let (normal_csv, shutdown_csv) = (out.join("normal.csv"), out.join("shutdown.csv"));
    run_scene(&normal_dir, &normal_csv)?;
    run_scene(&shutdown_dir, &shutdown_csv)?;

    let n = Channels {
        t: read_channel(&normal_csv, "torsional.hss_torque")?.0,
        csv: normal_csv,
    };
    let s = Channels {
        t: read_channel(&shutdown_csv, "torsional.hss_torque")?.0,
        csv: shutdown_csv,
    };
    let t = &s.t;

    // shafts and their rated torques: LSS carries the rotor's, each stage divides by its ratio
    let mut shafts = vec![("lss", drivetrain.rated_rotor_torque())];
    let mut rated = drivetrain.rated_rotor_torque();
    for (k, stage) in drivetrain.stages.iter().enumerate() {
        rated /= stage.ratio();
        let name = if k + 1 == drivetrain.stages.len() {
            "hss"
        } else if k == 0 {
            "is1"
        } else {
            "is2"
        };
        shafts.push((name, rated));
    }
    let mut summary = String::new();
    summary.push_str(&format!("drivetrain {preset}, shutdown vs normal operation\n\n"));
    summary.push_str(&format!(
        "{:<6} {:>14} {:>16} {:>16} {:>18}\n",
        "shaft", "rated [N·m]", "max |T| / rated", "vs 1.35 design", "range shut/normal"
    ));
    for (name, rated) in &shafts {
        let shut = s.get(&format!("torsional.{name}_torque"))?;
        let norm = n.get(&format!("torsional.{name}_torque"))?;
        let ratio = shut.iter().fold(0.0f64, |m, v| m.max(v.abs())) / rated;
        summary.push_str(&format!(
            "{name:<6} {rated:>14.1} {ratio:>16.3} {:>16} {:>18.2}\n",
            if ratio > 1.35 { "exceeds" } else { "within" },
            range(&shut) / range(&norm)
        ));
    }

    let hss = s.get("torsional.hss_torque")?;
    let locked = s.get("torsional.brake_locked")?;
    let brake = s.get("rotor.brake_command")?;
    let full = t[brake.iter().position(|&b| b >= 1.0).unwrap_or(0)];
    let t_lock = locked.iter().position(|&l| l > 0.5).map(|i| t[i]);
    let free = lowest_mode(&preset, Boundary::Disconnected)?;
    let held_mode = lowest_mode(&preset, Boundary::HssLocked)?;
    let slip = dominant(t, &hss, full + 0.1, t_lock.map_or(t[t.len() - 1], |l| l - 0.1));
    let held = t_lock.and_then(|l| dominant(t, &hss, l + 0.5, t[t.len() - 1]));
    summary.push_str(&format!(
        "\nbrake fully applied at {full:.2} s, HSS locked at {}\n",
        t_lock.map_or("never".into(), |l| format!("{l:.2} s"))
    ));
    summary.push_str(&format!(
        "dominant HSS-torque frequency while the brake slips: {} (lowest free-free mode {free:.3} Hz{})\n",
        slip.as_ref().map_or("-".into(), |d| format!("{:.3} Hz", d.0)),
        if preset == "D" { "; thesis 2.61 Hz" } else { "" }
    ));
    summary.push_str(&format!(
        "dominant HSS-torque frequency with the HSS held:    {} (lowest HSS-locked mode {held_mode:.3} Hz)\n",
        held.as_ref().map_or("-".into(), |d| format!("{:.3} Hz", d.0))
    ));
    let sp = s.get("torsional.mesh_force_sun_planet_1")?;
    let (last_mesh, last_label) = last_stage_mesh(&drivetrain);
    let gp = s.get(&format!("torsional.{last_mesh}"))?;
    summary.push_str(&format!(
        "mesh-force reversal: sun-planet min {:.1} kN, {last_label} min {:.1} kN (normal operation min {:.1} / {:.1} kN)\n",
        sp.iter().cloned().fold(f64::MAX, f64::min) / 1e3,
        gp.iter().cloned().fold(f64::MAX, f64::min) / 1e3,
        n.get("torsional.mesh_force_sun_planet_1")?.iter().cloned().fold(f64::MAX, f64::min) / 1e3,
        n.get(&format!("torsional.{last_mesh}"))?.iter().cloned().fold(f64::MAX, f64::min) / 1e3,
    ));
    print!("\n{summary}");
    std::fs::write(out.join("summary.txt"), &summary)?;

    // plots
    let pairs = |x: &[f64], scale: f64| -> Vec<(f64, f64)> { t.iter().zip(x).map(|(a, b)| (*a, b * scale)).collect() };
    let (lss_rated, hss_rated) = (shafts[0].1, shafts[shafts.len() - 1].1);
    let lss = s.get("torsional.lss_torque")?;
    let p_hss = pairs(&hss, 1.0 / hss_rated);
    let p_lss = pairs(&lss, 1.0 / lss_rated);
    let marks = vec![(5.0, "shutdown".to_string()), (full, "brake on".into())];
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
    let (wr, wg) = (s.get("torsional.rotor_speed")?, s.get("torsional.generator_speed")?);
    let rpm = 30.0 / std::f64::consts::PI;
    let (p_wr, p_wg) = (
        pairs(&wr, rpm / (drivetrain.rated_rotor_speed * rpm)),
        pairs(&wg, 1.0 / (drivetrain.rated_rotor_speed * drivetrain.gear_ratio())),
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
    let (p_sp, p_gp) = (pairs(&sp, 1e-3), pairs(&gp, 1e-3));
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
    if let Some((d, f, a)) = &slip {
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
            ("shutdown".into(), cloud(&hss)),
            ("normal operation".into(), cloud(&n.get("torsional.hss_torque")?)),
        ],
    )?;
    println!("  {}", path.display());
    Ok(())
}
