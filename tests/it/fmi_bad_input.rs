//! Every bad-input class of the export layer, called through the real C boundary of the packed FMU:
//! each answers an error status (never a crash) and logs a message naming the problem.

use crate::common;
use common::*;
use std::ffi::{CString, c_int};
use std::ptr::{null, null_mut};
use windrive::fmi2::host::import::{Fmu, Instance};
use windrive::fmi2::types::*;

fn logged(inst: &mut Instance) -> String {
    inst.take_log().into_iter().map(|r| r.2).collect::<Vec<_>>().join(" | ")
}

fn expect_error(inst: &mut Instance, status: Fmi2Status, words: &[&str]) {
    assert_eq!(status, Fmi2Status::Error);
    let log = logged(inst);
    for w in words {
        assert!(log.contains(w), "log {log:?} does not mention {w:?}");
    }
}

#[test]
fn null_pointers_are_refused() {
    let fmu = torsional();
    let api = fmu.api();
    let mut inst = initialised(&fmu, &[], &[]);
    let c = inst.raw();
    unsafe {
        // null component: nothing to log to, but an error status and no crash
        assert_eq!((api.do_step)(null_mut(), 0.0, 1e-3, 1), Fmi2Status::Error);
        assert_eq!((api.get_real)(null_mut(), null(), 0, null_mut()), Fmi2Status::Error);
        (api.free_instance)(null_mut());
        // null arrays with n > 0
        let s = (api.get_real)(c, null(), 2, null_mut());
        expect_error(&mut inst, s, &["fmi2GetReal", "null"]);
    }
    inst.reset().unwrap();
    let c = inst.raw();
    unsafe {
        let s = (api.set_real)(c, null(), 1, null());
        expect_error(&mut inst, s, &["fmi2SetReal", "null"]);
        inst.reset().unwrap();
        let s = (api.get_fmu_state)(c, null_mut());
        expect_error(&mut inst, s, &["null"]);
        inst.reset().unwrap();
        let s = (api.set_string)(c, [0u32].as_ptr(), 1, [null()].as_ptr());
        expect_error(&mut inst, s, &["preset", "null"]);
        inst.reset().unwrap();
        let s = (api.deserialize_fmu_state)(c, null(), 10, null_mut());
        expect_error(&mut inst, s, &["null"]);
    }
    // n = 0 with null arrays is legal
    inst.reset().unwrap();
    unsafe { assert_eq!((api.set_real)(inst.raw(), null(), 0, null()), Fmi2Status::Ok) };
}

#[test]
fn instantiate_refuses_wrong_guid_type_and_name() {
    let fmu = torsional();
    let api = fmu.api();
    let name = CString::new("x").unwrap();
    let bad_guid = CString::new("{00000000-0000-0000-0000-000000000000}").unwrap();
    let guid = CString::new(fmu.description.guid.clone()).unwrap();
    let res = CString::new(fmu.resource_uri()).unwrap();
    unsafe {
        let fns = null();
        assert!(
            (api.instantiate)(
                name.as_ptr(),
                FMI2_CO_SIMULATION,
                bad_guid.as_ptr(),
                res.as_ptr(),
                fns,
                0,
                0
            )
            .is_null()
        );
        assert!(
            (api.instantiate)(
                name.as_ptr(),
                FMI2_MODEL_EXCHANGE,
                guid.as_ptr(),
                res.as_ptr(),
                fns,
                0,
                0
            )
            .is_null()
        );
        assert!((api.instantiate)(null(), FMI2_CO_SIMULATION, guid.as_ptr(), res.as_ptr(), fns, 0, 0).is_null());
        assert!((api.instantiate)(name.as_ptr(), FMI2_CO_SIMULATION, null(), res.as_ptr(), fns, 0, 0).is_null());
        // a null resource location and null callbacks are tolerated
        let c = (api.instantiate)(name.as_ptr(), FMI2_CO_SIMULATION, guid.as_ptr(), null(), fns, 0, 0);
        assert!(!c.is_null());
        (api.free_instance)(c);
    }
}

