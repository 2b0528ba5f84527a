//! Shafts: beam shafts' nodes and element springs, every shaft's torsion spring, and the mass
//! matrix once all bodies exist.

use super::builder::Builder;
use crate::physics::gearbox::beam;
use crate::physics::gearbox::description::{self as desc};
use crate::physics::gearbox::model::{BodyKind, SPIN, ShaftSpring, TX, TY, UX, UY, UZ};
use crate::physics::gearbox::row::Row;
use nalgebra::DMatrix;

/// Area, second moment of area and shear coefficient of a beam's section; Poisson's ratio from E and G.
fn section(beam: &desc::Beam) -> (f64, f64, f64) {
    beam::hollow_section(
        beam.outer_diameter_mm * 1e-3,
        beam.inner_diameter_mm * 1e-3,
        beam.youngs_modulus / (2.0 * beam.shear_modulus) - 1.0,
    )
}

/// Nodes between the elements of every beam of two or more elements, evenly along its free length,
/// on the axis of the body upstream and in its frame. A lumped-mass beam: each node carries one
/// element's mass ρAL/n and its section's rotary inertia, ρIL/n about a diameter and 2ρIL/n about
/// the axis; the half-elements at the two ends belong to the bodies the shaft joins (their described
/// masses).
pub(super) fn add_beam_nodes(b: &mut Builder) {
    let density = b.d.model.density;
    for index in 0..b.shafts.len() {
        let (u, _, spec, name) = b.shafts[index].clone();
        let Some(beam) = spec.beam.filter(|beam| beam.elements > 1) else {
            b.beam_nodes.push(Vec::new());
            continue;
        };
        let (area, second_moment, _) = section(&beam);
        let element = beam.length_m / f64::from(beam.elements);
        let inertia = (
            density * area * element,
            2.0 * density * second_moment * element,
            density * second_moment * element,
        );
        let (frame, centre) = (b.bodies[u].frame, b.bodies[u].centre);
        let nodes = (1..beam.elements)
            .map(|k| {
                b.add_body(
                    format!("{name}_node_{k}"),
                    BodyKind::ShaftNode,
                    None,
                    frame,
                    centre,
                    inertia,
                    false,
                )
            })
            .collect();
        b.beam_nodes.push(nodes);
    }
}

/// One Timoshenko element of a flexible shaft, `length` long, from body `ends[0].0` (leaving it at
/// `ends[0].1` along the axis from its centre) to body `ends[1].0` (entering at `ends[1].1`): its
/// bending in the x–z plane (w = u_x, φ = θ_y) and the y–z plane (w = u_y, φ = −θ_x, as
/// du_y/dz = −θ_x), and its axial stretch, as springs on the ends' rows.
fn beam_springs(b: &mut Builder, ends: [(usize, f64); 2], beam: &desc::Beam, length: f64, tau: f64) {
    let (e, g) = (beam.youngs_modulus, beam.shear_modulus);
    let (area, second_moment, kappa) = section(beam);
    let k = beam::bending_stiffness(e * second_moment, kappa * g * area, length);
    let translation = |b: &Builder, (body, z): (usize, f64), n: [f64; 3]| {
        let mut row = Row::default();
        b.point(&mut row, body, [0.0, 0.0, z], n, 1.0);
        row
    };
    let tilt = |b: &Builder, body: usize, dof: usize, sign: f64| {
        let mut row = Row::default();
        if let Some(f) = b.bodies[body].first {
            row.add(f + dof, sign);
        }
        row
    };
    for (n, dof, sign) in [([1.0, 0.0, 0.0], TY, 1.0), ([0.0, 1.0, 0.0], TX, -1.0)] {
        let rows = [
            translation(b, ends[0], n),
            tilt(b, ends[0].0, dof, sign),
            translation(b, ends[1], n),
            tilt(b, ends[1].0, dof, sign),
        ];
        for (stiffness, v) in beam::springs(&k) {
            let mut row = Row::default();
            for (r, c) in rows.iter().zip(v) {
                for (i, x) in r.entries() {
                    row.add(i, c * x);
                }
            }
            row.compact();
            b.spring(row, stiffness, stiffness * tau, 0.0);
        }
    }
    let axial = e * area / length;
    let mut row = translation(b, ends[0], [0.0, 0.0, 1.0]);
    let downstream = translation(b, ends[1], [0.0, 0.0, 1.0]);
    for (i, x) in downstream.entries() {
        row.add(i, -x);
    }
    row.compact();
    b.spring(row, axial, axial * tau, 0.0);
}

