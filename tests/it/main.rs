//! Every Rust integration test in one binary: one crate to compile and one (thin-LTO) link instead of
//! one per file, which took most of the test suite's build time on a 2-core machine. Each file is a
//! module; `cargo test --release --test it MODULE::` runs one of them.

mod common;
mod cosim_errors;
mod cosim_master;
mod estimates;
mod fmi_bad_input;
mod fmi_fuzz;
mod fmi_lifecycle;
mod fmi_state;
mod fmu_faces;
mod fmu_package;
mod gearbox_bearing;
mod gearbox_lamina;
mod gearbox_model;
mod gearbox_scene;
mod import_hostile;
mod isolate;
mod newton_kept;
mod non_smooth;
mod paper_turbine;
mod physics_modes;
mod plain_step;
mod read_plan;
mod readme;
mod recorded_reads;
mod reproduction;
mod rotor_aero_damping;
mod rotor_blades;
mod scene_reference;
mod scenes_as_simulated;
mod scenes_thesis;
mod shaft_cut;
mod solver_zoo;
mod start_forces;
mod torsional_dynamics;
