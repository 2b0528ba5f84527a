//! The reference of any scene: its coupled equations solved to convergence at every step of a small
//! macro step, so that no coupling (splitting) error is left, only each model's own discretisation at
//! that step; the reference's remaining error is estimated by running it again at twice the step.
//!
//! This is what "monolithic" means for scenes whose models are FMUs from several tools: the solution
//! of the system as a whole, not of its parts with lagged inputs. It is obtained with the master's
//! implicit coupling (the `iterative` algorithm, interface quasi-Newton, relative tolerance 1e-9):
//! a single-matrix integrator of rotor, drivetrain and generator together is not built here. Its
//! quantities of interest are what `windrive chart work-precision` and `windrive fidelity` measure
//! every run against.

use crate::analysis::signal::quantities::{self, Quantity};
use crate::cosim::master::{ColumnRun, run_columns_with};
use crate::cosim::{Acceleration, Algorithm, Options, Override, Scene};

/// Default macro step of a reference, s: a quarter of the scenes' 1 ms.
pub const DEFAULT_STEP: f64 = 2.5e-4;

/// Relative coupling tolerance the reference converges every step to.
pub const TOLERANCE: f64 = 1e-9;

/// The master's options for a reference run at macro step `step`.
pub fn options(step: f64, stop_time: f64) -> Options {
    let mut o = Options::new(Algorithm::Iterative, step, stop_time);
    o.acceleration = Acceleration::IqnIls;
    o.rel_tol = TOLERANCE;
    o.abs_tol = 1e-12;
    o.max_iterations = 30;
    o
}

/// A scene's reference: its quantities at `step` and at 2·`step`.
#[derive(Debug, Clone)]
pub struct SceneReference {
    pub step: f64,
    pub values: Vec<f64>,
    /// The same quantities at twice the step: their difference estimates the reference's error.
    pub coarse: Vec<f64>,
    /// CPU time of the reference run at `step`, s.
    pub cpu_s: f64,
    /// Macro steps whose iteration hit the cap before the tolerance (0 for a converged reference).
    pub unconverged: u64,
}

impl SceneReference {
    /// Estimated relative error of quantity `i` of the reference (step halving: the change from 2h to h).
    pub fn own_error(&self, i: usize) -> f64 {
        quantities::relative_error(self.coarse[i], self.values[i])
    }
}

/// Runs `scene` (with `overrides`) to `stop_time` and evaluates `quantities`; errors name the scene.
pub fn run_quantities(
    scene: &Scene,
    overrides: &[Override],
    qs: &[Quantity],
    opts: Options,
) -> Result<(Vec<f64>, ColumnRun), String> {
    let channels = quantities::channels(qs);
    let names: Vec<&str> = channels.iter().map(|s| s.as_str()).collect();
    let run = run_columns_with(scene, overrides, &names, opts).map_err(|e| format!("scene {}: {e}", scene.name))?;
    let values =
        quantities::evaluate_all(qs, &channels, &run.columns).map_err(|e| format!("scene {}: {e}", scene.name))?;
    Ok((values, run))
}

/// The reference of `scene` at macro step `step`.
pub fn compute(
    scene: &Scene,
    overrides: &[Override],
    qs: &[Quantity],
    step: f64,
    stop_time: f64,
) -> Result<SceneReference, String> {
    let (values, run) = run_quantities(scene, overrides, qs, options(step, stop_time))?;
    let (coarse, _) = run_quantities(scene, overrides, qs, options(2.0 * step, stop_time))?;
    Ok(SceneReference {
        step,
        values,
        coarse,
        cpu_s: run.cpu_s,
        unconverged: run.stats.unconverged,
    })
}
