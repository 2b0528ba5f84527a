//! The 6-DOF-per-body gearbox (thesis ch. 5 and 7; the SIMPACK model with sliced gear meshes):
//! description files, involute geometry, the sliced mesh, the assembled model and its statics (its modes: `crate::linear::gearbox_modes`).

pub mod assembly;
pub mod beam;
pub mod bearing;
pub mod contact;
pub mod description;
pub mod involute;
pub mod loads;
pub mod mesh;
pub mod model;
pub mod near;
mod ninth_root;
pub mod roller_table;
pub mod row;
pub mod statics;
mod system;

pub use description::Description;
pub use model::Gearbox;
