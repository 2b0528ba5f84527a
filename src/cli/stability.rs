//! `windrive chart stability`: where each co-simulation algorithm holds on a stiff split, measured
//! and in theory, printed as a table and drawn as a map. The study is
//! [`crate::studies::stability`].

use crate::cosim::Scene;
use crate::studies::stability::{Case, STEPS, map};
use anyhow::{Context, bail};
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(clap::Args)]
#[command(after_help = "Examples:\n  \
    windrive chart stability                               the map (about 1 min), results/stability-map.{png,svg,csv}\n  \
    windrive chart stability --out docs/stability-map\n  \
    windrive chart stability --split shaft                 the main shaft cut across two FMUs instead\n\n\
    Reading it: a green dot is a run that kept its amplitude, a red cross one that grew or diverged; the black line\n\
    is the theory's boundary (stable to its left). Pick the largest macro step left of the line for your coupling\n\
    stiffness; where no step is stable, use --algorithm iterative --acceleration iqn-ils.")]
pub struct StabilityArgs {
    /// The split: generator (drivetrain | the generator's electrical spring, scene d-grid-step) or
    /// shaft (the rotor | the rest of the drivetrain, cut in the main shaft, scene d-shaft-cut)
    #[arg(long, default_value = "generator", value_parser = ["generator", "shaft"])]
    pub split: String,
    /// Simulated time per run, s
    #[arg(long, default_value_t = 20.0)]
    pub stop_time: f64,
    /// Amplitude growth over the run that counts as unstable (measured and in theory)
    #[arg(long, default_value_t = 2.0)]
    pub growth: f64,
    /// Output stem: STEM.png, STEM.svg, STEM.csv
    #[arg(long, default_value = "results/stability-map")]
    pub out: PathBuf,
}

pub fn run(args: &StabilityArgs) -> anyhow::Result<()> {
    if !(args.stop_time > 0.0 && args.stop_time.is_finite() && args.growth > 1.0) {
        bail!(
            "--stop-time {} --growth {}: the stop time must be a positive number of seconds, the growth a factor above 1",
            args.stop_time,
            args.growth
        );
    }
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create the output folder", dir.display()))?;
    }
    let root = crate::pack::workspace_root()?;
    let case = Case::new(&args.split)?;
    let scene = Scene::open(&root.join("scenes").join(case.scene))?;
    super::run::provide_own_fmus(&scene, false)?;
    println!(
        "{}; {} s per run;\n\
         unstable = diverged, or the amplitude grew more than {}× (theory: spectral radius of the macro-step map)\n",
        case.describe, args.stop_time, args.growth
    );
    println!(
        "{:<20} {:>26} {:>26} {:>10}",
        "algorithm", "largest stable H, theory", "largest stable H, runs", "agree"
    );
    let (shared, panels) = map(&scene, &case, args.stop_time, args.growth, |shared, p| {
        let show = |h: Option<f64>, last: f64| match h {
            Some(h) if h >= last => format!("all (to {last} s)"),
            Some(h) => format!("{:.4} s (H·ω {:.2})", h, h * shared.omega_1),
            None => "none".to_string(),
        };
        println!(
            "{:<20} {:>26} {:>26} {:>6}/{}",
            p.label,
            show(p.limit_theory, shared.fine_steps[shared.fine_steps.len() - 1]),
            show(p.limit_runs, STEPS[STEPS.len() - 1]),
            p.agree,
            p.points.len()
        );
    })?;
    println!(
        "(at κ = 1, ω of the top coupled mode = {:.1} rad/s; runs on the grid {:?} s)",
        shared.omega_1, STEPS
    );
    let mut csv = String::from("algorithm,step_s,stiffness_factor,h_omega,stable_measured,stable_theory\n");
    let mut drawn = Vec::new();
    for p in &panels {
        for x in &p.points {
            writeln!(
                csv,
                "{},{},{},{},{},{}",
                p.label, x.step, x.stiffness, x.h_omega, x.measured, x.theory
            )?;
        }
        let runs = |measured: bool| {
            let kept = p.points.iter().filter(|x| x.measured == measured);
            kept.map(|x| (x.step, x.stiffness)).collect()
        };
        drawn.push(crate::plot::StabilityPanel {
            title: p.label.to_string(),
            stable: runs(true),
            unstable: runs(false),
            boundary: p.boundary.clone(),
        });
    }
    let title = format!(
        "Co-simulation stability on a stiff split ({}): dots = runs ({} s), line = theory",
        case.title, args.stop_time
    );
    crate::plot::write_stability_map(&args.out, &csv, &title, ("macro step H [s]", case.y_label), &drawn)
}
