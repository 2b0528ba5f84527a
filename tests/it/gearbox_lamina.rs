//! The GRC 750 kW gearbox with roller–lamina bearings against what can be known without the
//! thesis's model: a helical planet's axial mesh forces cancel into a couple; roller passage
//! excites a bearing at Z·f_cage; Hertz depths are 0.786 of each contact's half-width. And the
//! thesis's ch. 7 findings it must show (docs/GEARBOX.md compares every number): upwind planet
//! bearings carrying more than downwind ones, 6–7 rollers loaded, planet-bearing pressures at the
//! IEC 61400-4 limit of 1.5 GPa. Where the upwind planet bearing peaks over a carrier revolution is
//! asserted as our model gives it, beside the thesis's finding for the GRC on its dynamometer (the
//! planet horizontal to the right of the sun seen from upwind, §7.1.1), which ours does not show.

use crate::common;
use windrive::physics::gearbox::description::{BearingModel, Description};
use windrive::physics::gearbox::loads::Loads;
use windrive::physics::gearbox::model::Gearbox;
use windrive::physics::gearbox::statics::equilibrium;
use windrive::studies::carrier_revolution::{self, Revolution, STEP_S};

const RATED_SPEED: f64 = 18.6 * std::f64::consts::TAU / 60.0;

fn grc(bearings: BearingModel) -> Gearbox {
    let mut d = Description::load("grc750").unwrap();
    d.model.bearings = bearings;
    Gearbox::new(&d).unwrap()
}

fn rated(g: &Gearbox) -> [f64; 3] {
    let t = g.rated_rotor_torque.unwrap();
    [t, t / g.gear_ratio, 0.0]
}

fn rated_loads(g: &Gearbox) -> (Vec<f64>, Vec<f64>, Loads) {
    let (q, v) = equilibrium(g, &rated(g), RATED_SPEED).unwrap();
    let loads = g.loads(&q, &v);
    (q, v, loads)
}

fn bearing(g: &Gearbox, name: &str) -> usize {
    g.bearings.iter().position(|b| b.name == name).unwrap()
}

/// A planet meshes the sun and the ring on opposite sides: with one tooth hand the axial components
/// of the two mesh forces are opposite, so a planet's bearings carry no net thrust (< 1 % of one
/// mesh's F_t·tan β_b) but the couple between them. Linear and lamina bearings alike.
#[test]
fn a_helical_planet_carries_its_mesh_thrust_as_a_couple() {
    for model in [BearingModel::Linear, BearingModel::Lamina] {
        let g = grc(model);
        let (_, _, loads) = rated_loads(&g);
        let m = g.meshes.iter().position(|m| m.name == "sun_planet_1").unwrap();
        let thrust = loads.meshes[m].force * g.geometry[m].base_helix.sin();
        for p in 1..=3 {
            let axial: f64 = ["uw", "dw"]
                .iter()
                .map(|end| loads.bearings[bearing(&g, &format!("planet_{p}_{end}"))].axial)
                .sum();
            assert!(
                axial.abs() < 0.01 * thrust,
                "{model:?}: planet {p} thrust {axial} N against {thrust} N"
            );
        }
        // the sun carries the three meshes' thrust on its axial support (each mesh its own share:
        // gravity makes them unequal, the more so the lower the torque)
        let total: f64 = (1..=3)
            .map(|p| {
                let m = g
                    .meshes
                    .iter()
                    .position(|m| m.name == format!("sun_planet_{p}"))
                    .unwrap();
                loads.meshes[m].force * g.geometry[m].base_helix.sin()
            })
            .sum();
        let sun = loads.bearings[bearing(&g, "sun_1_support")].axial.abs();
        assert!((sun / total - 1.0).abs() < 0.05, "{model:?}: sun {sun} vs {total}");
    }
}

