//! The faces generated from the XML, driven from Rust without the C boundary: start values, the
//! XML's min/max on Real and Integer parameters, refusals that name the variable, input clamping
//! and input polynomials.

use crate::common;

use common::Recorder;
use windrive::fmi2::fmu::slave::{NoLog, Slave};
use windrive::fmi2::fmu::variables::{Causality, Start, VarType};
use windrive::slaves::{
    gearbox6dof::Gearbox6dofSlave, generator::GeneratorSlave, rotor::RotorSlave, torsional::TorsionalSlave,
};

/// Every parameter and input of a fresh instance reads back as its XML start value.
fn starts_match_the_xml<S: Slave>() {
    let mut s = S::instantiate(None);
    for v in S::VARIABLES {
        let name = v.name;
        match v.start {
            Start::Real(x) => assert_eq!(s.get_real(v.vr).unwrap().to_bits(), x.to_bits(), "{name}"),
            Start::Integer(x) => assert_eq!(s.get_integer(v.vr).unwrap(), x, "{name}"),
            Start::Boolean(x) => assert_eq!(s.get_boolean(v.vr).unwrap(), x, "{name}"),
            Start::String(x) => assert_eq!(s.get_string(v.vr).unwrap(), x, "{name}"),
            Start::None => {}
        }
    }
}

#[test]
fn defaults_are_the_xml_start_values() {
    starts_match_the_xml::<TorsionalSlave>();
    starts_match_the_xml::<RotorSlave>();
    starts_match_the_xml::<GeneratorSlave>();
    starts_match_the_xml::<Gearbox6dofSlave>();
    // the generated Default is what the command line builds from
    let p = windrive::slaves::torsional::Params::default();
    assert_eq!(
        (p.preset.as_str(), p.contact_ratio, p.max_internal_step),
        ("D", 1.6, 1e-3)
    );
    // the gearbox FMU's default iteration (kept+predicted) stops at a looser tolerance than the solver's
    // own default (`pattern`, which the bare model's commands take): at 3e-8 the kept iteration lands
    // within a tenth of the step's own error of the converged answer (tests/it/newton_kept.rs), which at
    // 1e-7 it does not (docs/PERFORMANCE.md, "The forces on AVX, and the Newton tolerance as a parameter")
    let fmu = windrive::slaves::gearbox6dof::Params::default();
    assert_eq!(fmu.newton, "kept+predicted");
    assert!(fmu.newton_tolerance > windrive::solver::alpha::NEARLY_LINEAR_INCREMENT_TOLERANCE);
    assert!(fmu.newton_tolerance < 1e-7);
}

/// Each bounded Real or Integer parameter: just outside a bound is refused naming the parameter and
/// the bound, and the old value stays; the bound itself is accepted.
fn ranges_are_enforced<S: Slave>() -> usize {
    let mut checked = 0;
    for v in S::VARIABLES.iter().filter(|v| v.causality == Causality::Parameter) {
        for (bound, outside, words) in [(v.min, -1.0, "below its minimum"), (v.max, 1.0, "above its maximum")] {
            let Some(b) = bound else { continue };
            let mut s = S::instantiate(None);
            let err = match v.ty {
                VarType::Real => {
                    let before = s.get_real(v.vr).unwrap();
                    let bad = b + outside * b.abs().max(1.0);
                    let e = s.set_real(v.vr, bad, &mut NoLog).unwrap_err();
                    assert_eq!(s.get_real(v.vr).unwrap(), before, "{}", v.name);
                    s.set_real(v.vr, b, &mut NoLog).unwrap();
                    assert_eq!(s.get_real(v.vr).unwrap(), b);
                    e
                }
                VarType::Integer => {
                    let before = s.get_integer(v.vr).unwrap();
                    let e = s.set_integer(v.vr, b as i32 + outside as i32, &mut NoLog).unwrap_err();
                    assert_eq!(s.get_integer(v.vr).unwrap(), before, "{}", v.name);
                    s.set_integer(v.vr, b as i32, &mut NoLog).unwrap();
                    assert_eq!(s.get_integer(v.vr).unwrap(), b as i32);
                    e
                }
                _ => continue,
            };
            let msg = err.to_string();
            assert!(msg.contains(v.name) && msg.contains(words), "{msg}");
            checked += 1;
        }
    }
    checked
}

