//! The `generator` FMU: the generator of drivetrains A–D as the shaft sees it. All logic lives in
//! the windrive library (`windrive::slaves::generator`); this crate only exports the FMI symbols.

pub use windrive::slaves::generator::GeneratorSlave;

windrive::export_fmu!(GeneratorSlave);
