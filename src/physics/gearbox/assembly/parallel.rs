//! A parallel stage added to the gearbox under assembly: the gear on the axis of the body upstream
//! (`base`), the pinion off it, their bearings and the gear–pinion mesh, in the housing frame.

use super::builder::{Builder, MeshSpec, direction, inertia, pair};
use crate::physics::gearbox::description as desc;
use crate::physics::gearbox::model::BodyKind;

/// Adds parallel stage `s` (the `count`-th parallel one) with its gear centred at `base` and its
/// mesh's specification; returns its input (the gear) and output (the pinion) bodies.
pub(super) fn add_stage<'a>(
    b: &mut Builder<'a>,
    s: usize,
    p: &'a desc::Parallel,
    count: usize,
    base: [f64; 2],
    mesh_specs: &mut Vec<MeshSpec<'a>>,
) -> Result<(usize, usize), String> {
    let at = |f: &str| format!("stage[{}].{f}", s + 1);
    let density = b.d.model.density;
    let t = &p.toothing;
    let gp = pair(
        t,
        [p.teeth.pinion, p.teeth.gear],
        [p.profile_shift.pinion, p.profile_shift.gear],
        false,
        p.centre_distance_mm.map(|a| a * 1e-3),
    );
    let g = gp.geometry().map_err(|e| format!("{}: {e}", at("teeth")))?;
    let w = t.face_width_mm * 1e-3;
    let dir = direction(p.pinion_direction_deg);
    let gear = b.add_body(
        format!("gear_{count}"),
        BodyKind::Gear,
        Some(s),
        None,
        base,
        inertia(&p.gear, Some((gp.reference_radius(1), w)), density, &at("gear"))?,
        false,
    );
    b.supports("", gear, &p.gear, None, [0.0; 2]);
    let centre = [
        base[0] + g.centre_distance * dir[0],
        base[1] + g.centre_distance * dir[1],
    ];
    let pinion = b.add_body(
        format!("pinion_{count}"),
        BodyKind::Pinion,
        Some(s),
        None,
        centre,
        inertia(&p.pinion, Some((gp.reference_radius(0), w)), density, &at("pinion"))?,
        false,
    );
    b.supports("", pinion, &p.pinion, None, [0.0; 2]);
    mesh_specs.push(MeshSpec {
        name: format!("gear_pinion_{count}"),
        driver: gear,
        driven: pinion,
        internal: false,
        geometry: g,
        pair: gp,
        toothing: t,
        data: p.mesh,
        torsional_radius: gp.base_radius(0),
        roll_body: pinion,
        roll_teeth: p.teeth.pinion,
        phase: 0.0,
        hand: if t.helix_angle_deg < 0.0 { -1.0 } else { 1.0 },
    });
    Ok((gear, pinion))
}