/// At rated torque with gravity (static): the planets' upwind bearings carry 1.433× the downwind
/// ones — the carrier webs' stiffness is fitted to that (thesis: 42, 47 and 41 % more, by
/// `windrive gearbox --fit-webs 1.4333`), so this guards the fit; 6–10 rollers carry each
/// (thesis: 6–7); the most loaded planet bearing sits at IEC 61400-4's 1.5 GPa (thesis 1.51–2.05
/// GPa in normal operation; ours at the static rated point, before any dynamics: > 1.45 GPa).
#[test]
fn upwind_planet_bearings_carry_more_at_rated_torque() {
    let g = grc(BearingModel::Lamina);
    let (_, _, loads) = rated_loads(&g);
    let mean = |end: &str| -> f64 {
        (1..=3)
            .map(|p| loads.bearings[bearing(&g, &format!("planet_{p}_{end}"))].radial)
            .sum::<f64>()
            / 3.0
    };
    let ratio = mean("uw") / mean("dw");
    assert!((ratio - 1.4333).abs() < 5e-3, "upwind/downwind {ratio}");
    let mut p_max = 0.0f64;
    for p in 1..=3 {
        for end in ["uw", "dw"] {
            let b = &loads.bearings[bearing(&g, &format!("planet_{p}_{end}"))];
            assert!(
                (6..=10).contains(&b.rollers_in_contact),
                "planet {p} {end}: {} rollers",
                b.rollers_in_contact
            );
            p_max = p_max.max(b.stresses.inner_pressure);
        }
    }
    assert!(p_max > 1.45e9 && p_max < 2.1e9, "planet bearing p_max {p_max}");
}

/// Every contact's largest subsurface shear lies 0.786 of its own half-width deep (Johnson §4.2):
/// the gears' between 0.2 and 1.2 mm (thesis: ≈ 1 mm for the planetary gears, ≈ 0.4 mm for the
/// HSS gears), the bearings' between 0.1 and 0.65 mm (thesis 0.35–0.65 mm).
#[test]
fn subsurface_shear_lies_at_the_hertz_depth() {
    let g = grc(BearingModel::Lamina);
    let (_, _, loads) = rated_loads(&g);
    for (m, r) in g.meshes.iter().zip(&loads.meshes) {
        let c = r.contact;
        assert!(
            (c.max_shear_depth / c.half_width / 0.786 - 1.0).abs() < 5e-3,
            "{}",
            m.name
        );
        assert!((c.max_shear / c.pressure - 0.300).abs() < 1e-3, "{}", m.name);
        assert!(
            (0.2e-3..1.2e-3).contains(&c.max_shear_depth),
            "{}: {}",
            m.name,
            c.max_shear_depth
        );
    }
    for (b, l) in g.bearings.iter().zip(&loads.bearings) {
        if l.max_roller_load > 1e3 {
            let d = l.stresses.max_shear_depth;
            assert!((0.05e-3..0.65e-3).contains(&d), "{}: {d}", b.name);
        }
    }
}

/// One carrier revolution of `d` at its rated torque and `rpm`, with gravity and the rotor's
/// weight (the description's), from the study `windrive gearbox --revolution` prints; the radial
/// load on bearing `probe`, if named, every step.
fn revolution(d: &Description, g: &Gearbox, rpm: f64, probe: Option<&str>) -> Revolution {
    let speed = rpm * std::f64::consts::TAU / 60.0;
    carrier_revolution::revolution(d, g, rated(g)[0], speed, probe).unwrap()
}

/// The thesis's 2 MW gearbox over one carrier revolution at rated torque. The thesis gives no peak
/// angle for it (its "right of the sun" finding is the GRC's on the dynamometer, §7.1.1, Fig. 7.3);
/// this is our model's result: with the rotor's weight each planet's upwind bearing peaks left of
/// the sun seen from upwind, 26–32° below the left horizontal (149–154° from the right, `windrive
/// gearbox --gearbox c2mw --revolution`; tested: more than 135°), swinging once per revolution by
/// about 9 %. Without the rotor's weight it peaks at 172–178° (`--rotor-mass 1`).
#[test]
fn the_2mw_planets_upwind_bearings_peak_left_of_the_sun_under_the_rotors_weight() {
    let mut d = Description::load("c2mw").unwrap();
    d.model.bearings = BearingModel::Lamina;
    let g = Gearbox::new(&d).unwrap();
    let r = revolution(&d, &g, d.rated_rotor_speed_rpm.unwrap(), None);
    for (p, (swing, from_right)) in r.swing.iter().zip(r.peak_from_right_deg()).enumerate() {
        assert!(*swing > 1.02, "planet {}: once-per-rev swing {swing}", p + 1);
        assert!(
            from_right > 135.0,
            "planet {}: peak {from_right:.0}° from the right horizontal",
            p + 1
        );
    }
}

