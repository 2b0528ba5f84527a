//! A hostile host (issue 16): seeded random FMI 2.0 call sequences against every exported FMU —
//! calls in any order, unknown and out-of-range value references, NaN, ±inf and huge values of every
//! type, zero, negative, non-finite and huge steps, states taken, restored, freed, serialised with
//! flipped bits and truncated, NULL pointers. It fails on any fmi2Fatal (a panic reached the
//! boundary), any call slower than a second (a hang), and any non-finite output returned with fmi2OK.
//!
//! CI runs a modest count; `WINDRIVE_FUZZ_SEQUENCES=N` runs N per FMU, `WINDRIVE_FUZZ_FIRST=K`
//! starts at the K-th sequence of the same seeded stream, so a long run can be split
//! (docs/FMU-BOUNDARY.md).
//! A failure names the FMU, the sequence's seed and the call.

use crate::common;
use common::*;
use std::time::Duration;
use windrive::fmi2::host::error::ImportError;
use windrive::fmi2::host::import::{Fmu, Instance};
use windrive::fmi2::host::state::SavedState;
use windrive::fmi2::types::Fmi2Status;

use crate::common::Rng;

const REALS: [f64; 14] = [
    0.0,
    1.0,
    -1.0,
    0.5,
    1e3,
    -1e5,
    1e300,
    -1e300,
    1e-300,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    f64::MAX,
    f64::MIN_POSITIVE,
];
const INTS: [i32; 8] = [0, 1, -1, 2, 3, 1000, i32::MAX, i32::MIN];
const STEPS: [f64; 9] = [1e-3, 1e-2, 1e-4, 0.0, -1e-3, f64::NAN, f64::INFINITY, 1e9, 1e-300];
const STRINGS: [&str; 6] = ["", "C", "D", "no such preset", "../../etc/passwd", "αβγ"];

/// The variables of one type, plus value references nobody declared.
fn refs(fmu: &Fmu, ty: &str) -> Vec<u32> {
    let vars = &fmu.description.model_variables.variables;
    let mut r: Vec<u32> = vars
        .iter()
        .filter(|v| v.type_name() == ty)
        .map(|v| v.value_reference)
        .collect();
    r.extend([9_999, u32::MAX, 12_345]);
    r
}

fn outputs(fmu: &Fmu) -> Vec<u32> {
    let vars = &fmu.description.model_variables.variables;
    vars.iter()
        .filter(|v| v.causality == "output" && v.type_name() == "Real")
        .map(|v| v.value_reference)
        .collect()
}

/// Calls answered OK and refused, and outputs checked finite, over a run (printed at its end).
static ANSWERED: [std::sync::atomic::AtomicU64; 3] = [const { std::sync::atomic::AtomicU64::new(0) }; 3];

fn count(i: usize, n: u64) {
    ANSWERED[i].fetch_add(n, std::sync::atomic::Ordering::Relaxed);
}

/// What one call returned, checked: fmi2Fatal or a hang (a second of CPU) fails the run; an error
/// is an answer.
fn judge<T>(what: &str, start: Duration, r: Result<T, ImportError>) -> Option<T> {
    count(usize::from(r.is_err()), 1);
    let took = cpu_now().saturating_sub(start);
    assert!(
        took < Duration::from_secs(1),
        "{what} took {took:?}: a host sees a hang"
    );
    match r {
        Ok(v) => Some(v),
        Err(ImportError::Call { status, log, .. }) => {
            assert!(status != "fmi2Fatal", "{what} returned fmi2Fatal: {log:?}");
            None
        }
        Err(e) => panic!("{what}: {e}"),
    }
}

