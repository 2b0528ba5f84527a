//! A run's master options from what its user gave and what its scene and FMUs declare: the macro step
//! and stop time (given, else the scene's, else the smallest any of its FMUs declares in its
//! DefaultExperiment) and the coupling settings, each bounded where a value would make no run.

use super::master::{Algorithm, Options};
use super::{Acceleration, Scene, System};
use crate::fmi2::host::description::DefaultExperiment;

/// What a run is told; None where the scene and its FMUs decide.
#[derive(Debug, Clone)]
pub struct Settings {
    pub algorithm: Algorithm,
    /// Macro step, s.
    pub step: Option<f64>,
    pub stop_time: Option<f64>,
    /// Input extrapolation order [default: the algorithm's].
    pub order: Option<usize>,
    pub rel_tol: f64,
    pub abs_tol: f64,
    /// Most sweeps per macro step (at least one is made).
    pub max_iterations: usize,
    pub acceleration: Acceleration,
    pub divergence_growth: f64,
    /// Smallest and largest macro step of the adaptive algorithm [default: step/1000 and 100×step].
    pub min_step: Option<f64>,
    pub max_step: Option<f64>,
    /// Worker threads of the Jacobi algorithm (at least one).
    pub threads: usize,
}

/// What neither the settings, the scene nor any of its FMUs give.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum Missing {
    #[error("no step size")]
    Step,
    #[error("no stop time")]
    StopTime,
}

impl Settings {
    /// The master's options for `scene` built as `system`.
    pub fn options(&self, scene: &Scene, system: &System) -> Result<Options, Missing> {
        // the smallest value any FMU declares
        let fmu_default = |f: fn(&DefaultExperiment) -> Option<f64>| {
            system
                .units
                .iter()
                .filter_map(|u| u.fmu.description.default_experiment.as_ref().and_then(f))
                .fold(None, |m: Option<f64>, x| Some(m.map_or(x, |m| m.min(x))))
        };
        let step = self
            .step
            .or(scene.experiment.step_size)
            .or_else(|| fmu_default(|d| d.step_size))
            .ok_or(Missing::Step)?;
        let stop = self
            .stop_time
            .or(scene.experiment.stop_time)
            .or_else(|| fmu_default(|d| d.stop_time))
            .ok_or(Missing::StopTime)?;
        let mut opts = Options::new(self.algorithm, step, stop);
        if let Some(order) = self.order {
            opts.order = order;
        }
        opts.rel_tol = self.rel_tol;
        opts.abs_tol = self.abs_tol;
        opts.max_iterations = self.max_iterations.max(1);
        opts.acceleration = self.acceleration;
        opts.min_step = self.min_step.unwrap_or(step * 1e-3);
        opts.max_step = self.max_step.unwrap_or(step * 100.0);
        opts.threads = self.threads.max(1);
        opts.divergence_growth = self.divergence_growth;
        Ok(opts)
    }
}
