//! `windrive shutdown --preset C`: the thesis's normal-operation and shutdown scenes of a drivetrain
//! through the co-simulation master, then the summary of [`crate::analysis::shutdown`] and the plots a
//! drivetrain engineer reads ([`crate::studies::shutdown`]): shaft torques, speeds, mesh forces
//! (reversals visible), the HSS-torque spectrum while braking with the computed modes marked, the
//! rainflow range–mean cloud.

use crate::cosim::Scene;
use crate::physics::drivetrain::Drivetrain;
use crate::plot;
use crate::studies::shutdown::{aerodynamics, charts, read_runs, run_scene, scene_dirs};
use anyhow::{Context, bail};
use std::path::PathBuf;

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

pub fn run(args: &ShutdownArgs) -> anyhow::Result<()> {
    let preset = args.preset.trim().to_ascii_uppercase();
    let drivetrain =
        Drivetrain::preset(&preset).with_context(|| format!("unknown preset {preset:?}: use A, B, C, D or P"))?;
    let root = crate::pack::workspace_root()?;
    let (normal_dir, shutdown_dir) = scene_dirs(&root.join("scenes"), &preset, args.spring);
    if !shutdown_dir.is_dir() || !normal_dir.is_dir() {
        bail!(
            "no scenes {} and {} (scenes exist for A, B, C and D; spring scenes for C and D)",
            normal_dir.display(),
            shutdown_dir.display()
        );
    }
    let overrides = aerodynamics(args.aerodynamics.trim())?;
    let out = args
        .out_dir
        .clone()
        .unwrap_or_else(|| PathBuf::from("results").join(format!("{}-shutdown", preset.to_ascii_lowercase())));
    std::fs::create_dir_all(&out).with_context(|| out.display().to_string())?;
    println!("drivetrain {preset}: normal operation and shutdown through the co-simulation master");
    let (normal_csv, shutdown_csv) = (out.join("normal.csv"), out.join("shutdown.csv"));
    println!("rotor aerodynamics: {}", args.aerodynamics.trim());
    for (dir, csv) in [(&normal_dir, &normal_csv), (&shutdown_dir, &shutdown_csv)] {
        let scene = Scene::open(dir)?;
        super::run::provide_own_fmus(&scene, false)?;
        let (stop, wall) = run_scene(&scene, csv, &overrides)?;
        println!(
            "  {:<12} {stop} s in {wall:.2} s ({:.0}× real time) -> {}",
            scene.name,
            stop / wall,
            csv.display()
        );
    }
    let reading = read_runs(&preset, &drivetrain, &normal_csv, &shutdown_csv)?;
    print!("\n{}", reading.summary);
    std::fs::write(out.join("summary.txt"), reading.summary.to_string())?;
    println!("\nplots:");
    for c in charts(&preset, &drivetrain, &reading) {
        let path = out.join(c.file);
        if c.scatter {
            plot::scatter(&path, &c.title, c.x_label, c.y_label, &c.lines)?;
        } else {
            plot::named_lines(&path, &c.title, c.x_label, c.y_label, &c.lines, &c.markers)?;
        }
        println!("  {}", path.display());
    }
    Ok(())
}