/// One random sequence of `calls` calls on a fresh instance.
fn sequence(fmu: &Fmu, rng: &mut Rng, calls: usize) {
    let (reals, ints, bools, strings) = (
        refs(fmu, "Real"),
        refs(fmu, "Integer"),
        refs(fmu, "Boolean"),
        refs(fmu, "String"),
    );
    let outs = outputs(fmu);
    let mut inst: Instance = fmu.instantiate("fuzz", false).unwrap();
    let mut states: Vec<SavedState> = Vec::new();
    let mut time = 0.0;
    // half the sequences start from a properly initialised instance, so that steps get far
    if rng.below(2) == 0 {
        let start = cpu_now();
        judge("setup", start, inst.setup_experiment(0.0, None));
        judge("enter", start, inst.enter_initialization_mode());
        judge("exit", start, inst.exit_initialization_mode());
    }
    for k in 0..calls {
        let op = rng.below(16);
        let start = cpu_now();
        let what = format!("call {k}, op {op}");
        let n = 1 + rng.below(3);
        match op {
            0 => {
                judge(&what, start, inst.setup_experiment(rng.pick(&REALS), None));
            }
            1 => {
                judge(&what, start, inst.enter_initialization_mode());
            }
            2 => {
                judge(&what, start, inst.exit_initialization_mode());
            }
            3 => {
                let vr: Vec<u32> = (0..n).map(|_| rng.pick(&reals)).collect();
                let v: Vec<f64> = (0..n).map(|_| rng.pick(&REALS)).collect();
                judge(&what, start, inst.set_real(&vr, &v));
            }
            4 => {
                let vr: Vec<u32> = (0..n).map(|_| rng.pick(&ints)).collect();
                let v: Vec<i32> = (0..n).map(|_| rng.pick(&INTS)).collect();
                judge(&what, start, inst.set_integer(&vr, &v));
            }
            5 => {
                let vr: Vec<u32> = (0..n).map(|_| rng.pick(&bools)).collect();
                let v: Vec<bool> = (0..n).map(|_| rng.below(2) == 1).collect();
                judge(&what, start, inst.set_boolean(&vr, &v));
            }
            6 => {
                let vr: Vec<u32> = (0..n).map(|_| rng.pick(&strings)).collect();
                let v: Vec<&str> = (0..n).map(|_| rng.pick(&STRINGS)).collect();
                judge(&what, start, inst.set_string(&vr, &v));
            }
            7..=9 => {
                // mostly contiguous steps, sometimes a wrong communication point
                let t = if rng.below(5) == 0 { rng.pick(&REALS) } else { time };
                let h = rng.pick(&STEPS);
                if judge(&what, start, inst.do_step(t, h)).is_some() {
                    time = t + h;
                }
            }
            10 | 11 => {
                let mut v = vec![0.0; outs.len()];
                if judge(&what, start, inst.get_real(&outs, &mut v)).is_some() {
                    count(2, v.len() as u64);
                    for (r, x) in outs.iter().zip(&v) {
                        assert!(x.is_finite(), "{what}: output {r} = {x} returned with fmi2OK");
                    }
                }
            }
            12 => {
                if let Some(s) = judge(&what, start, inst.get_state()) {
                    states.push(s);
                }
            }
            13 => {
                if !states.is_empty() {
                    let i = rng.below(states.len());
                    if rng.below(3) == 0 {
                        let s = states.swap_remove(i);
                        judge(&what, start, inst.free_state(s));
                    } else {
                        judge(&what, start, inst.set_state(&states[i]));
                    }
                }
            }
            14 => {
                // a serialised state, whole or with a flipped bit, a cut or trailing bytes
                if let Some(s) = states.first()
                    && let Some(mut bytes) = judge(&what, start, inst.serialize_state(s))
                {
                    match rng.below(4) {
                        0 => {}
                        1 if !bytes.is_empty() => {
                            let i = rng.below(bytes.len());
                            bytes[i] ^= 1 << rng.below(8);
                        }
                        2 => bytes.truncate(rng.below(bytes.len() + 1)),
                        _ => bytes.extend([0u8, 1, 2]),
                    }
                    if let Some(back) = judge(&what, start, inst.deserialize_state(&bytes)) {
                        judge(&what, start, inst.set_state(&back));
                        judge(&what, start, inst.free_state(back));
                    }
                }
            }
            _ => match rng.below(3) {
                0 => {
                    judge(&what, start, inst.terminate());
                }
                1 => {
                    judge(&what, start, inst.reset());
                    time = 0.0;
                }
                _ => {
                    let vr: Vec<u32> = (0..n).map(|_| rng.pick(&reals)).collect();
                    let v: Vec<f64> = (0..n).map(|_| rng.pick(&REALS)).collect();
                    judge(
                        &what,
                        start,
                        inst.set_real_input_derivatives(&vr, 1 + rng.below(3) as i32, &v),
                    );
                }
            },
        }
    }
    // states left to the instance: fmi2FreeInstance frees them
    drop(states);
}

