//! Each mesh's line-of-action rows, slices, stiffness and damping, and the rigid-body rotation of the
//! chain that orients every drive flank.

use super::builder::{Builder, MeshSpec, cross};
use crate::physics::gearbox::description::{ForceLaw, MeshStiffnessModel};
use crate::physics::gearbox::mesh::{FlankSums, Law, Mesh, Phase};
use crate::physics::gearbox::model::SPIN;
use crate::physics::gearbox::row::Row;
use crate::solver::norms::max_abs;

/// The line-of-action rows of a mesh (drive flank oriented by σ), its slices, stiffness and damping.
pub(super) fn add_mesh(b: &mut Builder, m: &MeshSpec, sigma: f64) -> Result<(), String> {
    let g = &m.geometry;
    let (ca, cb) = (b.bodies[m.driver].centre, b.bodies[m.driven].centre);
    // e: unit vector from the driver's centre to the driven wheel's (for a ring, from the axis out
    // to the planet); t = e_z × e
    let (dx, dy) = (cb[0] - ca[0], cb[1] - ca[1]);
    let len = (dx * dx + dy * dy).sqrt();
    if len <= 0.0 {
        return Err(format!("mesh {}: the wheels' centres coincide", m.name));
    }
    let e = [dx / len, dy / len];
    let t = [-e[1], e[0]];
    // the pitch point from each centre, and the sense in which the contact force pushes the driven
    // wheel off the driver: an external pair's pitch point lies between the centres (wheel 2 of the
    // pair is the driver: the planet of sun–planet, the gear of gear–pinion) and the force separates
    // them; a ring's lies beyond the planet, and it pushes the planet towards the axis
    let (p_driver, p_driven, radial) = if m.internal {
        let (rw_planet, rw_ring) = (g.pitch_radius[0], g.pitch_radius[1]);
        (
            [rw_ring * e[0], rw_ring * e[1]],
            [rw_planet * e[0], rw_planet * e[1]],
            -1.0,
        )
    } else {
        let (rw_driven, rw_driver) = (g.pitch_radius[0], g.pitch_radius[1]);
        (
            [rw_driver * e[0], rw_driver * e[1]],
            [-rw_driven * e[0], -rw_driven * e[1]],
            1.0,
        )
    };
    let (sa, ca_) = g.pressure_angle.sin_cos();
    let (sb, cbb) = g.base_helix.sin_cos();
    // the 3-D normal in the plane of action: transverse line of action (tangential part oriented by
    // σ and the flank, radial part separating) inclined by the base helix angle; the axial thrust
    // turns with the tangential force
    let build = |flank: f64| -> [f64; 3] {
        let nt = [
            flank * sigma * ca_ * t[0] + radial * sa * e[0],
            flank * sigma * ca_ * t[1] + radial * sa * e[1],
        ];
        [cbb * nt[0], cbb * nt[1], flank * sigma * m.hand * sb]
    };
    let driver_arm = cross([p_driver[0], p_driver[1], 0.0], build(1.0))[2];
    let mut drive = [Row::default(), Row::default()];
    let mut back = [Row::default(), Row::default()];
    for (rows, flank) in [(&mut drive, 1.0), (&mut back, -1.0)] {
        let n = build(flank);
        b.point(&mut rows[0], m.driver, [p_driver[0], p_driver[1], 0.0], n, 1.0);
        b.point(&mut rows[0], m.driven, [p_driven[0], p_driven[1], 0.0], n, -1.0);
        b.lever(&mut rows[1], m.driver, n, 1.0);
        b.lever(&mut rows[1], m.driven, n, -1.0);
        rows[0].compact();
        rows[1].compact();
    }
    let settings = &b.d.model;
    let w = m.toothing.face_width_mm * 1e-3;
    let slices = settings.slices;
    let zeta: Vec<f64> = (0..slices)
        .map(|j| -0.5 * w + (j as f64 + 0.5) * w / slices as f64)
        .collect();
    let crown = m.toothing.crowning_um * 1e-6;
    let slope = m.toothing.lead_slope_um * 1e-6;
    let relief = |z: f64| -crown * (2.0 * z / w).powi(2);
    let error: Vec<f64> = zeta.iter().map(|&z| relief(z) + slope * z / w).collect();
    let error_back: Vec<f64> = zeta.iter().map(|&z| relief(z) - slope * z / w).collect();
    // mean normal stiffness of the whole mesh
    let arm = m.torsional_radius * cbb;
    let k_total = match (m.data.stiffness, m.data.torsional_stiffness) {
        (Some(k), _) => k,
        (None, Some(kt)) => kt / (arm * arm),
        (None, None) => m.pair.iso_stiffness(g.contact_ratio).1 * w,
    };
    // equivalent masses along the line of action for the damping ratio
    let along = |i: usize, r_point: [f64; 2]| -> f64 {
        let body = &b.bodies[i];
        if body.first.is_none() {
            return f64::INFINITY;
        }
        let r = (r_point[0] * r_point[0] + r_point[1] * r_point[1]).sqrt();
        let rb = r * ca_ * cbb;
        body.polar / (rb * rb).max(1e-300)
    };
    let line_masses = [along(m.driver, p_driver), along(m.driven, p_driven)];
    let m_eq = 1.0 / (1.0 / line_masses[0] + 1.0 / line_masses[1]);
    let c_total = match (m.data.damping, m.data.torsional_damping) {
        (Some(c), _) => c,
        (None, Some(ct)) => ct / (arm * arm),
        (None, None) => 2.0 * settings.mesh_damping_ratio * (k_total * m_eq).sqrt(),
    };
    let law = match settings.force_law {
        ForceLaw::Linear => Law::Linear,
        ForceLaw::Impact { exponent, penetration } => Law::Impact { exponent, penetration },
    };
    let phase = match settings.mesh_stiffness {
        MeshStiffnessModel::Mean => None,
        MeshStiffnessModel::Varying => {
            let mut roll = Row::default();
            if let Some(f) = b.bodies[m.roll_body].first {
                roll.add(f + SPIN, 1.0);
            }
            if let Some(fs) = b.frame_spin(m.roll_body) {
                roll.add(fs, -1.0);
            }
            roll.compact();
            Some(Phase {
                roll,
                teeth: f64::from(m.roll_teeth),
                offset: m.phase,
                stagger: g.base_helix.tan() / g.base_pitch,
                contact_ratio: g.contact_ratio,
                slice_roll: g.base_helix.tan() / g.base_pitch * w / slices as f64,
            })
        }
    };
    let sums = [FlankSums::of(&zeta, &error), FlankSums::of(&zeta, &error_back)];
    b.meshes.push(Mesh {
        name: m.name.clone(),
        drive,
        back,
        zeta,
        error,
        error_back,
        k_slice: k_total / slices as f64,
        c_slice: c_total / slices as f64,
        backlash: m.toothing.backlash_um * 1e-6,
        law,
        phase,
        face_width: w,
        driver_arm,
        line_masses,
        sums,
    });
    b.geometry.push(*g);
    Ok(())
}