#[test]
fn calls_in_the_wrong_state_are_refused() {
    let fmu = torsional();
    let mut inst = fmu.instantiate("state", false).unwrap();
    // doStep before initialisation
    let err = inst.do_step(0.0, 1e-3).unwrap_err().to_string();
    assert!(err.contains("fmi2DoStep is not allowed in state Instantiated"), "{err}");
    // Error state: only reset, get, set-state and free are meaningful
    let err = inst.enter_initialization_mode().unwrap_err().to_string();
    assert!(err.contains("not allowed in state Error"), "{err}");
    inst.reset().unwrap();
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization_mode().unwrap();
    let err = inst.setup_experiment(0.0, None).unwrap_err().to_string();
    assert!(
        err.contains("fmi2SetupExperiment is not allowed in state InitializationMode"),
        "{err}"
    );
    inst.reset().unwrap();
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    // a fixed parameter after initialisation
    let err = inst
        .set_real(&[fmu.vr("damping_scale").unwrap()], &[0.5])
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("damping_scale") && err.contains("cannot be set in state StepComplete"),
        "{err}"
    );
    inst.reset().unwrap();
    // outputs and calculated parameters are never settable
    let err = inst
        .set_real(&[fmu.vr("hss_torque").unwrap()], &[1.0])
        .unwrap_err()
        .to_string();
    assert!(err.contains("hss_torque"), "{err}");
}

#[test]
fn bad_numbers_and_references_are_refused() {
    let fmu = torsional();
    let cases: [(&str, f64, &str); 6] = [
        ("rotor_torque", f64::NAN, "not a finite number"),
        ("generator_torque", f64::INFINITY, "not a finite number"),
        ("max_internal_step", -1.0, "below its minimum"),
        ("contact_ratio", 3.0, "above its maximum"),
        ("damping_scale", f64::NEG_INFINITY, "not a finite number"),
        ("mesh_stiffness_variation", 5.0, "above its maximum"),
    ];
    for (name, value, words) in cases {
        let mut inst = fmu.instantiate("numbers", false).unwrap();
        inst.setup_experiment(0.0, None).unwrap();
        inst.enter_initialization_mode().unwrap();
        let err = inst
            .set_real(&[fmu.vr(name).unwrap()], &[value])
            .unwrap_err()
            .to_string();
        assert!(err.contains(name) && err.contains(words), "{name}: {err}");
    }
    let mut inst = fmu.instantiate("refs", false).unwrap();
    let mut out = [0.0];
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization_mode().unwrap();
    let err = inst.get_real(&[9999], &mut out).unwrap_err().to_string();
    assert!(err.contains("unknown Real value reference 9999"), "{err}");
    // a Real reference read as Integer
    inst.reset().unwrap();
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization_mode().unwrap();
    let mut i = [0];
    let err = inst
        .get_integer(&[fmu.vr("hss_torque").unwrap()], &mut i)
        .unwrap_err()
        .to_string();
    assert!(err.contains("unknown Integer value reference"), "{err}");
}

#[test]
fn absurd_parameters_fail_at_initialisation_with_the_parameter_named() {
    let fmu = torsional();
    for (kind, name, value, words) in [
        ("s", "preset", "Z", "unknown drivetrain"),
        ("s", "fidelity", "7", "use 2, 5 or full"),
        (
            "s",
            "integrator",
            "euler",
            "use implicit, hht, generalized-alpha or rk4",
        ),
        ("s", "lumping", "lumpy", "use physical or thesis"),
    ] {
        assert_eq!(kind, "s");
        let mut inst = fmu.instantiate("absurd", false).unwrap();
        inst.setup_experiment(0.0, None).unwrap();
        inst.set_string(&[fmu.vr(name).unwrap()], &[value]).unwrap();
        inst.enter_initialization_mode().unwrap();
        let err = inst.exit_initialization_mode().unwrap_err().to_string();
        assert!(err.contains(name) && err.contains(words), "{err}");
    }
    // backlash below full fidelity makes no sense: refused
    let mut inst = fmu.instantiate("absurd", false).unwrap();
    inst.setup_experiment(0.0, None).unwrap();
    inst.set_string(&[fmu.vr("fidelity").unwrap()], &["5"]).unwrap();
    inst.set_real(&[fmu.vr("mesh_backlash").unwrap()], &[1e-4]).unwrap();
    inst.enter_initialization_mode().unwrap();
    let err = inst.exit_initialization_mode().unwrap_err().to_string();
    assert!(err.contains("mesh_backlash"), "{err}");
}

