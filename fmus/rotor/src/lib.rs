//! The `rotor` FMU: the drivetrain's input (wind, aerodynamics, pitch control, shutdown sequence).
//! All logic lives in the windrive library (`windrive::slaves::rotor`); this crate only exports
//! the FMI symbols.

pub use windrive::slaves::rotor::RotorSlave;

windrive::export_fmu!(RotorSlave);
