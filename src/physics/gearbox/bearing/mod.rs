//! Rolling bearings by the roller–lamina model (the slicing of ISO/TS 16281): every roller at its
//! angle in a cage that turns at its kinematic speed, each roller cut into laminae along its length;
//! a lamina loaded as far as its approach exceeds half the clearance, q = (c/n)·δ^e with e = 10/9 for
//! line and 1.5 for point contact. The bearing acts on five relative coordinates of its races, inner
//! minus outer at the bearing's centre, x = (u_x, u_y, u_z, θ_x, θ_y): radial and axial approach,
//! and the tilt that loads the laminae of a roller unevenly. Forces and tangents on those five
//! coordinates reach the model's DOFs through five constant rows (as a linear bearing's springs do).

use super::description::{Contact, Rollers};
use super::mesh::KeyBits;
use super::ninth_root::{NinthRoots, ninth_root};
use super::roller_table::{RollerTable, RollerTables};
use super::row::{Row, add_outer};
use crate::physics::hertz::{EllipticContact, LineContact, effective_modulus, subsurface_peaks};
use nalgebra::DMatrix;
use std::f64::consts::TAU;
use std::sync::Arc;

mod geometry;
mod places;
mod tangent;
use geometry::Gradient;
use places::Places;
use tangent::Grid;
pub use tangent::{SetMemory, SetTangent};

/// A 5×5 block on the relative coordinates (stiffness or damping).
pub type Matrix5 = [[f64; 5]; 5];

/// ISO/TS 16281's line-contact constant for a roller between two steel races, N/mm^(10/9) per
/// mm^(8/9) of effective length: Q = 35 948·L_we^(8/9)·δ^(10/9) (N, mm).
const ISO_LINE_CONSTANT: f64 = 35_948.0;
const LINE_EXPONENT: f64 = 10.0 / 9.0;
const POINT_EXPONENT: f64 = 1.5;
/// Bearing steel (E = 210 GPa, ν = 0.3 for both races and rollers).
const STEEL_E: f64 = 210e9;
const STEEL_NU: f64 = 0.3;

/// δ^(e − 1) for the two contact laws, the roller sets' inner loop: a lamina's load is k·δ·δ^(e−1)
/// and its stiffness e·k·δ^(e−1), with no division (a division per lamina cost 7 % of the GRC's
/// run). δ^(1/9) by table and series (`ninth_root`), not exp(ln δ / 9), which measured 9 ns against
/// `powf`'s 12 and two `cbrt`s' 34 and took a quarter of the GRC shutdown's run.
fn power_less_one(delta: f64, exponent: f64) -> f64 {
    if exponent == LINE_EXPONENT {
        ninth_root(delta)
    } else if exponent == POINT_EXPONENT {
        delta.sqrt()
    } else {
        delta.powf(exponent - 1.0)
    }
}

/// One row of rollers: its contact angle and axial place in the bearing.
#[derive(Debug, Clone, Copy, PartialEq)]
struct RollerRow {
    cos: f64,
    sin: f64,
    /// Centre of the row from the bearing's centre along the axis, m.
    z: f64,
}

/// What one evaluation of a bearing yields.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RollerLoads {
    /// Generalised force on the five relative coordinates (what the races push back with).
    pub force: [f64; 5],
    /// Rollers with at least one loaded lamina.
    pub rollers_in_contact: usize,
    /// Largest roller load, N.
    pub max_roller_load: f64,
    /// Largest lamina load, N (the Hertz pressures follow from it).
    pub max_lamina_load: f64,
}

