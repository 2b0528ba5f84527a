//! A roller set's force from its own tangent between exact evaluations (the gearbox FMU's
//! `roller_update_distance`; [`super::super::near`] keeps each set's memory): the bounds on how far its
//! laminae can have moved, the margin of the nearest lamina to a kink of its law, and the memory itself.

use super::{Matrix5, RollerBearing, RollerRow};

/// What a roller set keeps between evaluations of its force ([`RollerBearing::add_forces_near`]).
// one per roller set, overwritten in place: a boxed tangent would allocate at each exact evaluation
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, Default)]
pub enum SetMemory {
    /// Nothing: the next evaluation is exact, with its tangent.
    #[default]
    Empty,
    /// The last exact evaluation, whether a force has been taken from it since, and how many exact
    /// evaluations without a tangent follow it if none is.
    Tangent {
        tangent: SetTangent,
        used: bool,
        backoff: u8,
    },
    /// So many more evaluations exact without a tangent: the set moved beyond its last tangent before
    /// any force was taken from it (a bearing rattling in its clearance, a fast cage), where each
    /// tangent costs more than it saves. The next tangent left unused doubles `backoff`.
    Exact { left: u8, backoff: u8 },
}

/// Evaluations a roller set takes exactly, without a tangent, after a tangent it never used (two or
/// three steps' Newton iterations), doubled after each further unused tangent up to
/// [`MOST_EXACT_AFTER_UNUSED`].
const EXACT_AFTER_UNUSED: u8 = 8;
const MOST_EXACT_AFTER_UNUSED: u8 = 128;

/// A roller set's force and its 5 × 5 stiffness and damping where it was last evaluated exactly: the
/// force near there is taken from them.
#[derive(Debug, Clone, Copy)]
pub struct SetTangent {
    x: [f64; 5],
    xd: [f64; 5],
    cage: f64,
    force: [f64; 5],
    k: Matrix5,
    c: Matrix5,
    /// How far the nearest lamina is from a change of its law, m ([`RollerBearing::contact_margin`]).
    margin: f64,
}

/// The laminae of a straight roller along its axis: s_k = first + k·width, k = 0..=last.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Grid {
    first: f64,
    width: f64,
    last: usize,
}

impl Grid {
    /// The grid of `laminae` (offset, profile drop) of `width` each; None when any is crowned.
    pub(super) fn of_straight(laminae: &[(f64, f64)], width: f64) -> Option<Self> {
        (!laminae.is_empty() && laminae.iter().all(|l| l.1 == 0.0)).then(|| Grid {
            first: laminae[0].0,
            width,
            last: laminae.len() - 1,
        })
    }

    /// The least |a + b·s_k| over the laminae lo..=hi.
    #[inline(always)]
    fn least(&self, a: f64, b: f64, lo: usize, hi: usize) -> f64 {
        let at = |k: usize| (a + b * (self.first + k as f64 * self.width)).abs();
        if b == 0.0 {
            return a.abs();
        }
        // the zero's place among the laminae, clamped (max and min: no panic on a NaN state): a
        // non-negative value, truncated to its floor
        let k = ((-a / b - self.first) / self.width).max(lo as f64).min(hi as f64) as usize;
        at(k).min(at((k + 1).min(hi)))
    }

    /// The laminae lo..=hi where c + p·s_k > 0 (they run to one end), None for none.
    #[inline(always)]
    fn positive(&self, c: f64, p: f64) -> Option<(usize, usize)> {
        if p == 0.0 {
            return (c > 0.0).then_some((0, self.last));
        }
        // where c + p·s is zero, in laminae
        let zero = (-c / p - self.first) / self.width;
        let n = self.last as f64;
        if zero.is_nan() {
            return Some((0, self.last));
        }
        if p > 0.0 {
            // positive beyond the zero
            match zero {
                z if z < 0.0 => Some((0, self.last)),
                z if z >= n => None,
                z => Some((z as usize + 1, self.last)),
            }
        } else {
            // positive before it
            match zero {
                z if z > n => Some((0, self.last)),
                z if z <= 0.0 => None,
                z => {
                    let floor = z as usize;
                    Some((0, if floor as f64 == z { floor - 1 } else { floor }))
                }
            }
        }
    }
}

