//! The driver's plain linear step (a communication step that is one internal step of a linear model
//! whose brake is open: `Driver::plain_linear_step`) gives the general way's bits. Each scenario runs
//! twice on the FMU's Rust face, once with the plain step and once with every step the general way
//! (`TorsionalSlave::general_steps_only`), and every output after every step is compared with
//! `to_bits()`; the solver's work counters must agree too, and the plain step's count says which way
//! the steps went (all plain, none, or handed over and back around a brake application).

use windrive::fmi2::fmu::slave::{NoLog as Quiet, Slave};
use windrive::models::torsional::vr;
use windrive::physics::drivetrain::Drivetrain;
use windrive::slaves::torsional::TorsionalSlave;
use windrive::solver::Statistics;

/// What one communication step sets before it runs: (value reference, value) of inputs, and
/// (value reference, order, value) of input derivatives.
#[derive(Default)]
struct Set {
    values: Vec<(u32, f64)>,
    derivatives: Vec<(u32, i32, f64)>,
}

struct Scenario {
    name: &'static str,
    strings: Vec<(u32, &'static str)>,
    parameters: Vec<(u32, f64)>,
    /// Communication step, s, and how many.
    h: f64,
    steps: usize,
    /// The inputs of the step from t.
    inputs: Box<dyn Fn(f64) -> Set>,
}

/// Every Real output, then the brake's lock, as bits.
fn outputs(s: &mut TorsionalSlave) -> Vec<u64> {
    let mut bits = crate::common::real_output_bits(s);
    bits.push(s.get_boolean(vr::BRAKE_LOCKED).unwrap() as u64);
    bits
}

/// The outputs at the start and after every step, and the solver's counters.
fn run(sc: &Scenario, plain: bool) -> (Vec<Vec<u64>>, Statistics) {
    let mut s = TorsionalSlave::instantiate(None);
    for &(r, v) in &sc.strings {
        s.set_string(r, v, &mut Quiet).unwrap();
    }
    for &(r, v) in &sc.parameters {
        s.set_real(r, v, &mut Quiet).unwrap();
    }
    s.initialize(0.0, &mut Quiet).unwrap();
    if !plain {
        s.general_steps_only().unwrap();
    }
    let mut rows = vec![outputs(&mut s)];
    for i in 0..sc.steps {
        let t = i as f64 * sc.h;
        let set = (sc.inputs)(t);
        for (r, v) in set.values {
            s.set_real(r, v, &mut Quiet).unwrap();
        }
        for (r, order, v) in set.derivatives {
            s.set_input_derivative(r, order, v).unwrap();
        }
        s.do_step(t, sc.h, &mut Quiet).unwrap();
        rows.push(outputs(&mut s));
    }
    (rows, s.solver_statistics())
}

/// Runs `sc` both ways, asserts the same bits and work; returns the plain way's counters and how
/// many steps ended with the brake locked.
fn same_both_ways(sc: &Scenario) -> (Statistics, usize) {
    let (general, general_stats) = run(sc, false);
    let (plain, plain_stats) = run(sc, true);
    assert_eq!(
        general_stats.plain_steps, 0,
        "{}: general way took plain steps",
        sc.name
    );
    if let Some(step) = (0..general.len()).find(|&i| general[i] != plain[i]) {
        let column = (0..general[step].len())
            .find(|&c| general[step][c] != plain[step][c])
            .unwrap();
        panic!(
            "{}: output {column} differs after step {step}: {:e} (general) vs {:e} (plain)",
            sc.name,
            f64::from_bits(general[step][column]),
            f64::from_bits(plain[step][column])
        );
    }
    let work = |s: Statistics| (s.steps, s.newton_iterations, s.factorizations, s.halvings);
    assert_eq!(work(general_stats), work(plain_stats), "{}: solver work", sc.name);
    let locked = plain.iter().filter(|row| *row.last().unwrap() == 1).count();
    (plain_stats, locked)
}

fn rated(preset: &str) -> (f64, f64) {
    let d = Drivetrain::preset(preset).unwrap();
    (d.rated_rotor_torque(), d.rated_generator_torque())
}

fn torques(preset: &'static str, rotor: f64, generator: f64) -> Box<dyn Fn(f64) -> Set> {
    let (tr, tg) = rated(preset);
    Box::new(move |_| Set {
        values: vec![(vr::ROTOR_TORQUE, rotor * tr), (vr::GENERATOR_TORQUE, generator * tg)],
        ..Set::default()
    })
}

/// Drivetrain D's rated-torque step from rest at rated speed, 3 s at 1 ms: every step after the
/// first (whose accelerations are not yet consistent with any inputs) is plain.
#[test]
fn step_response_is_the_same_to_the_bit() {
    let sc = Scenario {
        name: "D full, rated-torque step",
        strings: vec![(vr::PRESET, "D"), (vr::FIDELITY, "full")],
        parameters: vec![],
        h: 1e-3,
        steps: 3000,
        inputs: torques("D", 1.0, 1.0),
    };
    let (stats, _) = same_both_ways(&sc);
    assert_eq!(stats.plain_steps, 2999);
}

/// Without a brake: every preset at every fidelity and both implicit families (HHT-α weights the
/// start of the step, so the plain step's interpolated inputs differ from its end inputs), inputs
/// varying every step with first and second derivatives, the whole drivetrain and both sections of
/// a cut one (the drivetrain section has no rigid rotation and reads the cut's speed and angle).
#[test]
fn brake_free_runs_are_the_same_to_the_bit() {
    let wavy = |preset: &'static str| -> Box<dyn Fn(f64) -> Set> {
        let (tr, tg) = rated(preset);
        Box::new(move |t: f64| Set {
            values: vec![
                (vr::ROTOR_TORQUE, tr * (0.8 + 0.2 * (7.0 * t).sin())),
                (vr::GENERATOR_TORQUE, tg * (0.9 + 0.1 * (11.0 * t).cos())),
                (vr::CUT_SPEED, 1.5 + 0.1 * (3.0 * t).sin()),
                (vr::CUT_TORQUE, tr * (0.7 + 0.05 * t)),
            ],
            derivatives: vec![
                (vr::ROTOR_TORQUE, 1, tr * 1.4 * (7.0 * t).cos()),
                (vr::ROTOR_TORQUE, 2, -tr * 9.8 * (7.0 * t).sin()),
                (vr::GENERATOR_TORQUE, 1, -tg * 1.1 * (11.0 * t).sin()),
                (vr::CUT_SPEED, 1, 0.3 * (3.0 * t).cos()),
                (vr::CUT_SPEED, 2, -0.9 * (3.0 * t).sin()),
            ],
        })
    };
    let mut runs = 0;
    for preset in ["A", "B", "C", "D", "P"] {
        for fidelity in ["2", "5", "full"] {
            for integrator in ["implicit", "hht"] {
                for section in ["whole", "rotor", "drivetrain"] {
                    let sc = Scenario {
                        name: "brake-free",
                        strings: vec![
                            (vr::PRESET, preset),
                            (vr::FIDELITY, fidelity),
                            (vr::INTEGRATOR, integrator),
                            (vr::SECTION, section),
                        ],
                        parameters: vec![(vr::SPECTRAL_RADIUS, 0.8), (vr::INITIAL_SPEED_RATIO, 0.9)],
                        h: 1e-3,
                        steps: 400,
                        inputs: wavy(preset),
                    };
                    let (stats, locked) = same_both_ways(&sc);
                    assert_eq!(
                        (stats.plain_steps, locked),
                        (399, 0),
                        "{preset} {fidelity} {integrator} {section}"
                    );
                    runs += 1;
                }
            }
        }
    }
    assert_eq!(runs, 90);
}