/// NULL pointers where FMI passes arrays and components: an error status, never a crash.
fn null_pointers(fmu: &Fmu) {
    let inst = fmu.instantiate("null", false).unwrap();
    let api = inst.api();
    let null = std::ptr::null_mut();
    // SAFETY: the FMU must refuse these without dereferencing them; that is the test.
    unsafe {
        assert_eq!((api.do_step)(null, 0.0, 1e-3, 1), Fmi2Status::Error);
        assert_eq!(
            (api.set_real)(inst.raw(), std::ptr::null(), 3, std::ptr::null()),
            Fmi2Status::Error
        );
        assert_eq!(
            (api.get_real)(inst.raw(), std::ptr::null(), 2, std::ptr::null_mut()),
            Fmi2Status::Error
        );
        assert_eq!((api.get_fmu_state)(inst.raw(), std::ptr::null_mut()), Fmi2Status::Error);
        assert_eq!((api.set_fmu_state)(inst.raw(), null), Fmi2Status::Error);
        assert_eq!(
            (api.deserialize_fmu_state)(inst.raw(), std::ptr::null(), 10, std::ptr::null_mut()),
            Fmi2Status::Error
        );
    }
}

fn fuzz(name: &str, default_sequences: usize) {
    let sequences = std::env::var("WINDRIVE_FUZZ_SEQUENCES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default_sequences);
    // a long run may be split: WINDRIVE_FUZZ_FIRST=N starts at the N-th sequence of the same stream
    let first: usize = std::env::var("WINDRIVE_FUZZ_FIRST")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    let fmu = Fmu::open(&fmu_path(name)).unwrap();
    null_pointers(&fmu);
    let mut seeds = Rng(0x0f11_2026 ^ name.len() as u64);
    for _ in 0..first {
        seeds.next();
    }
    for done in first..first + sequences {
        if done > first && done % 100_000 == 0 {
            eprintln!("{name}: sequences {first} to {done} passed");
        }
        let seed = seeds.next() | 1;
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| sequence(&fmu, &mut Rng(seed), 40)));
        if let Err(e) = outcome {
            let why = e
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            panic!("{name}, sequence seed {seed:#x}: {why}");
        }
    }
    let n = |i: usize| ANSWERED[i].load(std::sync::atomic::Ordering::Relaxed);
    eprintln!(
        "{name}: {sequences} sequences of 40 calls; so far in this process {} calls answered OK, {} refused, {} outputs checked finite",
        n(0),
        n(1),
        n(2)
    );
}

// The rotor and the 6-DOF gearbox build their model at initialisation (≈ 6 ms), hence fewer of theirs.
#[test]
fn torsional_survives_random_call_sequences() {
    fuzz("torsional", 2000);
}

#[test]
fn generator_survives_random_call_sequences() {
    fuzz("generator", 2000);
}

#[test]
fn rotor_survives_random_call_sequences() {
    fuzz("rotor", 300);
}

#[test]
fn gearbox6dof_survives_random_call_sequences() {
    fuzz("gearbox6dof", 300);
}
