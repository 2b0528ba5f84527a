//! The FMI 2.0 boundary, both directions, each side apart:
//!
//! - [`types`]: the C types of the standard, shared by both sides;
//! - [`values`]: checks on the values that cross the boundary, shared by both sides;
//! - [`fmu`]: the FMU side (the [`fmu::slave::Slave`] trait a model implements, the export adapter
//!   that turns it into the 34 `fmi2*` symbols, the variable tables generated from the XML);
//! - `host` (with the `cli` feature): the importer side the master uses (archives, model
//!   descriptions, in-process instances, and instances isolated in processes of their own).
//!
//! An FMU binary links the FMU side only.

pub mod fmu;
pub mod types;
pub mod values;

#[cfg(feature = "cli")]
pub mod host;
