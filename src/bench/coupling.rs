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
