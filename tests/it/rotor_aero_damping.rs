//! Issue 13 §1: aerodynamic damping of the parked, feathered BEM rotor held by the HSS brake
//! (drivetrain C, 16 m/s, the wind of scenes/c-shutdown), measured through the co-simulation master
//! and checked against the linearised hand calculation of docs/AERODYNAMICS.md:
//!
//! - blade element at standstill, no induction: φ = 90° − Ωr/V, so dT'/dΩ = −½ρVc(C_lα + C_d)·r and
//!   c_aero = −∂Q/∂Ω = ½ρVB∫c(C_lα + C_d)r² dr, with C_lα the slope of the polar's table segment at
//!   α₀ = −twist (pitch 90°), evaluated on the same stations and trapezoidal rule as the BEM;
//! - the held-rotor mode of the full 11-DOF drivetrain with the HSS locked (`windrive modes --preset C
//!   --generator locked`, 0.813 Hz): its M-orthonormal shape x gives the modal inertia J = 1/x_rotor²
//!   on which the rotor's damping acts, and a 1-DOF mode ζ = c_aero/(2Jω), δ = 2πζ/√(1 − ζ²).
//!
//! The measurement: the brake holds a standing drivetrain from t = 0 (structural damping switched off
//! so only the aerodynamics damp); the wind load steps onto the untwisted shafts and the rotor rocks
//! about the twisted equilibrium. δ = ln of the ratio of successive rotor-speed maxima, one period
//! apart, averaged over the first three periods.
//!
//! Tolerance 10 %: the BEM keeps the small swirl of the standing rotor's wake (its own ∂Q/∂Ω is 4 %
//! below the hand value), the rocking sweeps α over ±1° at the tip, across table points of the
//! linearly interpolated polars (the hand slope is the one segment's), and the 1-DOF projection leaves
//! out the small coupling of the other modes; each is a few per cent. The analytic C_p, which has no
//! blade, gives the held rotor no damping: its decrement must stay below a tenth of the hand value.

use crate::common;

use windrive::cosim::{Algorithm, Master, Options, Record, Scene, System};
use windrive::linear::modes::{Boundary, eigenpairs_of, linearised};
use windrive::physics::aero::AIR_DENSITY;
use windrive::physics::bem::BemRotor;
use windrive::physics::blade::Blade;
use windrive::physics::drivetrain::Drivetrain;
use windrive::physics::rotor::preset_rotor;
use windrive::physics::torsional::{Fidelity, ModelOptions, TorsionalModel};

const WIND: f64 = 16.0;
/// The rotor's feathered pitch: its `pitch_max` default (90° to 7 digits), rad.
fn feather() -> f64 {
    windrive::slaves::rotor::Params::default().pitch_max
}

fn blade_c() -> Blade {
    let dt = Drivetrain::preset("C").unwrap();
    let (radius, _) = preset_rotor(&dt, "C");
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fmus/rotor/resources/blades/windpact-1.5mw");
    Blade::load(&dir).unwrap().scaled(radius)
}

/// c_aero = ½ρVB∫c(C_lα + C_d)r² dr over the BEM's stations, zero at hub and tip (trapezoidal).
fn hand_damping(blade: &Blade) -> f64 {
    let mut points = vec![(blade.hub_radius, 0.0)];
    for s in blade.stations() {
        let polar = &blade.polars[s.airfoil];
        let alpha0 = standstill_alpha(s.twist);
        let (_, cd) = polar.at(alpha0);
        points.push((
            s.radius,
            s.chord * (polar.lift_slope(alpha0) + cd) * s.radius * s.radius,
        ));
    }
    points.push((blade.tip_radius(), 0.0));
    let integral: f64 = points
        .windows(2)
        .map(|w| 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0))
        .sum();
    0.5 * AIR_DENSITY * WIND * f64::from(blade.blades) * integral
}

/// Angle of attack at standstill and feathered: φ − twist − pitch with φ = 90°, pitch 90° (= −twist).
fn standstill_alpha(twist: f64) -> f64 {
    std::f64::consts::FRAC_PI_2 - twist - feather()
}

/// (ω rad/s, modal inertia J = 1/x_rotor² kg·m²) of drivetrain C's lowest HSS-locked mode.
fn held_mode() -> (f64, f64) {
    let dt = Drivetrain::preset("C").unwrap();
    let model = TorsionalModel::new(&dt, Fidelity::Full, &ModelOptions::default()).unwrap();
    let (lin, keep) = linearised(&model, Boundary::HssLocked, dt.k_generator);
    let (lambda, x) = eigenpairs_of(&lin.mass, &lin.stiffness, &keep);
    let m = (0..lambda.len())
        .min_by(|&a, &b| lambda[a].total_cmp(&lambda[b]))
        .unwrap();
    let rotor = keep.iter().position(|&d| d == 0).unwrap();
    (lambda[m].sqrt(), 1.0 / x[(rotor, m)].powi(2))
}

