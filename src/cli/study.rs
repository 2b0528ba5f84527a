//! What `windrive chart work-precision` and `windrive fidelity` share: the options of a study of one
//! scene, and opening it ([`crate::studies::scene_study`]) with the scene's FMUs in place.

use crate::cosim::{Override, Scene};
use crate::studies::scene_study::{Setup, Study};
use std::path::PathBuf;

/// What every study of a scene is told: how long, how many runs per point, against which reference
/// and quantities.
#[derive(clap::Args)]
pub struct StudyArgs {
    /// Runs per point; the CPU time is the best of them
    #[arg(long, default_value_t = 3)]
    pub repeat: usize,
    /// Stop time, s [default: the scene's]
    #[arg(long)]
    pub stop_time: Option<f64>,
    /// Macro step of the reference, s (its own error is estimated at twice this step)
    #[arg(long, default_value_t = crate::reference::scene::DEFAULT_STEP)]
    pub reference_step: f64,
    /// Quantities of interest [default: quantities.toml beside the scene]
    #[arg(long)]
    pub quantities: Option<PathBuf>,
}

impl StudyArgs {
    /// The study of `scene` against its reference run with `reference_overrides`, saying on stderr
    /// when the reference, the longest run of a study, starts.
    pub fn open(&self, scene: Scene, reference_overrides: Vec<Override>) -> anyhow::Result<Study> {
        super::run::provide_own_fmus(&scene, false)?;
        let setup = Setup {
            quantities: self.quantities.as_deref(),
            stop_time: self.stop_time,
            reference_step: self.reference_step,
        };
        Study::open(scene, &setup, reference_overrides, |scene, step| {
            eprintln!(
                "reference: {} converged at every {} ms step (iterative, IQN-ILS, tolerance {:.0e}), and at twice the step ...",
                scene.name,
                step * 1e3,
                crate::reference::scene::TOLERANCE
            )
        })
    }
}
