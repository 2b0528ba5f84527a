//! The torsional model against independent answers: static torque split by the gear ratios, energy
//! conservation of the undamped implicit integrator, brake stiction without creep, backlash and
//! time-varying mesh stiffness at the physical mesh frequency. Runs the FMU's Rust face directly.

use windrive::fmi2::fmu::slave::{NoLog as Quiet, Slave};
use windrive::models::torsional::vr;
use windrive::physics::drivetrain::{Drivetrain, PRESETS, Stage};
use windrive::slaves::torsional::TorsionalSlave;

fn slave(preset: &str, fidelity: &str, reals: &[(u32, f64)]) -> TorsionalSlave {
    let mut s = TorsionalSlave::instantiate(None);
    s.set_string(vr::PRESET, preset, &mut Quiet).unwrap();
    s.set_string(vr::FIDELITY, fidelity, &mut Quiet).unwrap();
    for &(r, v) in reals {
        s.set_real(r, v, &mut Quiet).unwrap();
    }
    s.initialize(0.0, &mut Quiet).unwrap();
    s
}

fn run(s: &mut TorsionalSlave, t0: f64, steps: usize, h: f64) {
    for i in 0..steps {
        s.do_step(t0 + i as f64 * h, h, &mut Quiet).unwrap();
    }
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Every preset, the paper's P included: its second stage's 25/45/116 teeth are profile-shifted
/// (25 + 2·45 ≠ 116), where the ring mesh's carrier arm is r_ring − r_p, not r_s + r_p, and a rotating
/// planet carries the same force on both flanks only if both meshes follow the tooth counts.
#[test]
fn static_torque_split_follows_the_gear_ratios() {
    for preset in PRESETS.iter().copied().chain(["P"]) {
        let dt = Drivetrain::preset(preset).unwrap();
        let torque = dt.rated_rotor_torque();
        for fidelity in ["2", "5", "full"] {
            let mut s = slave(preset, fidelity, &[(vr::INITIAL_ROTOR_TORQUE, torque)]);
            s.set_real(vr::ROTOR_TORQUE, torque, &mut Quiet).unwrap();
            s.set_real(vr::GENERATOR_TORQUE, torque / dt.gear_ratio(), &mut Quiet)
                .unwrap();
            run(&mut s, 0.0, 200, 1e-3);
            // shaft i carries the rotor torque divided by the ratio of the stages before it
            let mut ratio = 1.0;
            let shafts = [vr::LSS_TORQUE, vr::IS1_TORQUE, vr::IS2_TORQUE, vr::HSS_TORQUE];
            let used: Vec<u32> = if dt.stages.len() == 2 {
                vec![shafts[0], shafts[1], shafts[3]]
            } else {
                shafts.to_vec()
            };
            for (i, r) in used.iter().enumerate() {
                let t = s.get_real(*r).unwrap();
                // 1e-9: the equilibrium is exact; what remains is round-off in angles of ~1e3 rad
                assert!(
                    rel(t, torque / ratio) < 1e-9,
                    "{preset} {fidelity} shaft {i}: {t} vs {}",
                    torque / ratio
                );
                if i < dt.stages.len() {
                    ratio *= dt.stages[i].ratio();
                }
            }
            // every planet carries 1/N of the carrier torque on both of its meshes:
            // T = N F ((r_s + r_p) + (r_ring − r_p)), so F = T / (N (r_s + r_ring))
            let planet_meshes = [
                (vr::MESH_FORCE_RING_PLANET_1, vr::MESH_FORCE_SUN_PLANET_1),
                (vr::MESH_FORCE_RING_PLANET2_1, vr::MESH_FORCE_SUN_PLANET2_1),
            ];
            let mut carrier_torque = torque;
            for (stage, meshes) in dt.stages.iter().zip(planet_meshes) {
                let Stage::Planetary(p) = stage else { break };
                let arms = p.geometry.base_radius(p.z_sun) + p.geometry.base_radius(p.z_ring);
                let expected = carrier_torque / (p.planets as f64 * arms);
                for k in 0..3 {
                    for first in [meshes.0, meshes.1] {
                        let f = s.get_real(first + k).unwrap();
                        assert!(
                            rel(f, expected) < 1e-9,
                            "{preset} {fidelity} stage {} planet {k}: {f} vs {expected}",
                            p.z_sun
                        );
                    }
                }
                carrier_torque /= stage.ratio();
            }
        }
    }
}

#[test]
fn undamped_free_vibration_conserves_energy_to_1e_9() {
    // pre-twisted by rated torque, released with no load: the trapezoidal rule conserves the
    // quadratic energy of a linear undamped system exactly, so only round-off remains
    let dt = Drivetrain::preset("D").unwrap();
    let mut s = slave(
        "D",
        "full",
        &[
            (vr::DAMPING_SCALE, 0.0),
            (vr::INITIAL_ROTOR_TORQUE, dt.rated_rotor_torque()),
            (vr::INITIAL_SPEED_RATIO, 0.0),
        ],
    );
    let e0 = s.get_real(vr::STORED_ENERGY).unwrap();
    assert!(e0 > 0.0);
    let mut worst: f64 = 0.0;
    for i in 0..10_000 {
        s.do_step(i as f64 * 1e-3, 1e-3, &mut Quiet).unwrap();
        worst = worst.max(rel(s.get_real(vr::STORED_ENERGY).unwrap(), e0));
    }
    assert!(worst < 1e-9, "energy drift {worst:e}");
}

#[test]
fn the_brake_stops_the_drivetrain_and_holds_it_without_creep() {
    let dt = Drivetrain::preset("D").unwrap();
    let mut s = slave("D", "full", &[(vr::INITIAL_SPEED_RATIO, 0.05)]);
    s.set_real(vr::BRAKE_COMMAND, 1.0, &mut Quiet).unwrap();
    let mut t = 0.0;
    let h = 1e-3;
    let mut locked_at = None;
    for _ in 0..60_000 {
        s.do_step(t, h, &mut Quiet).unwrap();
        t += h;
        if locked_at.is_none() && s.get_boolean(vr::BRAKE_LOCKED).unwrap() {
            locked_at = Some(t);
        }
    }
    let locked_at = locked_at.expect("the brake locks");
    assert!(locked_at < 30.0, "locked at {locked_at}");
    assert!(s.get_boolean(vr::BRAKE_LOCKED).unwrap());
    // held: the generator angle does not move by a single bit over the next 10 s
    let angle = s.get_real(vr::ANGLE_GENERATOR).unwrap();
    for _ in 0..10_000 {
        s.do_step(t, h, &mut Quiet).unwrap();
        t += h;
        assert_eq!(s.get_real(vr::SPEED_GENERATOR).unwrap(), 0.0);
    }
    assert_eq!(s.get_real(vr::ANGLE_GENERATOR).unwrap().to_bits(), angle.to_bits());
    // the rotor swings on the LSS against the held HSS about zero speed (D's published shaft damping
    // gives this mode a damping ratio of ~1e-7, so it rings on, but it cannot drift)
    let mut mean = 0.0;
    for _ in 0..10_000 {
        s.do_step(t, h, &mut Quiet).unwrap();
        t += h;
        mean += s.get_real(vr::ROTOR_SPEED).unwrap() / 10_000.0;
    }
    assert!(mean.abs() < 1e-3 * dt.rated_rotor_speed, "mean rotor speed {mean}");
    // the holding torque stays within the static capacity
    let hold = s.get_real(vr::BRAKE_TORQUE).unwrap().abs();
    assert!(hold <= 1.2 * 1.5 * dt.rated_generator_torque() * (1.0 + 1e-12));
}

#[test]
fn a_locked_brake_lets_go_when_the_torque_exceeds_static_friction() {
    let dt = Drivetrain::preset("D").unwrap();
    let mut s = slave("D", "5", &[(vr::INITIAL_SPEED_RATIO, 0.0)]);
    s.set_real(vr::BRAKE_COMMAND, 1.0, &mut Quiet).unwrap();
    run(&mut s, 0.0, 100, 1e-3);
    assert!(s.get_boolean(vr::BRAKE_LOCKED).unwrap());
    // an HSS torque well beyond 1.2 x 1.5 x rated (static capacity) tears it loose
    s.set_real(vr::GENERATOR_TORQUE, -3.0 * dt.rated_generator_torque(), &mut Quiet)
        .unwrap();
    run(&mut s, 0.1, 100, 1e-3);
    assert!(!s.get_boolean(vr::BRAKE_LOCKED).unwrap());
    assert!(s.get_real(vr::GENERATOR_SPEED).unwrap() > 0.0);
}

#[test]
fn backlash_gives_a_dead_zone_and_flank_reversal() {
    let dt = Drivetrain::preset("D").unwrap();
    let backlash = 2e-4;
    let mut s = slave(
        "D",
        "full",
        &[(vr::MESH_BACKLASH, backlash), (vr::INITIAL_SPEED_RATIO, 1.0)],
    );
    let h = 1e-3;
    let (mut positive, mut negative, mut zero) = (false, false, false);
    for i in 0..4000 {
        let t = i as f64 * h;
        // a torque that reverses: the HSS mesh must open, cross its gap and load the other flank
        let torque = 0.5 * dt.rated_rotor_torque() * (std::f64::consts::TAU * 0.5 * t).sin();
        s.set_real(vr::ROTOR_TORQUE, torque, &mut Quiet).unwrap();
        s.set_real(vr::GENERATOR_TORQUE, torque / dt.gear_ratio(), &mut Quiet)
            .unwrap();
        s.do_step(t, h, &mut Quiet).unwrap();
        let f = s.get_real(vr::MESH_FORCE_GEAR_PINION_2).unwrap();
        positive |= f > 100.0;
        negative |= f < -100.0;
        zero |= f == 0.0;
    }
    assert!(
        positive && negative && zero,
        "positive {positive} negative {negative} in-gap {zero}"
    );
}

fn hss_mesh_force(variation: f64) -> (Vec<f64>, f64, f64) {
    let dt = Drivetrain::preset("D").unwrap();
    let torque = dt.rated_rotor_torque();
    let mut s = slave(
        "D",
        "full",
        &[
            (vr::MESH_STIFFNESS_VARIATION, variation),
            (vr::INITIAL_ROTOR_TORQUE, torque),
            (vr::MAX_INTERNAL_STEP, 2e-5),
        ],
    );
    s.set_real(vr::ROTOR_TORQUE, torque, &mut Quiet).unwrap();
    s.set_real(vr::GENERATOR_TORQUE, torque / dt.gear_ratio(), &mut Quiet)
        .unwrap();
    let h = 2e-5;
    let x = (0..5000)
        .map(|i| {
            s.do_step(i as f64 * h, h, &mut Quiet).unwrap();
            s.get_real(vr::MESH_FORCE_GEAR_PINION_2).unwrap()
        })
        .collect();
    // HSS mesh: z_pinion x pinion speed = 22 x 18.6 rpm x 81.49 / 60 = 556 Hz
    (
        x,
        h,
        22.0 * dt.rated_rotor_speed * dt.gear_ratio() / std::f64::consts::TAU,
    )
}

#[test]
fn time_varying_mesh_stiffness_excites_the_physical_mesh_frequency() {
    let (x, h, f_mesh) = hss_mesh_force(0.3);
    let tail = &x[1000..];
    // between the 418 Hz and 869 Hz natural modes, the strongest line is the mesh frequency
    let f = windrive_dominant(tail, h, 450.0, 700.0);
    assert!(rel(f, f_mesh) < 0.01, "dominant {f} Hz vs mesh {f_mesh} Hz");
    // and it is the stiffness variation that puts it there
    let (steady, _, _) = hss_mesh_force(0.0);
    let ratio = power(tail, h, f_mesh) / power(&steady[1000..], h, f_mesh).max(1e-300);
    assert!(
        ratio > 1e4,
        "mesh-frequency power grows only {ratio}x with stiffness variation"
    );
}

fn power(x: &[f64], dt: f64, f: f64) -> f64 {
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    let (mut re, mut im) = (0.0, 0.0);
    for (i, v) in x.iter().enumerate() {
        let (s, c) = (std::f64::consts::TAU * f * dt * i as f64).sin_cos();
        re += (v - mean) * c;
        im += (v - mean) * s;
    }
    re * re + im * im
}

/// Largest spectral peak by a direct DFT scan on a 1 Hz grid (independent of the library's helper).
fn windrive_dominant(x: &[f64], dt: f64, lo: f64, hi: f64) -> f64 {
    let mut best = (0.0, lo);
    let mut f = lo;
    while f < hi {
        let p = power(x, dt, f);
        if p > best.0 {
            best = (p, f);
        }
        f += 1.0;
    }
    best.1
}

#[test]
fn rk4_and_implicit_agree_where_both_are_accurate() {
    let dt = Drivetrain::preset("D").unwrap();
    let limit = slave("D", "full", &[]).built().unwrap().rk4_step_limit;
    let mut a = slave("D", "full", &[(vr::MAX_INTERNAL_STEP, 1e-5)]);
    let mut b = slave("D", "full", &[(vr::MAX_INTERNAL_STEP, 0.5 * limit)]);
    b.set_string(vr::INTEGRATOR, "rk4", &mut Quiet).unwrap();
    b.initialize(0.0, &mut Quiet).unwrap();
    for s in [&mut a, &mut b] {
        s.set_real(vr::ROTOR_TORQUE, dt.rated_rotor_torque(), &mut Quiet)
            .unwrap();
        s.set_real(vr::GENERATOR_TORQUE, dt.rated_generator_torque(), &mut Quiet)
            .unwrap();
        run(s, 0.0, 1000, 1e-3);
    }
    let (ta, tb) = (a.get_real(vr::HSS_TORQUE).unwrap(), b.get_real(vr::HSS_TORQUE).unwrap());
    // both converge to the same solution: 1e-4 of rated covers their O(h²) and O(h⁴) errors
    assert!((ta - tb).abs() < 1e-4 * dt.rated_generator_torque(), "{ta} vs {tb}");
}

/// The FMU's `integrator` = hht and generalized-alpha with `spectral_radius`: at a 1 ms step they
/// damp the 300–870 Hz mesh ringing (h·ω ≈ 2–5) but leave the drivetrain's 2.5 Hz response, so after
/// 1 s of a rated-torque step they agree with Newmark on the HSS torque to 1 % of rated (Newmark's
/// undamped mesh ringing is the difference), and the step-to-step roughness of their HSS torque
/// (Σ|second difference|, what the mesh ringing leaves at 1 ms sampling) is lower; a spectral radius
/// outside a method's range is refused naming the parameter.
#[test]
fn numerically_damped_integrators_through_the_fmu_face() {
    let dt = Drivetrain::preset("D").unwrap();
    let step = |integrator: &str, rho: f64| {
        let mut s = TorsionalSlave::instantiate(None);
        s.set_string(vr::INTEGRATOR, integrator, &mut Quiet).unwrap();
        s.set_real(vr::SPECTRAL_RADIUS, rho, &mut Quiet).unwrap();
        s.initialize(0.0, &mut Quiet).unwrap();
        s.set_real(vr::ROTOR_TORQUE, dt.rated_rotor_torque(), &mut Quiet)
            .unwrap();
        s.set_real(vr::GENERATOR_TORQUE, dt.rated_generator_torque(), &mut Quiet)
            .unwrap();
        let mut hss = Vec::new();
        for i in 0..1000 {
            s.do_step(i as f64 * 1e-3, 1e-3, &mut Quiet).unwrap();
            hss.push(s.get_real(vr::HSS_TORQUE).unwrap());
        }
        let roughness: f64 = hss.windows(3).map(|w| (w[0] - 2.0 * w[1] + w[2]).abs()).sum();
        (hss[hss.len() - 1], roughness)
    };
    let (newmark, rough_newmark) = step("implicit", 1.0);
    for (name, rho) in [("hht", 0.6), ("generalized-alpha", 0.3)] {
        let (torque, roughness) = step(name, rho);
        assert!(
            (torque - newmark).abs() < 0.01 * dt.rated_generator_torque(),
            "{name}: {torque} vs {newmark}"
        );
        println!("{name}: roughness {roughness:.4e} vs Newmark {rough_newmark:.4e}");
        assert!(
            roughness < 0.5 * rough_newmark,
            "{name}: roughness {roughness} vs {rough_newmark}"
        );
    }
    let mut s = TorsionalSlave::instantiate(None);
    s.set_string(vr::INTEGRATOR, "hht", &mut Quiet).unwrap();
    s.set_real(vr::SPECTRAL_RADIUS, 0.3, &mut Quiet).unwrap();
    let e = s.initialize(0.0, &mut Quiet).unwrap_err();
    assert!(e.to_string().contains("spectral_radius"), "{e}");
}

/// `lumping` = thesis leaves the planets' spin inertia out of the 5-mass model's first stage only.
#[test]
fn thesis_lumping_through_the_fmu_face() {
    let mass = |lumping: &str| {
        let mut s = TorsionalSlave::instantiate(None);
        s.set_string(vr::FIDELITY, "5", &mut Quiet).unwrap();
        s.set_string(vr::LUMPING, lumping, &mut Quiet).unwrap();
        s.built().unwrap().model.mass.clone()
    };
    let (physical, thesis) = (mass("physical"), mass("thesis"));
    assert!(thesis[1] < physical[1], "{thesis:?} vs {physical:?}");
    for d in [0, 2, 3, 4] {
        assert_eq!(thesis[d], physical[d]);
    }
    let mut s = TorsionalSlave::instantiate(None);
    s.set_string(vr::LUMPING, "lumpy", &mut Quiet).unwrap();
    let e = s.initialize(0.0, &mut Quiet).unwrap_err();
    assert!(e.to_string().contains("lumping"), "{e}");
}
