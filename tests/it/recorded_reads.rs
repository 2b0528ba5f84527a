//! What the master reads for the recorder. After a Jacobi or Gauss–Seidel step whose row the recorder
//! keeps (`System::record_next`), each FMU's recorder-only variables come with its coupled outputs, one
//! fmi2GetReal for both (`Unit::fetch_with_recorded`); the recorder then reads nothing more. Those
//! values must be the ones the recorder's own reads after the sweep return, to the bit.

use crate::common;

use common::scene_copy;
use std::path::Path;
use windrive::cosim::recorder::Recorder;
use windrive::cosim::{Algorithm, Master, Options, Record, Scene, System};
use windrive::fmi2::host::isolate::Isolation;

/// Runs `scene` for 0.3 s with a recorder keeping one row in `every`; at each kept row after the
/// start, checks that every unit with recorder-only variables read them with its step (the recorder
/// said it would keep the row), then reads both groups again apart and compares every value's bits.
/// Returns the rows checked and, per unit, whether its coupled outputs include Integers or Booleans
/// (read through scratch then).
fn check(scene: &Scene, algorithm: Algorithm, every: u64, isolated: bool) -> (usize, Vec<bool>) {
    let mut system = if isolated {
        let host = Path::new(env!("CARGO_BIN_EXE_windrive"));
        System::build_isolated(scene, &[], &Record::Outputs, &Isolation::new(host)).unwrap()
    } else {
        System::build(scene, &[], &Record::Outputs).unwrap()
    };
    let stop = 0.3;
    system.initialize(Some(stop)).unwrap();
    let discrete = system
        .units
        .iter()
        .map(|u| u.coupled.len() > u.coupled.real.len())
        .collect();
    let mut recorder = Recorder::new(None, true, &system, every).unwrap();
    let (mut seen, mut checked) = (0u64, 0usize);
    let mut master = Master::new(&mut system, Options::new(algorithm, 1e-3, stop)).unwrap();
    master
        .run(|t, sys| {
            let keep = seen.is_multiple_of(every);
            seen += 1;
            if keep && t > 0.0 {
                for unit in &mut sys.units {
                    let with_step: Vec<u64> = unit.values.iter().map(|v| v.to_bits()).collect();
                    assert_eq!(
                        unit.recorded_fresh,
                        !unit.recorded_only.is_empty(),
                        "{} at t = {t}: recorder-only variables not read with the step",
                        unit.name
                    );
                    unit.fetch().unwrap();
                    unit.fetch_recorded().unwrap();
                    let apart: Vec<u64> = unit.values.iter().map(|v| v.to_bits()).collect();
                    assert!(with_step == apart, "{} at t = {t}: values differ", unit.name);
                }
                checked += 1;
            } else if !keep {
                // a row not kept: the step read the coupled outputs only
                assert!(sys.units.iter().all(|u| !u.recorded_fresh), "t = {t}");
            }
            recorder.observe(t, sys)
        })
        .unwrap();
    let rows = recorder.take_series().unwrap().time.len();
    assert_eq!(rows, 1 + 300 / every as usize);
    (checked, discrete)
}

#[test]
fn recorded_variables_read_with_the_step_are_those_read_apart() {
    let (_guard, dir) = scene_copy("c-shutdown");
    let scene = Scene::open(&dir).unwrap();
    for algorithm in [Algorithm::Jacobi, Algorithm::GaussSeidel] {
        for every in [1, 3] {
            let (checked, discrete) = check(&scene, algorithm, every, false);
            assert_eq!(checked, 300 / every as usize, "{} every {every}", algorithm.name());
            // both ways of the joined read are taken: beside the coupled Reals, and through scratch
            assert!(discrete.contains(&true) && discrete.contains(&false), "{discrete:?}");
        }
    }
    // through `--isolate`: a round trip to the FMU's process per call
    let (checked, _) = check(&scene, Algorithm::GaussSeidel, 1, true);
    assert_eq!(checked, 300);
}
