//! The 6-DOF gearbox against independent answers: the torsional model's modes and static torques,
//! the classical modal structure of a planetary stage, load sharing and face load under errors,
//! and the rotating-frame terms on a spinning carrier.

use crate::common;
use windrive::linear::gearbox_modes::{Family, modes};
use windrive::linear::modes::{Boundary, linearised, modal_analysis};
use windrive::physics::drivetrain::preset_d;
use windrive::physics::gearbox::description::{BearingModel, Description, PRESETS};
use windrive::physics::gearbox::model::{Gearbox, INPUT_GENERATOR_TORQUE, INPUT_ROTOR_TORQUE};
use windrive::physics::gearbox::statics::equilibrium;
use windrive::physics::torsional::{Fidelity, ModelOptions, TorsionalModel};

fn grc() -> Gearbox {
    Gearbox::new(&Description::load("grc750").unwrap()).unwrap()
}

/// Every shipped preset builds, turns at its published ratio, and settles statically at its rated
/// torque with the torque split through its stages.
#[test]
fn every_preset_builds_and_carries_its_rated_torque() {
    let ratios = [
        ("grc750", 81.491),
        ("nrel5mw", 96.354),
        ("c2mw", 6.0 * 4.0 * 111.0 / 29.0),
        ("paper1p5mw", 100.84),
        ("planetary-spur", 1.0 + 99.0 / 21.0),
    ];
    for (name, _) in PRESETS {
        let d = Description::load(name).unwrap_or_else(|e| panic!("{e}"));
        let g = Gearbox::new(&d).unwrap_or_else(|e| panic!("{name}: {e}"));
        let ratio = ratios.iter().find(|(n, _)| *n == name).unwrap().1;
        assert!(
            (g.gear_ratio / ratio - 1.0).abs() < 1e-4,
            "{name}: ratio {} vs {ratio}",
            g.gear_ratio
        );
        let t = g.rated_rotor_torque.unwrap_or(1e5);
        let (q, v) = loaded(&g, t, 0.0);
        let loads = g.loads(&q, &v);
        // the last shaft carries the input torque over the ratio (or the stage's output when alone)
        if let Some(&last) = loads.shafts.last() {
            assert!((last / (t / g.gear_ratio) - 1.0).abs() < 0.01, "{name}: {last}");
        }
        let lowest: Vec<String> = modes(&g)
            .iter()
            .filter(|m| m.family != Family::Rigid)
            .take(4)
            .map(|m| format!("{:.2}", m.frequency_hz))
            .collect();
        eprintln!(
            "{name}: {} DOF, ratio {:.3}, K_γ {:.4}, lowest modes {lowest:?} Hz",
            g.dofs(),
            g.gear_ratio,
            g.load_sharing(&loads, "").unwrap_or(0.0)
        );
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
    // docs/GEARBOX.md's verification table quotes both
    let quoted = common::gearbox_doc_measured("first drivetrain mode with supports as rigid");
    let expected = format!("{a:.4} Hz ({:.2} %)", 100.0 * (a / b - 1.0).abs());
    assert_eq!(quoted, expected);
    let quoted = common::gearbox_doc_measured("same, with the preset's estimated bearings");
    let expected = format!("{c:.3} Hz (−{:.1} %", 100.0 * (1.0 - c / b));
    assert!(quoted.starts_with(&expected), "{quoted} should start with {expected}");
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

/// Equilibrium of a model under a carrier torque (and the reaction at its output) at a spin.
fn loaded(g: &Gearbox, torque: f64, speed: f64) -> (Vec<f64>, Vec<f64>) {
    let mut u = vec![0.0; 3];
    u[INPUT_ROTOR_TORQUE] = torque;
    u[INPUT_GENERATOR_TORQUE] = torque / g.gear_ratio;
    equilibrium(g, &u, speed).unwrap()
}

fn planetary_mut(d: &mut Description) -> &mut windrive::physics::gearbox::description::Planetary {
    match &mut d.stages[0] {
        windrive::physics::gearbox::description::Stage::Planetary(p) => p,
        _ => unreachable!(),
    }
}

/// A planet pin ahead of its place takes more than its share (ISO 6336-1 / IEC 61400-4 K_γ > 1);
/// a floating sun moves to even the loads out, so K_γ falls when the sun floats: with three
/// planets the floating sun's two radial DOFs even them out completely (the classical result for a
/// statically determinate three-planet stage), with four it only partly does.
#[test]
fn a_pin_position_error_raises_the_load_sharing_factor_and_a_floating_sun_lowers_it() {
    let mut quoted = Vec::new();
    for planets in [3, 4] {
        let mut d = stage_only(planets);
        let t = 3e5;
        let sharing = |d: &Description| {
            let g = Gearbox::new(d).unwrap();
            let (q, v) = loaded(&g, t, 0.0);
            g.load_sharing(&g.loads(&q, &v), "").unwrap()
        };
        let p = planetary_mut(&mut d);
        p.sun.support = None;
        p.sun.support = Some(windrive::physics::gearbox::description::Support {
            axial: 1e8,
            tilting: 1e7,
            ..Default::default()
        });
        let perfect = sharing(&d);
        let mut errors = vec![0.0; planets];
        errors[0] = 30.0;
        planetary_mut(&mut d).pin_errors_um = errors;
        let floating = sharing(&d);
        planetary_mut(&mut d).sun.support.as_mut().unwrap().radial = 2e10;
        let held = sharing(&d);
        eprintln!(
            "{planets} planets, K_γ: no error {perfect:.4}, 30 µm pin error with floating sun {floating:.4}, held sun {held:.4}"
        );
        assert!((perfect - 1.0).abs() < 0.01);
        assert!(held > 1.02, "{held}");
        assert!(floating < held - 0.01, "{floating} vs {held}");
        if planets == 3 {
            assert!((floating - 1.0).abs() < 0.01, "{floating}");
        } else {
            assert!(floating > 1.005, "{floating}");
        }
        quoted.push(format!("{planets} planets: held sun {held:.3}, floating {floating:.3}"));
    }
    assert_eq!(
        common::gearbox_doc_measured("load sharing: 30 µm pin error"),
        quoted.join("; ")
    );
}

/// A lead slope (misalignment) loads one end of the face: K_Hβ > 1, growing with the slope, the
/// largest slice at the end the slope compresses.
#[test]
fn misalignment_loads_one_end_of_the_face() {
    let mut d = stage_only(3);
    let mut previous = 0.0;
    let mut quoted = Vec::new();
    for slope in [0.0, 10.0, 20.0, 40.0] {
        planetary_mut(&mut d).toothing.lead_slope_um = slope;
        let g = Gearbox::new(&d).unwrap();
        let (q, v) = loaded(&g, 3e5, 0.0);
        let loads = g.loads(&q, &v);
        let m = g.meshes.iter().position(|m| m.name == "sun_planet_1").unwrap();
        let r = loads.meshes[m];
        eprintln!(
            "lead slope {slope} µm: K_Hβ {:.3} at {:.3} m",
            r.face_load_factor, r.max_position
        );
        assert!(r.face_load_factor > previous, "{slope}");
        if slope == 0.0 {
            assert!((r.face_load_factor - 1.0).abs() < 1e-6, "{r:?}");
        } else {
            assert!(r.face_load_factor > 1.05 && r.max_position > 0.0, "{slope}: {r:?}");
        }
        previous = r.face_load_factor;
        quoted.push(format!("{:.3}", r.face_load_factor));
    }
    assert_eq!(
        common::gearbox_doc_measured("lead slope 0/10/20/40 µm"),
        quoted.join(", ")
    );
}

/// Without backlash a misalignment larger than the drive flank's compression brings the back flank
/// into contact at the other end of the face. K_Hβ and the largest slice are then the drive flank's
/// alone (ISO 6336's ratio on the flank carrying the torque): the back flank's slices neither add
/// to its mean nor cancel its slices. With backlash the back flank stays clear.
#[test]
fn the_face_load_factor_is_the_loaded_flanks_when_both_flanks_touch() {
    let mut d = stage_only(3);
    planetary_mut(&mut d).toothing.lead_slope_um = 60.0;
    for backlash in [0.0, 200.0] {
        planetary_mut(&mut d).toothing.backlash_um = backlash;
        let g = Gearbox::new(&d).unwrap();
        let (q, v) = loaded(&g, 2e4, 0.0);
        let loads = g.loads(&q, &v);
        let mut at = 0;
        for (m, r) in g.meshes.iter().zip(&loads.meshes) {
            let s = &loads.slices[at..at + m.slices()];
            at += m.slices();
            let drive: Vec<f64> = s.iter().copied().filter(|&f| f > 0.0).collect();
            let back: f64 = s.iter().filter(|&&f| f < 0.0).map(|f| -f).sum();
            let largest = drive.iter().fold(0.0f64, |a, &f| a.max(f));
            let mean = drive.iter().sum::<f64>() / s.len() as f64;
            eprintln!(
                "backlash {backlash} µm, {}: K_Hβ {:.3}, back flank {:.0} N of {:.0} N",
                m.name,
                r.face_load_factor,
                back,
                r.force + back
            );
            if backlash > 0.0 {
                assert_eq!(back, 0.0, "{}", m.name);
            } else {
                assert!(back > 0.0, "{}: the back flank should touch", m.name);
            }
            assert!((r.max_slice - largest).abs() <= 1e-9 * largest, "{}", m.name);
            assert!(
                (r.face_load_factor - largest / mean).abs() <= 1e-9 * largest / mean,
                "{}",
                m.name
            );
        }
    }
}

/// The shipped GRC and 2 MW gearboxes at rated torque with gravity and their rotors' weight: with
/// their estimated backlash no back flank touches (docs/GEARBOX.md: before they had backlash, the
/// planets were held on both flanks).
#[test]
fn the_shipped_gearboxes_load_only_their_drive_flanks_at_rated_torque() {
    for name in ["grc750", "c2mw"] {
        let g = Gearbox::new(&Description::load(name).unwrap()).unwrap();
        let (q, v) = loaded(&g, g.rated_rotor_torque.unwrap(), 0.0);
        let loads = g.loads(&q, &v);
        let back = loads.slices.iter().filter(|&&f| f < 0.0).count();
        assert_eq!(back, 0, "{name}: {back} back-flank slices in contact");
        assert!(loads.meshes.iter().all(|m| m.force > 0.0), "{name}");
    }
}

/// Spur gears with centred supports and no errors load the face symmetrically.
#[test]
fn spur_slices_are_symmetric_across_the_face() {
    let g = Gearbox::new(&stage_only(3)).unwrap();
    let (q, v) = loaded(&g, 2e5, 0.0);
    let loads = g.loads(&q, &v);
    let mut at = 0;
    for m in &g.meshes {
        let s = &loads.slices[at..at + m.slices()];
        let largest = s.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        assert!(largest > 0.0, "{} unloaded", m.name);
        for j in 0..s.len() {
            assert!(
                (s[j] - s[s.len() - 1 - j]).abs() <= 1e-9 * largest,
                "{} slice {j}",
                m.name
            );
        }
        at += m.slices();
    }
}

/// Newton's second law for a planet riding a carrier at Ω: the bearing and mesh forces on it add up
/// to the centripetal m·a·Ω² towards the axis (no torque, no gravity).
#[test]
fn a_planet_on_a_spinning_carrier_feels_the_centripetal_load() {
    let g = Gearbox::new(&stage_only(3)).unwrap();
    let omega = 12.0;
    let (q, v) = loaded(&g, 0.0, omega);
    let p = g.body("planet_1_1").unwrap();
    let f = g.bodies[p].first.unwrap();
    // elastic forces on the planet = −(their share of f_int): springs and meshes only
    let mut elastic = [0.0; 2];
    for s in &g.springs {
        let force = s.force(&q, &v);
        for (k, e) in elastic.iter_mut().enumerate() {
            if let Some(i) = s.row.indices().iter().position(|&i| i == f + k) {
                *e -= force * s.row.values()[i];
            }
        }
    }
    let mut fi = vec![0.0; g.dofs()];
    let mut slices = vec![0.0; g.slice_count()];
    let flanks = g.forces_with_slices(&q, &v, &mut fi, &mut slices);
    for (m, l) in g.meshes.iter().zip(&flanks) {
        for (rows, load) in [(&m.drive, l[0]), (&m.back, l[1])] {
            for (k, e) in elastic.iter_mut().enumerate() {
                if let Some(i) = rows[0].indices().iter().position(|&i| i == f + k) {
                    *e -= load.force * rows[0].values()[i];
                }
            }
        }
    }
    let b = &g.bodies[p];
    let a = b.centre[0].hypot(b.centre[1]);
    let expected = b.mass * a * omega * omega;
    let inward = -(elastic[0] * b.centre[0] + elastic[1] * b.centre[1]) / a;
    eprintln!("centripetal: {inward:.3} N, m·a·Ω² = {expected:.3} N");
    assert!((inward / expected - 1.0).abs() < 1e-3, "{inward} vs {expected}");
    assert_eq!(
        common::gearbox_doc_measured("planet on a carrier at 12 rad/s"),
        format!("{inward:.2} N vs {expected:.2} N")
    );
}

/// Started in its loaded, spinning equilibrium, the undisturbed GRC gearbox stays there: speeds,
/// shaft torques and mesh forces constant through 0.2 s of implicit steps (the frame terms of the
/// dynamics are those of the statics, and the rotating frames keep every row constant). Linear
/// bearings: rollers passing through a lamina bearing's load zone vary its stiffness (see
/// `roller_passage_excites_the_bearings_at_their_ball_pass_frequency`).
#[test]
fn the_loaded_spinning_gearbox_stays_in_equilibrium() {
    use windrive::solver::alpha::Alpha;
    use windrive::solver::{Driver, DynState, Method};
    let mut d = Description::load("grc750").unwrap();
    d.model.gravity = 0.0;
    d.model.bearings = BearingModel::Linear;
    let g = Gearbox::new(&d).unwrap();
    let t = g.rated_rotor_torque.unwrap();
    let speed = 18.6 * std::f64::consts::TAU / 60.0;
    let (q, v) = loaded(&g, t, speed);
    let before = g.loads(&q, &v);
    let mut st = DynState::new(q, v);
    let mut driver = Driver::new(Method::Implicit(Alpha::NEWMARK));
    let u = [t, t / g.gear_ratio, 0.0];
    for k in 0..200 {
        driver
            .advance(&g, &mut st, k as f64 * 1e-3, 1e-3, 1e-3, 3, |_, out| {
                out.copy_from_slice(&u)
            })
            .unwrap();
    }
    let after = g.loads(&st.q, &st.v);
    let rotor = g.speed(g.input_body, &st.v);
    assert!((rotor / speed - 1.0).abs() < 1e-6, "{rotor} vs {speed}");
    for (a, b) in after.shafts.iter().zip(&before.shafts) {
        assert!((a / b - 1.0).abs() < 1e-4, "{a} vs {b}");
    }
    for (a, b) in after.meshes.iter().zip(&before.meshes) {
        assert!((a.force / b.force - 1.0).abs() < 1e-4, "{a:?} vs {b:?}");
    }
    eprintln!("{:?}", driver.stats);
}

/// With the single/double tooth stiffness switched on, the sun–planet force rings at the mesh
/// frequencies the kinematics give (GRC at 18.6 rpm): strongest at the intermediate mesh's
/// 82·f_sun = 145.2 Hz (its gear sits on the sun shaft), and below 100 Hz at the planetary mesh's own
/// z_ring·f_carrier = 30.69 Hz; its mean stays the constant-stiffness value.
#[test]
fn varying_mesh_stiffness_excites_the_mesh_frequency() {
    use windrive::physics::gearbox::description::MeshStiffnessModel;
    use windrive::solver::alpha::Alpha;
    use windrive::solver::{Driver, DynState, Method};
    let mut d = Description::load("grc750").unwrap();
    d.model.gravity = 0.0;
    d.model.bearings = BearingModel::Linear;
    d.model.mesh_stiffness = MeshStiffnessModel::Varying;
    let g = Gearbox::new(&d).unwrap();
    let t = g.rated_rotor_torque.unwrap();
    let speed = 18.6 * std::f64::consts::TAU / 60.0;
    let (q, v) = loaded(&g, t, speed);
    let mut st = DynState::new(q, v);
    let mut driver = Driver::new(Method::Implicit(Alpha::NEWMARK));
    let u = [t, t / g.gear_ratio, 0.0];
    let m = g.meshes.iter().position(|m| m.name == "sun_planet_1").unwrap();
    let (mut time, mut force) = (Vec::new(), Vec::new());
    let h = 2.5e-4;
    for k in 0..8000 {
        driver
            .advance(&g, &mut st, k as f64 * h, h, h, 3, |_, out| out.copy_from_slice(&u))
            .unwrap();
        time.push((k + 1) as f64 * h);
        force.push(g.loads(&st.q, &st.v).meshes[m].force);
    }
    let (f, freq, amp) =
        windrive::analysis::signal::spectrum::dominant_in_window(&time, &force, 0.5, 2.0, 10.0).unwrap();
    let ims = 82.0 * 18.6 * (1.0 + 99.0 / 21.0) / 60.0;
    assert!((f / ims - 1.0).abs() < 0.02, "{f} vs {ims}");
    let ims_found = f;
    let (f, _) = windrive::analysis::signal::spectrum::peaks(&freq, &amp, 10.0, 100.0, 1)[0];
    let expected = 99.0 * 18.6 / 60.0;
    let mean = force.iter().sum::<f64>() / force.len() as f64;
    let constant = {
        let mut d = d.clone();
        d.model.mesh_stiffness = MeshStiffnessModel::Mean;
        let g = Gearbox::new(&d).unwrap();
        let (q, v) = loaded(&g, t, speed);
        g.loads(&q, &v).meshes[m].force
    };
    eprintln!(
        "below 100 Hz the mesh force rings at {f:.2} Hz (mesh frequency {expected:.2} Hz); mean {mean:.0} N vs {constant:.0} N; {:?}",
        driver.stats
    );
    assert!((f / expected - 1.0).abs() < 0.02, "{f} vs {expected}");
    assert!((mean / constant - 1.0).abs() < 0.02, "{mean} vs {constant}");
    assert_eq!(
        common::gearbox_doc_measured("varying mesh stiffness"),
        format!("{f:.2} Hz (z_ring·f_c = {expected:.2}), {ims_found:.0} Hz (82·f_sun)")
    );
}

/// A main shaft given as a Timoshenko beam (`shaft.beam`) adds exactly the element's stiffness between
/// where it leaves the rotor and enters the carrier: no force for a rigid motion of the pair (their
/// centres `from_m + length − to_m` apart), and held at the rotor, the carrier's entry point resisting a
/// transverse push with 12EI/((1 + Φ)L³) (Φ = 12EI/(κGAL²)) and a stretch with EA/L, by hand.
#[test]
fn a_beam_main_shaft_is_a_timoshenko_element() {
    let beam = main_shaft_beam(1);
    let (with, without) = (with_beam_shaft(Some(beam), true), with_beam_shaft(None, true));
    let k = spring_stiffness(&with) - spring_stiffness(&without);
    let n = with.dofs();
    let (rotor, carrier) = (with.body("rotor").unwrap(), with.body("carrier_1").unwrap());
    let dof = |b: usize, i: usize| with.dof(b, i).unwrap();
    const UX: usize = 0;
    const UZ: usize = 2;
    const TY: usize = 4;
    // a rigid rotation θ about y of the pair: the carrier's centre lies D downwind of the rotor's
    let distance = beam.from_m + beam.length_m - beam.to_m;
    let mut q = nalgebra::DVector::<f64>::zeros(n);
    q[dof(rotor, TY)] = 1e-3;
    q[dof(carrier, TY)] = 1e-3;
    q[dof(carrier, UX)] = 1e-3 * distance;
    q[dof(rotor, UX)] = 0.0;
    let scale = k.abs().max();
    assert!(
        (&k * &q).abs().max() < 1e-9 * scale * 1e-3,
        "a rigid rotation strains the shaft"
    );
    // the carrier pushed sideways at its entry point (u_x + θ_y·to_m = 1, θ_y = 0), the rotor held
    let (e, g) = (beam.youngs_modulus, beam.shear_modulus);
    let (od, id) = (0.42f64, 0.12f64);
    let area = std::f64::consts::PI / 4.0 * (od * od - id * id);
    let i = std::f64::consts::PI / 64.0 * (od.powi(4) - id.powi(4));
    let nu = e / (2.0 * g) - 1.0;
    let m2 = (1.0 + (id / od).powi(2)).powi(2);
    let kappa = 6.0 * (1.0 + nu) * m2 / ((7.0 + 6.0 * nu) * m2 + (20.0 + 12.0 * nu) * (id / od).powi(2));
    let l = beam.length_m;
    let phi = 12.0 * e * i / (kappa * g * area * l * l);
    let transverse = 12.0 * e * i / ((1.0 + phi) * l.powi(3));
    let got = k[(dof(carrier, UX), dof(carrier, UX))];
    assert!((got / transverse - 1.0).abs() < 1e-9, "{got} vs {transverse}");
    let got = k[(dof(carrier, UZ), dof(carrier, UZ))];
    assert!((got / (e * area / l) - 1.0).abs() < 1e-9, "{got} vs {}", e * area / l);
    // and the gearbox with it still carries its rated torque statically
    let t = with.rated_rotor_torque.unwrap();
    let mut u = [0.0; 3];
    (u[INPUT_ROTOR_TORQUE], u[INPUT_GENERATOR_TORQUE]) = (t, t / with.gear_ratio);
    equilibrium(&with, &u, 2.0).unwrap();
}

/// The GRC is a three-point mount: one main bearing, and the gearbox as the main shaft's second
/// support. With its main shaft a beam (the preset's), the overhung rotor weighs on the main bearing
/// through the shaft's lever, W·(a + L)/L for a rotor a ahead of the bearing and a shaft end L behind
/// it, if the end were a pin; the shaft's own nodes add their weight by the same rule. The carrier
/// end is no pin (its bearings, the planets and the ring share a moment there), so the statics may
/// differ from the pin's lever by up to 10 %; they give a little less (the page quotes how much). The carrier's bearings then carry
/// the shaft end's lift, not the rotor's weight.
#[test]
fn the_grc_main_bearing_carries_the_overhung_rotor_through_the_shafts_lever() {
    let d = Description::load("grc750").unwrap();
    let g = grc();
    let rotor = d.rotor.as_ref().unwrap();
    let beam = rotor
        .shaft
        .as_ref()
        .unwrap()
        .beam
        .expect("the GRC preset's main shaft is a beam");
    let main = rotor.bearings.iter().find(|b| b.name == "main").unwrap();
    let (a, l) = (main.position, beam.length_m);
    assert!((beam.from_m - a).abs() < 1e-12, "the beam starts at the main bearing");
    let weight = d.model.gravity * d.model.shaft_tilt_deg.to_radians().cos();
    let nodes = shaft_nodes(&g);
    let node_moment: f64 = nodes
        .iter()
        .enumerate()
        .map(|(i, &n)| g.bodies[n].mass * weight * (l - l * (i + 1) as f64 / (nodes.len() + 1) as f64))
        .sum();
    let lever = (rotor.mass.unwrap() * weight * (a + l) + node_moment) / l;
    let (q, v) = loaded(&g, g.rated_rotor_torque.unwrap(), 0.0);
    let loads = g.loads(&q, &v);
    let at = |name: &str| loads.bearings[g.bearings.iter().position(|b| b.name == name).unwrap()].radial;
    let got = at("main");
    assert!(
        (got / lever - 1.0).abs() < 0.10,
        "main bearing {got:.0} N, lever {lever:.0} N"
    );
    // docs/GEARBOX.md quotes how far below the pin-ended lever
    let below = 100.0 * (1.0 - got / lever);
    let page = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/GEARBOX.md")).unwrap();
    let quoted = format!("{below:.0} % below the pin-ended lever");
    assert!(
        page.split_whitespace().collect::<Vec<_>>().join(" ").contains(&quoted),
        "docs/GEARBOX.md should say {quoted}"
    );
    assert!(got > 2.0 * rotor.mass.unwrap() * weight, "main bearing {got:.0} N");
    let carrier = at("carrier_a") + at("carrier_b");
    assert!(
        carrier < got - rotor.mass.unwrap() * weight,
        "carrier bearings {carrier:.0} N"
    );
}

/// An estimated GRC main shaft: 1.1 m of 420/120 mm from 1.6 m behind the rotor's centre to 0.4 m
/// before the carrier's.
fn main_shaft_beam(elements: u32) -> windrive::physics::gearbox::description::Beam {
    windrive::physics::gearbox::description::Beam {
        length_m: 1.1,
        outer_diameter_mm: 420.0,
        inner_diameter_mm: 120.0,
        from_m: 1.6,
        to_m: -0.4,
        youngs_modulus: 2.1e11,
        shear_modulus: 8.1e10,
        elements,
    }
}

/// The GRC (linear bearings) with its main shaft as a beam (None: without the shaft's springs);
/// `gravity` off leaves only the springs and the inputs to compare.
fn with_beam_shaft(beam: Option<windrive::physics::gearbox::description::Beam>, gravity: bool) -> Gearbox {
    let mut d = Description::load("grc750").unwrap();
    d.model.bearings = BearingModel::Linear;
    if !gravity {
        d.model.gravity = 0.0;
    }
    let shaft = d.rotor.as_mut().unwrap().shaft.as_mut().unwrap();
    (shaft.radial, shaft.axial, shaft.tilting, shaft.beam) = (0.0, 0.0, 0.0, beam);
    Gearbox::new(&d).unwrap()
}

fn spring_stiffness(g: &Gearbox) -> nalgebra::DMatrix<f64> {
    let n = g.dofs();
    let mut k = nalgebra::DMatrix::<f64>::zeros(n, n);
    for s in &g.springs {
        windrive::physics::gearbox::row::add_outer(&mut k, s.stiffness, &s.row, &s.row);
    }
    k
}

fn shaft_nodes(g: &Gearbox) -> Vec<usize> {
    use windrive::physics::gearbox::model::BodyKind;
    (0..g.bodies.len())
        .filter(|&i| g.bodies[i].kind == BodyKind::ShaftNode)
        .collect()
}

/// Timoshenko elements are exact for loads at their ends, so a shaft cut into four elements,
/// condensed onto the bodies it joins (its nodes loaded by nothing), is the one-element shaft to
/// rounding: bending, shear, stretch and torsion. Its nodes carry three quarters of its mass ρAL
/// (the end half-elements belong to the rotor and the carrier), and with gravity off the gearbox
/// carries its rated torque with the same bearing loads.
#[test]
fn a_shaft_of_several_elements_condenses_to_one() {
    let (one, four) = (
        with_beam_shaft(Some(main_shaft_beam(1)), false),
        with_beam_shaft(Some(main_shaft_beam(4)), false),
    );
    let nodes = shaft_nodes(&four);
    assert_eq!(nodes.len(), 3);
    assert_eq!(four.dofs(), one.dofs() + 18);
    // the nodes come last: the first DOFs are the same bodies' in both models
    let m = one.dofs();
    let k = spring_stiffness(&four);
    let (kaa, kab) = (k.view((0, 0), (m, m)), k.view((0, m), (m, 18)));
    let kbb = k.view((m, m), (18, 18)).into_owned();
    let condensed = kaa - kab * kbb.lu().solve(&kab.transpose()).unwrap();
    let reference = spring_stiffness(&one);
    let scale = reference.abs().max();
    let worst = (&condensed - &reference).abs().max();
    assert!(worst < 1e-9 * scale, "condensed differs by {worst:e} of {scale:e}");
    // the shaft's mass on its nodes
    let (area, length) = (std::f64::consts::PI / 4.0 * (0.42f64.powi(2) - 0.12f64.powi(2)), 1.1);
    let lumped: f64 = nodes.iter().map(|&i| four.bodies[i].mass).sum();
    let density = Description::load("grc750").unwrap().model.density;
    assert!((lumped / (0.75 * density * area * length) - 1.0).abs() < 1e-12);
    // the same bearing loads at rated torque (the torque each shaft reports, too)
    let rated = |g: &Gearbox| {
        let (q, v) = loaded(g, g.rated_rotor_torque.unwrap(), 0.0);
        g.loads(&q, &v)
    };
    let (lo, lf) = (rated(&one), rated(&four));
    for (a, b) in lo.bearings.iter().zip(&lf.bearings) {
        assert!(
            (a.radial - b.radial).abs() <= 1e-6 * a.radial.max(1.0),
            "{a:?} vs {b:?}"
        );
    }
    for (a, b) in lo.shafts.iter().zip(&lf.shafts) {
        assert!((a - b).abs() <= 1e-9 * a.abs(), "{a} vs {b}");
    }
}

/// A shaft clamped at both ends (the bodies it joins held) bends at the clamped–clamped beam's first
/// frequency, (4.7300²/2πL²)·√(EI/ρA), and twists at (1/2L)·√(k_t·L/ρJ) with its torsional stiffness
/// k_t spread along it. The shaft is slender (L/D = 40), so shear and rotary inertia, which the
/// Euler–Bernoulli formula leaves out, lower the bending frequency by only 0.3 % (a 200-element
/// Timoshenko model with consistent ends gives −0.31 %): ten elements come within 0.5 %, three are
/// further off. The torsion chain's lumped inertias converge as 1/n²: ten elements within 0.5 %,
/// five four times further.
#[test]
fn a_clamped_shaft_has_the_beams_first_bending_and_torsion_frequencies() {
    use windrive::physics::gearbox::description::Beam;
    use windrive::physics::gearbox::model::{SPIN, TY, UX};
    let (l, od) = (4.0, 0.1);
    let frequencies = |elements: u32| {
        let beam = Beam {
            length_m: l,
            outer_diameter_mm: od * 1e3,
            inner_diameter_mm: 0.0,
            from_m: 0.5,
            to_m: -0.5,
            youngs_modulus: 2.1e11,
            shear_modulus: 8.1e10,
            elements,
        };
        let g = with_beam_shaft(Some(beam), true);
        let k = spring_stiffness(&g);
        let mass = g.mass_matrix();
        let nodes = shaft_nodes(&g);
        let lowest = |dofs: &[usize]| {
            let kk = nalgebra::DMatrix::from_fn(dofs.len(), dofs.len(), |i, j| k[(dofs[i], dofs[j])]);
            let mm = nalgebra::DMatrix::from_fn(dofs.len(), dofs.len(), |i, j| mass[(dofs[i], dofs[j])]);
            // M diagonal: the symmetric M^-1/2 K M^-1/2
            let s = nalgebra::DMatrix::from_fn(dofs.len(), dofs.len(), |i, j| {
                kk[(i, j)] / (mm[(i, i)] * mm[(j, j)]).sqrt()
            });
            let e = nalgebra::SymmetricEigen::new(s).eigenvalues;
            e.iter().cloned().fold(f64::INFINITY, f64::min).sqrt() / std::f64::consts::TAU
        };
        let bending: Vec<usize> = nodes
            .iter()
            .flat_map(|&b| [g.dof(b, UX).unwrap(), g.dof(b, TY).unwrap()])
            .collect();
        let torsion: Vec<usize> = nodes.iter().map(|&b| g.dof(b, SPIN).unwrap()).collect();
        (lowest(&bending), lowest(&torsion))
    };
    let (e, density) = (2.1e11, Description::load("grc750").unwrap().model.density);
    let (area, i) = (
        std::f64::consts::PI / 4.0 * od * od,
        std::f64::consts::PI / 64.0 * od.powi(4),
    );
    let bending = 4.7300f64.powi(2) / (std::f64::consts::TAU * l * l) * (e * i / (density * area)).sqrt();
    let (b10, t10) = frequencies(10);
    let kt = Description::load("grc750")
        .unwrap()
        .rotor
        .unwrap()
        .shaft
        .unwrap()
        .torsional;
    let torsion = (kt * l / (density * 2.0 * i)).sqrt() / (2.0 * l);
    let (b3, _) = frequencies(3);
    let (_, t5) = frequencies(5);
    let (eb10, et10) = (b10 / bending - 1.0, t10 / torsion - 1.0);
    let (eb3, et5) = (b3 / bending - 1.0, t5 / torsion - 1.0);
    eprintln!(
        "bending {bending:.2} Hz: 10 elements {b10:.2} ({eb10:+.4}), 3 {b3:.2} ({eb3:+.4}); \
         torsion {torsion:.1} Hz: 10 elements {t10:.1} ({et10:+.4}), 5 {t5:.1} ({et5:+.4})"
    );
    assert!(eb10.abs() < 0.005 && et10.abs() < 0.005);
    assert!(eb3.abs() > 2.0 * eb10.abs());
    assert!((et5 / et10 - 4.0).abs() < 0.2, "1/n²: {et5} against {et10}");
}

/// The model's dynamic factor (`windrive gearbox --dynamic-factor`) is converged in the step and in the
/// slices: halving the step and cutting the GRC's slices from 35 to 11 move no mesh's K_v by 1e-3 (a
/// tenth of the smallest K_v − 1 the page reports is 5e-4; 1e-3 keeps every ratio's reading). Until the
/// slices took their mean pair count, 11 slices gave K_v − 1 about twice 35's. A shorter window than the
/// page's (0.1 s after 0.05 s) keeps the test at a few seconds: the comparison is between runs of the same
/// timing. Each K_v is at least 1 (the varying stiffness adds load peaks) and the helical GRC's stay below
/// IEC 61400-4's 1.05.
#[test]
fn the_models_dynamic_factor_is_converged_in_step_and_slices() {
    use windrive::studies::dynamic_factor::{Timing, dynamic_factors};
    let mut d = Description::load("grc750").unwrap();
    d.model.bearings = BearingModel::Linear;
    let g = Gearbox::new(&d).unwrap();
    let speed = d.rated_rotor_speed_rpm.unwrap() * std::f64::consts::TAU / 60.0;
    let torque = g.rated_rotor_torque.unwrap();
    let timing = Timing {
        settle_s: 0.05,
        window_s: 0.1,
        mesh_periods: 3.0,
        ..Timing::default()
    };
    let base = dynamic_factors(&d, torque, speed, &timing).unwrap();
    let half = dynamic_factors(
        &d,
        torque,
        speed,
        &Timing {
            step_s: Some(0.5 * base.step_s),
            ..timing
        },
    )
    .unwrap();
    let mut coarse = d.clone();
    coarse.model.slices = 11;
    let coarse = dynamic_factors(&coarse, torque, speed, &timing).unwrap();
    for ((b, h), c) in base.meshes.iter().zip(&half.meshes).zip(&coarse.meshes) {
        eprintln!(
            "{}: K_v {:.5} (h/2 {:.5}, 11 slices {:.5})",
            b.mesh, b.k_v_model, h.k_v_model, c.k_v_model
        );
        assert!(!b.spur);
        assert!((1.0..1.05).contains(&b.k_v_model), "{}: {}", b.mesh, b.k_v_model);
        assert!((h.k_v_model - b.k_v_model).abs() < 1e-3, "{}: step", b.mesh);
        assert!((c.k_v_model - b.k_v_model).abs() < 1e-3, "{}: slices", b.mesh);
    }
}

/// An owner that reports a few elements evaluates each on its own (`mesh_report`, `bearing_load`,
/// `shaft_torque`, `load_sharing_by`): the bits of the whole report at the same state, for every
/// bearing law, at rated equilibria shaken off their balance so that rollers tilt, back flanks and
/// damping act. (A mutant that evaluates a bearing's roller set without its loads fails it.)
#[test]
fn each_elements_loads_on_its_own_are_the_whole_reports_bits() {
    let mut rng = common::Rng(0x5eed_10ad);
    for name in ["grc750", "c2mw"] {
        for law in [BearingModel::Linear, BearingModel::Lamina, BearingModel::LaminaTable] {
            let mut d = Description::load(name).unwrap();
            d.model.bearings = law;
            let g = Gearbox::new(&d).unwrap();
            let (q0, v0) = loaded(&g, g.rated_rotor_torque.unwrap(), 1.5);
            for shake in 0..4 {
                let (mut q, mut v) = (q0.clone(), v0.clone());
                for (x, y) in q.iter_mut().zip(v.iter_mut()) {
                    *x += 1e-6 * shake as f64 * rng.symmetric();
                    *y += 1e-3 * shake as f64 * rng.symmetric();
                }
                let whole = g.loads(&q, &v);
                let mut scratch = vec![0.0; g.dofs()];
                for (i, m) in g.meshes.iter().enumerate() {
                    let mut slices = vec![f64::NAN; m.slices()];
                    let own = g.mesh_report(i, &q, &v, &mut slices, &mut scratch);
                    assert_eq!(
                        format!("{own:?}"),
                        format!("{:?}", whole.meshes[i]),
                        "{name} {law:?} mesh {i}"
                    );
                }
                for i in 0..g.bearings.len() {
                    let own = g.bearing_load(i, &q, &v, &mut scratch);
                    assert_eq!(
                        format!("{own:?}"),
                        format!("{:?}", whole.bearings[i]),
                        "{name} {law:?} bearing {i}"
                    );
                }
                for i in 0..g.shafts.len() {
                    assert_eq!(
                        g.shaft_torque(i, &q, &v).to_bits(),
                        whole.shafts[i].to_bits(),
                        "{name} shaft {i}"
                    );
                }
                let by = g.load_sharing_by("", |i| {
                    g.mesh_report(i, &q, &v, &mut vec![0.0; g.meshes[i].slices()], &mut scratch)
                        .force
                });
                assert_eq!(
                    by.map(f64::to_bits),
                    g.load_sharing(&whole, "").map(f64::to_bits),
                    "{name} load sharing"
                );
            }
        }
    }
}
