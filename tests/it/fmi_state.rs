//! FMU state through the C boundary: get → step → set → step repeats bit for bit, a serialised
//! state restored into a fresh instance continues bit-identically, and instances on several threads
//! are independent.

use crate::common;
use common::*;
use windrive::fmi2::host::import::{Fmu, Instance};

const OUTPUTS: [&str; 6] = [
    "hss_torque",
    "lss_torque",
    "generator_speed",
    "mesh_force_sun_planet_2",
    "angle_rotor",
    "stored_energy",
];

fn outputs(fmu: &Fmu, inst: &mut Instance) -> Vec<u64> {
    let vrs: Vec<u32> = OUTPUTS.iter().map(|n| fmu.vr(n).unwrap()).collect();
    let mut v = vec![0.0; vrs.len()];
    inst.get_real(&vrs, &mut v).unwrap();
    v.into_iter().map(f64::to_bits).collect()
}

fn drive(fmu: &Fmu, inst: &mut Instance, t0: f64, steps: usize, brake_from: f64) -> Vec<Vec<u64>> {
    let h = 1e-3;
    (0..steps)
        .map(|i| {
            let t = t0 + i as f64 * h;
            set(fmu, inst, "rotor_torque", 3.8e5 * (1.0 + 0.2 * (7.0 * t).sin()));
            set(fmu, inst, "generator_torque", 4.7e3);
            set(fmu, inst, "brake_command", if t >= brake_from { 1.0 } else { 0.0 });
            inst.do_step(t, h).unwrap();
            outputs(fmu, inst)
        })
        .collect()
}

#[test]
fn get_step_set_step_repeats_bit_for_bit() {
    let fmu = torsional();
    // backlash and a brake engaging mid-way: the state includes contact and stiction
    let mut inst = initialised(&fmu, &[], &[("mesh_backlash", 1e-4)]);
    drive(&fmu, &mut inst, 0.0, 200, 0.25);
    let saved = inst.get_state().unwrap();
    let first = drive(&fmu, &mut inst, 0.2, 300, 0.25);
    inst.set_state(&saved).unwrap();
    let again = drive(&fmu, &mut inst, 0.2, 300, 0.25);
    assert_eq!(first, again);
    inst.free_state(saved).unwrap();
}

#[test]
fn a_serialised_state_continues_bit_identically_in_a_new_instance() {
    let fmu = torsional();
    let mut a = initialised(&fmu, &[("preset", "C")], &[("mesh_stiffness_variation", 0.2)]);
    drive(&fmu, &mut a, 0.0, 150, 0.1);
    let st = a.get_state().unwrap();
    let bytes = a.serialize_state(&st).unwrap();
    a.free_state(st).unwrap();
    let reference = drive(&fmu, &mut a, 0.15, 200, 0.1);

    // a fresh instance with default parameters: everything comes from the bytes
    let mut b = initialised(&fmu, &[], &[]);
    let restored = b.deserialize_state(&bytes).unwrap();
    b.set_state(&restored).unwrap();
    b.free_state(restored).unwrap();
    let continued = drive(&fmu, &mut b, 0.15, 200, 0.1);
    assert_eq!(reference, continued);
}

#[test]
fn corrupt_serialised_state_is_refused() {
    let fmu = torsional();
    let mut a = initialised(&fmu, &[], &[]);
    let st = a.get_state().unwrap();
    let mut bytes = a.serialize_state(&st).unwrap();
    a.free_state(st).unwrap();
    let whole = bytes.clone();
    bytes.truncate(bytes.len() / 2);
    let err = a.deserialize_state(&bytes).unwrap_err().to_string();
    assert!(err.contains("corrupt serialised state"), "{err}");
    // one flipped bit anywhere, trailing garbage, another format version: each refused
    for at in [0, 5, 9, 13, 20, whole.len() / 2, whole.len() - 1] {
        let mut flipped = whole.clone();
        flipped[at] ^= 0x10;
        let err = a.deserialize_state(&flipped).unwrap_err().to_string();
        assert!(err.contains("serialised state"), "bit flipped at {at}: {err}");
    }
    let mut padded = whole.clone();
    padded.extend_from_slice(b"garbage");
    let err = a.deserialize_state(&padded).unwrap_err().to_string();
    assert!(err.contains("payload bytes where the header says"), "{err}");
    let mut future = whole.clone();
    future[4] = 2;
    let err = a.deserialize_state(&future).unwrap_err().to_string();
    assert!(err.contains("format 2"), "{err}");
    // the intact bytes still restore
    let st = a.deserialize_state(&whole).unwrap();
    a.free_state(st).unwrap();
}