/// Rotor speed of scene c-shutdown with the overrides, through the master (Gauss–Seidel, 1 ms).
fn rotor_speed(overrides: &[(&str, &str, &str)], stop: f64) -> (Vec<f64>, Vec<f64>) {
    let (_guard, dir) = common::scene_copy("c-shutdown-spring");
    let scene = Scene::open(&dir).unwrap();
    let overrides: Vec<(String, String, String)> = overrides
        .iter()
        .map(|(c, v, x)| (c.to_string(), v.to_string(), x.to_string()))
        .collect();
    let channels = vec![
        "torsional.rotor_speed".to_string(),
        "torsional.brake_locked".to_string(),
    ];
    let mut system = System::build(&scene, &overrides, &Record::Only(channels)).unwrap();
    system.initialize(Some(stop)).unwrap();
    let (mut t, mut w, mut locked) = (Vec::new(), Vec::new(), Vec::new());
    let mut master = Master::new(&mut system, Options::new(Algorithm::GaussSeidel, 1e-3, stop)).unwrap();
    master
        .run(|time, sys| {
            windrive::cosim::master::read_recorded(sys, time)?;
            let (_, u, i) = sys.recorded[0];
            let (_, ul, il) = sys.recorded[1];
            t.push(time);
            w.push(sys.units[u].values[i]);
            locked.push(sys.units[ul].values[il] > 0.5);
            Ok(())
        })
        .unwrap();
    // the brake catches the standing disk within the first steps and never lets go
    let lock = locked.iter().position(|&l| l).expect("the brake locks");
    let slip: Vec<(f64, f64)> = (lock..t.len())
        .filter(|&k| !locked[k])
        .map(|k| (t[k], w[k]))
        .take(5)
        .collect();
    assert!(
        t[lock] < 0.05 && slip.is_empty(),
        "lock at {} s, slipping at {slip:?}",
        t[lock]
    );
    (t[lock..].to_vec(), w[lock..].to_vec())
}

/// Local maxima of `w` (parabola through the three samples around each).
fn maxima(t: &[f64], w: &[f64]) -> Vec<(f64, f64)> {
    (1..w.len() - 1)
        .filter(|&k| w[k] > w[k - 1] && w[k] >= w[k + 1])
        .map(|k| {
            let (a, b, c) = (w[k - 1], w[k], w[k + 1]);
            let d = 0.5 * (a - c) / (a - 2.0 * b + c);
            (t[k] + d * (t[k + 1] - t[k]), b - 0.25 * (a - c) * d)
        })
        .collect()
}

/// Parked, feathered, held from t = 0 in steady 16 m/s: the aerodynamics as the only damping.
fn parked_decay(aerodynamics: &str) -> (Vec<f64>, Vec<f64>) {
    let pitch = feather().to_string(); // parked at feather from the start
    rotor_speed(
        &[
            ("rotor", "aerodynamics", aerodynamics),
            ("rotor", "turbulence", "none"),
            ("rotor", "wind_speed", "16"),
            ("rotor", "initial_pitch", &pitch),
            ("rotor", "shutdown_time", "0"),
            ("rotor", "trip_delay", "0"),
            ("rotor", "brake_delay", "0"),
            ("rotor", "brake_ramp_time", "0"),
            ("torsional", "initial_speed_ratio", "0"),
            ("torsional", "initial_rotor_torque", "0"),
            ("torsional", "damping_scale", "0"),
            // the generator spring's field stands still too, so it puts no torque on the held HSS
            // (a spring started disconnected keeps pulling at synchronous speed until its first trip)
            ("generator", "initial_torque", "0"),
            ("generator", "synchronous_speed", "1e-9"),
        ],
        6.0,
    )
}

/// Mean log decrement of the positive peaks over the first `n` periods (peaks above 1 % of the first,
/// so the rounding floor is never measured).
fn decrement(t: &[f64], w: &[f64], n: usize) -> (f64, f64) {
    let peaks: Vec<(f64, f64)> = maxima(t, w).into_iter().filter(|p| p.1 > 0.0).collect();
    assert!(peaks.len() > n, "only {} peaks", peaks.len());
    let first = peaks[0].1;
    let used: Vec<_> = peaks.iter().take(n + 1).filter(|p| p.1 > 0.01 * first).collect();
    let k = used.len() - 1;
    assert!(k >= 2, "the rocking died within {k} periods: {peaks:?}");
    let delta = (used[0].1 / used[k].1).ln() / k as f64;
    let period = (used[k].0 - used[0].0) / k as f64;
    (delta, period)
}