#[test]
fn bad_step_sizes_and_times_are_refused() {
    let fmu = torsional();
    for (t, h, words) in [
        (0.0, 0.0, "must be positive"),
        (0.0, -1e-3, "must be positive"),
        (0.0, f64::NAN, "not finite"),
        (0.5, 1e-3, "does not match the FMU's time 0"),
    ] {
        let mut inst = initialised(&fmu, &[], &[]);
        let err = inst.do_step(t, h).unwrap_err().to_string();
        assert!(err.contains(words), "{t} {h}: {err}");
    }
    // passing the announced stop time
    let mut inst = fmu.instantiate("stop", false).unwrap();
    inst.setup_experiment(0.0, Some(0.01)).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    let err = inst.do_step(0.0, 0.02).unwrap_err().to_string();
    assert!(err.contains("stopTime"), "{err}");
}

#[test]
fn unsupported_functions_answer_honestly() {
    let fmu = torsional();
    let api = fmu.api();
    let mut inst = initialised(&fmu, &[], &[]);
    unsafe {
        let s = (api.get_directional_derivative)(inst.raw(), null(), 0, null(), 0, null(), null_mut());
        expect_error(&mut inst, s, &["providesDirectionalDerivative"]);
    }
    let mut inst = initialised(&fmu, &[], &[]);
    unsafe {
        let s = (api.cancel_step)(inst.raw());
        expect_error(&mut inst, s, &["no step in progress"]);
    }
    inst.reset().unwrap();
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    unsafe {
        let order = [3 as c_int];
        let s = (api.set_real_input_derivatives)(
            inst.raw(),
            [fmu.vr("rotor_torque").unwrap()].as_ptr(),
            1,
            order.as_ptr(),
            [1.0].as_ptr(),
        );
        expect_error(&mut inst, s, &["order 3"]);
    }
}

#[test]
fn brake_command_outside_its_range_is_clamped_with_a_warning() {
    let fmu = torsional();
    let mut inst = initialised(&fmu, &[], &[]);
    let vr = fmu.vr("brake_command").unwrap();
    let s = unsafe { (fmu.api().set_real)(inst.raw(), [vr].as_ptr(), 1, [1.5].as_ptr()) };
    assert_eq!(s, Fmi2Status::Warning);
    assert!(logged(&mut inst).contains("clamped"));
    assert_eq!(get(&fmu, &mut inst, "brake_command"), 1.0);
    inst.do_step(0.0, 1e-3).unwrap();
}

#[test]
fn status_queries_after_a_failed_step() {
    let fmu = torsional();
    // RK4 at the default 1 ms internal step is unstable: the step fails visibly
    let mut inst = initialised(&fmu, &[("integrator", "rk4")], &[]);
    assert!(inst.do_step(0.0, 1e-3).is_err());
    // the failed instance refuses further steps
    let err = inst.do_step(0.0, 1e-3).unwrap_err().to_string();
    assert!(err.contains("not allowed in state Error"), "{err}");
    let mut t = 0.0;
    let mut terminated: Fmi2Boolean = 0;
    unsafe {
        assert_eq!(
            (fmu.api().get_real_status)(inst.raw(), FMI2_LAST_SUCCESSFUL_TIME, &mut t),
            Fmi2Status::Ok
        );
        assert_eq!(
            (fmu.api().get_boolean_status)(inst.raw(), FMI2_TERMINATED, &mut terminated),
            Fmi2Status::Ok
        );
        let mut x = 0;
        assert_eq!(
            (fmu.api().get_integer_status)(inst.raw(), 0, &mut x),
            Fmi2Status::Discard
        );
    }
    assert_eq!(t, 0.0);
    assert_eq!(terminated, 1);
}

#[test]
fn rk4_beyond_its_limit_names_the_limit() {
    let fmu: Fmu = torsional();
    let mut inst = initialised(&fmu, &[("integrator", "rk4")], &[]);
    let limit = get(&fmu, &mut inst, "rk4_step_limit");
    assert!(limit > 1e-5 && limit < 1e-3, "{limit}");
    let err = inst.do_step(0.0, 1e-3).unwrap_err().to_string();
    assert!(
        err.contains("RK4 is unstable") && err.contains("stability limit") && err.contains("max_internal_step"),
        "{err}"
    );
    // just below the limit it runs
    let mut ok = initialised(&fmu, &[("integrator", "rk4")], &[("max_internal_step", 0.95 * limit)]);
    for i in 0..10 {
        ok.do_step(i as f64 * 1e-3, 1e-3).unwrap();
    }
}

