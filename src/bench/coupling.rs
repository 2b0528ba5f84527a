//! `windrive bench coupling`: error against wall time of every co-simulation algorithm on the
//! d-grid-step scene against its exact solution ([`crate::reference::grid_step`]), over macro steps
//! until each fails, and the adaptive algorithm over tolerances.

use crate::cosim::{Acceleration, Algorithm, Options};
use crate::reference::grid_step::{Outcome, compare};
use std::path::Path;

/// Macro steps of the fixed-step runs, s.
pub const STEPS: [f64; 8] = [0.5e-3, 1e-3, 2e-3, 5e-3, 1e-2, 2e-2, 5e-2, 0.1];
/// Relative tolerances of the adaptive runs.
pub const TOLERANCES: [f64; 4] = [1e-2, 1e-3, 1e-4, 1e-5];
/// Angular frequency of the stiffest coupled mode of d-grid-step (5.89 Hz), rad/s: H·ω says how
/// finely a macro step resolves it.
pub const OMEGA_RAD_S: f64 = 37.0;

/// The head of the table over `stop_time` s: the scene, the error's definition and the columns; a row
/// per run follows ([`fixed_row`], [`adaptive_row`]).
pub fn head(stop_time: f64) -> String {
    format!(
        "d-grid-step: drivetrain D (2-mass, undamped) + generator spring K_gen = 2.81e4 N·m/rad, {} s;\n\
         error = max |T_gen − exact| / max |exact| (exact: modal solution); stiffest coupled mode 5.89 Hz (ω = 37.0 rad/s)\n\n\
         {:<17} {:>9} {:>8} {:>12} {:>10} {:>8}",
        stop_time, "algorithm", "step [s]", "H·ω", "error", "wall [ms]", "sweeps"
    )
}

/// The row of a fixed-step run: `label` at macro step `h` s.
pub fn fixed_row(label: &str, h: f64, o: &Outcome) -> String {
    let error = match (&o.error, &o.failure) {
        (Some(e), _) if *e < 1.0 => format!("{e:.3e}"),
        (Some(e), _) => format!("unstable ({e:.1e})"),
        (None, Some(f)) => format!("failed: {}", f.chars().take(50).collect::<String>()),
        _ => unreachable!(),
    };
    format!(
        "{label:<17} {h:>9} {:>8.3} {error:>12} {:>10.2} {:>8}",
        h * OMEGA_RAD_S,
        o.wall_s * 1e3,
        o.stats.sweeps
    )
}

/// The row of an adaptive run at relative tolerance `tol`.
pub fn adaptive_row(tol: f64, o: &Outcome) -> String {
    format!(
        "{:<17} {:>9} {:>8} {:>12} {:>10.2} {:>8}  ({} steps, {} rejected)",
        format!("adaptive {tol:.0e}"),
        "-",
        "-",
        o.error.map_or("failed".into(), |e| format!("{e:.3e}")),
        o.wall_s * 1e3,
        o.stats.sweeps,
        o.stats.steps,
        o.stats.rejected
    )
}

/// The fixed-step variants compared: (label, algorithm, input order, acceleration).
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

/// Every variant at every step of [`STEPS`], then the adaptive algorithm at every tolerance of
/// [`TOLERANCES`], on the scene folder `scene_dir` over `stop_time` s; `fixed(label, step, outcome)`
/// and `adaptive(tolerance, outcome)` after each run. Per line its stable runs as (log10 wall s,
/// log10 error), the adaptive runs last.
pub fn run(
    scene_dir: &Path,
    stop_time: f64,
    mut fixed: impl FnMut(&str, f64, &Outcome),
    mut adaptive: impl FnMut(f64, &Outcome),
) -> anyhow::Result<super::Curves> {
    let mut series: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for (label, algorithm, order, acceleration) in variants() {
        let mut points = Vec::new();
        for &h in &STEPS {
            let mut opts = Options::new(algorithm, h, stop_time);
            opts.order = order;
            opts.acceleration = acceleration;
            let o = compare(scene_dir, opts)?;
            if let Some(e) = o.error.filter(|e| *e < 1.0) {
                points.push((o.wall_s.log10(), e.log10()));
            }
            fixed(&label, h, &o);
        }
        series.push((label, points));
    }
    for tol in TOLERANCES {
        let mut opts = Options::new(Algorithm::Adaptive, 1e-3, stop_time);
        opts.rel_tol = tol;
        let o = compare(scene_dir, opts)?;
        adaptive(tol, &o);
        if let Some(e) = o.error {
            match series.iter_mut().find(|(l, _)| l == "adaptive") {
                Some((_, p)) => p.push((o.wall_s.log10(), e.log10())),
                None => series.push(("adaptive".into(), vec![(o.wall_s.log10(), e.log10())])),
            }
        }
    }
    Ok(series)
}