#[test]
fn parameters_outside_the_xml_range_are_refused_by_name() {
    assert!(ranges_are_enforced::<TorsionalSlave>() >= 10);
    assert!(ranges_are_enforced::<GeneratorSlave>() >= 20);
    ranges_are_enforced::<RotorSlave>();
    assert!(ranges_are_enforced::<Gearbox6dofSlave>() >= 5);
}

/// Issue 16: `poles = -2` used to answer fmi2OK.
#[test]
fn generator_poles_outside_0_to_400_are_refused() {
    let mut g = GeneratorSlave::instantiate(None);
    let poles = windrive::models::generator::vr::POLES;
    for bad in [-2, 401, i32::MIN] {
        let msg = g.set_integer(poles, bad, &mut NoLog).unwrap_err().to_string();
        assert!(msg.contains(&format!("parameter poles = {bad}")), "{msg}");
    }
    assert_eq!(g.params.poles, 0);
    g.set_integer(poles, 4, &mut NoLog).unwrap();
    assert_eq!(g.get_integer(poles).unwrap(), 4);
}

#[test]
fn outputs_calculated_parameters_and_absent_types_are_refused_by_name() {
    use windrive::models::{generator, rotor, torsional};
    let mut t = TorsionalSlave::instantiate(None);
    let msg = t.set_real(torsional::vr::HSS_TORQUE, 1.0, &mut NoLog).unwrap_err().0;
    assert!(msg.contains("hss_torque") && msg.contains("Output"), "{msg}");
    let msg = t.set_real(torsional::vr::GEAR_RATIO, 1.0, &mut NoLog).unwrap_err().0;
    assert!(
        msg.contains("gear_ratio") && msg.contains("CalculatedParameter"),
        "{msg}"
    );
    // the trait's defaults: torsional has no settable Integer or Boolean
    let msg = t.set_integer(torsional::vr::DOF_COUNT, 3, &mut NoLog).unwrap_err().0;
    assert!(msg.contains("dof_count") && msg.contains("cannot be set"), "{msg}");
    let msg = t
        .set_boolean(torsional::vr::BRAKE_LOCKED, true, &mut NoLog)
        .unwrap_err()
        .0;
    assert!(msg.contains("brake_locked") && msg.contains("cannot be set"), "{msg}");
    let mut r = RotorSlave::instantiate(None);
    let msg = r
        .set_boolean(rotor::vr::GENERATOR_CONNECTED, false, &mut NoLog)
        .unwrap_err()
        .0;
    assert!(msg.contains("generator_connected"), "{msg}");
    let mut g = GeneratorSlave::instantiate(None);
    let msg = g
        .set_string(generator::vr::RATED_TORQUE, "x", &mut NoLog)
        .unwrap_err()
        .0;
    assert!(msg.contains("String value reference"), "{msg}");
}

#[test]
fn parameter_errors_name_the_parameter_and_what_is_accepted() {
    use windrive::models::{generator, rotor};
    let mut g = GeneratorSlave::instantiate(None);
    g.set_string(generator::vr::KIND, "squirrel", &mut NoLog).unwrap();
    let msg = g.initialize(0.0, &mut NoLog).unwrap_err().0;
    assert_eq!(msg, "parameter kind = \"squirrel\": use spring, fixed, dfig or pmg");
    let mut r = RotorSlave::instantiate(None);
    r.set_string(rotor::vr::MODE, "wind", &mut NoLog).unwrap();
    let msg = r.initialize(0.0, &mut NoLog).unwrap_err().0;
    assert_eq!(msg, "parameter mode = \"wind\": use aero or playback");
}