/// The generator FMU: absurd electrical parameters are refused by their declared range, a DFIG step
/// of a day is refused (its current loop would need 10⁸ sub-steps), NaN speed is refused; every
/// refusal names the culprit (an error leaves the instance in the Error state, so each case starts
/// from fmi2Reset).
#[test]
fn generator_refuses_absurd_parameters_and_steps() {
    let fmu = Fmu::open(&fmu_path("generator")).expect("the packed generator FMU opens");
    let mut inst = fmu.instantiate("gen", false).unwrap();
    inst.setup_experiment(0.0, None).unwrap();
    let err = inst
        .set_real(&[fmu.vr("current_bandwidth").unwrap()], &[1e9])
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("current_bandwidth") && err.contains("above its maximum"),
        "{err}"
    );
    let dfig = |inst: &mut Instance| {
        inst.reset().unwrap();
        inst.setup_experiment(0.0, None).unwrap();
        inst.set_string(&[fmu.vr("kind").unwrap()], &["dfig"]).unwrap();
        inst.set_string(&[fmu.vr("preset").unwrap()], &["C"]).unwrap();
        inst.set_real(&[fmu.vr("generator_speed").unwrap()], &[150.0]).unwrap();
        inst.enter_initialization_mode().unwrap();
        inst.exit_initialization_mode().unwrap();
    };
    dfig(&mut inst);
    let err = inst.do_step(0.0, 86_400.0).unwrap_err().to_string();
    assert!(
        err.contains("internal steps") && err.contains("current_bandwidth"),
        "{err}"
    );
    dfig(&mut inst);
    inst.do_step(0.0, 1e-3).unwrap();
    let err = inst
        .set_real(&[fmu.vr("generator_speed").unwrap()], &[f64::NAN])
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("generator_speed") && err.contains("not a finite number"),
        "{err}"
    );
}

/// Issue 16: an Integer parameter outside the XML's min/max (`poles`, 0..=400) answered fmi2OK.
#[test]
fn generator_integer_parameters_outside_their_range_are_refused() {
    let fmu = Fmu::open(&fmu_path("generator")).expect("the packed generator FMU opens");
    let poles = fmu.vr("poles").unwrap();
    let mut inst = fmu.instantiate("gen", true).unwrap();
    for (bad, words) in [(-2, "below its minimum 0"), (402, "above its maximum 400")] {
        inst.reset().unwrap();
        inst.setup_experiment(0.0, None).unwrap();
        let s = unsafe { (fmu.api().set_integer)(inst.raw(), [poles].as_ptr(), 1, [bad].as_ptr()) };
        expect_error(
            &mut inst,
            s,
            &["fmi2SetInteger", &format!("parameter poles = {bad}"), words],
        );
    }
    inst.reset().unwrap();
    inst.setup_experiment(0.0, None).unwrap();
    inst.set_integer(&[poles], &[4]).unwrap();
    inst.enter_initialization_mode().unwrap();
    let mut v = [0];
    inst.get_integer(&[poles], &mut v).unwrap();
    assert_eq!(v[0], 4);
}

/// fmi2DoStep(0, 1e6) is legal but absurd: every FMU refuses it at once (the torsional and rotor
/// FMUs ran for minutes; the generator already refused), naming max_steps_per_call and the step
/// asked for.
#[test]
fn an_absurd_communication_step_is_refused_at_once() {
    for name in ["torsional", "rotor", "gearbox6dof"] {
        let fmu = Fmu::open(&fmu_path(name)).unwrap();
        let mut inst = initialised(&fmu, &[], &[]);
        // CPU time, not wall time: a busy machine must not fail it; running the step would take minutes
        let start = cpu_now();
        let err = inst.do_step(0.0, 1e6).unwrap_err().to_string();
        let took = cpu_now().saturating_sub(start);
        assert!(took.as_secs_f64() < 1.0, "{name}: took {took:?} of CPU");
        assert!(
            err.contains("max_steps_per_call") && err.contains("1000000 s"),
            "{name}: {err}"
        );
    }
    // the limit is the user's: 100 internal steps of 1 ms pass a 0.1 s step and refuse 0.2 s
    let fmu = torsional();
    let mut inst = initialised(&fmu, &[], &[("max_steps_per_call", 100.0), ("max_internal_step", 1e-3)]);
    inst.do_step(0.0, 0.1).unwrap();
    let err = inst.do_step(0.1, 0.2).unwrap_err().to_string();
    assert!(
        err.contains("200 internal steps") && err.contains("max_steps_per_call = 100"),
        "{err}"
    );
}