/// Contact stresses of the most loaded lamina.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RaceStresses {
    /// Maximum Hertz pressure at the inner and the outer race, Pa.
    pub inner_pressure: f64,
    pub outer_pressure: f64,
    /// Largest subsurface shear (Tresca) under the inner race, the more loaded contact, Pa, and its
    /// depth, m.
    pub max_shear: f64,
    pub max_shear_depth: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub struct RollerBearing {
    /// Index of the named bearing this roller set belongs to.
    pub bearing: usize,
    /// x = rows·q: inner race minus outer race, (u_x, u_y, u_z, θ_x, θ_y).
    pub rows: [Row; 5],
    /// The cage angle in the bearing's frame, rad (cage·q).
    pub cage: Row,
    /// Subtracted from the radial approach (a pin position error), m.
    offset: [f64; 2],
    /// −1 when the body the bearing belongs to is its outer race (a planet on its pin), else 1:
    /// the rows are the linear springs' (body minus the other side) times this.
    pub sign: f64,
    /// The rollers' places round the cage.
    places: Places,
    pitch_radius: f64,
    roller_rows: Vec<RollerRow>,
    /// Lamina offsets from the roller's centre along the axis, m, and their profile drop, m.
    laminae: Vec<(f64, f64)>,
    /// Per lamina: q = k·δ^e (N, m).
    k_lamina: f64,
    exponent: f64,
    /// Diametral radial and axial clearance, m (negative: preload).
    clearance: f64,
    axial_clearance: f64,
    damping_time: f64,
    lamina_width: f64,
    /// The Hertz contact at the inner and outer race.
    hertz: RaceContacts,
    /// Subsurface Tresca shear peak per unit p_max and its depth per unit (semi-minor) half-width,
    /// at the inner race.
    shear_peak: (f64, f64),
    /// The roller's sums by table instead of the lamina loop (`bearing_model = lamina-table`; line
    /// contact without crowning only).
    table: Option<Arc<RollerTable>>,
    /// Half the roller's length, m.
    half_roller: f64,
    /// The laminae's offsets counted from either end: from the first (a roller tilted to load it
    /// most) and from the last, for the table's search.
    offsets_from: [Vec<f64>; 2],
    /// e·τ: a lamina's damping per unit of its secant stiffness.
    exponent_damping: f64,
    /// How far a tilt of 1 rad moves the farthest lamina's approach at most, m (through the contact
    /// angle's arm at the pitch radius and the lamina's place along the axis).
    tilt_reach: f64,
    /// The laminae of a straight (uncrowned) roller, for the kink margin without a loop; None crowned.
    grid: Option<Grid>,
}

/// A loaded roller's load, moment about the row's centre and the sums of its laminae's stiffness and
/// damping times 1, z, z².
struct RollerSums {
    load: f64,
    moment: f64,
    stiffness: [f64; 3],
    damping: [f64; 3],
}

/// How a roller meets its races, for their pressures.
#[derive(Debug, Clone, PartialEq)]
enum RaceContacts {
    /// Line contact: effective radii at the inner and outer race (m) and E* (Pa), per lamina.
    Line { inner: f64, outer: f64, e_star: f64 },
    /// Point contact from the roller's and the grooves' profile radii: the whole roller's load.
    Point {
        inner: EllipticContact,
        outer: EllipticContact,
    },
    /// Point contact given by its stiffness alone: no geometry, no pressure.
    Unknown,
}

/// The geometry a roller set needs from the model: its rows, its cage row and which race is the
/// body's.
pub struct Mounting {
    pub bearing: usize,
    pub rows: [Row; 5],
    pub cage: Row,
    pub offset: [f64; 2],
    pub sign: f64,
}