#[test]
fn a_bounded_input_is_clamped_with_a_warning_naming_it() {
    let vr = windrive::models::torsional::vr::BRAKE_COMMAND;
    let mut t = TorsionalSlave::instantiate(None);
    let mut log = Recorder::default();
    t.set_real(vr, 1.5, &mut log).unwrap();
    assert_eq!(t.get_real(vr).unwrap(), 1.0);
    assert_eq!(log.0, ["brake_command = 1.5 outside [0, 1], clamped"]);
    t.set_real(vr, 0.5, &mut log).unwrap();
    assert_eq!((t.get_real(vr).unwrap(), log.0.len()), (0.5, 1));
}

#[test]
fn input_polynomials_follow_their_derivatives_and_a_new_value_clears_them() {
    let vr = windrive::models::rotor::vr::ROTOR_SPEED;
    let mut r = RotorSlave::instantiate(None);
    r.set_real(vr, 2.0, &mut NoLog).unwrap();
    r.set_input_derivative(vr, 1, 0.5).unwrap();
    r.set_input_derivative(vr, 2, 4.0).unwrap();
    assert!(r.set_input_derivative(vr, 3, 1.0).unwrap_err().0.contains("order 3"));
    r.inputs.advance(0.5);
    // u(0.5) = 2 + 0.5·0.5 + 4·0.25/2, u'(0.5) = 0.5 + 4·0.5
    assert_eq!(r.inputs.rotor_speed.0, [2.75, 2.5, 4.0]);
    r.set_real(vr, 1.0, &mut NoLog).unwrap();
    assert_eq!(r.inputs.rotor_speed.0, [1.0, 0.0, 0.0]);
}

/// `initial_torque_from_input`: the initial equilibrium carries the rotor_torque input as it stands
/// before the first step (re-read each time the importer sets it), then the state is the simulation's.
/// Without it, `initial_rotor_torque` alone. The LSS torque of a static equilibrium is the torque it
/// carries; 1 % allows the bearing and mesh compliance's small share of the moment balance.
#[test]
fn gearbox_initial_equilibrium_follows_the_input_until_the_first_step() {
    use windrive::models::gearbox6dof::vr;
    let lss = |g: &mut Gearbox6dofSlave| g.get_real(vr::LSS_TORQUE).unwrap();
    let close = |a: f64, b: f64| (a / b - 1.0).abs() < 0.01;
    let mut g = Gearbox6dofSlave::instantiate(None);
    g.set_real(vr::ROTOR_TORQUE, 1e5, &mut NoLog).unwrap();
    g.initialize(0.0, &mut NoLog).unwrap();
    let rated = g.get_real(vr::INITIAL_ROTOR_TORQUE).unwrap();
    assert!(close(lss(&mut g), rated), "{} vs {rated}", lss(&mut g));

    let mut g = Gearbox6dofSlave::instantiate(None);
    g.set_boolean(vr::INITIAL_TORQUE_FROM_INPUT, true, &mut NoLog).unwrap();
    assert!(g.get_boolean(vr::INITIAL_TORQUE_FROM_INPUT).unwrap());
    g.set_real(vr::ROTOR_TORQUE, 1e5, &mut NoLog).unwrap();
    g.initialize(0.0, &mut NoLog).unwrap();
    assert!(close(lss(&mut g), 1e5), "{}", lss(&mut g));
    g.set_real(vr::ROTOR_TORQUE, 5e4, &mut NoLog).unwrap();
    assert!(close(lss(&mut g), 5e4), "{}", lss(&mut g));
    let ratio = g.get_real(vr::GEAR_RATIO).unwrap();
    g.set_real(vr::GENERATOR_TORQUE, 5e4 / ratio, &mut NoLog).unwrap();
    g.do_step(0.0, 1e-3, &mut NoLog).unwrap();
    g.set_real(vr::ROTOR_TORQUE, 0.0, &mut NoLog).unwrap();
    assert!(close(lss(&mut g), 5e4), "after the first step: {}", lss(&mut g));
}
