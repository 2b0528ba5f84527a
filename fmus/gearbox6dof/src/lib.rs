//! The `gearbox6dof` FMU: a gearbox with 6 DOF per body from a description file. All logic lives in
//! the windrive library (`windrive::slaves::gearbox6dof`); this crate only exports the FMI symbols.

pub use windrive::slaves::gearbox6dof::Gearbox6dofSlave;

windrive::export_fmu!(Gearbox6dofSlave);
