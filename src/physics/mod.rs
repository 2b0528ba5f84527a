//! Pure Rust models: no FFI, no globals. Every test of the physics runs without an FMU.

pub mod drivetrain;
pub mod generator;
pub mod modes;
pub mod torsional;
