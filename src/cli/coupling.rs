//! `windrive bench coupling`: error against wall time of every co-simulation algorithm on the
//! d-grid-step scene against its exact solution ([`crate::reference::grid_step`]), as a
//! work–precision chart, with the step where each fails.

use crate::cosim::{Acceleration, Algorithm, Options, Scene};
use crate::reference::grid_step::compare as run_grid_step;
use std::path::Path;

/// The fixed-step variants the chart compares: (label, algorithm, input order, acceleration).
fn variants() -> Vec<(String, Algorithm, usize, Acceleration)> {
    let plain = Acceleration::None;
    vec![
        ("jacobi p0".into(), Algorithm::Jacobi, 0, plain),
        ("jacobi p1".into(), Algorithm::Jacobi, 1, plain),
        ("jacobi p2".into(), Algorithm::Jacobi, 2, plain),
        ("gauss-seidel p0".into(), Algorithm::GaussSeidel, 0, plain),
        ("gauss-seidel p1".into(), Algorithm::GaussSeidel, 1, plain),
        ("iterative p1".into(), Algorithm::Iterative, 1, plain),
        ("iterative aitken".into(), Algorithm::Iterative, 1, Acceleration::Aitken),
        (
            "iterative iqn-ils".into(),
            Algorithm::Iterative,
            1,
            Acceleration::IqnIls,
        ),
    ]
}

pub fn run(stop_time: f64, plot: Option<&Path>) -> anyhow::Result<()> {
    let root = crate::pack::workspace_root()?;
    let scene_dir = root.join("scenes").join("d-grid-step");
    super::run::provide_own_fmus(&Scene::open(&scene_dir)?, true)?;
    let steps = [0.5e-3, 1e-3, 2e-3, 5e-3, 1e-2, 2e-2, 5e-2, 0.1];
    println!(
        "d-grid-step: drivetrain D (2-mass, undamped) + generator spring K_gen = 2.81e4 N·m/rad, {} s;\n\
         error = max |T_gen − exact| / max |exact| (exact: modal solution); stiffest coupled mode 5.89 Hz (ω = 37.0 rad/s)\n",
        stop_time
    );
    println!(
        "{:<17} {:>9} {:>8} {:>12} {:>10} {:>8}",
        "algorithm", "step [s]", "H·ω", "error", "wall [ms]", "sweeps"
    );
    let mut series: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    let omega = 37.0;
    for (label, algorithm, order, acceleration) in variants() {
        let mut points = Vec::new();
        for &h in &steps {
            let mut opts = Options::new(algorithm, h, stop_time);
            opts.order = order;
            opts.acceleration = acceleration;
            let o = run_grid_step(&scene_dir, opts)?;
            let error = match (&o.error, &o.failure) {
                (Some(e), _) if *e < 1.0 => {
                    points.push((o.wall_s.log10(), e.log10()));
                    format!("{e:.3e}")
                }
                (Some(e), _) => format!("unstable ({e:.1e})"),
                (None, Some(f)) => format!("failed: {}", f.chars().take(50).collect::<String>()),
                _ => unreachable!(),
            };
            println!(
                "{label:<17} {h:>9} {:>8.3} {error:>12} {:>10.2} {:>8}",
                h * omega,
                o.wall_s * 1e3,
                o.stats.sweeps
            );
        }
        series.push((label, points));
    }
    for tol in [1e-2, 1e-3, 1e-4, 1e-5] {
        let mut opts = Options::new(Algorithm::Adaptive, 1e-3, stop_time);
        opts.rel_tol = tol;
        let o = run_grid_step(&scene_dir, opts)?;
        println!(
            "{:<17} {:>9} {:>8} {:>12} {:>10.2} {:>8}  ({} steps, {} rejected)",
            format!("adaptive {tol:.0e}"),
            "-",
            "-",
            o.error.map_or("failed".into(), |e| format!("{e:.3e}")),
            o.wall_s * 1e3,
            o.stats.sweeps,
            o.stats.steps,
            o.stats.rejected
        );
        if let Some(e) = o.error {
            match series.iter_mut().find(|(l, _)| l == "adaptive") {
                Some((_, p)) => p.push((o.wall_s.log10(), e.log10())),
                None => series.push(("adaptive".into(), vec![(o.wall_s.log10(), e.log10())])),
            }
        }
    }
    if let Some(path) = plot {
        let series: Vec<crate::plot::Series> = series
            .iter()
            .map(|(label, points)| crate::plot::Series {
                label: label.clone(),
                points,
            })
            .collect();
        crate::plot::lines(
            path,
            "d-grid-step (drivetrain D + generator spring): co-simulation error vs wall time",
            "log10 wall time / s",
            "log10 (max |error| / peak), stable runs",
            &series,
            &[],
        )?;
        println!("\nwork-precision chart: {}", path.display());
    }
    Ok(())
}