/// Every Real parameter of the rotor, set to values inside, at the edge of and far beyond anything
/// meaningful (a seeded sweep, 400 combinations): initialisation and steps end in OK or a named
/// error, never in a panic turned fmi2Fatal, and what comes back with OK is finite.
#[test]
fn no_rotor_parameter_combination_panics() {
    let fmu = Fmu::open(&fmu_path("rotor")).unwrap();
    let reals: Vec<(String, u32)> = fmu
        .description
        .model_variables
        .variables
        .iter()
        .filter(|v| v.causality == "parameter" && v.real.is_some())
        .map(|v| (v.name.clone(), v.value_reference))
        .collect();
    let values = [
        0.0,
        -1.0,
        1e-12,
        1.0,
        7.5,
        1e9,
        -1e9,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
    ];
    let mut random = windrive::xorshift::Xorshift::new(0x2545_f491_4f6c_dd1d);
    let mut next = || random.next_u64();
    for _ in 0..400 {
        let mut inst = fmu.instantiate("fuzz", false).unwrap();
        inst.setup_experiment(0.0, None).unwrap();
        for _ in 0..3 {
            let (name, vr) = &reals[next() as usize % reals.len()];
            let v = values[next() as usize % values.len()];
            // a refused value is fine (named by the FMU); a panic is not
            if let Err(e) = inst.set_real(&[*vr], &[v]) {
                let e = e.to_string();
                assert!(
                    !e.contains("Fatal") && !e.contains("internal error"),
                    "{name} = {v}: {e}"
                );
            }
        }
        let init = inst
            .enter_initialization_mode()
            .and_then(|_| inst.exit_initialization_mode());
        if let Err(e) = init {
            let e = e.to_string();
            assert!(!e.contains("Fatal") && !e.contains("internal error"), "{e}");
            continue;
        }
        for k in 0..3 {
            match inst.do_step(k as f64 * 0.05, 0.05) {
                Ok(_) => {
                    let torque = get(&fmu, &mut inst, "rotor_torque");
                    assert!(torque.is_finite(), "rotor_torque = {torque} returned with OK");
                }
                Err(e) => {
                    let e = e.to_string();
                    assert!(!e.contains("Fatal") && !e.contains("internal error"), "{e}");
                    break;
                }
            }
        }
    }
}

/// Inputs at 1e300 drive a model's outputs out of range: whatever an FMU then returns with OK is
/// finite, and a non-finite output is an error naming the variable (the generator returned
/// stored_energy = inf and electrical_power = −inf with OK). The torsional FMU also in its two cut
/// sections, where `cut_speed` and `cut_torque` drive the model.
#[test]
fn non_finite_outputs_are_errors_naming_the_variable() {
    let mut refused = 0;
    let cases: [(&str, &[(&str, &str)]); 6] = [
        ("torsional", &[]),
        ("torsional", &[("section", "rotor")]),
        ("torsional", &[("section", "drivetrain")]),
        ("rotor", &[]),
        ("generator", &[]),
        ("gearbox6dof", &[]),
    ];
    for (name, strings) in cases {
        let fmu = Fmu::open(&fmu_path(name)).unwrap();
        let vars = &fmu.description.model_variables.variables;
        let inputs: Vec<u32> = vars
            .iter()
            .filter(|v| v.causality == "input" && v.real.is_some())
            .map(|v| v.value_reference)
            .collect();
        let outputs: Vec<(&str, u32)> = vars
            .iter()
            .filter(|v| v.causality == "output" && v.real.is_some())
            .map(|v| (v.name.as_str(), v.value_reference))
            .collect();
        let mut inst = initialised(&fmu, strings, &[]);
        for &vr in &inputs {
            let _ = inst.set_real(&[vr], &[1e300]);
        }
        let _ = inst.do_step(0.0, 1e-3);
        for (out, vr) in outputs {
            let mut v = [0.0];
            match inst.get_real(&[vr], &mut v) {
                Ok(()) => assert!(v[0].is_finite(), "{name}: {out} = {} returned with OK", v[0]),
                Err(e) => {
                    let e = e.to_string();
                    assert!(!e.contains("internal error"), "{name}: {out}: {e}");
                    if e.contains("not finite") {
                        assert!(e.contains(out), "{name}: the error does not name {out}: {e}");
                        refused += 1;
                    }
                }
            }
        }
    }
    // the rotor, the generator and the gearbox each had outputs out of range here
    assert!(refused >= 3, "only {refused} non-finite outputs refused");
}