/// The GRC over one carrier revolution at rated torque, our model's results beside the thesis's
/// finding (§7.1.1, Figs. 7.1–7.3: the upwind planet bearing peaks with the planet horizontal to the
/// right of the sun seen from upwind, at rated torque on NREL's dynamometer, which carries no rotor):
/// - with the overhung rotor's weight (the preset; `windrive gearbox --revolution`): each peaks left
///   of the sun, 147–177° from the right horizontal (tested: more than 135°);
/// - on the dynamometer, the rotor's weight gone (`--rotor-mass 1`): each peaks left of the sun too,
///   159–172° from the right horizontal (tested: more than 135°). Neither is the thesis's right
///   horizontal: the weight is not what puts ours elsewhere (docs/GEARBOX.md).
///
/// Both swing once per revolution. The HSS bearing hss_a rings at its roller-passage frequency
/// Z·f_cage, f_cage = f_shaft·(1 − D/d_m)/2 (varying compliance).
#[test]
fn a_carrier_revolution_shows_the_once_per_rev_swing_and_the_roller_passage() {
    let d = Description::load("grc750").unwrap();
    let g = grc(BearingModel::Lamina);
    let rpm = d.rated_rotor_speed_rpm.unwrap();
    let r = revolution(&d, &g, rpm, Some("hss_a"));
    for (p, (swing, from_right)) in r.swing.iter().zip(r.peak_from_right_deg()).enumerate() {
        assert!(*swing > 1.02, "planet {}: once-per-rev swing {swing}", p + 1);
        assert!(
            from_right > 135.0,
            "planet {}: peak {from_right:.0}° from the right horizontal",
            p + 1
        );
    }
    let hss_load = r.probe;
    let time: Vec<f64> = (1..=hss_load.len()).map(|k| k as f64 * STEP_S).collect();
    let (f, _, _) =
        windrive::analysis::signal::spectrum::dominant_in_window(&time, &hss_load, 0.5, 2.5, 100.0).unwrap();
    let shaft = r.output_speed_rad_s / std::f64::consts::TAU;
    let expected = 22.0 * shaft * (1.0 - 22.0 / 160.0) / 2.0;
    assert!(
        (f / expected - 1.0).abs() < 0.01,
        "hss_a rings at {f} Hz, roller passage {expected} Hz"
    );
    // docs/GEARBOX.md's verification row: the reference and the measured frequency
    assert_eq!(
        common::gearbox_doc_measured("HSS bearing hss_a in a carrier revolution"),
        format!("{f:.1} Hz")
    );
    let page = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/GEARBOX.md")).unwrap();
    let reference = format!("roller passage Z·f_shaft·(1 − D/d_m)/2 = {expected:.0} Hz");
    assert!(page.contains(&reference), "docs/GEARBOX.md should give {reference}");

    let mut dyno = d.clone();
    dyno.rotor.as_mut().unwrap().mass = Some(1.0);
    let r = revolution(&dyno, &Gearbox::new(&dyno).unwrap(), rpm, None);
    for p in 0..3 {
        assert!(r.swing[p] > 1.02, "dynamometer, planet {}: swing {}", p + 1, r.swing[p]);
        let from_right = r.peak_from_right_deg()[p];
        assert!(
            from_right > 135.0,
            "dynamometer, planet {}: peak {from_right:.0}° from the right horizontal, not left of the sun",
            p + 1
        );
    }
}
