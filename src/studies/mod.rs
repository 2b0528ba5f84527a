//! Research studies as library functions that return data, for the command line to print and plot.
//! Values taken from the thesis are data with their source (data/thesis.toml), not code.
//!
//! - the thesis's main case: a drivetrain's normal operation and shutdown through the master, their
//!   summary and charts (`shutdown`);
//! - the thesis beside us: every number of the thesis we compute, beside ours (`reproduce`, its values
//!   in data/thesis.toml, its 6-DOF gearbox quantities in `chapter7`, its 20-year conclusions in `thesis_life`); the calibration of drivetrain C's estimated inputs against the thesis's
//!   measured statistics ([`calibration`], its fit over C's scenes in `calibration::fit`, with the
//!   [`nelder_mead`] minimiser);
//! - which method, step and model for a scene: error against CPU time over a grid of runs
//!   (`work_precision`), the cheapest drivetrain model within the scene's tolerances (`fidelity`),
//!   both against the scene's reference (`scene_study`);
//! - numerics: the integrators' stability on the torsional model (`integrators`), chatter at the
//!   brake and the backlash (`nonsmooth`), the co-simulation stability map (`stability`);
//! - the 6-DOF gearbox at a steady operating point: its bearings' and meshes' loads and stresses, and
//!   the carrier-web stiffness that gives a measured load split (`operating_point`), and one carrier
//!   revolution there: where each planet's upwind bearing peaks (`carrier_revolution`), and every
//!   mesh's dynamic factor K_v there, the model's beside ISO 6336-1 method B (`dynamic_factor`);
//! - lifetime fatigue: the climate, the gear tooth or bearing a channel loads, and the reports of
//!   their lifetimes (`life`);
//! - shared: a preset's modes chosen by name (`preset_modes`).
//!
//! The studies that report with `anyhow` errors or run the master come with the `cli` feature, as
//! those do.

#[cfg(feature = "cli")]
pub mod aero;
pub mod calibration;
#[cfg(feature = "cli")]
pub mod carrier_revolution;
#[cfg(feature = "cli")]
pub mod chapter7;
#[cfg(feature = "cli")]
pub mod dynamic_factor;
#[cfg(feature = "cli")]
pub mod estimates;
#[cfg(feature = "cli")]
pub mod fidelity;
#[cfg(feature = "cli")]
pub mod integrators;
#[cfg(feature = "cli")]
pub mod life;
pub mod nelder_mead;
#[cfg(feature = "cli")]
pub mod nonsmooth;
#[cfg(feature = "cli")]
pub mod operating_point;
#[cfg(feature = "cli")]
pub mod preset_modes;
#[cfg(feature = "cli")]
pub mod reproduce;
#[cfg(feature = "cli")]
pub mod scene_study;
#[cfg(feature = "cli")]
pub mod shutdown;
#[cfg(feature = "cli")]
pub mod stability;
#[cfg(feature = "cli")]
pub mod thesis_life;
#[cfg(feature = "cli")]
pub mod work_precision;
