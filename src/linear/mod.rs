//! Linear analysis of both drivetrain models, in one place: natural frequencies and mode shapes of
//! any linearisation ([`modes`]; the gearbox's modes classified in [`gearbox_modes`]), frequency
//! responses ([`response`]) and their Bode data ([`bode`]), and Campbell diagrams ([`campbell`]).

pub mod bode;
pub mod campbell;
pub mod gearbox_modes;
pub mod modes;
pub mod response;