impl RollerBearing {
    /// With `tables` (the model's), a roller set with line contact and no crowning sums its rollers'
    /// laminae by [`RollerTable`] (within 2e-10 of the loop's sums); any other keeps the lamina loop.
    pub fn new(r: &Rollers, m: Mounting, damping_time: f64, tables: Option<&mut RollerTables>) -> Self {
        let mm = 1e-3;
        let (length, dm) = (r.length_mm * mm, r.pitch_diameter_mm * mm);
        let alpha = r.contact_angle_deg.to_radians();
        let roller_rows: Vec<RollerRow> = if r.rows == 2 {
            let half = 0.5 * r.row_spacing_mm * mm;
            vec![
                RollerRow {
                    cos: alpha.cos(),
                    sin: -alpha.sin(),
                    z: -half,
                },
                RollerRow {
                    cos: alpha.cos(),
                    sin: alpha.sin(),
                    z: half,
                },
            ]
        } else {
            vec![RollerRow {
                cos: alpha.cos(),
                sin: alpha.sin(),
                z: 0.0,
            }]
        };
        let n = r.laminae as usize;
        let width = length / n as f64;
        let crown = r.crowning_um * 1e-6;
        let laminae: Vec<(f64, f64)> = (0..n)
            .map(|k| {
                let s = -0.5 * length + (k as f64 + 0.5) * width;
                // parabolic crown: the full drop at the roller's ends
                (s, crown * (2.0 * s / length).powi(2))
            })
            .collect();
        let offsets_from = [
            laminae.iter().map(|l| l.0).collect(),
            laminae.iter().rev().map(|l| l.0).collect(),
        ];
        let e_star = effective_modulus(STEEL_E, STEEL_NU, STEEL_E, STEEL_NU);
        let (rolling, across) = r.contact_radii();
        let hertz = match (r.contact, across) {
            (Contact::Line, _) => RaceContacts::Line {
                inner: rolling[0],
                outer: rolling[1],
                e_star,
            },
            (Contact::Point, Some(across)) => {
                // the description's check has built both ellipses once already
                let point = |k: usize| EllipticContact::new(rolling[k], across[k], e_star);
                match (point(0), point(1)) {
                    (Some(inner), Some(outer)) => RaceContacts::Point { inner, outer },
                    _ => RaceContacts::Unknown,
                }
            }
            (Contact::Point, None) => RaceContacts::Unknown,
        };
        let (exponent, c_roller) = match (r.contact, r.roller_stiffness, &hertz) {
            (Contact::Line, None, _) => {
                // N/mm^(10/9) with L in mm, in SI: × 1000^(8/9 + 10/9) = 1e6
                (LINE_EXPONENT, ISO_LINE_CONSTANT * 1e6 * length.powf(8.0 / 9.0))
            }
            (Contact::Line, Some(c), _) => (LINE_EXPONENT, c),
            (Contact::Point, Some(c), _) => (POINT_EXPONENT, c),
            // the two contacts in series: δ = (Q/c_i)^(2/3) + (Q/c_o)^(2/3)
            (Contact::Point, None, RaceContacts::Point { inner, outer }) => (
                POINT_EXPONENT,
                (inner.stiffness().powf(-2.0 / 3.0) + outer.stiffness().powf(-2.0 / 3.0)).powf(-1.5),
            ),
            (Contact::Point, None, _) => (POINT_EXPONENT, 0.0),
        };
        let shear_peak = match &hertz {
            RaceContacts::Point { inner, .. } => inner.max_shear(STEEL_NU),
            _ => subsurface_peaks(STEEL_NU).max_shear,
        };
        let tilt_reach = roller_rows
            .iter()
            .map(|row| row.sin.abs() * 0.5 * dm + row.cos * (row.z.abs() + 0.5 * length))
            .fold(0.0, f64::max);
        let grid = Grid::of_straight(&laminae, width);
        let uncrowned = crown == 0.0;
        let table = tables
            .filter(|_| uncrowned && exponent == LINE_EXPONENT)
            .and_then(|t| t.for_laminae(n));
        RollerBearing {
            bearing: m.bearing,
            rows: m.rows,
            cage: m.cage,
            offset: m.offset,
            sign: m.sign,
            places: Places::new(r.count as usize),
            pitch_radius: 0.5 * dm,
            roller_rows,
            laminae,
            k_lamina: c_roller / n as f64,
            exponent,
            clearance: r.clearance_um * 1e-6,
            axial_clearance: r.axial_clearance_um * 1e-6,
            damping_time,
            lamina_width: width,
            hertz,
            shear_peak,
            table,
            half_roller: 0.5 * length,
            offsets_from,
            exponent_damping: exponent * damping_time,
            tilt_reach,
            grid,
        }
    }

    /// Whether the roller sums come from the table.
    pub fn tabulated(&self) -> bool {
        self.table.is_some()
    }

    /// The five relative coordinates, their rates and the cage angle at (q, v).
    #[inline(always)]
    pub fn kinematics(&self, q: &[f64], v: &[f64]) -> ([f64; 5], [f64; 5], f64) {
        let both: [(f64, f64); 5] = std::array::from_fn(|i| self.rows[i].dot2(q, v));
        let x = std::array::from_fn(|i| both[i].0 - self.offset.get(i).copied().unwrap_or(0.0));
        (x, both.map(|(_, rate)| rate), self.cage.dot(q))
    }

