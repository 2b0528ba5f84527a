//! The sliced gear mesh: N springs across the face width along the 3-D line of action.
//!
//! Slice j at axial position ζ_j (from the face centre) is compressed by
//! δ_j = g₀·q + ζ_j·g₁·q + e_j, where g₀ is the line-of-action row at the pitch point (both bodies'
//! translations, tilts and spins relative to their frames) and g₁ its change across the face (the
//! tilt lever), e_j the lead error (crowning relief, lead slope: misalignment). The back flank has
//! its own rows (mirrored line of action) and contacts when its compression exceeds the backlash.
//! Forces, tangents and patterns only need the slice sums Σf, Σζf, Σk, Σζk, Σζ²k, so a mesh costs
//! O(slices) scalar work and two row updates whatever the DOF count; under the linear law at the mean
//! stiffness a flank whose slices all touch, or none, costs O(1) (its sums in closed form, [`FlankSums`]).

use super::contact::ContactStress;
use super::involute::{mean_pairs_in_contact, pairs_in_contact};
use super::row::{Row, add_outer, add_symmetric};
use nalgebra::DMatrix;

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Law {
    /// f = k·δ + c·δ̇ while δ > 0.
    Linear,
    /// f = k·δ^e + c·s(δ/d)·δ̇ while δ > 0, s the cubic step from 0 to 1 over the penetration d.
    Impact { exponent: f64, penetration: f64 },
}

/// Mesh phase for the single/double tooth stiffness: roll position s = teeth·(row·q)/2π + offset
/// (base pitches), slice j at s + stagger·ζ_j (helical contact lines cross the face).
#[derive(Debug, Clone, PartialEq)]
pub struct Phase {
    pub roll: Row,
    pub teeth: f64,
    pub offset: f64,
    pub stagger: f64,
    pub contact_ratio: f64,
    /// Roll a slice spans across its width, base pitches (stagger × slice width; 0 for spur).
    pub slice_roll: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// Output name: `sun_planet_1`, `ring_planet2_3`, `gear_pinion_1` (as `torsional`'s mesh forces).
    pub name: String,
    pub drive: [Row; 2],
    pub back: [Row; 2],
    pub zeta: Vec<f64>,
    pub error: Vec<f64>,
    pub error_back: Vec<f64>,
    /// Mean stiffness and damping per slice (N/m, or N/m^e for the impact law; N·s/m).
    pub k_slice: f64,
    pub c_slice: f64,
    /// Normal backlash, m.
    pub backlash: f64,
    pub law: Law,
    pub phase: Option<Phase>,
    pub face_width: f64,
    /// (r × n)_z of the driver's contact point: its spin's lever on the drive flank.
    pub driver_arm: f64,
    /// Driver's and driven wheel's polar inertia over the squared base-radius lever, kg: each
    /// wheel's mass along the line of action (infinite for a housing ring). They set the damping
    /// ratio's critical damping and ISO 6336-1's reduced mass.
    pub line_masses: [f64; 2],
    /// The drive and back flanks' slice sums ([`FlankSums::of`] of `zeta` and `error`, `error_back`).
    pub sums: [FlankSums; 2],
}

/// What a flank's force and moment under the linear law at the mean stiffness need when every slice
/// touches: the slices' sums Σ1, Σζ, Σζ² and Σe, Σζe of their lead errors; and where to look to tell
/// that every slice touches or none does. A slice's compression d₀ + ζ·d₁ + e − gap is affine in the
/// flank's (d₀, d₁), so the smallest over the slices is at a vertex of the lower convex hull of the
/// points (ζ_j, e_j) (with crowning, the face's two ends) and the largest is at most d₀ − gap +
/// max e + max(ζ_first·d₁, ζ_last·d₁).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FlankSums {
    zeta: [f64; 3],
    error: [f64; 2],
    /// The slices at the lower hull's vertices.
    lowest: Vec<usize>,
    largest_error: f64,
}

