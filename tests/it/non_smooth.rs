//! Chatter at the drivetrain's non-smooth places in drivetrain C's shutdown: the brake holding at
//! standstill, and the meshes' backlash under torque reversal (`windrive chart non-smooth` runs the
//! full grid; docs/SPEED-ACCURACY.md).

use crate::common;

use windrive::cosim::master::run_columns_with;
use windrive::cosim::{Algorithm, Options, Scene};

fn run(dir: &std::path::Path, overrides: &[(&str, &str)], channels: &[&str]) -> Vec<Vec<f64>> {
    let scene = Scene::open(dir).unwrap();
    let o: Vec<(String, String, String)> = overrides
        .iter()
        .map(|(k, v)| ("torsional".into(), k.to_string(), v.to_string()))
        .collect();
    run_columns_with(&scene, &o, channels, Options::new(Algorithm::GaussSeidel, 1e-3, 30.0))
        .unwrap()
        .columns
}

fn changes(x: &[f64], state: impl Fn(f64) -> i8) -> usize {
    x.windows(2).filter(|w| state(w[0]) != state(w[1])).count()
}

/// Once the HSS brake locks it stays locked, the generator exactly still (the implicit integrator
/// solves the stick exactly); with 100 µm backlash at the scene's 1 ms internal step Newmark's
/// undamped mesh modes (h·ω up to 7) rattle in the dead zone: the sun-planet contact changes thousands
/// of times in 30 000 communication points, against tens in the converged reference; a 0.25 ms internal
/// step or HHT-α (ρ∞ = 0.6) at 1 ms removes it (docs/speed-accuracy/non-smooth.csv has the counts).
#[test]
fn brake_holds_and_backlash_rattles_only_at_a_coarse_undamped_internal_step() {
    let (_guard, dir) = common::scene_copy("c-shutdown");
    let c = run(&dir, &[], &["torsional.brake_locked", "torsional.generator_speed"]);
    let first = c[1].iter().position(|l| *l > 0.5).expect("the brake locks");
    assert!(c[1][first..].iter().all(|l| *l > 0.5));
    assert!(c[2][first..].iter().all(|w| *w == 0.0));
    let sign = |f: f64| (f > 0.0) as i8 - (f < 0.0) as i8;
    let rattle = |extra: &[(&str, &str)]| {
        let mut o = vec![("mesh_backlash", "1e-4")];
        o.extend_from_slice(extra);
        changes(&run(&dir, &o, &["torsional.mesh_force_sun_planet_1"])[1], sign)
    };
    let newmark = rattle(&[]);
    let fine = rattle(&[("max_internal_step", "0.00025")]);
    let hht = rattle(&[("integrator", "hht"), ("spectral_radius", "0.6")]);
    assert!(newmark > 3000, "{newmark}");
    assert!(fine < 150 && hht < 150, "{fine} {hht}");
}

/// The torsional FMU says so at initialisation when backlash meets Newmark at an internal step far above
/// the mesh modes (C at 1 ms), with the remedies; not at 0.25 ms, not with HHT-alpha (rho_inf 0.6), not
/// for D at 1 ms.
#[test]
fn backlash_with_a_coarse_undamped_step_is_warned_about() {
    use windrive::fmi2::fmu::slave::Slave;
    use windrive::models::torsional::vr;
    use windrive::slaves::torsional::TorsionalSlave;
    // hht at its default spectral_radius 1 is Newmark: the HHT-alpha case sets 0.6
    let warnings = |preset: &str, integrator: &str, step: f64| {
        let mut log = common::Recorder::default();
        let mut s = TorsionalSlave::instantiate(None);
        s.set_string(vr::PRESET, preset, &mut log).unwrap();
        s.set_string(vr::INTEGRATOR, integrator, &mut log).unwrap();
        s.set_real(vr::MESH_BACKLASH, 1e-4, &mut log).unwrap();
        s.set_real(vr::MAX_INTERNAL_STEP, step, &mut log).unwrap();
        if integrator == "hht" {
            s.set_real(vr::SPECTRAL_RADIUS, 0.6, &mut log).unwrap();
        }
        s.initialize(0.0, &mut log).unwrap();
        log.0
    };
    let w = warnings("C", "implicit", 1e-3);
    assert!(
        w.len() == 1 && w[0].contains("rattle") && w[0].contains("integrator = hht"),
        "{w:?}"
    );
    assert!(warnings("C", "implicit", 2.5e-4).is_empty());
    assert!(warnings("C", "hht", 1e-3).is_empty());
    assert!(warnings("D", "implicit", 1e-3).is_empty());
}
