//! Research studies as library functions that return data, for the command line to print and plot.
//! So far: the calibration of drivetrain C's estimated inputs against the thesis's measured
//! statistics ([`calibration`], with the [`nelder_mead`] minimiser it uses), the integrators'
//! stability on the torsional model (`integrators`), chatter at the brake and the backlash
//! (`nonsmooth`) and the co-simulation stability map (`stability`). The studies that report with
//! `anyhow` errors or run the master come with the `cli` feature, as those do.

pub mod calibration;
#[cfg(feature = "cli")]
pub mod integrators;
pub mod nelder_mead;
#[cfg(feature = "cli")]
pub mod nonsmooth;
#[cfg(feature = "cli")]
pub mod stability;