impl FlankSums {
    /// The sums over slices at `zeta` (ascending) with lead errors `error`.
    pub fn of(zeta: &[f64], error: &[f64]) -> Self {
        let (mut z, mut e) = ([0.0; 3], [0.0; 2]);
        for (&zj, &ej) in zeta.iter().zip(error) {
            z[0] += 1.0;
            z[1] += zj;
            z[2] += zj * zj;
            e[0] += ej;
            e[1] += zj * ej;
        }
        // Andrew's monotone chain, lower half: a vertex leaves when the turn it makes is not convex
        let mut lowest: Vec<usize> = Vec::new();
        for j in 0..zeta.len() {
            while let [.., a, b] = lowest[..] {
                let cross = (zeta[b] - zeta[a]) * (error[j] - error[a]) - (error[b] - error[a]) * (zeta[j] - zeta[a]);
                if cross > 0.0 {
                    break;
                }
                lowest.pop();
            }
            lowest.push(j);
        }
        Self {
            zeta: z,
            error: e,
            lowest,
            largest_error: error.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        }
    }
}

/// Slice sums of one flank, and where the per-slice loads are asked for ([`Mesh::add_forces`] with
/// `slice`), its largest slice load and that slice's place across the face (the first of equal ones;
/// 0 and 0 when no slice touches or the slices were not asked for).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FlankLoad {
    pub force: f64,
    pub moment: f64,
    pub largest: f64,
    pub largest_at: f64,
}

/// The loads a mesh reports.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MeshReport {
    /// Drive-flank minus back-flank total normal force, N.
    pub force: f64,
    /// Largest slice load of the loaded flank (N, negative on the back flank) and its position
    /// across the face (m from the centre).
    pub max_slice: f64,
    pub max_position: f64,
    /// Face load factor K_Hβ of the loaded flank: its largest over its mean slice load (1 when
    /// unloaded).
    pub face_load_factor: f64,
    /// Mean compression at the face centre along the line of action (transmission error), m.
    pub transmission_error: f64,
    /// Hertz contact of the most loaded slice (filled by the gearbox, which knows the geometry).
    pub contact: ContactStress,
}

impl Mesh {
    pub fn slices(&self) -> usize {
        self.zeta.len()
    }

    /// Roll position of the face centre in base pitches, with varying stiffness (None: mean).
    fn roll(&self, q: &[f64]) -> Option<f64> {
        self.phase
            .as_ref()
            .map(|p| p.teeth * p.roll.dot(q) / std::f64::consts::TAU + p.offset)
    }

    /// Tooth-mesh frequency at speeds `v` (Hz): teeth passing per second of the wheel whose spin,
    /// relative to its frame, rolls the mesh. None at mean stiffness (no roll phase kept).
    pub fn mesh_frequency(&self, v: &[f64]) -> Option<f64> {
        self.phase
            .as_ref()
            .map(|p| (p.teeth * p.roll.dot(v) / std::f64::consts::TAU).abs())
    }

    /// Tooth pairs at slice j (its contact line staggered across the face) and the contact ratio.
    fn pairs(&self, roll: Option<f64>, j: usize) -> Option<(u32, f64)> {
        let p = self.phase.as_ref()?;
        let s = roll? + p.stagger * self.zeta[j];
        Some((pairs_in_contact(s, p.contact_ratio), p.contact_ratio))
    }

    /// Stiffness of slice j: the mean per slice, scaled by its tooth pairs (their mean over the roll
    /// the slice spans) over the contact ratio.
    fn slice_stiffness(&self, roll: Option<f64>, j: usize) -> f64 {
        match (self.phase.as_ref(), roll) {
            (Some(p), Some(r)) => {
                let s = r + p.stagger * self.zeta[j];
                self.k_slice * mean_pairs_in_contact(s, p.slice_roll, p.contact_ratio) / p.contact_ratio
            }
            _ => self.k_slice,
        }
    }

