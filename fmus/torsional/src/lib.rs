//! The `torsional` FMU: drivetrains A–D as a lumped torsional model. All logic lives in the
//! windrive library (`windrive::slaves::torsional`); this crate only exports the FMI symbols.

pub use windrive::slaves::torsional::TorsionalSlave;

windrive::export_fmu!(TorsionalSlave);
