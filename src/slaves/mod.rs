//! FMU faces of the physics: each maps one modelDescription's variables onto a model and implements
//! [`crate::fmi2::slave::Slave`]. The `fmus/<name>` crates only export them.

pub mod generator;
pub mod rotor;
pub mod torsional;
