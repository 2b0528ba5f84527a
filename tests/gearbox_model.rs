//! The 6-DOF gearbox against independent answers: the torsional model's modes and static torques,
//! the classical modal structure of a planetary stage, load sharing and face load under errors,
//! and the rotating-frame terms on a spinning carrier.

use windrive::physics::drivetrain::preset_d;
use windrive::physics::gearbox::description::{Description, PRESETS};
use windrive::physics::gearbox::modal::{Family, modes};
use windrive::physics::gearbox::model::{Gearbox, INPUT_GENERATOR_TORQUE, INPUT_ROTOR_TORQUE, SPIN};
use windrive::physics::gearbox::statics::equilibrium;
use windrive::physics::modes::{Boundary, linearised, modal_analysis};
use windrive::physics::torsional::{Fidelity, ModelOptions, TorsionalModel};
use windrive::solver::system::SecondOrderSystem;

fn grc() -> Gearbox {
    Gearbox::new(&Description::load("grc750").unwrap()).unwrap()
}

#[test]
fn every_preset_builds() {
    for (name, _) in PRESETS {
        let d = Description::load(name).unwrap_or_else(|e| panic!("{e}"));
        let g = Gearbox::new(&d).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(g.dofs() > 0);
    }
}

#[test]
fn grc_kinematics_are_the_gear_ratio_and_blind_to_the_elements() {
    let g = grc();
    assert!((g.gear_ratio - 81.491).abs() < 1e-3, "{}", g.gear_ratio);
    let r = g.rigid.clone().expect("the GRC chain is free");
    let lin = g.engaged_linearisation();
    let kr = &lin.stiffness * nalgebra::DVector::from_vec(r.clone());
    let scale = lin.stiffness.amax();
    assert!(kr.amax() < 1e-9 * scale, "K·r = {} (K ~ {scale})", kr.amax());
}

/// The preset with every bearing and shaft 1000× stiffer in translation and tilt: the supports the
/// torsional model takes as rigid.
fn with_rigid_supports(mut d: Description) -> Description {
    use windrive::physics::gearbox::description::{Body, Stage};
    let f = 1000.0;
    let scale = |b: &mut Body| {
        for br in &mut b.bearings {
            br.radial *= f;
            br.axial *= f;
            br.tilting *= f;
        }
        if let Some(s) = &mut b.support {
            s.radial *= f;
            s.axial *= f;
            s.tilting *= f;
        }
        if let Some(s) = &mut b.shaft {
            s.radial *= f;
            s.tilting *= f;
            s.axial *= f;
        }
    };
    d.rotor.iter_mut().chain(d.generator.iter_mut()).for_each(scale);
    for st in &mut d.stages {
        match st {
            Stage::Planetary(p) => [&mut p.carrier, &mut p.planet, &mut p.sun].into_iter().for_each(scale),
            Stage::Parallel(p) => [&mut p.gear, &mut p.pinion].into_iter().for_each(scale),
        }
    }
    d
}

fn torsional_modes(g: &Gearbox) -> Vec<f64> {
    modes(g)
        .iter()
        .filter(|m| m.torsional_projection > 0.5)
        .map(|m| m.frequency_hz)
        .collect()
}

/// The first torsional mode (rotor against generator through the LSS) is the torsional model's
/// within 2 % once the supports are as rigid as that model takes them; the preset's bearing
/// compliance (mostly the planet bearings, in series with the planetary torque path) lowers it by
/// under 6 %. Higher modes differ more: the planets' orbit adds 45 kg·m² to the carrier, which the
/// torsional model leaves out (docs/GEARBOX.md).
#[test]
fn grc_torsional_modes_agree_with_the_torsional_model() {
    let g = Gearbox::new(&with_rigid_supports(Description::load("grc750").unwrap())).unwrap();
    let ours = torsional_modes(&g);
    let flexible = torsional_modes(&grc());
    let model = TorsionalModel::new(&preset_d(), Fidelity::Full, &ModelOptions::default()).unwrap();
    let (lin, keep) = linearised(&model, Boundary::Disconnected, 0.0);
    let names: Vec<String> = (0..keep.len()).map(|i| i.to_string()).collect();
    let reference = vec![1.0; model.dofs()];
    let theirs = modal_analysis(&lin, &keep, &names, &reference).frequencies_hz;
    eprintln!("6-DOF torsional-projection modes: {ours:?}\ntorsional: {theirs:?}");
    // the lowest torsional mode (rotor against the generator through the LSS) within 2 %
    let first = |v: &[f64]| v.iter().copied().find(|&f| f > 0.5).unwrap();
    let (a, b) = (first(&ours), first(&theirs));
    assert!((a / b - 1.0).abs() < 0.02, "{a} vs {b}");
    let c = first(&flexible);
    assert!(c < a && c / b > 0.94, "with the preset's bearings {c} vs {b}");
}

