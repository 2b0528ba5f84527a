//! The 6-DOF gearbox hands the internal forces at a step's end, as the step's equation of motion left
//! them (`Driver::set_forces_by_equation`), to the next step's consistent accelerations
//! (`Driver::give_start_forces`) instead of evaluating them again. Reading outputs evaluates only the
//! elements read and changes nothing of the run: two instances step the GRC through a brake
//! application with the rotor's moments and thrust changing every step (they enter f_int, so the
//! handed forces must take the new ones), one reading every output after every step, the other
//! nothing until the end, and every output of both is compared with `to_bits()`. A state taken or
//! restored drops the handed forces (the next step evaluates its own), so a run restored before every
//! step repeats one that takes a state before every step. On the driver: the forces by equation are
//! the evaluated ones to within what the Newton tolerance leaves, and given forces serve one advance.

use crate::common::real_output_bits;
use windrive::fmi2::fmu::slave::{NoLog, Slave};
use windrive::slaves::gearbox6dof::Gearbox6dofSlave;

fn vr(name: &str) -> u32 {
    Gearbox6dofSlave::VARIABLES
        .iter()
        .find(|v| v.name == name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .vr
}

fn instance(bearing_model: &str, newton: &str) -> Gearbox6dofSlave {
    let mut s = Gearbox6dofSlave::instantiate(None);
    s.set_string(vr("bearing_model"), bearing_model, &mut NoLog).unwrap();
    s.set_string(vr("newton"), newton, &mut NoLog).unwrap();
    s.set_integer(vr("slices"), 5, &mut NoLog).unwrap();
    s.initialize(0.0, &mut NoLog).unwrap();
    s
}

/// One communication step of 1 ms from step `k`: rotor torque and moments varying, the brake from
/// step 60 on.
fn step(s: &mut Gearbox6dofSlave, k: usize) {
    let t = k as f64 * 1e-3;
    for (name, value) in [
        ("rotor_torque", 3.2e5 * (1.0 + 0.1 * (40.0 * t).sin())),
        ("main_shaft_tilt_moment", 2e5 * (30.0 * t).cos()),
        ("main_shaft_yaw_moment", 1e5 * (25.0 * t).sin()),
        ("rotor_thrust", 1e5 + 2e4 * (20.0 * t).sin()),
        ("brake_command", if k >= 60 { 1.0 } else { 0.0 }),
    ] {
        s.set_real(vr(name), value, &mut NoLog).unwrap();
    }
    s.do_step(t, 1e-3, &mut NoLog).unwrap();
}

/// Both lamina laws and both iterations.
#[test]
fn reads_change_no_bit_and_states_drop_the_handed_forces() {
    for model in ["lamina", "lamina-table"] {
        for newton in ["pattern", "kept+predicted"] {
            handed_start_forces_with(model, newton);
        }
    }
}

fn handed_start_forces_with(model: &str, newton: &str) {
    let (mut reading, mut quiet) = (instance(model, newton), instance(model, newton));
    let mut read = Vec::new();
    for k in 0..120 {
        step(&mut reading, k);
        read = real_output_bits(&mut reading);
        step(&mut quiet, k);
    }
    assert_eq!(real_output_bits(&mut quiet), read, "{model}, {newton}");
    // the same run with every state restored into the instance before its step, against one that takes
    // a state before every step: both drop the handed forces and the factorisations, so every step
    // evaluates its own start forces and builds its own J
    let (mut taking, mut restored) = (instance(model, newton), instance(model, newton));
    for k in 0..120 {
        taking.state_taken();
        step(&mut taking, k);
        let snap = restored.snapshot();
        restored.restore(&snap);
        step(&mut restored, k);
        assert_eq!(
            real_output_bits(&mut restored),
            real_output_bits(&mut taking),
            "{model}, {newton}, step {k}"
        );
    }
}

/// On the driver itself: forces given for the start are what its consistent accelerations take (the
/// true ones change no bit, wrong ones change the step), and an advance that is refused at once (a NaN
/// step) forgets them as any other does, so they never reach a later step.
#[test]
fn the_driver_takes_given_forces_for_one_advance_only() {
    use windrive::physics::gearbox::Gearbox;
    use windrive::physics::gearbox::description::{BearingModel, Description};
    use windrive::physics::gearbox::statics::equilibrium;
    use windrive::solver::alpha::Alpha;
    use windrive::solver::{Driver, DynState, Method, SecondOrderSystem};

    let mut d = Description::load("grc750").unwrap();
    d.model.bearings = BearingModel::Linear;
    d.model.slices = 5;
    let g = Gearbox::new(&d).unwrap();
    let t = g.rated_rotor_torque.unwrap();
    let (q, v) = equilibrium(&g, &[t, t / g.gear_ratio, 0.0], 2.0).unwrap();
    let u = [0.9 * t, t / g.gear_ratio, 0.0];
    // three advances of 1 ms, `give` called before each with its index
    let run = |give: &dyn Fn(usize, &mut Driver, &DynState)| {
        let mut st = DynState::new(q.clone(), v.clone());
        let mut driver = Driver::new(Method::Implicit(Alpha::hht(0.8).unwrap()));
        for k in 0..3 {
            give(k, &mut driver, &st);
            driver
                .advance(&g, &mut st, k as f64 * 1e-3, 1e-3, 1e-3, 3, |_, out| {
                    out.copy_from_slice(&u)
                })
                .unwrap();
        }
        st.q.iter().chain(&st.v).map(|x| x.to_bits()).collect::<Vec<_>>()
    };
    let n = g.dofs();
    let plain = run(&|_, _, _| {});
    let true_forces = run(&|_, driver, st| {
        driver.give_start_forces(n, |fi| g.internal_forces(0.0, &st.q, &st.v, fi));
    });
    assert_eq!(plain, true_forces);
    let doubled = run(&|k, driver, st| {
        if k == 1 {
            driver.give_start_forces(n, |fi| {
                g.internal_forces(0.0, &st.q, &st.v, fi);
                fi.iter_mut().for_each(|f| *f *= 2.0);
            });
        }
    });
    assert_ne!(plain, doubled, "given forces must be the ones the step takes");
    let refused_first = run(&|k, driver, st| {
        if k == 1 {
            driver.give_start_forces(n, |fi| fi.fill(1e9));
            let mut copy = st.clone();
            assert!(
                driver
                    .advance(&g, &mut copy, 0.0, f64::NAN, 1e-3, 3, |_, _| {})
                    .is_err()
            );
        }
    });
    assert_eq!(plain, refused_first);
}

/// The forces a Newton step leaves by its equation of motion are the evaluated ones at its end state
/// to within what the Newton tolerance leaves: the GRC (linear bearings, 5 slices) loaded off its
/// equilibrium and braked (slipping, then sticking), 60 steps of 1 ms under generalised-α (both α
/// weights nonzero), every end's forces by equation against an evaluation there, relative to the
/// largest force. At the tolerance 1e-12 they agree within 1e-8 (2e-11 measured), at the FMU's default
/// 3e-8 within 1e-4 (2e-5 measured; d-shutdown-6dof's 30 s with lamina bearings, 5e-6 at the median,
/// docs/PERFORMANCE.md). A slip in the equation is of the order of the forces themselves (the friction
/// force left out: 2e-2; α_m's start term left out: 0.2).
#[test]
fn forces_by_equation_are_the_evaluated_ones_within_the_newton_tolerance() {
    use windrive::physics::gearbox::Gearbox;
    use windrive::physics::gearbox::description::{BearingModel, Description};
    use windrive::physics::gearbox::statics::equilibrium;
    use windrive::solver::alpha::{Alpha, Newton};
    use windrive::solver::{Driver, DynState, Method, SecondOrderSystem};

    let mut d = Description::load("grc750").unwrap();
    d.model.bearings = BearingModel::Linear;
    d.model.slices = 5;
    let mut g = Gearbox::new(&d).unwrap();
    let t = g.rated_rotor_torque.unwrap();
    g.brake = windrive::physics::brake::DiskBrake {
        torque_max: 1.5 * t / g.gear_ratio,
        static_ratio: 1.2,
    };
    let (q, v) = equilibrium(&g, &[t, t / g.gear_ratio, 0.0], 2.0).unwrap();
    let worst = |tolerance: f64| {
        let mut st = DynState::new(q.clone(), v.clone());
        let mut driver = Driver::new(Method::Implicit(Alpha::generalised(0.8).unwrap()));
        driver.set_newton(Newton {
            tolerance,
            ..Newton::parse("kept+predicted").unwrap()
        });
        driver.set_forces_by_equation(true);
        let mut worst: f64 = 0.0;
        for k in 0..60 {
            let u = [0.7 * t, t / g.gear_ratio, if k >= 30 { 1.0 } else { 0.0 }];
            driver
                .advance(&g, &mut st, k as f64 * 1e-3, 1e-3, 1e-3, 3, |_, out| {
                    out.copy_from_slice(&u)
                })
                .unwrap();
            let by_equation = driver
                .end_forces(&st.q, &st.v)
                .expect("a Newton step leaves them")
                .to_vec();
            let mut evaluated = vec![0.0; g.dofs()];
            g.internal_forces(0.0, &st.q, &st.v, &mut evaluated);
            let scale = evaluated.iter().fold(0.0f64, |m, f| m.max(f.abs()));
            let gap = evaluated
                .iter()
                .zip(&by_equation)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            worst = worst.max(gap / scale);
        }
        assert!(st.friction_force != 0.0, "the brake acts");
        worst
    };
    let (tight, default) = (worst(1e-12), worst(3e-8));
    eprintln!("forces by equation against evaluated: {tight:.2e} at 1e-12, {default:.2e} at the default");
    assert!(tight < 1e-8, "{tight:e}");
    assert!(default < 1e-4, "{default:e}");
}
