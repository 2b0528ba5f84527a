//! What the studies of one scene share (the work-precision chart, the fidelity ladder): the scene with
//! its quantities of interest and its reference, and one measured run (CPU time best of several, the
//! relative error of every quantity against the reference).

use crate::analysis::signal::quantities::{self, Quantity};
use crate::cosim::{Options, Override, Scene};
use crate::reference::scene::{SceneReference, compute, run_quantities};
use anyhow::{Context, anyhow, bail};
use std::path::{Path, PathBuf};

/// Where a run's relative error is drawn when it is exactly zero (a log axis has no zero).
pub const ERROR_FLOOR: f64 = 1e-12;

pub struct Study {
    pub scene: Scene,
    pub quantities: Vec<Quantity>,
    pub stop_time: f64,
    pub reference: SceneReference,
    /// The scene's macro step (osp:FixedStepAlgorithm), s.
    pub scene_step: f64,
    /// Parameters the reference sets beyond the scene's (the top of a fidelity ladder).
    pub reference_overrides: Vec<Override>,
}

/// How a study of a scene is set up: its quantities of interest, stop time and reference step.
pub struct Setup<'a> {
    /// The quantities file [default: quantities.toml in the scene's folder].
    pub quantities: Option<&'a Path>,
    /// Stop time, s [default: the scene's].
    pub stop_time: Option<f64>,
    /// Macro step of the reference, s (its own error is estimated at twice this step).
    pub reference_step: f64,
}

/// The quantities file of a scene: the given one, else quantities.toml in the scene's folder.
fn quantities_path(scene: &Scene, given: Option<&Path>) -> PathBuf {
    given
        .map(Path::to_path_buf)
        .unwrap_or_else(|| scene.root.join(quantities::FILE_NAME))
}

impl Study {
    /// Reads the scene's quantities and computes its reference with `reference_overrides` set;
    /// `starting(scene, step)` is told before the reference, the longest run of a study, starts.
    pub fn open(
        scene: Scene,
        setup: &Setup,
        reference_overrides: Vec<Override>,
        starting: impl FnOnce(&Scene, f64),
    ) -> anyhow::Result<Self> {
        let qpath = quantities_path(&scene, setup.quantities);
        if !qpath.is_file() {
            bail!(
                "{}: no quantities of interest for scene {}; write one (see scenes/c-shutdown/{}) or pass --quantities FILE",
                qpath.display(),
                scene.name,
                quantities::FILE_NAME
            );
        }
        let quantities = quantities::load(&qpath).map_err(|e| anyhow!(e))?;
        let stop_time = setup
            .stop_time
            .or(scene.experiment.stop_time)
            .ok_or_else(|| anyhow!("scene {}: no stop time; pass --stop-time", scene.name))?;
        let scene_step = scene.experiment.step_size.unwrap_or(1e-3);
        let reference_step = setup.reference_step;
        if !(reference_step > 0.0 && reference_step.is_finite()) {
            bail!("--reference-step {reference_step}: must be a positive number of seconds");
        }
        starting(&scene, reference_step);
        let reference =
            compute(&scene, &reference_overrides, &quantities, reference_step, stop_time).map_err(|e| anyhow!(e))?;
        Ok(Self {
            reference_overrides,
            scene,
            quantities,
            stop_time,
            reference,
            scene_step,
        })
    }

    /// The reference's quantities and its own error estimate, as lines of text.
    pub fn describe_reference(&self) -> String {
        let mut s = format!(
            "reference: {} at {} ms, {:.2} s CPU{}\n",
            self.scene.name,
            self.reference.step * 1e3,
            self.reference.cpu_s,
            if self.reference.unconverged > 0 {
                format!(", {} steps not converged to the tolerance", self.reference.unconverged)
            } else {
                String::new()
            }
        );
        for (i, q) in self.quantities.iter().enumerate() {
            s += &format!(
                "  {:<44} {:>14.6e}   tolerance {:>5.1} %   reference's own error ≈ {:.1e}\n",
                q.name,
                self.reference.values[i],
                q.tolerance * 100.0,
                self.reference.own_error(i)
            );
        }
        s
    }

    /// The largest of the reference's own error estimates over the quantities.
    pub fn reference_error(&self) -> f64 {
        (0..self.quantities.len())
            .map(|i| self.reference.own_error(i))
            .fold(0.0, f64::max)
    }

    /// The component whose FMU is `fmu` (e.g. "torsional"), for the parameters a study varies.
    pub fn component_of(&self, fmu: &str) -> anyhow::Result<String> {
        component_of(&self.scene, fmu)
            .with_context(|| format!("scene {} has no {fmu} component ({fmu}.fmu)", self.scene.name))
    }

    /// Runs the scene `repeat` times with `overrides` and `opts`; best CPU time, errors per quantity.
    pub fn measure(&self, overrides: &[Override], opts: &Options, repeat: usize) -> Measured {
        let mut best = f64::INFINITY;
        let mut values = Vec::new();
        for _ in 0..repeat.max(1) {
            match run_quantities(&self.scene, overrides, &self.quantities, opts.clone()) {
                Ok((v, run)) => {
                    best = best.min(run.cpu_s);
                    values = v;
                }
                Err(e) => {
                    return Measured {
                        cpu_s: f64::NAN,
                        errors: Vec::new(),
                        failure: Some(e),
                    };
                }
            }
        }
        let errors = values
            .iter()
            .zip(&self.reference.values)
            .map(|(v, r)| quantities::relative_error(*v, *r))
            .collect();
        Measured {
            cpu_s: best,
            errors,
            failure: None,
        }
    }
}

/// The component of `scene` whose FMU is `fmu` (e.g. "torsional"), if any.
pub fn component_of(scene: &Scene, fmu: &str) -> Option<String> {
    let file = format!("{fmu}.fmu");
    scene
        .components
        .iter()
        .find(|c| c.path.file_name().and_then(|n| n.to_str()) == Some(file.as_str()))
        .map(|c| c.name.clone())
}

/// One measured run.
#[derive(Debug, Clone)]
pub struct Measured {
    pub cpu_s: f64,
    /// Relative error of each quantity against the reference (empty when the run failed).
    pub errors: Vec<f64>,
    pub failure: Option<String>,
}

impl Measured {
    /// The largest relative error over the quantities.
    pub fn worst(&self) -> f64 {
        self.errors.iter().cloned().fold(0.0, f64::max)
    }

    /// The quantity with the largest relative error, "" when the run failed.
    pub fn worst_quantity<'q>(&self, qs: &'q [Quantity]) -> &'q str {
        self.errors
            .iter()
            .zip(qs)
            .max_by(|a, b| a.0.total_cmp(b.0))
            .map(|(_, q)| q.name.as_str())
            .unwrap_or("")
    }

    /// Every quantity within its tolerance.
    pub fn within(&self, qs: &[Quantity]) -> bool {
        self.failure.is_none() && self.errors.iter().zip(qs).all(|(e, q)| *e <= q.tolerance)
    }

    /// The largest error in units of each quantity's tolerance (≤ 1: within).
    pub fn worst_in_tolerances(&self, qs: &[Quantity]) -> f64 {
        self.errors
            .iter()
            .zip(qs)
            .map(|(e, q)| e / q.tolerance)
            .fold(0.0, f64::max)
    }
}
