//! Research studies as library functions that return data, for the command line to print and plot.
//! So far: the calibration of drivetrain C's estimated inputs against the thesis's measured
//! statistics ([`calibration`], with the [`nelder_mead`] minimiser it uses).

pub mod calibration;
pub mod nelder_mead;
