//! Shared helpers for tests that load the packed FMU through the FMI boundary.
#![allow(dead_code)]

use std::path::PathBuf;
use windrive::fmi2::import::{Fmu, Instance};

/// The packed torsional FMU (scripts/test packs it before running the tests).
pub fn torsional_fmu_path() -> PathBuf {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target"));
    let path = target.join("fmu").join("torsional.fmu");
    assert!(
        path.is_file(),
        "{} is missing: run `cargo run --release -- pack` first (scripts/test does)",
        path.display()
    );
    path
}

pub fn torsional() -> Fmu {
    Fmu::open(&torsional_fmu_path()).expect("the packed FMU opens")
}

/// An instance in step mode with string and real parameters applied.
pub fn initialised(fmu: &Fmu, strings: &[(&str, &str)], reals: &[(&str, f64)]) -> Instance {
    let mut inst = fmu.instantiate("test", true).unwrap();
    inst.setup_experiment(0.0, None).unwrap();
    for (name, value) in strings {
        inst.set_string(&[fmu.vr(name).unwrap()], &[value]).unwrap();
    }
    for (name, value) in reals {
        inst.set_real(&[fmu.vr(name).unwrap()], &[*value]).unwrap();
    }
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    inst
}

pub fn get(fmu: &Fmu, inst: &mut Instance, name: &str) -> f64 {
    let mut v = [0.0];
    inst.get_real(&[fmu.vr(name).unwrap()], &mut v).unwrap();
    v[0]
}

pub fn set(fmu: &Fmu, inst: &mut Instance, name: &str, value: f64) {
    inst.set_real(&[fmu.vr(name).unwrap()], &[value]).unwrap();
}
