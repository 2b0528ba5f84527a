//! The thesis's spring scenes for drivetrains C and D (scenes/{c,d}-{normal,shutdown}-spring: synthetic rotor in
//! above-rated NTM wind with power-regulating pitch, full-fidelity torsional drivetrain, fixed-speed
//! generator spring; shutdown at 5 s) through the master, checked against what the thesis reports and
//! against the modal analysis:
//! - normal operation: mean HSS torque and electrical power within 4 % of rated (the pitch integrator
//!   winds up from fine pitch through the whole 20 s, so C's means sit 2.8 % above rated), no mesh-force
//!   reversal;
//! - shutdown: no reversal before it, a reversal after the generator trips;
//! - while the brake slips the HSS torque rings at the lowest non-zero free–free mode, and once the
//!   brake holds at the lowest HSS-locked mode (each within 10 %, measured within 0.4 %);
//! - the brake locks and stays locked (A's and B's may slip once within 0.5 s of locking, their played-back
//!   rotor torque still pulling backwards); the generator angle does not creep; the held rotor rocks
//!   about a fixed angle without drift, and in the spring scenes (no forcing) its rocking does not grow.

use crate::common;

use windrive::analysis::signal::metrics::range;
use windrive::analysis::signal::spectrum::dominant_in_window;
use windrive::linear::modes::Boundary;
use windrive::reference::modes::lowest_mode;

struct Run {
    t: Vec<f64>,
    power: Vec<f64>,
    gear_pinion: Vec<f64>,
    hss: Vec<f64>,
    sun_planet: Vec<f64>,
    lss: Vec<f64>,
    locked: Vec<f64>,
    generator_angle: Vec<f64>,
    rotor_speed: Vec<f64>,
}

fn run(scene: &str) -> Run {
    let names = [
        "hss_torque",
        "mesh_force_sun_planet_1",
        "brake_locked",
        "angle_generator",
        "mesh_force_gear_pinion_2",
        "lss_torque",
        "rotor_speed",
    ];
    let mut channels: Vec<String> = names.iter().map(|n| format!("torsional.{n}")).collect();
    channels.push("generator.electrical_power".into());
    let cols = common::run_scene(scene, &[], &channels, None);
    let mut c = cols.into_iter();
    Run {
        t: c.next().unwrap(),
        hss: c.next().unwrap(),
        sun_planet: c.next().unwrap(),
        locked: c.next().unwrap(),
        generator_angle: c.next().unwrap(),
        gear_pinion: c.next().unwrap(),
        lss: c.next().unwrap(),
        rotor_speed: c.next().unwrap(),
        power: c.next().unwrap(),
    }
}

fn check(scene: &str, preset: &str) {
    let r = run(scene);
    let before = r.t.iter().position(|&t| t >= 5.0).unwrap();
    assert!(
        r.sun_planet[..before].iter().all(|&f| f > 0.0),
        "{scene}: reversal in normal operation"
    );
    assert!(
        r.sun_planet[before..].iter().any(|&f| f < 0.0),
        "{scene}: no reversal after the trip"
    );
    // A's and B's rotor torque is C's played back open loop: C's feathering rotor still pulls backwards
    // when A's brake has already locked, and the reverse swing may slip it once within 0.5 s; after that
    // it holds. The spring scenes' brake never lets go.
    let played_back = matches!(preset, "A" | "B");
    let first_lock = r.locked.iter().position(|&l| l > 0.5).expect("the brake locks");
    let lock = r.locked.iter().rposition(|&l| l < 0.5).map_or(0, |i| i + 1);
    assert!(lock < r.locked.len(), "{scene}: the brake let go for good");
    let slipped_for = r.t[lock] - r.t[first_lock];
    assert!(
        slipped_for == 0.0 || (played_back && slipped_for < 0.5),
        "{scene}: the brake slipped again {slipped_for:.2} s after it first locked"
    );
    let held = r.generator_angle[lock + 1];
    assert!(
        r.generator_angle[lock + 1..].iter().all(|&a| a == held),
        "{scene}: the generator creeps"
    );
    let t_lock = r.t[lock];
    // the rotor, held through the gearbox, rocks on the shafts' stiffness about a fixed angle: its
    // mean speed over the held phase is nil (no drift) and the rocking never grows
    let held_phase = r.t.iter().position(|&t| t >= t_lock + 0.5).unwrap();
    let w = &r.rotor_speed[held_phase..];
    let amplitude = |w: &[f64]| w.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mean = w.iter().sum::<f64>() / w.len() as f64;
    let (first, last) = (amplitude(&w[..w.len() / 4]), amplitude(&w[3 * w.len() / 4..]));
    println!("{scene}: held rotor speed: mean {mean:.2e} rad/s, rocking {first:.2e} -> {last:.2e} rad/s");
    assert!(
        mean.abs() < 0.1 * first,
        "{scene}: the held rotor drifts at {mean} rad/s"
    );
    // C's and D's spring scenes hold an unforced rotor: its rocking cannot grow, which checks the held
    // drivetrain's integration. A's and B's rotor torque is C's played back, the feathered rotor's in the
    // turbulent field on the blades, which keeps forcing the held rotor: its rocking waxes and wanes with the
    // wind (measured 1.3x and 2.0x from the first quarter held to the last), so it bounds nothing there
    if !played_back {
        assert!(
            last <= 1.01 * first,
            "{scene}: the held rotor's rocking grows, {first} -> {last}"
        );
    }
    let dt = windrive::physics::drivetrain::Drivetrain::preset(preset).unwrap();
    let peak = r.lss.iter().fold(0.0f64, |m, v| m.max(v.abs())) / dt.rated_rotor_torque();
    println!("{scene}: max |LSS torque| / rated = {peak:.3} (design factor 1.35)");
    let slipping = dominant_in_window(&r.t, &r.hss, 6.2, t_lock - 0.1, 0.3).unwrap().0;
    let held_f = dominant_in_window(&r.t, &r.hss, t_lock + 0.5, 30.0, 0.3).unwrap().0;
    let free = lowest_mode(preset, Boundary::Disconnected).unwrap();
    let locked = lowest_mode(preset, Boundary::HssLocked).unwrap();
    println!(
        "{scene}: brake locks at {t_lock:.2} s; slipping {slipping:.3} Hz (free-free {free:.3}); held {held_f:.3} Hz (HSS locked {locked:.3})"
    );
    assert!(
        (slipping / free - 1.0).abs() < 0.1,
        "{scene}: {slipping} Hz while slipping vs {free}"
    );
    assert!(
        (held_f / locked - 1.0).abs() < 0.1,
        "{scene}: {held_f} Hz when held vs {locked}"
    );
}