#[test]
fn held_feathered_rotor_rocking_decays_at_the_hand_calculated_rate() {
    let blade = blade_c();
    let c_hand = hand_damping(&blade);
    // the BEM's own slope at Ω = 0 (central difference; the torque is smooth through standstill)
    let bem = BemRotor::new(blade.clone(), AIR_DENSITY);
    let h = 1e-4;
    let c_bem = -(bem.torque_thrust(WIND, h, feather()).0 - bem.torque_thrust(WIND, -h, feather()).0) / (2.0 * h);
    let (omega, j) = held_mode();
    let zeta = c_hand / (2.0 * j * omega);
    let delta_hand = std::f64::consts::TAU * zeta / (1.0 - zeta * zeta).sqrt();
    let (t, w) = parked_decay("bem");
    let (delta, period) = decrement(&t, &w, 3);
    println!(
        "c_aero hand {c_hand:.4e} N·m·s/rad, BEM -dQ/dΩ {c_bem:.4e}; held mode {:.4} Hz, J {j:.4e} kg·m² \
         (rotor 6.03e6); ζ {zeta:.4}, δ hand {delta_hand:.4}; measured δ {delta:.4}, damped period {period:.4} s \
         (hand {:.4} s)",
        omega / std::f64::consts::TAU,
        std::f64::consts::TAU / (omega * (1.0 - zeta * zeta).sqrt())
    );
    assert!(
        (c_bem / c_hand - 1.0).abs() < 0.10,
        "BEM slope {c_bem} vs hand {c_hand}"
    );
    // with the BEM's own slope in the same 1-DOF formula only the amplitude (±1° of α at the tip) and
    // the modal coupling are left: 2 %
    let zeta_bem = c_bem / (2.0 * j * omega);
    let delta_bem = std::f64::consts::TAU * zeta_bem / (1.0 - zeta_bem * zeta_bem).sqrt();
    println!("δ from the BEM's own -dQ/dΩ: {delta_bem:.4}");
    assert!(
        (delta / delta_bem - 1.0).abs() < 0.02,
        "measured δ {delta} vs BEM-linear {delta_bem}"
    );
    assert!(
        (delta / delta_hand - 1.0).abs() < 0.10,
        "measured δ {delta} vs hand {delta_hand}"
    );

    // the analytic C_p has no standstill damping: the same release barely decays
    let (t, w) = parked_decay("analytic");
    let (delta_analytic, _) = decrement(&t, &w, 3);
    println!("analytic C_p: measured δ {delta_analytic:.4}");
    assert!(delta_analytic < 0.1 * delta_hand, "analytic δ {delta_analytic}");
}

/// The shutdown scene itself (steady wind so the decay is not masked by turbulence; structural damping
/// as the preset has it): once the brake holds and the blades reach feather the rocking decays, at a
/// decrement at least the aerodynamic hand value's (structure adds to it; the larger amplitude here
/// sweeps the polars' stall points too, so no upper bound is claimed) and within 5 s to under a tenth.
#[test]
fn shutdown_scene_rocking_decays_once_held_and_feathered() {
    let (omega, j) = held_mode();
    let c_hand = hand_damping(&blade_c());
    let zeta = c_hand / (2.0 * j * omega);
    let delta_hand = std::f64::consts::TAU * zeta / (1.0 - zeta * zeta).sqrt();
    let (_guard, dir) = common::scene_copy("c-shutdown-spring");
    let scene = Scene::open(&dir).unwrap();
    let overrides: Vec<(String, String, String)> =
        [("aerodynamics", "bem"), ("initial_pitch", "-1"), ("turbulence", "none")]
            .iter()
            .map(|(v, x)| ("rotor".to_string(), v.to_string(), x.to_string()))
            .collect();
    let channels = vec![
        "torsional.rotor_speed".to_string(),
        "torsional.brake_locked".to_string(),
        "rotor.pitch".to_string(),
    ];
    let mut system = System::build(&scene, &overrides, &Record::Only(channels)).unwrap();
    system.initialize(Some(30.0)).unwrap();
    let (mut t, mut w, mut locked, mut pitch) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut master = Master::new(&mut system, Options::new(Algorithm::GaussSeidel, 1e-3, 30.0)).unwrap();
    master
        .run(|time, sys| {
            windrive::cosim::master::read_recorded(sys, time)?;
            let v = |k: usize| {
                let (_, u, i) = sys.recorded[k];
                sys.units[u].values[i]
            };
            t.push(time);
            w.push(v(0));
            locked.push(v(1));
            pitch.push(v(2));
            Ok(())
        })
        .unwrap();
    let lock = locked.iter().position(|&l| l > 0.5).expect("the brake locks");
    let feathered = pitch
        .iter()
        .position(|&p| p >= feather() - 1e-9)
        .expect("the blades feather");
    let from = lock.max(feathered);
    let (t, w) = (&t[from..], &w[from..]);
    let (delta, _) = decrement(t, w, 3);
    let amplitude = |a: f64, b: f64| {
        t.iter()
            .zip(w)
            .filter(|(x, _)| **x >= a && **x < b)
            .fold(0.0f64, |m, (_, v)| m.max(v.abs()))
    };
    let (first, later) = (amplitude(t[0], t[0] + 1.3), amplitude(t[0] + 5.0, t[0] + 6.3));
    println!(
        "c-shutdown (steady 16 m/s): held and feathered from {:.2} s; δ {delta:.4} (aerodynamic hand value \
         {delta_hand:.4}); rotor-speed amplitude {first:.3e} -> {later:.3e} rad/s 5 s later",
        t[0]
    );
    assert!(delta > 0.9 * delta_hand, "δ {delta} below the aerodynamic {delta_hand}");
    assert!(later < 0.1 * first, "{first} -> {later}");
}