impl RollerBearing {
    /// f_int += the bearing's force at (q, v) as [`Self::add_forces`] gives it without peaks, or, while no
    /// lamina's approach to its races can have moved more than `distance` (m) from `memory`'s exact
    /// evaluation and none can have crossed a kink of its law (touching or leaving its race, its damping
    /// pulling it to zero load), f₀ + K·Δx + C·Δẋ from `memory`'s tangent; else evaluated exactly with its
    /// tangent, which `memory` then keeps. A tangent left before any force was taken from it is followed
    /// by [`EXACT_AFTER_UNUSED`] exact evaluations without one, twice as many after the next such. The tangent holds the cage where it was:
    /// the bounds count the load zone's turn with the cage as a motion of the laminae.
    #[inline(always)]
    pub fn add_forces_near(&self, q: &[f64], v: &[f64], distance: f64, memory: &mut SetMemory, out: &mut [f64]) {
        let (x, xd, cage) = self.kinematics(q, v);
        let force = match memory {
            SetMemory::Tangent { tangent: t, used, .. } if self.within(t, &x, &xd, cage, distance) => {
                *used = true;
                std::array::from_fn(|a| {
                    let (k, c) = (&t.k[a], &t.c[a]);
                    t.force[a]
                        + (0..5)
                            .map(|b| k[b] * (x[b] - t.x[b]) + c[b] * (xd[b] - t.xd[b]))
                            .sum::<f64>()
                })
            }
            SetMemory::Tangent {
                used: false, backoff, ..
            } => {
                let backoff = *backoff;
                *memory = SetMemory::Exact {
                    left: backoff,
                    backoff: backoff.saturating_mul(2).min(MOST_EXACT_AFTER_UNUSED),
                };
                self.evaluate(&x, &xd, cage, false, None).force
            }
            SetMemory::Exact { left, .. } if *left > 0 => {
                *left -= 1;
                self.evaluate(&x, &xd, cage, false, None).force
            }
            _ => {
                // after exact evaluations the back-off grows; after a tangent used it starts again
                let backoff = match memory {
                    SetMemory::Exact { backoff, .. } => *backoff,
                    _ => EXACT_AFTER_UNUSED,
                };
                let (mut k, mut c, mut margin) = ([[0.0; 5]; 5], [[0.0; 5]; 5], f64::INFINITY);
                let force = self
                    .evaluate_with_margin(&x, &xd, cage, false, Some((&mut k, &mut c)), Some(&mut margin))
                    .force;
                let tangent = SetTangent {
                    x,
                    xd,
                    cage,
                    force,
                    k,
                    c,
                    margin,
                };
                *memory = SetMemory::Tangent {
                    tangent,
                    used: false,
                    backoff,
                };
                force
            }
        };
        self.add_to(force, out);
    }

    /// Whether (x, ẋ, ψ_c) lies near enough `t` for its tangent: no lamina's approach δ can have moved
    /// more than `distance`, and neither δ nor δ + e·τ·δ̇ (what a lamina's load is proportional to)
    /// further than `t`'s margin to a kink of the law.
    #[inline(always)]
    fn within(&self, t: &SetTangent, x: &[f64; 5], xd: &[f64; 5], cage: f64, distance: f64) -> bool {
        let turn = cage - t.cage;
        let moved = self.lamina_motion(&std::array::from_fn(|i| x[i] - t.x[i]), x, turn);
        moved <= distance
            && moved + self.exponent_damping * self.lamina_motion(&std::array::from_fn(|i| xd[i] - t.xd[i]), xd, turn)
                <= t.margin
    }

    /// The most any lamina's approach (or, given rates, its rate) can change, m (m/s), under the change
    /// `d` of the relative coordinates (or their rates) `x` and the cage's turn: the translations', the
    /// tilts' at the farthest lamina, and the turn's, which moves each roller's approach by at most the
    /// radial displacement at its laminae times the angle.
    #[inline(always)]
    fn lamina_motion(&self, d: &[f64; 5], x: &[f64; 5], turn: f64) -> f64 {
        // micrometres: no overflow for hypot's care to guard against
        let norm = |a: f64, b: f64| (a * a + b * b).sqrt();
        let radial = norm(x[0], x[1]) + self.tilt_reach * norm(x[3], x[4]);
        d[0].abs() + d[1].abs() + d[2].abs() + self.tilt_reach * (d[3].abs() + d[4].abs()) + radial * turn.abs()
    }

    /// How far, m, the nearest lamina is from a kink of its law at (x, ẋ, ψ_c): a lamina out of contact
    /// from touching (a roller clear of its races: its most compressed end, the crown ignored, which
    /// only widens the gap), a loaded one as [`Self::loaded_edge`]. Between two evaluations no kink is
    /// crossed while the laminae move less. The exact evaluation with a tangent finds the same margin
    /// in its own pass ([`Self::evaluate_with_margin`]); this one is the tests' (`by_loop` takes every
    /// lamina of a straight roller too).
    #[cfg(test)]
    fn contact_margin(&self, x: &[f64; 5], xd: &[f64; 5], cage: f64, by_loop: bool) -> f64 {
        use super::{Gradient, Places};
        let half_length = self.laminae.last().map_or(0.0, |l| l.0.abs());
        let grid = self.grid.as_ref().filter(|_| !by_loop);
        let cage = cage.sin_cos();
        let mut margin = f64::INFINITY;
        for row in &self.roller_rows {
            let approach = self.row_approach(row, x, cage);
            for place in self.places.iter() {
                let (centre, spread) = approach.at(place);
                let most = centre + spread.abs() * half_length;
                if most <= 0.0 {
                    margin = margin.min(-most);
                    continue;
                }
                let Gradient { rate_u, rate_w, .. } = self.gradient(row, Places::unit(place, cage), xd);
                margin = margin.min(self.loaded_edge(grid, row, centre, spread, rate_u, rate_w));
            }
        }
        margin
    }

