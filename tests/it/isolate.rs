//! FMU instances in host processes of their own (`windrive run --isolate`): the same results bit
//! for bit as in-process, under every algorithm (the iterative and adaptive ones save and restore
//! states in the host); FMU errors come back with their function, status and log, a queued call's
//! error with the queued call's name; a host that dies is reported with its signal and the call, and
//! the instance refuses every later call. The crash of a third-party FMU mid-run, with every row
//! kept, is in tests/python/test_master.py.

use crate::common;

use common::{fmu_path, scene_copy};
use std::path::Path;
use windrive::cosim::{Algorithm, Master, Options, Record, Scene, System};
use windrive::fmi2::host::error::ImportError;
use windrive::fmi2::host::import::{Fmu, Instance};
use windrive::fmi2::host::isolate::Isolation;

fn host() -> &'static Path {
    Path::new(env!("CARGO_BIN_EXE_windrive"))
}

/// Every recorded value of a run of `scene` as bits, row by row.
fn run(scene: &Scene, algorithm: Algorithm, stop: f64, isolated: bool) -> Vec<u64> {
    let mut system = if isolated {
        System::build_isolated(scene, &[], &Record::Outputs, &Isolation::new(host())).unwrap()
    } else {
        System::build(scene, &[], &Record::Outputs).unwrap()
    };
    system.initialize(Some(stop)).unwrap();
    let mut bits = Vec::new();
    let mut master = Master::new(&mut system, Options::new(algorithm, 1e-3, stop)).unwrap();
    master
        .run(|t, sys| {
            windrive::cosim::master::read_recorded(sys, t)?;
            bits.push(t.to_bits());
            bits.extend(sys.recorded.iter().map(|&(_, u, i)| sys.units[u].values[i].to_bits()));
            Ok(())
        })
        .unwrap();
    bits
}

#[test]
fn isolated_runs_are_bit_identical_to_in_process_runs_under_every_algorithm() {
    let (_guard, dir) = scene_copy("c-shutdown");
    let scene = Scene::open(&dir).unwrap();
    // 0.5 s from 19.7 s would need the brake: run the start, where every algorithm steps and the
    // iterative and adaptive ones restore states
    for algorithm in [
        Algorithm::GaussSeidel,
        Algorithm::Jacobi,
        Algorithm::Iterative,
        Algorithm::Adaptive,
    ] {
        let local = run(&scene, algorithm, 0.3, false);
        let isolated = run(&scene, algorithm, 0.3, true);
        assert!(local.len() > 300 * 70, "{}: {} values", algorithm.name(), local.len());
        assert!(local == isolated, "{}: isolated results differ", algorithm.name());
    }
}

fn isolated(name: &str) -> (Fmu, Instance) {
    let fmu = Fmu::open_for_host(&fmu_path(name)).unwrap();
    let inst = fmu.instantiate_isolated(name, false, &Isolation::new(host())).unwrap();
    (fmu, inst)
}

fn initialised(name: &str) -> (Fmu, Instance) {
    let (fmu, mut inst) = isolated(name);
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    (fmu, inst)
}

#[test]
fn states_made_in_the_host_serialise_and_restore_bit_identically() {
    let (fmu, mut inst) = initialised("torsional");
    let torque = fmu.vr("rotor_torque").unwrap();
    let speed = [fmu.vr("generator_speed").unwrap()];
    let read = |inst: &mut Instance| {
        let mut v = [0.0];
        inst.get_real(&speed, &mut v).unwrap();
        v[0].to_bits()
    };
    inst.set_real(&[torque], &[4e5]).unwrap();
    inst.do_step(0.0, 1e-3).unwrap();
    let mut saved = inst.get_state().unwrap();
    let bytes = inst.serialize_state(&saved).unwrap();
    // 19 steps from 1 ms, the generator speed after each
    let steps = |inst: &mut Instance| -> Vec<u64> {
        (1..20)
            .map(|k| {
                inst.do_step(k as f64 * 1e-3, 1e-3).unwrap();
                read(inst)
            })
            .collect()
    };
    let ahead = steps(&mut inst);
    inst.set_state(&saved).unwrap();
    let again = steps(&mut inst);
    assert_eq!(ahead, again);
    inst.update_state(&mut saved).unwrap();
    inst.free_state(saved).unwrap();
    // the serialised bytes, restored in a second isolated instance (another process)
    let (_, mut other) = initialised("torsional");
    let restored = other.deserialize_state(&bytes).unwrap();
    other.set_state(&restored).unwrap();
    other.free_state(restored).unwrap();
    assert_eq!(ahead, steps(&mut other));
    // corrupt bytes are refused there as in-process
    let mut bad = bytes.clone();
    bad[bytes.len() / 2] ^= 1;
    assert!(matches!(other.deserialize_state(&bad), Err(ImportError::Call { .. })));
}

