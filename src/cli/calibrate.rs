//! `windrive calibrate`: fits the inputs of drivetrain C's scenes that no source gives (turbulence
//! intensity, brake torque, brake ramp, pitch rate towards feather, trip delay) to the statistics the
//! thesis measured on the field turbine ([`crate::studies::calibration`]), by Nelder–Mead over both
//! scenes run through the master ([`crate::studies::calibration::fit`]); prints target, achieved and
//! misfit per statistic, writes the table as Markdown, and with `--apply` writes the fitted values into
//! the scenes' parameter files.

use crate::cosim::Scene;
use crate::studies::calibration;
use crate::studies::calibration::fit::{FREE, Scenes, markdown, write_values};
use anyhow::{Context as _, bail};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct CalibrateArgs {
    /// Most scene-pair evaluations of the optimiser (each runs 20 s normal operation and 30 s shutdown,
    /// about 1 s); the documented fit converged after 189
    #[arg(long, default_value_t = 250)]
    pub evaluations: usize,
    /// Evaluate the scenes' current values only, no fit
    #[arg(long)]
    pub no_fit: bool,
    /// Write the fitted values into scenes/c-normal and scenes/c-shutdown (rotor.ssv, torsional.ssv)
    #[arg(long)]
    pub apply: bool,
    /// Markdown table of target, achieved and misfit per statistic
    #[arg(long, default_value = "results/calibration-c.md")]
    pub out: PathBuf,
}

/// C's scene folders, opened with our FMUs in place.
fn open_scenes(normal_dir: &Path, shutdown_dir: &Path) -> anyhow::Result<Scenes> {
    let normal = Scene::open(normal_dir)?;
    let shutdown = Scene::open(shutdown_dir)?;
    super::run::provide_own_fmus(&normal, false)?;
    super::run::provide_own_fmus(&shutdown, false)?;
    Ok(Scenes::new(normal, shutdown))
}

pub fn run(args: &CalibrateArgs) -> anyhow::Result<()> {
    if !args.no_fit && args.evaluations < FREE.len() + 2 {
        bail!(
            "--evaluations {}: the simplex needs at least {}",
            args.evaluations,
            FREE.len() + 2
        );
    }
    let root = crate::pack::workspace_root()?;
    let (normal_dir, shutdown_dir) = (root.join("scenes/c-normal"), root.join("scenes/c-shutdown"));
    let scenes = open_scenes(&normal_dir, &shutdown_dir)?;
    let start_values = scenes.current_values();
    println!(
        "drivetrain C: fitting {} inputs to {} measured statistics",
        FREE.len(),
        calibration::statistics().len()
    );
    let started = std::time::Instant::now();
    let start = scenes.evaluate(&start_values)?;
    println!(
        "  start: objective {:.4} ({:.1} s a scene pair)",
        start.objective,
        started.elapsed().as_secs_f64()
    );
    let (best, evaluations) = if args.no_fit {
        (start.clone(), 1)
    } else {
        let fitted = scenes.fit(&start_values, args.evaluations, |count, objective, best| {
            eprint!(
                "\r  evaluation {count:>4}/{}: objective {objective:.4}, best {best:.4}   ",
                args.evaluations
            )
        });
        eprintln!();
        fitted?
    };
    let best = if args.apply {
        let rated_generator = scenes.drivetrain.rated_generator_torque();
        write_values(&[&normal_dir, &shutdown_dir], &best.values, rated_generator)?;
        println!(
            "fitted values written to {} and {}",
            normal_dir.display(),
            shutdown_dir.display()
        );
        // the table shows what the scenes now give, read back from their files
        let scenes = Scenes::new(Scene::open(&normal_dir)?, Scene::open(&shutdown_dir)?);
        scenes.evaluate(&scenes.current_values())?
    } else {
        best
    };
    let report = markdown(&best, &start, evaluations);
    println!("\n{report}");
    if let Some(parent) = args.out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).with_context(|| parent.display().to_string())?;
    }
    std::fs::write(&args.out, &report).with_context(|| args.out.display().to_string())?;
    println!("table written to {}", args.out.display());
    Ok(())
}
