//! The 6-DOF gearbox hands the forces its reported loads were evaluated with to the next step's
//! consistent accelerations (`Driver::give_start_forces`) instead of evaluating them again: the same
//! bits as evaluating them. Two instances step the GRC through a brake application with the rotor's
//! moments and thrust changing every step (they enter f_int, so the handed forces must take the new
//! ones); one reads every output after every step (its loads, and so the handed forces), the other
//! reads nothing until the end; every output of both is compared with `to_bits()` at the end, and
//! the reading one's after every step against a third that reads them all but never hands forces on
//! (its state restored before each step, which drops them), against a fourth that takes a state before
//! each step (a restore and a taken state both drop the integrator's factorisations).

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

/// Both lamina laws: the table's reported loads evaluate each lamina's load besides its sums, which
/// must leave the forces they hand on the bits a step evaluates.
#[test]
fn handed_start_forces_give_the_evaluated_bits() {
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
    // the same run with every state restored into the instance before its step: a restore drops the
    // held forces, so every step evaluates its own. A restore drops the factorisations as well, so
    // the run it is compared with takes a state before every step (which drops those alone) and
    // still hands its forces on
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
