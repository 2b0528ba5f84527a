//! Ratings a certification engineer reads: gear teeth after ISO 6336 (geometry, root form, contact
//! and root stresses, every tooth of a gearbox from one series), rolling bearings after ISO 281, and
//! the allowable stresses the thesis checks against. Hertz contact itself is physics
//! ([`crate::physics::hertz`]).

pub mod bearing_set;
pub mod gear;
pub mod gear_set;
pub mod life_modification;
pub mod limits;
pub mod tooth_root;