    fn slice_force(&self, k: f64, d: f64, rate: f64) -> f64 {
        match self.law {
            Law::Linear => k * d + self.c_slice * rate,
            Law::Impact { exponent, penetration } => k * d.powf(exponent) + self.c_slice * ramp(d / penetration) * rate,
        }
    }

    /// d f/d δ and d f/d δ̇ of one slice.
    fn slice_tangent(&self, k: f64, d: f64, rate: f64) -> (f64, f64) {
        match self.law {
            Law::Linear => (k, self.c_slice),
            Law::Impact { exponent, penetration } => {
                let x = d / penetration;
                (
                    k * exponent * d.powf(exponent - 1.0) + self.c_slice * ramp_slope(x) / penetration * rate,
                    self.c_slice * ramp(x),
                )
            }
        }
    }

    /// Compressions of one flank at the face centre and their slope across the face, and rates.
    fn flank(&self, rows: &[Row; 2], q: &[f64], v: &[f64]) -> (f64, f64, f64, f64) {
        let ((d0, r0), (d1, r1)) = (rows[0].dot2(q, v), rows[1].dot2(q, v));
        (d0, d1, r0, r1)
    }

    /// Flank 0 (drive) or 1 (back): its rows, its lead errors and the gap it closes before contact.
    fn flank_parts(&self, flank: usize) -> (&[Row; 2], &[f64], f64) {
        if flank == 0 {
            (&self.drive, &self.error, 0.0)
        } else {
            (&self.back, &self.error_back, self.backlash)
        }
    }

    /// Calls `each(j, force)` for every slice of one flank (0 drive, 1 back) in contact: the plain slice
    /// loop, which the tests hold [`Self::flank_load`]'s blocks to.
    #[cfg(test)]
    fn each_slice(&self, flank: usize, roll: Option<f64>, q: &[f64], v: &[f64], mut each: impl FnMut(usize, f64)) {
        let (rows, errors, gap) = self.flank_parts(flank);
        let (d0, d1, r0, r1) = self.flank(rows, q, v);
        for j in 0..self.slices() {
            let z = self.zeta[j];
            let d = d0 + z * d1 + errors[j] - gap;
            if d > 0.0 {
                each(j, self.slice_force(self.slice_stiffness(roll, j), d, r0 + z * r1));
            }
        }
    }