/// Every String parameter of every FMU set to a value the model does not know is refused at
/// initialisation with the parameter named, in each of the rotor's modes: also a parameter the mode
/// does not use (a misspelt `series_unit` in aero mode, `turbulence_class` in playback), since a
/// user who set it meant something by it. `series` is a file the aero mode never reads.
#[test]
fn every_string_parameter_is_checked_in_every_mode() {
    let dir = windrive::fmi2::host::archive::TempDir::new("windrive-test-series").unwrap();
    let series = dir.path().join("torque.csv");
    std::fs::write(&series, "time,torque\n0,0.5\n100,0.5\n").unwrap();
    let series = series.to_string_lossy().into_owned();
    let cases: [(&str, &[(&str, &str)]); 5] = [
        ("rotor", &[("mode", "aero")]),
        ("rotor", &[("mode", "playback"), ("series", &series)]),
        ("torsional", &[]),
        ("generator", &[]),
        ("gearbox6dof", &[]),
    ];
    let mut checked = 0;
    for (name, base) in cases {
        let fmu = Fmu::open(&fmu_path(name)).unwrap();
        // the base set-up alone initialises
        drop(initialised(&fmu, base, &[]));
        let strings: Vec<&str> = fmu
            .description
            .model_variables
            .variables
            .iter()
            .filter(|v| v.type_name() == "String")
            .map(|v| v.name.as_str())
            .collect();
        for &param in &strings {
            if param == "mode" || (param == "series" && base.contains(&("mode", "aero"))) {
                continue;
            }
            let mut inst = fmu.instantiate("strings", true).unwrap();
            inst.setup_experiment(0.0, None).unwrap();
            for (p, v) in base.iter().chain([&(param, "bogus-value")]) {
                inst.set_string(&[fmu.vr(p).unwrap()], &[v]).unwrap();
            }
            let err = inst
                .enter_initialization_mode()
                .and_then(|()| inst.exit_initialization_mode())
                .expect_err(&format!("{name} {base:?}: {param} = bogus-value was accepted"))
                .to_string();
            assert!(
                err.contains(param) && err.to_lowercase().contains("bogus-value"),
                "{name} {base:?}: {param}: {err}"
            );
            checked += 1;
        }
    }
    // the rotor's wind_sampling and wind_file in both modes: 4 more than before them; the gearbox's
    // newton and linear_solver: 2 more
    assert_eq!(checked, 41);
}

/// A finite torque thousands of times rated (found by fuzzing: 1e9 N·m into the GRC, a 2 s step)
/// ran for 44 s before failing. It is refused before stepping, naming the input and the rating; the
/// generator torque likewise. CPU time, not wall time: a busy machine must not fail it.
#[test]
fn an_absurd_torque_into_the_gearbox_is_refused_at_once() {
    let fmu = Fmu::open(&fmu_path("gearbox6dof")).unwrap();
    for (input, value) in [("rotor_torque", 1e9), ("generator_torque", -2e7)] {
        let mut inst = initialised(&fmu, &[], &[]);
        set(&fmu, &mut inst, input, value);
        let start = cpu_now();
        let e = inst.do_step(0.0, 2.0).unwrap_err().to_string();
        let took = cpu_now().saturating_sub(start);
        assert!(took.as_secs_f64() < 1.0, "{input}: took {took:?} of CPU");
        assert!(
            e.contains(&format!("input {input} = ")) && e.contains("times the gearbox's rated"),
            "{e}"
        );
    }
    // 15× rated is a load the model takes (inside the 20× limit): a short step runs
    let mut inst = initialised(&fmu, &[], &[]);
    let rated = get(&fmu, &mut inst, "rated_rotor_torque");
    set(&fmu, &mut inst, "rotor_torque", 15.0 * rated);
    inst.do_step(0.0, 0.01).unwrap();
}

