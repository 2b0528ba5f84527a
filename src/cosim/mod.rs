//! The co-simulation master: SSP scenes (`ssp`), made runnable and checked (`system`), stepped by
//! an algorithm (`master`) with the options a run's settings and its scene give (`settings`),
//! recorded to CSV or Parquet (`recorder`, `parquet`) and summed up when it ends (`summary`); where each algorithm is stable
//! in theory (`stability`).

pub mod acceleration;
mod checks;
pub mod divergence;
pub mod error;
pub mod master;
pub mod parquet;
pub mod profile;
pub mod recorder;
pub mod settings;
pub mod ssp;
pub mod stability;
pub mod summary;
pub mod system;
pub mod unit;
pub mod xml;

pub use acceleration::Acceleration;
pub use master::{Algorithm, Master, MasterError, Options, Stats};
pub use ssp::{Scene, SspError, Value};

/// A parameter set on top of a scene's bindings: (component, variable, value as text), as `--param`.
pub type Override = (String, String, String);

/// The override `component.variable = value`.
pub fn param(component: &str, variable: &str, value: impl ToString) -> Override {
    (component.to_string(), variable.to_string(), value.to_string())
}
pub use error::SystemError;
pub use system::{Record, System};
pub use unit::{Kind, Link, Unit};
