//! The co-simulation master: SSP scenes (`ssp`), made runnable and checked (`system`), stepped by
//! an algorithm (`master`), recorded to CSV (`recorder`).

pub mod acceleration;
pub mod divergence;
mod checks;
pub mod master;
pub mod recorder;
pub mod ssp;
pub mod system;
pub mod unit;
pub mod xml;

pub use acceleration::Acceleration;
pub use master::{Algorithm, Master, MasterError, Options, Stats};
pub use ssp::{Scene, SspError, Value};
pub use system::{Record, System, SystemError};
pub use unit::{Kind, Link, Unit};