    /// Loads at relative displacement x, rate xd and cage angle ψ_c. With `tangent`, also adds
    /// ∂f/∂x to the first and ∂f/∂ẋ to the second matrix (the cage angle held: the load zone
    /// moves slowly against the contact stiffness). `max_lamina_load` is the largest lamina's load
    /// only with `peaks` (a tabulated roller set has no lamina loads of its own: it evaluates them
    /// when asked, once per reported step); without, it is a lower bound.
    ///
    /// Inlined, so a caller without a tangent (every force evaluation) compiles without the six
    /// stiffness and damping sums per lamina.
    #[inline(always)]
    pub fn evaluate(
        &self,
        x: &[f64; 5],
        xd: &[f64; 5],
        cage: f64,
        peaks: bool,
        tangent: Option<(&mut Matrix5, &mut Matrix5)>,
    ) -> RollerLoads {
        self.evaluate_with_margin(x, xd, cage, peaks, tangent, None)
    }

    /// [`Self::evaluate`], with `margin` also the distance of the nearest lamina to a kink of its law
    /// (as the tests' `contact_margin` gives it, in the same pass over the rollers).
    #[inline(always)]
    fn evaluate_with_margin(
        &self,
        x: &[f64; 5],
        xd: &[f64; 5],
        cage: f64,
        peaks: bool,
        tangent: Option<(&mut Matrix5, &mut Matrix5)>,
        margin: Option<&mut f64>,
    ) -> RollerLoads {
        // chosen once, so the lamina loop's copy has no table test per roller
        match self.table.as_deref() {
            Some(table) => self.evaluate_by(x, xd, cage, peaks, tangent, Some(table), margin),
            None => self.evaluate_by(x, xd, cage, peaks, tangent, None, margin),
        }
    }

    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn evaluate_by(
        &self,
        x: &[f64; 5],
        xd: &[f64; 5],
        cage: f64,
        peaks: bool,
        mut tangent: Option<(&mut Matrix5, &mut Matrix5)>,
        table: Option<&RollerTable>,
        mut margin: Option<&mut f64>,
    ) -> RollerLoads {
        let mut out = RollerLoads::default();
        let roots = NinthRoots::get();
        let half_length = self.laminae.last().map_or(0.0, |l| l.0.abs());
        let cage = cage.sin_cos();
        for row in &self.roller_rows {
            let approach = self.row_approach(row, x, cage);
            for place in self.places.iter() {
                let (centre, spread) = approach.at(place);
                let most = centre + spread.abs() * half_length;
                if most <= 0.0 {
                    if let Some(m) = margin.as_deref_mut() {
                        *m = m.min(-most);
                    }
                    continue;
                }
                let Gradient { u, w, rate_u, rate_w } = self.gradient(row, Places::unit(place, cage), xd);
                if let Some(m) = margin.as_deref_mut() {
                    *m = m.min(self.loaded_edge(self.grid.as_ref(), row, centre, spread, rate_u, rate_w));
                }
                let tabulated = table.and_then(|t| self.by_table(t, roots, row, centre, spread, rate_u, rate_w));
                let sums = match tabulated {
                    Some(sums) => {
                        // the table has no lamina loads: the more loaded end's where it is the
                        // largest, else the loop's (its sums unused)
                        if peaks {
                            match self.end_lamina_load(row, centre, spread, rate_u, rate_w) {
                                Some(q) => out.max_lamina_load = out.max_lamina_load.max(q),
                                None => {
                                    self.by_laminae(row, centre, spread, rate_u, rate_w, &mut out.max_lamina_load);
                                }
                            }
                        }
                        sums
                    }
                    None => self.by_laminae(row, centre, spread, rate_u, rate_w, &mut out.max_lamina_load),
                };
                let (roller, moment) = (sums.load, sums.moment);
                for i in 0..3 {
                    out.force[i] += roller * u[i];
                }
                for i in 3..5 {
                    out.force[i] += roller * u[i] + moment * w[i - 3];
                }
                if let Some((k, c)) = tangent.as_mut() {
                    // the upper triangle (both blocks are symmetric: mirrored once below); w is zero
                    // on the translations, so their 3 × 3 block has the u·uᵀ sums alone
                    let ([k0, k1, k2], [c0, c1, c2]) = (sums.stiffness, sums.damping);
                    for a in 0..3 {
                        for b in a..3 {
                            let uu = u[a] * u[b];
                            k[a][b] += k0 * uu;
                            c[a][b] += c0 * uu;
                        }
                        for b in 3..5 {
                            let (uu, uw) = (u[a] * u[b], u[a] * w[b - 3]);
                            k[a][b] += k0 * uu + k1 * uw;
                            c[a][b] += c0 * uu + c1 * uw;
                        }
                    }
                    for a in 3..5 {
                        for b in a..5 {
                            let uu = u[a] * u[b];
                            let uw = u[a] * w[b - 3] + w[a - 3] * u[b];
                            let ww = w[a - 3] * w[b - 3];
                            k[a][b] += k0 * uu + k1 * uw + k2 * ww;
                            c[a][b] += c0 * uu + c1 * uw + c2 * ww;
                        }
                    }
                }
                if roller > 0.0 {
                    out.rollers_in_contact += 1;
                    out.max_roller_load = out.max_roller_load.max(roller);
                }
            }
        }
        if let Some((k, c)) = tangent {
            for a in 1..5 {
                for b in 0..a {
                    (k[a][b], c[a][b]) = (k[b][a], c[b][a]);
                }
            }
        }
        out
    }