#[test]
fn drivetrain_d_shutdown() {
    check("d-shutdown-spring", "D");
}

/// A and B: drivetrain C's shutdown torque scaled by (D/D_C)³ (thesis Eq. 4.40), the generator
/// (A: PMG, B: DFIG) holding speed with its regulator until the trip.
#[test]
fn drivetrains_a_and_b_shutdown_with_the_scaled_input() {
    check("a-shutdown", "A");
    check("b-shutdown", "B");
}

/// The variable-speed torque law in region 2 with the analytic rotor in steady wind: the rotor
/// settles at the C_p optimum, λ = 8.10 and P = ½ρπR²V³·0.480 (Heier's C_p by hand), through the
/// DFIG (C) and the PMG (A) with their current loops. Started 3 % off the equilibrium speed; the
/// tolerance (0.05 % on both; measured 1e-5) covers what 60 s of the slow k·ω² convergence leaves.
#[test]
fn region_2_law_holds_the_optimal_tip_speed_ratio() {
    use windrive::physics::aero::{AIR_DENSITY, optimum};
    for (scene, kind, wind) in [("c-normal-spring", "dfig", 7.5), ("a-normal", "pmg", 7.2)] {
        let (lambda_opt, cp_max) = optimum(0.0);
        let preset = scene[..1].to_ascii_uppercase();
        let dt = windrive::physics::drivetrain::Drivetrain::preset(&preset).unwrap();
        let (radius, _) = windrive::physics::rotor::preset_rotor(&dt, &preset);
        let ratio = (lambda_opt * wind / radius / dt.rated_rotor_speed * 0.97).to_string();
        let wind_text = wind.to_string();
        let overrides = [
            ("generator", "kind", kind),
            ("generator", "torque_control", "law"),
            ("rotor", "mode", "aero"),
            // the generators' k·ω² gain is built on the analytic C_p's optimum, the law checked here
            ("rotor", "aerodynamics", "analytic"),
            ("rotor", "pitch_control", "speed"),
            ("rotor", "turbulence", "none"),
            ("rotor", "wind_speed", wind_text.as_str()),
            ("torsional", "fidelity", "2"),
            ("torsional", "initial_speed_ratio", ratio.as_str()),
        ];
        let channels = [
            "torsional.rotor_speed".to_string(),
            "rotor.aerodynamic_power".to_string(),
        ];
        let c = common::run_scene(scene, &overrides, &channels, Some(60.0));
        let (w, p) = (c[1][c[1].len() - 1], c[2][c[2].len() - 1]);
        let lambda = w * radius / wind;
        let p_opt = 0.5 * AIR_DENSITY * std::f64::consts::PI * radius * radius * wind.powi(3) * cp_max;
        println!("{scene} {kind}: λ {lambda:.4} (optimum {lambda_opt:.4}), P {p:.0} W (optimum {p_opt:.0} W)");
        assert!((lambda / lambda_opt - 1.0).abs() < 5e-4, "{scene}: λ = {lambda}");
        assert!((p / p_opt - 1.0).abs() < 5e-4, "{scene}: P = {p}");
    }
}

#[test]
fn drivetrain_c_shutdown() {
    check("c-shutdown-spring", "C");
}

/// Normal operation, then the shutdown's HSS torque range against it (thesis: 5–6.5× for shafts).
#[test]
fn normal_operation_c_and_d() {
    for (scene, shutdown, preset) in [
        ("c-normal-spring", "c-shutdown-spring", "C"),
        ("d-normal-spring", "d-shutdown-spring", "D"),
    ] {
        let dt = windrive::physics::drivetrain::Drivetrain::preset(preset).unwrap();
        let (rated_power, rated_hss) = (dt.rated_power, dt.rated_generator_torque());
        let r = run(scene);
        let mean = |x: &[f64]| x.iter().sum::<f64>() / x.len() as f64;
        let torque = mean(&r.hss) / rated_hss;
        let power = mean(&r.power) / rated_power;
        assert!(
            (torque - 1.0).abs() < 0.04,
            "{scene}: mean HSS torque {torque} of rated"
        );
        assert!(
            (power - 1.0).abs() < 0.04,
            "{scene}: mean electrical power {power} of rated"
        );
        assert!(
            r.sun_planet.iter().chain(&r.gear_pinion).all(|&f| f > 0.0),
            "{scene}: mesh-force reversal"
        );
        let s = run(shutdown);
        let ratio = range(&s.hss) / range(&r.hss);
        println!(
            "{scene}: mean HSS torque {torque:.4}, power {power:.4} of rated; HSS torque range shutdown/normal {ratio:.2}"
        );
        assert!(ratio > 1.5, "{shutdown}: HSS range only {ratio}x normal");
    }
}