    /// One flank's force and moment, summed as [`Self::each_slice`] hands them over, the same bits:
    /// the slices' forces first, a block of them at a time (a slice out of contact gives +0, which
    /// leaves the sums as they are), then their sums in order. Under the linear law at the mean
    /// stiffness the block has no branch and vectorises: the branch per slice cost about 20
    /// instructions a slice, a tenth of the GRC's normal step. Under that law, where no per-slice
    /// loads are asked for (the Newton iteration's evaluations), a flank whose slices all touch or none
    /// does is summed in closed form instead ([`FlankSums`]): the loop's sums within their rounding, at
    /// two compressions' cost instead of 35 slices' (linear bearings: the gearbox FMU 1.12× faster over
    /// d-shutdown-6dof, docs/PERFORMANCE.md).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn flank_load(
        &self,
        flank: usize,
        roll: Option<f64>,
        q: &[f64],
        v: &[f64],
        load: &mut FlankLoad,
        mut slice: Option<&mut [f64]>,
        sign: f64,
    ) {
        const BLOCK: usize = 64;
        let (rows, errors, gap) = self.flank_parts(flank);
        let (d0, d1, r0, r1) = self.flank(rows, q, v);
        if slice.is_none() && self.law == Law::Linear && roll.is_none() {
            let sums = &self.sums[flank];
            let (Some(&first), Some(&last)) = (self.zeta.first(), self.zeta.last()) else {
                return;
            };
            if d0 - gap + sums.largest_error + (first * d1).max(last * d1) <= 0.0 {
                // no slice touches: +0 as the loop sums it
                return;
            }
            if sums
                .lowest
                .iter()
                .all(|&j| d0 + self.zeta[j] * d1 + errors[j] - gap > 0.0)
            {
                // every slice touches: the loop's sums in closed form (other rounding, about 1e-16 of the
                // flank's force: the slices' forces are all of one sign when the flank is loaded)
                let (k, c, [n, z1, z2], [e0, e1]) = (self.k_slice, self.c_slice, sums.zeta, sums.error);
                let open = d0 - gap;
                load.force = k * (n * open + z1 * d1 + e0) + c * (n * r0 + z1 * r1);
                load.moment = k * (z1 * open + z2 * d1 + e1) + c * (z1 * r0 + z2 * r1);
                return;
            }
        }
        let mut forces = [0.0; BLOCK];
        for start in (0..self.slices()).step_by(BLOCK) {
            let end = (start + BLOCK).min(self.slices());
            let (zeta, errors) = (&self.zeta[start..end], &errors[start..end]);
            let slices = forces.iter_mut().zip(zeta).zip(errors);
            if self.law == Law::Linear && roll.is_none() {
                // `slice_force`'s arithmetic at the mean stiffness, out of contact too
                let (k, c) = (self.k_slice, self.c_slice);
                for ((f, &z), &e) in slices {
                    let d = d0 + z * d1 + e - gap;
                    let force = k * d + c * (r0 + z * r1);
                    *f = if d > 0.0 { force } else { 0.0 };
                }
            } else {
                // a slice's stiffness (and the impact law's power) only where it touches
                for (k, ((f, &z), &e)) in slices.enumerate() {
                    let d = d0 + z * d1 + e - gap;
                    *f = if d > 0.0 {
                        self.slice_force(self.slice_stiffness(roll, start + k), d, r0 + z * r1)
                    } else {
                        0.0
                    };
                }
            }
            for (k, (&f, &z)) in forces.iter().zip(zeta).enumerate() {
                load.force += f;
                load.moment += z * f;
                if let Some(out) = slice.as_deref_mut() {
                    out[start + k] += sign * f;
                    // the reported largest slice: `report` took it from a second pass over the slices
                    // (a slice out of contact gives +0, never above the largest so far)
                    if f > load.largest {
                        load.largest = f;
                        load.largest_at = z;
                    }
                }
            }
        }
    }

    /// Adds the mesh's forces to f_int; per-slice loads into `slice` when given (drive positive,
    /// back negative; a slice whose flanks both touch, possible only without backlash, nets them).
    #[inline(always)]
    pub fn add_forces(&self, q: &[f64], v: &[f64], f_int: &mut [f64], mut slice: Option<&mut [f64]>) -> [FlankLoad; 2] {
        let roll = self.roll(q);
        if let Some(out) = slice.as_deref_mut() {
            out.iter_mut().for_each(|x| *x = 0.0);
        }
        let mut loads = [FlankLoad::default(); 2];
        for flank in 0..2 {
            let sign = if flank == 0 { 1.0 } else { -1.0 };
            let load = &mut loads[flank];
            self.flank_load(flank, roll, q, v, load, slice.as_deref_mut(), sign);
            let rows = self.flank_parts(flank).0;
            rows[0].axpy(load.force, f_int);
            rows[1].axpy(load.moment, f_int);
        }
        loads
    }

    /// j += c_c·C_t + c_k·K_t of this mesh at (q, v).
    pub fn add_tangent(&self, q: &[f64], v: &[f64], c_c: f64, c_k: f64, jac: &mut DMatrix<f64>) {
        let roll = self.roll(q);
        for flank in 0..2 {
            let (rows, errors, gap) = self.flank_parts(flank);
            let (d0, d1, r0, r1) = self.flank(rows, q, v);
            let mut s = [0.0; 3];
            for j in 0..self.slices() {
                let z = self.zeta[j];
                let d = d0 + z * d1 + errors[j] - gap;
                if d > 0.0 {
                    let (kt, ct) = self.slice_tangent(self.slice_stiffness(roll, j), d, r0 + z * r1);
                    let w = c_k * kt + c_c * ct;
                    s[0] += w;
                    s[1] += w * z;
                    s[2] += w * z * z;
                }
            }
            add_outer(jac, s[0], &rows[0], &rows[0]);
            add_symmetric(jac, s[1], &rows[0], &rows[1]);
            add_outer(jac, s[2], &rows[1], &rows[1]);
        }
    }

    /// Pattern bits: each slice's contact on either flank and, with varying stiffness, whether it
    /// has the larger of its two possible pair counts.
    pub fn key(&self, q: &[f64], bits: &mut KeyBits) {
        let roll = self.roll(q);
        for flank in 0..2 {
            let (rows, errors, gap) = self.flank_parts(flank);
            let (d0, d1) = (rows[0].dot(q), rows[1].dot(q));
            for j in 0..self.slices() {
                let d = d0 + self.zeta[j] * d1 + errors[j] - gap;
                bits.push(d > 0.0);
                if flank == 0
                    && let Some((pairs, ratio)) = self.pairs(roll, j)
                {
                    bits.push(f64::from(pairs) > ratio.floor());
                }
            }
        }
    }

    /// The loads a user sees at `q`, from the flank loads there as [`Self::add_forces`] gave them with
    /// the per-slice loads (which find each flank's largest slice). The face load factor and the
    /// largest slice are the loaded flank's (the one carrying more load): ISO 6336's K_Hβ is the ratio
    /// on the flank that transmits the torque, and a slice of the other flank touching at the face's
    /// end (misalignment larger than the backlash) neither adds to that flank's mean nor cancels its
    /// slices.
    pub fn report(&self, q: &[f64], loads: &[FlankLoad; 2]) -> MeshReport {
        let flank = usize::from(loads[1].force > loads[0].force);
        let sign = if flank == 0 { 1.0 } else { -1.0 };
        let (max, at) = (loads[flank].largest, loads[flank].largest_at);
        let mean = loads[flank].force / self.slices() as f64;
        MeshReport {
            force: loads[0].force - loads[1].force,
            max_slice: sign * max,
            max_position: at,
            face_load_factor: if mean > 0.0 { max / mean } else { 1.0 },
            transmission_error: self.drive[0].dot(q),
            contact: ContactStress::default(),
        }
    }
}