    /// A roller's sums lamina by lamina, the largest lamina load into `max_lamina`.
    #[inline(always)]
    fn by_laminae(
        &self,
        row: &RollerRow,
        centre: f64,
        spread: f64,
        rate_u: f64,
        rate_w: f64,
        max_lamina: &mut f64,
    ) -> RollerSums {
        let (mut roller, mut moment) = (0.0, 0.0);
        let (mut k0, mut k1, mut k2, mut c0, mut c1, mut c2) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        for &(s, drop) in &self.laminae {
            let delta = centre + spread * s - drop;
            if delta <= 0.0 {
                continue;
            }
            let z = row.z + s;
            let (q, stiffness, damping) = self.lamina(delta, z, rate_u, rate_w);
            // a contact pushes, never pulls: damping cannot make it sticky
            if q <= 0.0 {
                continue;
            }
            roller += q;
            moment += q * z;
            *max_lamina = max_lamina.max(q);
            (k0, k1, k2) = (k0 + stiffness, k1 + stiffness * z, k2 + stiffness * z * z);
            (c0, c1, c2) = (c0 + damping, c1 + damping * z, c2 + damping * z * z);
        }
        RollerSums {
            load: roller,
            moment,
            stiffness: [k0, k1, k2],
            damping: [c0, c1, c2],
        }
    }

    /// A lamina's load, stiffness and damping at approach `delta` > 0, `z` along the axis from the
    /// bearing's centre.
    #[inline(always)]
    fn lamina(&self, delta: f64, z: f64, rate_u: f64, rate_w: f64) -> (f64, f64, f64) {
        // the secant stiffness q/δ, so neither load nor tangent divides by δ
        let secant = self.k_lamina * power_less_one(delta, self.exponent);
        let stiffness = self.exponent * secant;
        let damping = self.damping_time * stiffness;
        (secant * delta + damping * (rate_u + z * rate_w), stiffness, damping)
    }

    /// The load of a tabulated roller's lamina at its more loaded end, when that lamina carries the
    /// largest load: q = k·δ^(1/9)·(δ + e·τ·ṙ), δ falls away from that end and so does δ + e·τ·ṙ
    /// unless the tilting rate's damping rises faster (then None: the loop decides). Both factors
    /// are positive over the loaded laminae, where the table was used.
    #[inline(always)]
    fn end_lamina_load(&self, row: &RollerRow, centre: f64, spread: f64, rate_u: f64, rate_w: f64) -> Option<f64> {
        let falls = spread + self.exponent_damping * rate_w;
        let (&(s, drop), falling) = if spread >= 0.0 {
            (self.laminae.last()?, falls >= 0.0)
        } else {
            (self.laminae.first()?, falls <= 0.0)
        };
        // the loop's arithmetic for that lamina, so the same bits where the loop finds it largest
        falling.then(|| self.lamina(centre + spread * s - drop, row.z + s, rate_u, rate_w).0)
    }