/// A state holds only what changes: every FMU's serialised state stays below a bound (the rotor's
/// carried its synthesised turbulence and was 472 kB; the parameters rebuild what never changes).
#[test]
fn serialised_states_hold_only_what_changes() {
    for (name, bound) in [
        ("rotor", 4_096),
        ("torsional", 8_192),
        ("generator", 4_096),
        ("gearbox6dof", 16_384),
    ] {
        let fmu = Fmu::open(&fmu_path(name)).unwrap();
        let mut inst = initialised(&fmu, &[], &[]);
        inst.do_step(0.0, 1e-3).unwrap();
        let st = inst.get_state().unwrap();
        let size = inst.serialize_state(&st).unwrap().len();
        println!("{name}: {size} bytes");
        assert!(
            size < bound,
            "{name}: a serialised state of {size} bytes (bound {bound})"
        );
        inst.free_state(st).unwrap();
    }
}

/// A host that takes states and frees the instance without fmi2FreeFMUstate leaks nothing: the
/// instance frees what it handed out. Run under valgrind by the test below.
#[test]
#[ignore = "run under valgrind by states_kept_across_free_instance_leak_nothing"]
fn cycles_keeping_states_across_free_instance() {
    for name in ["rotor", "torsional", "generator", "gearbox6dof"] {
        let fmu = Fmu::open(&fmu_path(name)).unwrap();
        for _ in 0..3 {
            let mut inst = initialised(&fmu, &[], &[]);
            inst.do_step(0.0, 1e-3).unwrap();
            let kept = inst.get_state().unwrap();
            let bytes = inst.serialize_state(&kept).unwrap();
            let _restored = inst.deserialize_state(&bytes).unwrap();
            let _another = inst.get_state().unwrap();
            // the host lets go of its states (SavedState has no Drop) and frees the instance
            drop(inst);
        }
    }
}

/// valgrind (on every machine of this project's kind) over the cycles above: no byte definitely
/// or indirectly lost. Before states were tracked, 10 such cycles lost 4.7 MB (rotor), 13.6 kB
/// (torsional) and 6.5 kB (generator).
#[test]
fn states_kept_across_free_instance_leak_nothing() {
    crate::common::valgrind_clean("fmi_state::cycles_keeping_states_across_free_instance");
}

#[test]
fn instances_on_several_threads_are_independent() {
    let fmu = torsional();
    let mut alone = initialised(&fmu, &[], &[]);
    let expected = drive(&fmu, &mut alone, 0.0, 400, 0.3);
    std::thread::scope(|scope| {
        let handles: Vec<_> = (0..4)
            .map(|_| {
                scope.spawn(|| {
                    let mut inst = initialised(&fmu, &[], &[]);
                    drive(&fmu, &mut inst, 0.0, 400, 0.3)
                })
            })
            .collect();
        for h in handles {
            assert_eq!(h.join().unwrap(), expected);
        }
    });
}

#[test]
fn reset_applies_the_start_values_again() {
    let fmu = torsional();
    let mut inst = initialised(&fmu, &[("preset", "A")], &[("damping_scale", 0.5)]);
    drive(&fmu, &mut inst, 0.0, 10, 1.0);
    inst.reset().unwrap();
    inst.setup_experiment(0.0, None).unwrap();
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    assert_eq!(get(&fmu, &mut inst, "damping_scale"), 1.0);
    assert_eq!(get(&fmu, &mut inst, "rotor_torque"), 0.0);
    let mut dofs = [0];
    inst.get_integer(&[fmu.vr("dof_count").unwrap()], &mut dofs).unwrap();
    assert_eq!(dofs[0], 11, "reset returns to preset D, full fidelity");
}