/// Spins of the free chain when the input turns one radian: the kinematic ratios read off the mesh
/// rows (a rigid rotation compresses no mesh) and shafts; a spin held to the housing by a rotational
/// support (an elastically mounted ring) stays at 0. None when the chain is not free (the input is
/// held, or a held spin contradicts the kinematics).
pub(super) fn rigid_mode(b: &Builder, input: usize) -> Option<Vec<f64>> {
    let n = b.dofs;
    let mut r = vec![f64::NAN; n];
    for body in &b.bodies {
        if let Some(f) = body.first {
            r[f..f + SPIN].iter_mut().for_each(|x| *x = 0.0);
        }
    }
    let held: Vec<usize> = b
        .springs
        .iter()
        .filter(|s| s.stiffness > 0.0)
        .filter_map(|s| match *s.row.indices() {
            [i] if b.bodies.iter().any(|x| x.first.map(|f| f + SPIN) == Some(i)) => Some(i),
            _ => None,
        })
        .collect();
    for &h in &held {
        r[h] = 0.0;
    }
    let start = b.bodies[input].first? + SPIN;
    if held.contains(&start) {
        return None;
    }
    r[start] = 1.0;
    // a shaft's nodes turn with its upstream end
    let links: Vec<(usize, usize)> = b
        .shafts
        .iter()
        .map(|&(u, d, _, _)| (u, d))
        .chain(
            b.shafts
                .iter()
                .zip(&b.beam_nodes)
                .flat_map(|(&(u, _, _, _), nodes)| nodes.iter().map(move |&k| (u, k))),
        )
        .collect();
    for _ in 0..4 * b.bodies.len() + 4 {
        let mut changed = false;
        for &(u, d) in &links {
            let (fu, fd) = (b.bodies[u].first? + SPIN, b.bodies[d].first? + SPIN);
            if r[fu].is_nan() != r[fd].is_nan() {
                let v = if r[fu].is_nan() { r[fd] } else { r[fu] };
                r[fu] = v;
                r[fd] = v;
                changed = true;
            }
        }
        for m in &b.meshes {
            let (idx, val) = (m.drive[0].indices(), m.drive[0].values());
            let unknown: Vec<usize> = (0..idx.len()).filter(|&k| r[idx[k]].is_nan()).collect();
            if let [k] = unknown[..] {
                let known: f64 = (0..idx.len()).filter(|&i| i != k).map(|i| val[i] * r[idx[i]]).sum();
                r[idx[k]] = -known / val[k];
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    if r.iter().any(|x| x.is_nan()) {
        return None;
    }
    // every mesh and shaft must be blind to it
    let scale = max_abs(&r);
    let consistent = b.meshes.iter().all(|m| {
        let g = m.drive[0].dot(&r);
        let size: f64 = m.drive[0].values().iter().map(|v| v.abs()).sum::<f64>() * scale;
        g.abs() <= 1e-9 * size
    });
    consistent.then_some(r)
}