    /// A roller's sums from the table (line contact, no crowning), or None where the loop has to
    /// decide: a lamina the damping would unload (its load's sign is affine along the roller, so the
    /// two extreme loaded laminae tell), or signs of the laminae that contradict each other.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn by_table(
        &self,
        table: &RollerTable,
        roots: NinthRoots,
        row: &RollerRow,
        centre: f64,
        spread: f64,
        rate_u: f64,
        rate_w: f64,
    ) -> Option<RollerSums> {
        // laminae counted from the more loaded end, their approaches as the loop computes them
        let offset = &self.offsets_from[usize::from(spread >= 0.0)][..];
        let n = offset.len();
        let approach = |j: usize| centre + spread * offset[j];
        let m = approach(0);
        if m <= 0.0 {
            return None;
        }
        let u = m / (spread.abs() * self.lamina_width);
        // ⌈u⌉ without libm's ceil (baseline x86_64 has no rounding instruction): u > 0
        let whole = u as usize;
        let mut count = if u >= n as f64 {
            n
        } else {
            (whole + usize::from((whole as f64) < u)).clamp(1, n)
        };
        if count < n && approach(count) > 0.0 {
            count += 1;
        } else if count > 1 && approach(count - 1) <= 0.0 {
            count -= 1;
        }
        if (count < n && approach(count) > 0.0) || (count > 1 && approach(count - 1) <= 0.0) {
            return None;
        }
        let last = count - 1;
        let (s_last, d_last) = (offset[last], approach(last));
        // no lamina unloaded by its damping: δ + e·τ·(ṙ_u + z·ṙ_w) > 0 at both ends of the loaded ones
        let kept = |d: f64, s: f64| d + self.exponent_damping * (rate_u + (row.z + s) * rate_w) > 0.0;
        if !(kept(m, offset[0]) && kept(d_last, s_last)) {
            return None;
        }
        let rest = table.rest(last, u);
        let h = if spread >= 0.0 {
            self.half_roller
        } else {
            -self.half_roller
        };
        let [mb, b] = roots.of_two([m, d_last]);
        let (me, e) = (mb * m, b * d_last);
        // Σδ^(10/9)·{1, s} and Σδ^(1/9)·{1, s, s²} over the loaded laminae
        let e0 = me * rest[0] + e;
        let e1 = h * me * rest[1] + e * s_last;
        let s0 = mb * rest[2] + b;
        let s1 = h * mb * rest[3] + b * s_last;
        let s2 = h * h * mb * rest[4] + b * s_last * s_last;
        // about z = z_row + s
        let zr = row.z;
        let (sz1, sz2, ez1) = (zr * s0 + s1, zr * zr * s0 + 2.0 * zr * s1 + s2, zr * e0 + e1);
        let k = self.exponent * self.k_lamina;
        let stiffness = [k * s0, k * sz1, k * sz2];
        let damping = stiffness.map(|x| self.damping_time * x);
        Some(RollerSums {
            load: self.k_lamina * e0 + rate_u * damping[0] + rate_w * damping[1],
            moment: self.k_lamina * ez1 + rate_u * damping[1] + rate_w * damping[2],
            stiffness,
            damping,
        })
    }

    /// The contact pattern the integrators key their factorisations by: per row, how many rollers
    /// approach their races (6 bits) and the octant the radial approach points to (3 bits). The
    /// lamina law is nearly linear between patterns (its stiffness goes as δ^(1/9): a load twice as
    /// high stiffens a roller by 8 %), so a factorisation serves while the pattern holds and the
    /// modified Newton iteration converges in a few steps.
    pub fn key(&self, q: &[f64], bits: &mut KeyBits) {
        let x: [f64; 5] = std::array::from_fn(|i| self.rows[i].dot(q) - self.offset.get(i).copied().unwrap_or(0.0));
        let cage = self.cage.dot(q).sin_cos();
        let octant = ((x[1].atan2(x[0]) / TAU * 8.0).floor() as i64).rem_euclid(8) as u64;
        for row in &self.roller_rows {
            let gap = row.cos * 0.5 * self.clearance + row.sin.abs() * 0.5 * self.axial_clearance;
            // the approach at the row's centre without the tilt's part (evaluate's at z = 0)
            let (p, q) = Places::turned(self.approach_round_the_row(row, &x, 0.0), cage);
            let touching = self
                .places
                .iter()
                .filter(|&(c, s)| p * c + q * s + row.sin * x[2] > gap)
                .count() as u64;
            let touching = touching.min(63);
            for b in 0..6 {
                bits.push(touching >> b & 1 == 1);
            }
            for b in 0..3 {
                bits.push(touching > 0 && octant >> b & 1 == 1);
            }
        }
    }

    /// f_int += the bearing's force at (q, v); returns its loads (`max_lamina_load` only with `peaks`:
    /// see [`Self::evaluate`]).
    #[inline(always)]
    pub fn add_forces(&self, q: &[f64], v: &[f64], peaks: bool, out: &mut [f64]) -> RollerLoads {
        let (x, xd, cage) = self.kinematics(q, v);
        let loads = self.evaluate(&x, &xd, cage, peaks, None);
        self.add_to(loads.force, out);
        loads
    }

    /// f_int += a force on the five relative coordinates, through their rows.
    #[inline(always)]
    fn add_to(&self, force: [f64; 5], out: &mut [f64]) {
        for (row, f) in self.rows.iter().zip(force) {
            if f != 0.0 {
                row.axpy(f, out);
            }
        }
    }

    /// j += c_c·C + c_k·K of the bearing at (q, v).
    pub fn add_tangent(&self, q: &[f64], v: &[f64], c_c: f64, c_k: f64, j: &mut DMatrix<f64>) {
        let (x, xd, cage) = self.kinematics(q, v);
        let (mut k, mut c) = ([[0.0; 5]; 5], [[0.0; 5]; 5]);
        self.evaluate(&x, &xd, cage, false, Some((&mut k, &mut c)));
        for a in 0..5 {
            for b in 0..5 {
                add_outer(j, c_k * k[a][b] + c_c * c[a][b], &self.rows[a], &self.rows[b]);
            }
        }
    }

    /// Hertz pressures and the subsurface shear of the most loaded lamina of `loads` (line
    /// contact) or the most loaded roller (point contact); zeros for a point contact given by its
    /// stiffness alone.
    pub fn stresses(&self, loads: &RollerLoads) -> RaceStresses {
        if loads.max_lamina_load <= 0.0 {
            return RaceStresses::default();
        }
        let (inner_pressure, outer_pressure, half_width) = match &self.hertz {
            RaceContacts::Line { inner, outer, e_star } => {
                let w = loads.max_lamina_load / self.lamina_width;
                let (i, o) = (
                    LineContact::new(w, *inner, *e_star),
                    LineContact::new(w, *outer, *e_star),
                );
                (i.max_pressure, o.max_pressure, i.half_width)
            }
            RaceContacts::Point { inner, outer } => {
                let (i, o) = (inner.at(loads.max_roller_load), outer.at(loads.max_roller_load));
                (i.max_pressure, o.max_pressure, i.semi_minor)
            }
            RaceContacts::Unknown => return RaceStresses::default(),
        };
        RaceStresses {
            inner_pressure,
            outer_pressure,
            max_shear: self.shear_peak.0 * inner_pressure,
            max_shear_depth: self.shear_peak.1 * half_width,
        }
    }

    /// Radial stiffness along the radial load at (q, v), N/m (the tangent a linear bearing at this
    /// operating point would need); 0 with no radial load.
    pub fn radial_stiffness(&self, q: &[f64], v: &[f64]) -> f64 {
        let (x, xd, cage) = self.kinematics(q, v);
        let (mut k, mut c) = ([[0.0; 5]; 5], [[0.0; 5]; 5]);
        let l = self.evaluate(&x, &xd, cage, false, Some((&mut k, &mut c)));
        let f = l.force[0].hypot(l.force[1]);
        if f == 0.0 {
            return 0.0;
        }
        let n = [l.force[0] / f, l.force[1] / f];
        (0..2).map(|a| (0..2).map(|b| n[a] * k[a][b] * n[b]).sum::<f64>()).sum()
    }

    pub fn roller_count(&self) -> usize {
        self.places.count() * self.roller_rows.len()
    }
}