/// Shaft springs (with damping from the shaft ratio and the inertia on either side) and the mass matrix.
pub(super) fn finish(b: &mut Builder, rigid: &Option<Vec<f64>>) -> Result<(Vec<ShaftSpring>, DMatrix<f64>), String> {
    let n = b.dofs;
    let mut shafts = Vec::new();
    let spin_ratio = |b: &Builder, i: usize| -> f64 {
        match (rigid, b.bodies[i].first) {
            (Some(r), Some(f)) => r[f + SPIN],
            _ => 1.0,
        }
    };
    let shaft_list = b.shafts.clone();
    for (index, (u, d, spec, name)) in shaft_list.into_iter().enumerate() {
        let same_frame = b.bodies[u].frame == b.bodies[d].frame;
        if !same_frame && (spec.radial > 0.0 || spec.tilting > 0.0 || spec.beam.is_some()) {
            return Err(format!(
                "shaft {name} ({} → {}): radial or tilting stiffness joins bodies in different rotating frames; \
                 only a spline (torsional, axial) can join them",
                b.bodies[u].name, b.bodies[d].name
            ));
        }
        let ratio = spin_ratio(b, d);
        let inertia_side = |up: bool| -> f64 {
            b.bodies
                .iter()
                .enumerate()
                .filter(|(i, body)| {
                    body.first.is_some() && body.kind != BodyKind::ShaftNode && if up { *i <= u } else { *i >= d }
                })
                .map(|(i, body)| body.polar * (spin_ratio(b, i) / ratio).powi(2))
                .sum()
        };
        let (ju, jd) = (inertia_side(true), inertia_side(false));
        let j_eq = ju * jd / (ju + jd);
        let c = spec
            .torsional_damping
            .unwrap_or(2.0 * b.d.model.shaft_damping_ratio * (spec.torsional * j_eq).sqrt());
        let (fu, fd) = (
            b.bodies[u].first.ok_or("shaft from the housing")?,
            b.bodies[d].first.ok_or("shaft to the housing")?,
        );
        // a beam of n elements: n torsion springs in series, each n times as stiff and as damped as
        // the shaft, the first (at the upstream end) reporting the shaft's torque
        let nodes = b.beam_nodes[index].clone();
        // spin DOFs along the chain: the ends' checked above, a node's always its own
        let spins: Vec<usize> = std::iter::once(fu)
            .chain(nodes.iter().filter_map(|&k| b.bodies[k].first))
            .chain(std::iter::once(fd))
            .map(|f| f + SPIN)
            .collect();
        let elements = (spins.len() - 1) as f64;
        let first_torsion = b.springs.len();
        for pair in spins.windows(2) {
            let mut torsion = Row::default();
            torsion.add(pair[0], 1.0);
            torsion.add(pair[1], -1.0);
            b.spring(torsion, elements * spec.torsional, elements * c, 0.0);
        }
        if !b.webs.contains(&index) {
            shafts.push(ShaftSpring {
                name: name.clone(),
                spring: first_torsion,
                sign: ratio.signum(),
            });
        }
        let tau = b.d.model.bearing_damping_time;
        if let Some(beam) = &spec.beam {
            let chain: Vec<usize> = std::iter::once(u).chain(nodes).chain(std::iter::once(d)).collect();
            let length = beam.length_m / elements;
            let last = chain.len() - 2;
            for (k, pair) in chain.windows(2).enumerate() {
                let from = if k == 0 { beam.from_m } else { 0.0 };
                let to = if k == last { beam.to_m } else { 0.0 };
                beam_springs(b, [(pair[0], from), (pair[1], to)], beam, length, tau);
            }
        }
        for (k, stiffness) in [
            (UX, spec.radial),
            (UY, spec.radial),
            (UZ, spec.axial),
            (TX, spec.tilting),
            (TY, spec.tilting),
        ] {
            if stiffness > 0.0 {
                let mut row = Row::default();
                row.add(fu + k, 1.0);
                row.add(fd + k, -1.0);
                b.spring(row, stiffness, stiffness * tau, 0.0);
            }
        }
    }
    // mass: six diagonal terms per body plus a planet's orbit coupled to its carrier's spin
    let mut m = DMatrix::zeros(n, n);
    for body in &b.bodies {
        let Some(f) = body.first else { continue };
        for k in 0..3 {
            m[(f + k, f + k)] = body.mass;
        }
        m[(f + TX, f + TX)] = body.transverse;
        m[(f + TY, f + TY)] = body.transverse;
        m[(f + SPIN, f + SPIN)] = body.polar;
        if let Some(c) = body.frame
            && let Some(fc) = b.bodies[c].first
        {
            let p = body.centre;
            let jp = [-p[1], p[0]];
            for (k, v) in [(UX, jp[0]), (UY, jp[1])] {
                m[(f + k, fc + SPIN)] += body.mass * v;
                m[(fc + SPIN, f + k)] += body.mass * v;
            }
            m[(fc + SPIN, fc + SPIN)] += body.mass * (p[0] * p[0] + p[1] * p[1]);
        }
    }
    Ok((shafts, m))
}