#[test]
fn fmu_errors_come_back_with_their_function_status_and_log() {
    // answered at once
    let (_, mut inst) = initialised("generator");
    let err = inst.get_real(&[999_999], &mut [0.0]).unwrap_err().to_string();
    assert!(
        err.contains("generator: fmi2GetReal returned fmi2Error") && err.contains("999999"),
        "{err}"
    );
    // a queued call's error is reported by the next call that waits, naming the queued call
    let (_, mut inst) = initialised("generator");
    inst.set_real(&[999_998], &[1.0]).unwrap();
    let err = inst.do_step(0.0, 1e-3).unwrap_err().to_string();
    assert!(
        err.contains("fmi2SetReal returned fmi2Error") && err.contains("999998"),
        "{err}"
    );
    // NaN input: refused by the FMU as in-process
    let (fmu, mut inst) = initialised("generator");
    let speed = fmu.vr("generator_speed").unwrap();
    inst.set_real(&[speed], &[f64::NAN]).unwrap();
    let err = inst.do_step(0.0, 1e-3).unwrap_err().to_string();
    assert!(err.contains("fmi2SetReal returned fmi2Error"), "{err}");
}

#[test]
fn a_host_that_dies_is_named_with_its_signal_and_every_later_call_is_refused() {
    let (fmu, mut inst) = initialised("torsional");
    let torque = fmu.vr("rotor_torque").unwrap();
    inst.do_step(0.0, 1e-3).unwrap();
    let pid = inst.pid();
    assert_ne!(pid, std::process::id());
    // SAFETY: kills the host process this test started. (A SIGSEGV sent by kill would be survived:
    // Rust's stack-overflow handler returns from one that is not a guard-page fault.)
    assert_eq!(unsafe { libc::kill(pid as i32, libc::SIGKILL) }, 0);
    inst.set_real(&[torque], &[1.0]).unwrap(); // queued: nothing crosses yet
    let err = inst.do_step(1e-3, 1e-3).unwrap_err();
    let text = err.to_string();
    assert!(matches!(err, ImportError::Crashed { .. }), "{text}");
    assert!(
        text.contains("torsional: its process ended during fmi2SetReal, fmi2DoStep: killed by signal 9"),
        "{text}"
    );
    let later = inst.get_real(&[torque], &mut [0.0]).unwrap_err().to_string();
    assert!(later.contains("killed by signal 9"), "{later}");
    drop(inst); // nothing to wait for: returns at once
}

#[test]
fn a_missing_host_or_a_failing_instantiation_is_an_error_naming_the_instance() {
    let fmu = Fmu::open_for_host(&fmu_path("generator")).unwrap();
    let err = fmu
        .instantiate_isolated("g", false, &Isolation::new("/nonexistent/windrive"))
        .err()
        .unwrap()
        .to_string();
    assert!(
        err.starts_with("g: cannot start /nonexistent/windrive fmu-host"),
        "{err}"
    );
    // opened for a host, the binary is not loaded here: an in-process instance is refused
    let err = fmu.instantiate("g", false).err().unwrap().to_string();
    assert!(err.contains("instantiate it isolated"), "{err}");
}

/// `fmu-host` started by hand, and the run options of isolation and acceleration, with bad input:
/// a message naming the problem and a failing exit, never a hang.
#[test]
fn bad_host_and_option_input_is_refused_with_its_reason() {
    let run = |args: &[&str]| {
        let out = std::process::Command::new(host())
            .args(args)
            .stdin(std::process::Stdio::null())
            .output()
            .unwrap();
        (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned())
    };
    let me = std::process::id().to_string();
    let host_for = |master: &str| {
        run(&[
            "fmu-host",
            "--fd",
            "0",
            "--dir",
            "/nonexistent",
            "--name",
            "x",
            "--master",
            master,
        ])
    };
    let (code, err) = host_for("1");
    assert_eq!(code, Some(1));
    assert!(err.contains("fmu-host x: the master is gone"), "{err}");
    let (code, err) = host_for(&me);
    assert_eq!(code, Some(1));
    assert!(err.contains("fmu-host x: descriptor 0 is not a mailbox"), "{err}");
    let (code, err) = run(&["run", "scenes/c-shutdown", "--isolate", "--call-timeout", "0"]);
    assert_eq!(code, Some(2));
    assert!(err.contains("\"0\" is not a positive number of seconds"), "{err}");
    let (code, err) = run(&["run", "scenes/c-shutdown", "--acceleration", "newton"]);
    assert_eq!(code, Some(2));
    assert!(
        err.contains("unknown acceleration \"newton\" (one of none, aitken, iqn-ils)"),
        "{err}"
    );
}