/// Without a rated point (a user's description may give none) nothing refuses the torque, and the
/// step's work is what bounds it: Newton iterations in proportion to the step's length, then an
/// error that says so, instead of minutes of halving.
#[test]
fn a_step_the_model_cannot_follow_ends_within_its_iteration_budget() {
    let dir = windrive::fmi2::host::archive::TempDir::new("norated").unwrap();
    let preset = std::fs::read_to_string("fmus/gearbox6dof/resources/grc750.toml").unwrap();
    let text: String = preset
        .lines()
        .filter(|l| !l.starts_with("rated_power") && !l.starts_with("rated_rotor_speed_rpm"))
        .map(|l| format!("{l}\n"))
        .collect();
    let path = dir.path().join("no-rated-point.toml");
    std::fs::write(&path, text).unwrap();
    let fmu = Fmu::open(&fmu_path("gearbox6dof")).unwrap();
    let mut inst = initialised(&fmu, &[("gearbox", path.to_str().unwrap())], &[]);
    assert_eq!(get(&fmu, &mut inst, "rated_rotor_torque"), 0.0);
    set(&fmu, &mut inst, "rotor_torque", 1e9);
    // the GRC follows 1e9 N·m for about a second, then every step iterates and halves
    let e = inst.do_step(0.0, 1.5).unwrap_err().to_string();
    // 1.5 s of 1 ms steps: 32 iterations each and 4096 spare
    assert!(e.contains("more than its budget of 52096"), "{e}");
}

/// fmi2GetReal with an array (how a master reads a row of recorded variables) answers what one call
/// per variable answers, bit for bit, also when the same array comes again (its references are then
/// not looked up again) and after an input changed; an unknown reference or a non-finite output in
/// the middle of a long array is still refused naming it.
#[test]
fn an_array_of_references_reads_what_one_call_per_variable_reads() {
    for name in ["torsional", "rotor", "generator", "gearbox6dof"] {
        let fmu = Fmu::open(&fmu_path(name)).unwrap();
        let vars = &fmu.description.model_variables.variables;
        let reals: Vec<u32> = vars
            .iter()
            .filter(|v| v.real.is_some())
            .map(|v| v.value_reference)
            .collect();
        let input = vars
            .iter()
            .find(|v| v.causality == "input" && v.real.is_some())
            .map(|v| v.value_reference)
            .unwrap();
        let mut inst = initialised(&fmu, &[], &[]);
        inst.do_step(0.0, 1e-3).unwrap();
        for round in 0..3 {
            if round == 2 {
                inst.set_real(&[input], &[0.5]).unwrap();
            }
            let mut array = vec![0.0; reals.len()];
            inst.get_real(&reals, &mut array).unwrap();
            for (&vr, a) in reals.iter().zip(&array) {
                let mut one = [0.0];
                inst.get_real(&[vr], &mut one).unwrap();
                assert_eq!(a.to_bits(), one[0].to_bits(), "{name}: reference {vr}, round {round}");
            }
        }
        let mut with_unknown = reals.clone();
        with_unknown.insert(reals.len() / 2, 99_999);
        let mut out = vec![0.0; with_unknown.len()];
        let err = inst.get_real(&with_unknown, &mut out).unwrap_err().to_string();
        assert!(err.contains("unknown Real value reference 99999"), "{name}: {err}");
    }
    // a torque no drivetrain holds: the outputs go non-finite, and the array read names the first
    let fmu = Fmu::open(&fmu_path("generator")).unwrap();
    let vars = &fmu.description.model_variables.variables;
    let outputs: Vec<(&str, u32)> = vars
        .iter()
        .filter(|v| v.causality == "output" && v.real.is_some())
        .map(|v| (v.name.as_str(), v.value_reference))
        .collect();
    let mut inst = initialised(&fmu, &[], &[]);
    for v in vars.iter().filter(|v| v.causality == "input" && v.real.is_some()) {
        let _ = inst.set_real(&[v.value_reference], &[1e300]);
    }
    let _ = inst.do_step(0.0, 1e-3);
    let first_bad = outputs.iter().find(|(_, vr)| {
        let mut v = [0.0];
        inst.get_real(&[*vr], &mut v).is_err()
    });
    if let Some((bad, _)) = first_bad {
        let vrs: Vec<u32> = outputs.iter().map(|o| o.1).collect();
        let mut out = vec![0.0; vrs.len()];
        let err = inst.get_real(&vrs, &mut out).unwrap_err().to_string();
        assert!(err.contains(bad), "the error does not name {bad}: {err}");
    }
}