#[test]
fn variable_step_sizes_are_accepted() {
    let fmu = torsional();
    let mut inst = initialised(&fmu, &[], &[]);
    let mut t = 0.0;
    for h in [1e-3, 2.5e-3, 1e-4, 7e-3, 1e-3] {
        inst.do_step(t, h).unwrap();
        t += h;
    }
    assert!(get(&fmu, &mut inst, "rotor_speed") > 0.0);
}

/// The rotor (turbulent wind, pitch control) and a DFIG generator: a serialised state restored into
/// a fresh instance continues bit-identically, parameters and inputs included.
#[test]
fn rotor_and_generator_states_restore_bit_identically() {
    type Drive = fn(&Fmu, &mut Instance, usize) -> Vec<u64>;
    type Case<'a> = (&'a str, &'a [(&'a str, &'a str)], &'a [(&'a str, f64)], Drive);
    let rotor: Drive = |fmu, inst, k| {
        set(fmu, inst, "rotor_speed", 1.6 + 0.01 * (k as f64).sin());
        vec![
            get(fmu, inst, "rotor_torque").to_bits(),
            get(fmu, inst, "pitch").to_bits(),
        ]
    };
    let generator: Drive = |fmu, inst, k| {
        set(fmu, inst, "generator_speed", 160.0 + 0.1 * (k as f64).sin());
        vec![
            get(fmu, inst, "generator_torque").to_bits(),
            get(fmu, inst, "stator_current").to_bits(),
        ]
    };
    let cases: [Case; 2] = [
        (
            "rotor",
            &[("preset", "C")],
            &[("wind_speed", 14.0), ("shutdown_time", 0.3)],
            rotor,
        ),
        (
            "generator",
            &[("preset", "C"), ("kind", "dfig")],
            &[("generator_speed", 160.0)],
            generator,
        ),
    ];
    for (name, strings, reals, drive) in cases {
        let fmu = Fmu::open(&fmu_path(name)).unwrap();
        let run = |inst: &mut Instance, from: usize, to: usize| -> Vec<Vec<u64>> {
            (from..to)
                .map(|k| {
                    let out = drive(&fmu, inst, k);
                    inst.do_step(k as f64 * 1e-2, 1e-2).unwrap();
                    out
                })
                .collect()
        };
        let mut a = initialised(&fmu, strings, reals);
        run(&mut a, 0, 40);
        let st = a.get_state().unwrap();
        let bytes = a.serialize_state(&st).unwrap();
        a.free_state(st).unwrap();
        let reference = run(&mut a, 40, 80);
        let mut b = initialised(&fmu, &[], &[]);
        let restored = b.deserialize_state(&bytes).unwrap();
        b.set_state(&restored).unwrap();
        b.free_state(restored).unwrap();
        assert_eq!(reference, run(&mut b, 40, 80), "{name}");
    }
}

#[test]
fn a_state_keeps_the_parameters_it_was_taken_with() {
    // the parameters are shared copy-on-write between an instance and its states: setting one after
    // a state was taken must change the instance only, and restoring the state must bring it back
    for name in ["torsional", "generator", "rotor", "gearbox6dof"] {
        let fmu = Fmu::open(&fmu_path(name)).unwrap();
        let mut inst = fmu.instantiate("params", false).unwrap();
        inst.setup_experiment(0.0, None).unwrap();
        inst.enter_initialization_mode().unwrap();
        let st = inst.get_state().unwrap();
        // the first Real parameter that takes a value 1 % above its start
        let (var, before, changed) = fmu
            .description
            .model_variables
            .variables
            .iter()
            .filter(|v| v.causality == "parameter" && v.type_name() == "Real")
            .find_map(|v| {
                let vr = [v.value_reference];
                let mut x = [0.0];
                inst.get_real(&vr, &mut x).ok()?;
                let changed = if x[0] == 0.0 { 1e-3 } else { x[0] * 1.01 };
                inst.set_real(&vr, &[changed]).ok()?;
                Some((v, x[0], changed))
            })
            .unwrap_or_else(|| panic!("{name}: no Real parameter could be changed"));
        let vr = [var.value_reference];
        let mut now = [0.0];
        inst.get_real(&vr, &mut now).unwrap();
        assert_eq!(now[0], changed, "{name}.{}", var.name);
        inst.set_state(&st).unwrap();
        inst.get_real(&vr, &mut now).unwrap();
        assert_eq!(
            now[0].to_bits(),
            before.to_bits(),
            "{name}.{} after the restore",
            var.name
        );
        // the state itself did not change when the instance's parameter did
        inst.set_real(&vr, &[changed]).unwrap();
        let bytes = inst.serialize_state(&st).unwrap();
        let back = inst.deserialize_state(&bytes).unwrap();
        inst.set_state(&back).unwrap();
        inst.get_real(&vr, &mut now).unwrap();
        assert_eq!(
            now[0].to_bits(),
            before.to_bits(),
            "{name}.{} from the serialised state",
            var.name
        );
        inst.free_state(back).unwrap();
        inst.free_state(st).unwrap();
    }
}

/// The gearbox's factorisations are history: a pattern's J is assembled where the pattern was first
/// met, and the default iteration (`newton = kept+predicted`) keeps one from step to step, and which
/// J a step starts from decides where, within the Newton tolerance, it ends. No state holds them: the
/// FMU drops them when a state is taken and when one is restored, so the run that goes on, a rerun
/// restored in memory (a master's rollback) and a fresh instance given the serialised state all
/// repeat bit for bit, over 200 steps with a brake engaging on the way.
#[test]
fn gearbox_states_repeat_the_kept_iteration() {
    // the presets' lamina bearings by table, the lamina loop and linear bearings, by dense LU; then
    // J on its sparsity pattern, whose ordering is history too
    for (bearings, solver) in [
        ("", "dense"),
        ("lamina", "dense"),
        ("linear", "dense"),
        ("", "sparse"),
        ("linear", "sparse"),
    ] {
        gearbox_states_repeat(bearings, solver);
    }
}

fn gearbox_states_repeat(bearings: &str, solver: &str) {
    let fmu = Fmu::open(&fmu_path("gearbox6dof")).unwrap();
    let names = [
        "hss_torque",
        "lss_torque",
        "planet_1_uw_radial_load",
        "mesh_force_sun_planet_1",
    ];
    let vrs: Vec<u32> = names.iter().map(|n| fmu.vr(n).unwrap()).collect();
    // `load` scales the rotor torque: a rollback's trial steps with other inputs
    let drive = |inst: &mut Instance, from: usize, to: usize, load: f64| -> Vec<Vec<u64>> {
        (from..to)
            .map(|k| {
                let t = k as f64 * 1e-3;
                set(&fmu, inst, "rotor_torque", load * 3.2e5 * (1.0 + 0.1 * (9.0 * t).sin()));
                set(&fmu, inst, "brake_command", if k >= 90 { 1.0 } else { 0.0 });
                inst.do_step(t, 1e-3).unwrap();
                let mut v = vec![0.0; vrs.len()];
                inst.get_real(&vrs, &mut v).unwrap();
                v.into_iter().map(f64::to_bits).collect()
            })
            .collect()
    };
    let mut a = initialised(&fmu, &[("bearing_model", bearings), ("linear_solver", solver)], &[]);
    drive(&mut a, 0, 40, 1.0);
    let saved = a.get_state().unwrap();
    let bytes = a.serialize_state(&saved).unwrap();
    let first = drive(&mut a, 40, 240, 1.0);
    // a trial with other inputs, then the same inputs again from the state (as iterative coupling)
    a.set_state(&saved).unwrap();
    drive(&mut a, 40, 240, 0.9);
    a.set_state(&saved).unwrap();
    assert_eq!(
        first,
        drive(&mut a, 40, 240, 1.0),
        "{bearings:?} bearings, {solver} LU, restored in memory after a trial"
    );
    a.free_state(saved).unwrap();

    let mut b = initialised(&fmu, &[], &[]);
    let restored = b.deserialize_state(&bytes).unwrap();
    b.set_state(&restored).unwrap();
    b.free_state(restored).unwrap();
    assert_eq!(
        first,
        drive(&mut b, 40, 240, 1.0),
        "{bearings:?} bearings, {solver} LU, a serialised state in a fresh instance"
    );
}