/// The brake applied from 0.2 s to a slowly turning drivetrain, which it stops and holds, then
/// released at 1.2 s: the plain step hands over to the general way while the brake acts (its
/// friction force then decides stick and slip) and takes over again once the brake has let go.
/// The command ramps, and its derivative carries the ramp into the step that starts it.
#[test]
fn a_brake_application_hands_over_and_back_to_the_bit() {
    let (tr, tg) = rated("D");
    let sc = Scenario {
        name: "D full, brake applied and released",
        strings: vec![(vr::PRESET, "D"), (vr::FIDELITY, "full")],
        parameters: vec![(vr::INITIAL_SPEED_RATIO, 0.002), (vr::INITIAL_ROTOR_TORQUE, 0.05 * tr)],
        h: 1e-3,
        steps: 2000,
        inputs: Box::new(move |t: f64| {
            let command: f64 = if (0.2..1.2).contains(&t) {
                ((t - 0.2) / 0.1).min(1.0)
            } else {
                0.0
            };
            let ramping = (0.2..0.3).contains(&t);
            Set {
                values: vec![
                    (vr::ROTOR_TORQUE, 0.05 * tr),
                    (vr::GENERATOR_TORQUE, 0.05 * tg),
                    (vr::BRAKE_COMMAND, command),
                ],
                derivatives: if ramping {
                    vec![(vr::BRAKE_COMMAND, 1, 10.0)]
                } else {
                    vec![]
                },
            }
        }),
    };
    let (stats, locked) = same_both_ways(&sc);
    assert!(locked > 100, "the brake holds the drivetrain: {locked} steps locked");
    // 199 before the brake (the first step's accelerations are not yet consistent), none of the 1 000
    // with a command, 799 after it (the first clears the friction force the brake left)
    assert_eq!(stats.plain_steps, 199 + 799);
}

/// Where the plain step does not apply, every step goes the general way with the same bits: a
/// communication step of two internal steps or of a step and a half, one of half an internal step
/// (which is plain), backlash (piecewise linear) and RK4.
#[test]
fn steps_the_plain_step_does_not_take_are_the_same_to_the_bit() {
    let base = |name, h: f64, strings: Vec<(u32, &'static str)>, parameters: Vec<(u32, f64)>| Scenario {
        name,
        strings: [vec![(vr::PRESET, "C"), (vr::FIDELITY, "full")], strings].concat(),
        parameters: [vec![(vr::MAX_INTERNAL_STEP, 1e-3)], parameters].concat(),
        h,
        steps: 300,
        inputs: torques("C", 0.7, 0.9),
    };
    let cases = [
        (base("two internal steps", 2e-3, vec![], vec![]), 0),
        (base("a step and a half", 1.5e-3, vec![], vec![]), 0),
        (base("half an internal step", 0.5e-3, vec![], vec![]), 299),
        (base("backlash", 1e-3, vec![], vec![(vr::MESH_BACKLASH, 1e-4)]), 0),
        (
            base(
                "rk4",
                1e-3,
                vec![(vr::INTEGRATOR, "rk4")],
                vec![(vr::MAX_INTERNAL_STEP, 1e-5)],
            ),
            0,
        ),
    ];
    for (sc, plain) in cases {
        let (stats, _) = same_both_ways(&sc);
        assert_eq!(stats.plain_steps, plain, "{}", sc.name);
    }
}
