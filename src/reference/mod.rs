//! Reference solutions: the same physics assembled in one process, no co-simulation, so that what the
//! FMUs and the master compute can be checked and timed against it.
//!
//! - [`step`]: the rated-torque step on a drivetrain, run on the torsional model directly or through
//!   its FMU (the step response and the torsional benchmark).
//! - [`grid_step`]: the exact modal solution of the d-grid-step scene, and a run of the scene through
//!   the master compared with it (the coupling benchmark's work–precision chart).
//! - [`shaft_cut`]: the exact two-mass solution of the d-shaft-cut scene (a drivetrain cut in its
//!   main shaft across two FMUs).
//!
//! What needs the master or FMI import is behind the `cli` feature, as those are.

pub mod grid_step;
pub mod modes;
#[cfg(feature = "cli")]
pub mod scene;
pub mod shaft_cut;
pub mod step;

/// Errors of the reference runs, naming the preset, variable or time at fault.
#[derive(Debug, thiserror::Error)]
pub enum ReferenceError {
    #[error("unknown preset {0:?}: use A, B, C or D")]
    UnknownPreset(String),
    #[error("torsional model: {0}")]
    Model(String),
    #[cfg(feature = "cli")]
    #[error(transparent)]
    Fmu(#[from] crate::fmi2::host::error::ImportError),
    #[cfg(feature = "cli")]
    #[error("at t = {time} s: {source}")]
    Step {
        time: f64,
        source: crate::fmi2::host::error::ImportError,
    },
    #[cfg(feature = "cli")]
    #[error(transparent)]
    Scene(#[from] crate::cosim::SspError),
    #[cfg(feature = "cli")]
    #[error(transparent)]
    System(#[from] crate::cosim::SystemError),
    #[cfg(feature = "cli")]
    #[error(transparent)]
    Master(#[from] crate::cosim::MasterError),
}

impl From<crate::fmi2::fmu::error::SlaveError> for ReferenceError {
    fn from(e: crate::fmi2::fmu::error::SlaveError) -> Self {
        Self::Model(e.0)
    }
}