    /// How far, m, the nearest lamina of a roller in contact is from leaving its race (δ) or from its
    /// damping pulling its load to zero (δ + e·τ·δ̇). A straight roller's δ and δ + e·τ·δ̇ are affine
    /// along it: their least magnitudes lie at the laminae nearest their zeros, found on `grid` without
    /// the loop (None: the loop over every lamina, which a crowned roller keeps).
    #[inline(always)]
    pub(super) fn loaded_edge(
        &self,
        grid: Option<&Grid>,
        row: &RollerRow,
        centre: f64,
        spread: f64,
        rate_u: f64,
        rate_w: f64,
    ) -> f64 {
        // δ + e·τ·δ̇ = load_at + load_slope·s along the roller
        let et = self.exponent_damping;
        let (load_at, load_slope) = (centre + et * (rate_u + row.z * rate_w), spread + et * rate_w);
        if let Some(g) = grid {
            let loaded = g.positive(centre, spread);
            return g
                .least(centre, spread, 0, g.last)
                .min(loaded.map_or(f64::INFINITY, |(lo, hi)| g.least(load_at, load_slope, lo, hi)));
        }
        let mut edge = f64::INFINITY;
        for &(s, drop) in &self.laminae {
            let delta = centre + spread * s - drop;
            edge = edge.min(if delta <= 0.0 {
                -delta
            } else {
                delta.min((load_at + load_slope * s - drop).abs())
            });
        }
        edge
    }
}

#[cfg(test)]
mod tests {
    use super::super::Mounting;
    use super::*;
    use crate::physics::gearbox::description::{Contact, Rollers};
    use crate::physics::gearbox::row::Row;

    fn unit(i: usize) -> Row {
        let mut row = Row::default();
        row.add(i, 1.0);
        row
    }

    /// A damped two-row angular set with clearance, `crowning_um` crowned.
    fn set(crowning_um: f64) -> RollerBearing {
        let r = Rollers {
            count: 17,
            diameter_mm: 30.0,
            length_mm: 50.0,
            pitch_diameter_mm: 400.0,
            contact_angle_deg: 10.0,
            rows: 2,
            row_spacing_mm: 60.0,
            clearance_um: 30.0,
            axial_clearance_um: 20.0,
            laminae: 12,
            contact: Contact::Line,
            roller_stiffness: None,
            profile_radius_mm: None,
            race_profile_radii_mm: None,
            crowning_um,
        };
        let m = Mounting {
            bearing: 0,
            rows: std::array::from_fn(unit),
            cage: unit(5),
            offset: [0.0; 2],
            sign: 1.0,
        };
        RollerBearing::new(&r, m, 2e-4, None)
    }

    /// A straight roller's margin found at the laminae nearest the zeros is the loop's over every
    /// lamina, over states loaded and clear, tilted either way, approaching and receding fast enough
    /// for the damping to pull laminae to zero load.
    #[test]
    fn a_straight_rollers_margin_without_the_loop_is_the_loops() {
        let b = set(0.0);
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut uniform = |scale: f64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            scale * ((seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0)
        };
        let mut kinks = 0;
        for _ in 0..3000 {
            let x = [
                uniform(60e-6),
                uniform(60e-6),
                uniform(30e-6),
                uniform(3e-4),
                uniform(3e-4),
            ];
            let xd = [uniform(0.2), uniform(0.2), uniform(0.1), uniform(2.0), uniform(2.0)];
            let cage = uniform(7.0);
            let (grid, looped) = (
                b.contact_margin(&x, &xd, cage, false),
                b.contact_margin(&x, &xd, cage, true),
            );
            assert!(
                (grid - looped).abs() <= 1e-12 * looped.abs() + 1e-18,
                "{grid} against the loop's {looped}"
            );
            kinks += usize::from(looped < 1e-6);
        }
        assert!(kinks > 100, "the states must reach near kinks: {kinks}");
        // a crowned roller keeps the loop
        let crowned = set(5.0);
        let (x, xd) = ([50e-6, 10e-6, 5e-6, 1e-4, 0.0], [0.01, 0.0, 0.0, 0.0, 0.0]);
        assert_eq!(
            crowned.contact_margin(&x, &xd, 0.3, false),
            crowned.contact_margin(&x, &xd, 0.3, true)
        );
    }
}
