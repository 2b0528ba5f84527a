//! Research studies as library functions that return data, for the command line to print and plot.
//! So far: the calibration of drivetrain C's estimated inputs against the thesis's measured
//! statistics ([`calibration`], with the [`nelder_mead`] minimiser it uses) and the co-simulation
//! stability map (`stability`, with the master).

pub mod calibration;
pub mod nelder_mead;
#[cfg(feature = "cli")]
pub mod stability;
