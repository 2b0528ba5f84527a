//! The co-simulation master: SSP scenes (`ssp`), made runnable and checked (`system`), stepped by
//! an algorithm (`master`), recorded to CSV (`recorder`).

pub mod master;
pub mod recorder;
pub mod ssp;
pub mod system;
mod xml;

pub use master::{Algorithm, Master, MasterError, Options, Stats};
pub use ssp::{Scene, SspError, Value};
pub use system::{Record, System, SystemError};
