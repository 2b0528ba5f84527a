//! A planetary stage added to the gearbox under assembly: carrier (with its downwind plate when the
//! webs are modelled), planets on their pins, sun and ring, with their bearings and the ring–planet
//! and sun–planet meshes, every small motion in the carrier's frame.

use super::builder::{Builder, MeshSpec, direction, inertia, pair};
use crate::physics::gearbox::description as desc;
use crate::physics::gearbox::model::BodyKind;
use std::f64::consts::TAU;

/// Adds planetary stage `s` (the `count`-th planetary one) and its meshes' specifications; returns
/// its input (the carrier) and output (the sun) bodies.
pub(super) fn add_stage<'a>(
    b: &mut Builder<'a>,
    s: usize,
    p: &'a desc::Planetary,
    count: usize,
    mesh_specs: &mut Vec<MeshSpec<'a>>,
) -> Result<(usize, usize), String> {
    let at = |f: &str| format!("stage[{}].{f}", s + 1);
    let density = b.d.model.density;
    let suffix = if count == 1 { String::new() } else { count.to_string() };
    let t = &p.toothing;
    let sp = pair(
        t,
        [p.teeth.sun, p.teeth.planet],
        [p.profile_shift.sun, p.profile_shift.planet],
        false,
        p.centre_distance_mm.map(|a| a * 1e-3),
    );
    let gsp = sp.geometry().map_err(|e| format!("{}: sun–planet {e}", at("teeth")))?;
    let a = gsp.centre_distance;
    let rp = pair(
        t,
        [p.teeth.planet, p.teeth.ring],
        [p.profile_shift.planet, p.profile_shift.ring],
        true,
        Some(a),
    );
    let grp = rp.geometry().map_err(|e| format!("{}: ring–planet {e}", at("teeth")))?;
    let w = t.face_width_mm * 1e-3;
    let carrier_index = b.bodies.len();
    let carrier_inertia = inertia(&p.carrier, None, density, &at("carrier"))?;
    let upwind_share = p.carrier_webs.map_or(1.0, |w| 1.0 - w.downwind_share);
    let share = |s: f64| (carrier_inertia.0 * s, carrier_inertia.1 * s, carrier_inertia.2 * s);
    let carrier = b.add_body(
        format!("carrier_{count}"),
        BodyKind::Carrier,
        Some(s),
        Some(carrier_index),
        [0.0; 2],
        share(upwind_share),
        false,
    );
    let plate = p.carrier_webs.map(|w| {
        let plate = b.add_body(
            format!("carrier_{count}_downwind"),
            BodyKind::Carrier,
            Some(s),
            Some(carrier),
            [0.0; 2],
            share(w.downwind_share),
            false,
        );
        // the webs' damping from the shaft damping ratio and the plate's own inertia
        let c = 2.0 * b.d.model.shaft_damping_ratio * (w.torsional * carrier_inertia.1 * w.downwind_share).sqrt();
        let webs = desc::Shaft {
            torsional: w.torsional,
            torsional_damping: Some(c),
            radial: w.radial,
            axial: w.radial,
            tilting: w.tilting,
            beam: None,
        };
        b.webs.push(b.shafts.len());
        b.shafts.push((carrier, plate, webs, format!("carrier_webs{suffix}")));
        plate
    });
    b.downwind_plate = plate.map(|pl| (carrier, pl));
    b.supports("", carrier, &p.carrier, None, [0.0; 2]);
    let sun_r = sp.reference_radius(0);
    let planet_r = sp.reference_radius(1);
    let planet_inertia = inertia(&p.planet, Some((planet_r, w)), density, &at("planet"))?;
    let sun_inertia = inertia(&p.sun, Some((sun_r, w)), density, &at("sun"))?;
    let mut planets = Vec::new();
    for n in 0..p.planets {
        let psi = p.first_planet_deg + 360.0 * n as f64 / p.planets as f64;
        let e = direction(psi);
        let centre = [a * e[0], a * e[1]];
        let i = b.add_body(
            format!("planet_{count}_{}", n + 1),
            BodyKind::Planet,
            Some(s),
            Some(carrier),
            centre,
            planet_inertia,
            false,
        );
        // pin error: tangential, positive ahead in the +spin sense (e_z × e)
        let err = p.pin_errors_um.get(n).copied().unwrap_or(0.0) * 1e-6;
        let tangent = [-e[1], e[0]];
        b.supports(
            &format!("planet{suffix}_{}", n + 1),
            i,
            &p.planet,
            Some((carrier, centre)),
            [err * tangent[0], err * tangent[1]],
        );
        planets.push((i, psi.to_radians(), e));
    }
    b.downwind_plate = None;
    let sun = b.add_body(
        format!("sun_{count}"),
        BodyKind::Sun,
        Some(s),
        Some(carrier),
        [0.0; 2],
        sun_inertia,
        false,
    );
    b.supports("", sun, &p.sun, None, [0.0; 2]);
    let ring = match &p.ring {
        None => b.add_body(
            format!("ring_{count}"),
            BodyKind::Ring,
            Some(s),
            Some(carrier),
            [0.0; 2],
            (0.0, 0.0, 0.0),
            true,
        ),
        Some(r) => {
            let i = b.add_body(
                format!("ring_{count}"),
                BodyKind::Ring,
                Some(s),
                Some(carrier),
                [0.0; 2],
                inertia(r, None, density, &at("ring"))?,
                false,
            );
            b.supports("", i, r, None, [0.0; 2]);
            i
        }
    };
    let hand = if t.helix_angle_deg < 0.0 { -1.0 } else { 1.0 };
    for (n, &(planet, psi, _)) in planets.iter().enumerate() {
        // in the carrier's frame the ring drives the planets and the planets drive the sun
        mesh_specs.push(MeshSpec {
            name: format!("ring_planet{suffix}_{}", n + 1),
            driver: ring,
            driven: planet,
            internal: true,
            geometry: grp,
            pair: rp,
            toothing: t,
            data: p.ring_planet,
            torsional_radius: sp.base_radius(0),
            roll_body: ring,
            roll_teeth: p.teeth.ring,
            phase: (-f64::from(p.teeth.ring) * psi / TAU).rem_euclid(1.0),
            hand,
        });
        mesh_specs.push(MeshSpec {
            name: format!("sun_planet{suffix}_{}", n + 1),
            driver: planet,
            driven: sun,
            internal: false,
            geometry: gsp,
            pair: sp,
            toothing: t,
            data: p.sun_planet,
            torsional_radius: sp.base_radius(0),
            roll_body: sun,
            roll_teeth: p.teeth.sun,
            phase: (f64::from(p.teeth.sun) * psi / TAU).rem_euclid(1.0),
            // the planet meshes the sun and the ring on opposite sides, so the same
            // planet tooth hand tilts the normal the other way against the carrier's
            // tangent t (built from driver to driven, which flips between the two
            // meshes): with `hand` as for the ring, the axial components on a planet
            // cancel and form the overturning couple of a helical planet
            hand,
        });
    }
    Ok((carrier, sun))
}