#[test]
fn rated_torque_splits_through_the_stages_as_the_torsional_statics() {
    let d = Description::load("grc750").unwrap();
    let mut d = d;
    d.model.gravity = 0.0;
    let g = Gearbox::new(&d).unwrap();
    let t = g.rated_rotor_torque.unwrap();
    let mut u = vec![0.0; 3];
    u[INPUT_ROTOR_TORQUE] = t;
    u[INPUT_GENERATOR_TORQUE] = t / g.gear_ratio;
    let (q, v) = equilibrium(&g, &u, 0.0).unwrap();
    let loads = g.loads(&q, &v);
    let expected = [
        t,
        t / 5.714285714285714,
        t / (5.714285714285714 * 82.0 / 23.0),
        t / g.gear_ratio,
    ];
    eprintln!("shafts {:?} expected {expected:?}", loads.shafts);
    for (s, e) in loads.shafts.iter().zip(expected) {
        assert!((s / e - 1.0).abs() < 0.01, "{s} vs {e}");
    }
    let k = g.load_sharing(&loads, "").unwrap();
    assert!((k - 1.0).abs() < 0.01, "K_γ = {k}");
    let _ = SPIN;
}

fn stage_only(planets: usize) -> Description {
    let mut d = Description::load("planetary-spur").unwrap();
    if let windrive::physics::gearbox::description::Stage::Planetary(p) = &mut d.stages[0] {
        p.planets = planets;
    }
    d
}

/// Lin & Parker (1999): an equally spaced spur planetary stage's in-plane modes are rotational
/// (single), translational (double) or planet modes (multiplicity N − 3, central members still);
/// with C central members there are C + 3 rotational, 2(C + 3) translational and 3(N − 3) planet
/// modes. The out-of-plane (axial/tilting) modes separate from them for spur gears.
#[test]
fn a_spur_planetary_stage_has_the_classical_modal_structure() {
    for planets in [3, 4, 5] {
        let g = Gearbox::new(&stage_only(planets)).unwrap();
        let all = modes(&g);
        let in_plane: Vec<_> = all.iter().filter(|m| m.family != Family::AxialTilting).collect();
        let central = 3; // carrier, sun, elastically mounted ring
        assert_eq!(in_plane.len(), 3 * (central + planets), "{planets} planets");
        let multiplicity = |f: f64| {
            in_plane
                .iter()
                .filter(|m| (m.frequency_hz - f).abs() <= 1e-6 * f.max(1.0))
                .count()
        };
        let count = |family: Family| in_plane.iter().filter(|m| m.family == family).count();
        for m in &in_plane {
            let k = multiplicity(m.frequency_hz);
            match m.family {
                Family::Rotational | Family::Rigid => assert_eq!(k, 1, "{planets} planets: {m:?}"),
                Family::Translational => assert_eq!(k, 2, "{planets} planets: {m:?}"),
                Family::Planet => assert_eq!(k, planets - 3, "{planets} planets: {m:?}"),
                Family::AxialTilting => unreachable!(),
            }
        }
        assert_eq!(
            count(Family::Rotational) + count(Family::Rigid),
            central + 3,
            "{planets} planets"
        );
        assert_eq!(count(Family::Translational), 2 * (central + 3), "{planets} planets");
        assert_eq!(count(Family::Planet), 3 * (planets - 3), "{planets} planets");
        // out of plane: nothing couples to the spins
        for m in all.iter().filter(|m| m.family == Family::AxialTilting) {
            assert!(m.torsional_projection < 1e-9, "{m:?}");
        }
    }
}