/// The cubic step 3x² − 2x³ on [0, 1] (damping ramped in over the penetration depth).
fn ramp(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

fn ramp_slope(x: f64) -> f64 {
    if (0.0..1.0).contains(&x) {
        6.0 * x * (1.0 - x)
    } else {
        0.0
    }
}

/// Bits packed into the solver's factor key.
pub struct KeyBits<'a> {
    pub key: &'a mut Vec<u64>,
    word: u64,
    used: u32,
}

impl<'a> KeyBits<'a> {
    pub fn new(key: &'a mut Vec<u64>) -> Self {
        key.clear();
        KeyBits { key, word: 0, used: 0 }
    }

    pub fn push(&mut self, bit: bool) {
        self.word |= u64::from(bit) << self.used;
        self.used += 1;
        if self.used == 64 {
            self.key.push(self.word);
            self.word = 0;
            self.used = 0;
        }
    }

    pub fn finish(self) {
        if self.used > 0 {
            self.key.push(self.word);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::gearbox::description::{ForceLaw, MeshStiffnessModel};
    use crate::physics::gearbox::{Description, Gearbox};
    use crate::xorshift::Xorshift;

    /// Both flanks' loads and the slices' loads, slice by slice as `each_slice` hands them over.
    fn slice_by_slice(m: &Mesh, q: &[f64], v: &[f64]) -> ([FlankLoad; 2], Vec<f64>) {
        let roll = m.roll(q);
        let mut loads = [FlankLoad::default(); 2];
        let mut slices = vec![0.0; m.slices()];
        for (flank, load) in loads.iter_mut().enumerate() {
            let sign = if flank == 0 { 1.0 } else { -1.0 };
            m.each_slice(flank, roll, q, v, |j, f| {
                load.force += f;
                load.moment += m.zeta[j] * f;
                slices[j] += sign * f;
                if f > load.largest {
                    load.largest = f;
                    load.largest_at = m.zeta[j];
                }
            });
        }
        (loads, slices)
    }

    /// A flank's forces by blocks of slices give the bits of the slice loop (its largest slice load and
    /// where, which the report takes, included), under both force laws
    /// and both stiffness models, across the blocks' boundaries (101 and 200 slices), at states that
    /// load the drive flanks, the back flanks (the deflections reversed past the backlash) and parts of
    /// a face only (a tilt across it).
    #[test]
    fn flank_loads_by_blocks_give_the_slice_loops_bits() {
        let mut random = Xorshift::new(0x2545_f491_4f6c_dd1d);
        let mut uniform = || random.symmetric();
        // the paper's Table 5 impact law
        let impact = ForceLaw::Impact {
            exponent: 1.5,
            penetration: 1e-4,
        };
        let mut every_or_none = [0usize; 2];
        for (slices, stiffness, law) in [
            (35, MeshStiffnessModel::Mean, ForceLaw::Linear),
            (101, MeshStiffnessModel::Mean, ForceLaw::Linear),
            (35, MeshStiffnessModel::Varying, ForceLaw::Linear),
            (200, MeshStiffnessModel::Varying, ForceLaw::Linear),
            (101, MeshStiffnessModel::Mean, impact),
            (35, MeshStiffnessModel::Varying, impact),
        ] {
            let mut d = Description::load("grc750").unwrap();
            d.model.slices = slices;
            d.model.mesh_stiffness = stiffness;
            d.model.force_law = law;
            let g = Gearbox::new(&d).unwrap();
            let n = g.dofs();
            let mut loaded = [0usize; 2];
            for _ in 0..200 {
                // rotations of a milliradian and displacements of a tenth of a millimetre
                let q: Vec<f64> = (0..n).map(|_| 1e-3 * uniform()).collect();
                let v: Vec<f64> = (0..n).map(|_| 1e-2 * uniform()).collect();
                for m in &g.meshes {
                    assert_eq!(matches!(m.law, Law::Linear), law == ForceLaw::Linear);
                    let (want, want_slices) = slice_by_slice(m, &q, &v);
                    let mut f_int = vec![0.0; n];
                    let mut got_slices = vec![0.0; m.slices()];
                    let got = m.add_forces(&q, &v, &mut f_int, Some(&mut got_slices));
                    for flank in 0..2 {
                        let (a, b) = (got[flank], want[flank]);
                        let bits = |l: FlankLoad| [l.force, l.moment, l.largest, l.largest_at].map(f64::to_bits);
                        assert_eq!(bits(a), bits(b), "{} flank {flank}, {slices} slices", m.name);
                        loaded[flank] += usize::from(b.force != 0.0);
                    }
                    let bits = |x: &[f64]| x.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    assert_eq!(bits(&got_slices), bits(&want_slices), "{}", m.name);
                    // without the slices: no largest slice, and the same sums; under the linear law at
                    // the mean stiffness a flank all of whose slices touch, or none, is summed in closed
                    // form, its rounding within 1e-13 of the slices' terms (k·δ and c·δ̇ apart: they may
                    // cancel in a slice's force)
                    let mut alone = vec![0.0; n];
                    let closed = m.law == Law::Linear && m.phase.is_none();
                    for (flank, l) in m.add_forces(&q, &v, &mut alone, None).into_iter().enumerate() {
                        assert_eq!([l.largest, l.largest_at], [0.0, 0.0]);
                        let (touching, scale) = slice_terms(m, flank, &q, &v);
                        let want = want[flank];
                        if !closed || (touching > 0 && touching < m.slices()) {
                            assert_eq!([l.force, l.moment], [want.force, want.moment], "{}", m.name);
                        } else {
                            assert!(
                                (l.force - want.force).abs() <= 1e-13 * scale,
                                "{} {l:?} {want:?}",
                                m.name
                            );
                            assert!(
                                (l.moment - want.moment).abs() <= 1e-13 * scale,
                                "{} {l:?} {want:?}",
                                m.name
                            );
                            every_or_none[usize::from(touching > 0)] += 1;
                        }
                    }
                }
            }
            assert!(loaded[0] > 100 && loaded[1] > 100, "{loaded:?}");
        }
        // the closed form was taken both ways
        assert!(every_or_none.iter().all(|&k| k > 100), "{every_or_none:?}");
    }

    /// How many slices of a flank touch, and the sum of their terms' sizes |k·δ| + |c·δ̇|.
    fn slice_terms(m: &Mesh, flank: usize, q: &[f64], v: &[f64]) -> (usize, f64) {
        let (rows, errors, gap) = m.flank_parts(flank);
        let (d0, d1, r0, r1) = m.flank(rows, q, v);
        let (mut touching, mut scale) = (0, 0.0);
        for (j, &z) in m.zeta.iter().enumerate() {
            let d = d0 + z * d1 + errors[j] - gap;
            if d > 0.0 {
                touching += 1;
                scale += (m.k_slice * d).abs() + (m.c_slice * (r0 + z * r1)).abs();
            }
        }
        (touching, scale)
    }

    /// The lower hull's vertices are the slices where the compression can be least: with crowning and a
    /// lead slope (both flanks of every GRC mesh) the face's two ends; for scattered lead errors, the
    /// smallest compression over the vertices is the smallest over every slice, whatever the tilt.
    #[test]
    fn the_lower_hull_holds_the_least_compressed_slice() {
        let zeta: Vec<f64> = (0..35).map(|j| -0.1 + 0.2 * (j as f64 + 0.5) / 35.0).collect();
        let crowned: Vec<f64> = zeta
            .iter()
            .map(|&z| -4e-6 * (z / 0.1).powi(2) + 1e-6 * z / 0.1)
            .collect();
        assert_eq!(FlankSums::of(&zeta, &crowned).lowest, [0, 34]);
        let mut random = Xorshift::new(0x9e37_79b9_7f4a_7c15);
        let scattered: Vec<f64> = zeta.iter().map(|_| 1e-5 * random.symmetric()).collect();
        let scattered_hull = FlankSums::of(&zeta, &scattered).lowest;
        assert!(
            scattered_hull.len() > 2 && scattered_hull.len() < 35,
            "{scattered_hull:?}"
        );
        // a straight lead: the ends, and whichever slices the rounding of e_j puts a hair below the line
        let straight: Vec<f64> = zeta.iter().map(|&z| 3e-6 * z).collect();
        for errors in [&crowned, &straight, &scattered] {
            let sums = FlankSums::of(&zeta, errors);
            assert_eq!((sums.lowest.first(), sums.lowest.last()), (Some(&0), Some(&34)));
            for _ in 0..1000 {
                let tilt = 1e-3 * random.symmetric();
                let d = |j: usize| zeta[j] * tilt + errors[j];
                let least = (0..35).map(d).fold(f64::INFINITY, f64::min);
                assert_eq!(sums.lowest.iter().map(|&j| d(j)).fold(f64::INFINITY, f64::min), least);
            }
            assert_eq!(sums.zeta[0], 35.0);
            assert_eq!(
                sums.largest_error,
                errors.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            );
        }
    }
}
