//! Pure Rust models: no FFI, no globals. Every test of the physics runs without an FMU.

pub mod aero;
pub mod bem;
pub mod blade;
pub mod blades;
pub mod brake;
pub mod drivetrain;
pub mod gearbox;
pub mod generator;
pub mod hertz;
pub mod rotor;
pub mod torsional;
pub mod turbulence;
pub mod wind_field;
