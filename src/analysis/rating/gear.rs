//! Gear geometry (ISO 21771) and tooth stresses after ISO 6336-2 (contact, method B) and ISO 6336-3
//! (root bending, method B), from a mesh force. Factors come from the geometry where the standard
//! gives a formula (α_t, β_b, α_wt, ε_α, ε_β, Z_H, Z_E, Z_ε, Z_β, Y_β) and are parameters otherwise
//! (K_A, K_v, K_Hβ, K_Fβ, K_Hα, K_Fα, K_γ); Y_F and Y_S of external teeth come from the root geometry
//! in `tooth_root`. Life factors Z_NT and Y_NT for case-carburised
//! steel are interpolated log–log between the standard's knots (ISO 6336-2/-3; docs/SOURCES.md §Published inputs).

use std::f64::consts::PI;

fn inv(a: f64) -> f64 {
    a.tan() - a
}

/// α with inv α = y (Newton from a good start; inv is monotonic on (0, π/2)).
fn inv_inverse(y: f64) -> f64 {
    let mut a = (3.0 * y).cbrt().min(1.4);
    for _ in 0..50 {
        let step = (inv(a) - y) / a.tan().powi(2);
        a -= step;
        if step.abs() < 1e-15 {
            break;
        }
    }
    a
}

/// A gear pair: pinion 1 (sun or pinion) with gear 2 (planet, wheel or, `internal`, the ring).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GearPair {
    pub z1: u32,
    pub z2: u32,
    pub internal: bool,
    /// Normal module, m.
    pub module: f64,
    /// Normal pressure angle α_n, rad.
    pub pressure_angle: f64,
    /// Helix angle β, rad.
    pub helix_angle: f64,
    /// Face width b, m.
    pub face_width: f64,
    pub shift1: f64,
    pub shift2: f64,
    /// Tip diameters when known (tip alteration); None = d + 2m(1 + x) (external), d − 2m(1 − x) (ring).
    pub tip_diameters: Option<(f64, f64)>,
}

/// What the geometry gives: angles in rad, lengths in m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry {
    pub transverse_pressure_angle: f64,
    pub base_helix_angle: f64,
    pub working_pressure_angle: f64,
    pub centre_distance: f64,
    pub d1: f64,
    pub d2: f64,
    pub transverse_contact_ratio: f64,
    pub overlap_ratio: f64,
}

impl GearPair {
    pub fn geometry(&self) -> Geometry {
        let (mn, an, b) = (self.module, self.pressure_angle, self.helix_angle);
        let at = (an.tan() / b.cos()).atan();
        let bb = (b.tan() * at.cos()).atan();
        let mt = mn / b.cos();
        let (z1, z2) = (self.z1 as f64, self.z2 as f64);
        let (d1, d2) = (z1 * mt, z2 * mt);
        let (db1, db2) = (d1 * at.cos(), d2 * at.cos());
        // inv α_wt = inv α_t + 2 tan α_n (x2 ± x1)/(z2 ± z1); internal pairs take differences
        let (zs, xs) = if self.internal {
            (z2 - z1, self.shift2 - self.shift1)
        } else {
            (z2 + z1, self.shift2 + self.shift1)
        };
        let awt = inv_inverse(inv(at) + 2.0 * an.tan() * xs / zs);
        let aw = if self.internal { db2 - db1 } else { db1 + db2 } / (2.0 * awt.cos());
        let (da1, da2) = self.tip_diameters_or_standard();
        let path = |da: f64, db: f64| ((da / 2.0).powi(2) - (db / 2.0).powi(2)).max(0.0).sqrt();
        let pbt = PI * mt * at.cos();
        let eps_a = if self.internal {
            (path(da1, db1) - path(da2, db2) + aw * awt.sin()) / pbt
        } else {
            (path(da1, db1) + path(da2, db2) - aw * awt.sin()) / pbt
        };
        Geometry {
            transverse_pressure_angle: at,
            base_helix_angle: bb,
            working_pressure_angle: awt,
            centre_distance: aw,
            d1,
            d2,
            transverse_contact_ratio: eps_a,
            overlap_ratio: self.face_width * b.sin() / (PI * mn),
        }
    }

    /// Tip diameters: as given, or d + 2m(1 + x) (external) and d − 2m(1 − x) (ring) without tip
    /// alteration.
    pub fn tip_diameters_or_standard(&self) -> (f64, f64) {
        let mt = self.module / self.helix_angle.cos();
        let (d1, d2) = (self.z1 as f64 * mt, self.z2 as f64 * mt);
        self.tip_diameters.unwrap_or((
            d1 + 2.0 * self.module * (1.0 + self.shift1),
            if self.internal {
                d2 - 2.0 * self.module * (1.0 - self.shift2)
            } else {
                d2 + 2.0 * self.module * (1.0 + self.shift2)
            },
        ))
    }

    /// Gear ratio u = z2/z1, negative for an internal pair (ISO 6336 sign).
    pub fn ratio(&self) -> f64 {
        let u = self.z2 as f64 / self.z1 as f64;
        if self.internal { -u } else { u }
    }
}

/// Zone factor Z_H = √(2 cos β_b cos α_wt / (cos² α_t sin α_wt)).
pub fn zone_factor(g: &Geometry) -> f64 {
    (2.0 * g.base_helix_angle.cos() * g.working_pressure_angle.cos()
        / (g.transverse_pressure_angle.cos().powi(2) * g.working_pressure_angle.sin()))
    .sqrt()
}

/// Elasticity factor Z_E = √(1/(π[(1−ν₁²)/E₁ + (1−ν₂²)/E₂])), in √Pa.
pub fn elasticity_factor(e1: f64, nu1: f64, e2: f64, nu2: f64) -> f64 {
    (1.0 / (PI * ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2))).sqrt()
}

/// Contact-ratio factor Z_ε (ISO 6336-2 method B).
pub fn contact_ratio_factor(g: &Geometry) -> f64 {
    let (ea, eb) = (g.transverse_contact_ratio, g.overlap_ratio);
    if eb >= 1.0 {
        (1.0 / ea).sqrt()
    } else {
        ((4.0 - ea) / 3.0 * (1.0 - eb) + eb / ea).sqrt()
    }
}

/// Helix-angle factor for contact, Z_β = 1/√(cos β) (ISO 6336-2:2006).
pub fn helix_factor_contact(helix_angle: f64) -> f64 {
    1.0 / helix_angle.cos().sqrt()
}

/// Helix-angle factor for bending, Y_β = 1 − ε_β·β/120° with ε_β ≤ 1 and β ≤ 30° (ISO 6336-3).
pub fn helix_factor_bending(g: &Geometry, helix_angle: f64) -> f64 {
    1.0 - g.overlap_ratio.min(1.0) * helix_angle.to_degrees().min(30.0) / 120.0
}

/// Load factors (ISO 6336-1) and the factors of ISO 6336-3 this module takes as given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Factors {
    pub k_a: f64,
    pub k_v: f64,
    pub k_h_beta: f64,
    pub k_h_alpha: f64,
    pub k_f_beta: f64,
    pub k_f_alpha: f64,
    /// Load sharing of a planetary stage (1.10 for 3 planets, IEC 61400-4).
    pub k_gamma: f64,
    /// Single-pair contact factor Z_B,D.
    pub z_bd: f64,
    /// Tooth form and stress correction factors (from the root geometry in the standard).
    pub y_f: f64,
    pub y_s: f64,
    pub y_b: f64,
    pub y_dt: f64,
}

impl Default for Factors {
    /// Everything 1, except K_A = 1.25 (as gfsReboucas/Drivetrain's NREL 5 MW rating takes it) and Y_F·Y_S
    /// of a standard 20° tooth with about 25 teeth (Y_F 2.6, Y_S 1.6: ISO 6336-3 charts, for illustration;
    /// give your own).
    fn default() -> Self {
        Factors {
            k_a: 1.25,
            k_v: 1.0,
            k_h_beta: 1.0,
            k_h_alpha: 1.0,
            k_f_beta: 1.0,
            k_f_alpha: 1.0,
            k_gamma: 1.0,
            z_bd: 1.0,
            y_f: 2.6,
            y_s: 1.6,
            y_b: 1.0,
            y_dt: 1.0,
        }
    }
}

/// What a mesh-force channel holds. Both act along the line of action; they differ by the helix.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum MeshForce {
    /// In the transverse plane, F_bt (torque / base radius): the torsional FMU's mesh forces.
    Transverse,
    /// Normal to the tooth, F_bn = F_bt / cos β_b: the gearbox6dof FMU's mesh forces.
    Normal,
}

/// Stresses of one pair made of steel (E = 206 GPa, ν = 0.3) unless given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ToothStress {
    pub pair: GearPair,
    pub factors: Factors,
    pub z_e: f64,
}

impl ToothStress {
    pub fn steel(pair: GearPair, factors: Factors) -> Self {
        ToothStress {
            pair,
            factors,
            z_e: elasticity_factor(206e9, 0.3, 206e9, 0.3),
        }
    }

    /// Nominal contact stress σ_H0 (Pa) at transverse tangential force F_t (N) on the pinion's
    /// reference circle: Z_H Z_E Z_ε Z_β √(F_t/(d₁ b)·(u+1)/u).
    pub fn nominal_contact(&self, ft: f64) -> f64 {
        let g = self.pair.geometry();
        let u = self.pair.ratio();
        zone_factor(&g)
            * self.z_e
            * contact_ratio_factor(&g)
            * helix_factor_contact(self.pair.helix_angle)
            * (ft.abs() / (g.d1 * self.pair.face_width) * (u + 1.0) / u).sqrt()
    }

    /// Contact stress σ_H = Z_B,D σ_H0 √(K_γ K_A K_v K_Hβ K_Hα).
    pub fn contact(&self, ft: f64) -> f64 {
        let f = &self.factors;
        f.z_bd * self.nominal_contact(ft) * (f.k_gamma * f.k_a * f.k_v * f.k_h_beta * f.k_h_alpha).sqrt()
    }

    /// Root bending stress σ_F = F_t/(b m_n)·Y_F Y_S Y_β Y_B Y_DT·K_γ K_A K_v K_Fβ K_Fα (Pa).
    pub fn bending(&self, ft: f64) -> f64 {
        let f = &self.factors;
        let g = self.pair.geometry();
        ft.abs() / (self.pair.face_width * self.pair.module)
            * f.y_f
            * f.y_s
            * helix_factor_bending(&g, self.pair.helix_angle)
            * f.y_b
            * f.y_dt
            * f.k_gamma
            * f.k_a
            * f.k_v
            * f.k_f_beta
            * f.k_f_alpha
    }

    /// Transverse tangential force on the reference circle from the normal force along the line of
    /// action (the gearbox6dof FMU's mesh force): F_bt = F_t / cos α_t and F_bn = F_bt / cos β_b.
    pub fn tangential_from_normal(&self, f_normal: f64) -> f64 {
        let g = self.pair.geometry();
        f_normal * g.transverse_pressure_angle.cos() * g.base_helix_angle.cos()
    }

    /// Transverse tangential force on the reference circle from a mesh force of either kind.
    pub fn tangential(&self, force: f64, kind: MeshForce) -> f64 {
        match kind {
            MeshForce::Normal => self.tangential_from_normal(force),
            MeshForce::Transverse => force * self.pair.geometry().transverse_pressure_angle.cos(),
        }
    }
}

/// Log–log interpolation through (cycles, factor) knots, constant beyond the ends.
fn life_factor(knots: &[(f64, f64)], n: f64) -> f64 {
    if n <= knots[0].0 {
        return knots[0].1;
    }
    for w in knots.windows(2) {
        let ((n0, f0), (n1, f1)) = (w[0], w[1]);
        if n <= n1 {
            let s = (n / n0).ln() / (n1 / n0).ln();
            return (f0.ln() + s * (f1 / f0).ln()).exp();
        }
    }
    knots[knots.len() - 1].1
}

/// Z_NT knots (load cycles, factor) of case-carburised steel (ISO 6336-2): 1.6 up to 1e5 load cycles,
/// 1.0 at 5e7, 0.85 at 1e10.
pub const CONTACT_LIFE_KNOTS: [(f64, f64); 3] = [(1e5, 1.6), (5e7, 1.0), (1e10, 0.85)];

/// Y_NT knots of case-carburised steel (ISO 6336-3): 2.5 up to 1e3, 1.0 at 3e6, 0.85 at 1e10.
pub const BENDING_LIFE_KNOTS: [(f64, f64); 3] = [(1e3, 2.5), (3e6, 1.0), (1e10, 0.85)];

/// Z_NT for case-carburised steel ([`CONTACT_LIFE_KNOTS`]).
pub fn contact_life_factor(cycles: f64) -> f64 {
    life_factor(&CONTACT_LIFE_KNOTS, cycles)
}

/// Y_NT for case-carburised steel ([`BENDING_LIFE_KNOTS`]).
pub fn bending_life_factor(cycles: f64) -> f64 {
    life_factor(&BENDING_LIFE_KNOTS, cycles)
}

/// Load cycles to failure where the life factor equals `ratio` = stress / limit stress: the inverse
/// of the log–log curve, its end slopes extended beyond the knots.
fn cycles_at_ratio(knots: &[(f64, f64)], ratio: f64) -> f64 {
    let seg = |(n0, f0): (f64, f64), (n1, f1): (f64, f64)| {
        // ln N = ln n0 + ln(ratio/f0) · ln(n1/n0)/ln(f1/f0)
        (n0.ln() + (ratio / f0).ln() * (n1 / n0).ln() / (f1 / f0).ln()).exp()
    };
    for w in knots.windows(2) {
        if ratio >= w[1].1 {
            return seg(w[0], w[1]);
        }
    }
    let k = knots.len();
    seg(knots[k - 2], knots[k - 1])
}

/// Contact S-N of case-carburised steel: load cycles to pitting at σ_H = ratio·σ_Hlim (inverse Z_NT).
pub fn contact_cycles_to_failure(ratio: f64) -> f64 {
    cycles_at_ratio(&CONTACT_LIFE_KNOTS, ratio)
}

/// Bending S-N of case-carburised steel: load cycles to root breakage at σ_F = ratio·σ_FE·Y_M
/// (inverse Y_NT).
pub fn bending_cycles_to_failure(ratio: f64) -> f64 {
    cycles_at_ratio(&BENDING_LIFE_KNOTS, ratio)
}

/// Which tooth of a planetary or parallel stage: how its load cycles and its bending reversal follow.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tooth {
    /// Sun: one mesh per planet per revolution relative to the carrier.
    Sun,
    /// Planet: meshes with the sun and the ring on opposite flanks, so its root bending alternates
    /// (R = −1): ISO 6336-3's mean-stress factor Y_M = 0.7 lowers the allowable stress.
    Planet,
    /// Fixed ring: one mesh per planet per carrier revolution.
    Ring,
    /// Parallel-stage pinion or wheel: one mesh per revolution.
    Parallel,
}

impl Tooth {
    /// Load cycles of one tooth for `revolutions` of the gear relative to the carrier (the carrier's
    /// own revolutions for the fixed ring) in a stage with `planets` planets.
    pub fn load_cycles(&self, revolutions: f64, planets: u32) -> f64 {
        match self {
            Tooth::Sun | Tooth::Ring => revolutions.abs() * planets as f64,
            Tooth::Planet | Tooth::Parallel => revolutions.abs(),
        }
    }

    /// Mean-stress factor Y_M of the allowable bending stress.
    pub fn mean_stress_factor(&self) -> f64 {
        if *self == Tooth::Planet { 0.7 } else { 1.0 }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::physics::hertz::{LineContact, effective_modulus};

    /// A spur pair of module 10 mm, 20°, face width 100 mm, no profile shift.
    pub(crate) fn spur(z1: u32, z2: u32, internal: bool) -> GearPair {
        GearPair {
            z1,
            z2,
            internal,
            module: 0.01,
            pressure_angle: 20f64.to_radians(),
            helix_angle: 0.0,
            face_width: 0.1,
            shift1: 0.0,
            shift2: 0.0,
            tip_diameters: None,
        }
    }

    /// Textbook values: Z_H = 2.495 for a spur pair with α = 20° and no shift (ISO 6336-2 chart);
    /// Z_E = 189.8 √MPa for steel on steel (ISO 6336-2's formula, E = 206 GPa, ν = 0.3); ε_α = 1.557 for
    /// 20/20 teeth of standard full depth.
    #[test]
    fn standard_factors() {
        let g = spur(20, 20, false).geometry();
        assert!((zone_factor(&g) - 2.4946).abs() < 1e-4, "{}", zone_factor(&g));
        assert!((elasticity_factor(206e9, 0.3, 206e9, 0.3) / 1e3f64.sqrt() / 1e3f64.sqrt() - 189.8).abs() < 0.05);
        assert!(
            (g.transverse_contact_ratio - 1.557).abs() < 1e-3,
            "{}",
            g.transverse_contact_ratio
        );
        assert!((g.centre_distance - 0.2).abs() < 1e-12);
    }

    /// NREL 5 MW gearbox (Nejad et al. 2016 Table V): the profile shifts turn
    /// the standard centre distances 810 / 567 / 845.9 mm into the published 863 / 584 / 861 mm.
    #[test]
    fn nrel_5mw_centre_distances_from_profile_shift() {
        let pair = |z1, z2, m: f64, beta: f64, x1, x2| GearPair {
            z1,
            z2,
            internal: false,
            module: m * 1e-3,
            pressure_angle: 20f64.to_radians(),
            helix_angle: beta.to_radians(),
            face_width: 0.5,
            shift1: x1,
            shift2: x2,
            tip_diameters: None,
        };
        for (p, published) in [
            (pair(19, 17, 45.0, 0.0, 0.617, 0.802), 0.863),
            (pair(18, 36, 21.0, 0.0, 0.389, 0.504), 0.584),
            (pair(24, 95, 14.0, 10.0, 0.480, 0.669), 0.861),
        ] {
            let a = p.geometry().centre_distance;
            // the paper rounds to whole millimetres
            assert!((a - published).abs() < 1e-3, "{a} vs {published}");
        }
    }

    /// ISO's nominal contact stress of a spur pair (Z_ε = Z_β = 1 for a single pair) at the pitch
    /// point is the Hertz line-contact pressure there: load F_t/(b cos α) per length on two cylinders
    /// of radii d sin α / 2 (concave for the ring). Two independent formulas, equal to 1e-12.
    #[test]
    fn nominal_contact_stress_is_hertz_at_the_pitch_point() {
        for (z1, z2, internal) in [(20, 40, false), (19, 56, true)] {
            let pair = spur(z1, z2, internal);
            let s = ToothStress::steel(pair, Factors::default());
            let g = pair.geometry();
            let ft = 1e5;
            let iso = s.nominal_contact(ft) / contact_ratio_factor(&g);
            let (r1, r2) = (
                g.d1 * 20f64.to_radians().sin() / 2.0,
                g.d2 * 20f64.to_radians().sin() / 2.0,
            );
            let r_eff = if internal {
                r1 * r2 / (r2 - r1)
            } else {
                r1 * r2 / (r1 + r2)
            };
            let w = ft / (pair.face_width * 20f64.to_radians().cos());
            let hertz = LineContact::new(w, r_eff, effective_modulus(206e9, 0.3, 206e9, 0.3)).max_pressure;
            assert!((iso / hertz - 1.0).abs() < 1e-12, "{iso} vs {hertz}");
        }
    }

    #[test]
    fn contact_ratio_and_helix_factors() {
        let mut p = spur(20, 40, false);
        p.helix_angle = 15f64.to_radians();
        p.face_width = 0.2;
        let g = p.geometry();
        assert!(g.overlap_ratio > 1.0);
        assert!((contact_ratio_factor(&g) - (1.0 / g.transverse_contact_ratio).sqrt()).abs() < 1e-15);
        // ε_β ≥ 1 and β = 15°: Y_β = 1 − 15/120
        assert!((helix_factor_bending(&g, p.helix_angle) - 0.875).abs() < 1e-12);
        let spur_g = spur(20, 40, false).geometry();
        assert!((contact_ratio_factor(&spur_g) - ((4.0 - spur_g.transverse_contact_ratio) / 3.0).sqrt()).abs() < 1e-15);
    }

    /// The life factors pass through the standard's knots and are monotonic between them.
    #[test]
    fn life_factors_through_their_knots() {
        assert_eq!(contact_life_factor(1e4), 1.6);
        assert!((contact_life_factor(5e7) - 1.0).abs() < 1e-12);
        assert!((bending_life_factor(3e6) - 1.0).abs() < 1e-12);
        assert_eq!(bending_life_factor(1e12), 0.85);
        // ISO 6336-2/-3's knots imply S-N exponents (σ ∝ N^(−1/m)) 13.2 for contact, 8.74 for bending
        let slope = |f: fn(f64) -> f64, n0: f64, n1: f64| (n1 / n0).ln() / (f(n0) / f(n1)).ln();
        assert!((slope(contact_life_factor, 1e5, 5e7) - 13.2).abs() < 0.05);
        assert!((slope(bending_life_factor, 1e3, 3e6) - 8.74).abs() < 0.01);
        // the S-N curves invert the life factors (where those are not flat)
        for n in [1e5, 4e6, 5e7, 3e9] {
            assert!(
                (contact_cycles_to_failure(contact_life_factor(n)) / n - 1.0).abs() < 1e-9,
                "{n}"
            );
        }
        for n in [2e3, 4e6, 5e7, 3e9] {
            assert!(
                (bending_cycles_to_failure(bending_life_factor(n)) / n - 1.0).abs() < 1e-9,
                "{n}"
            );
        }
        assert_eq!(Tooth::Sun.load_cycles(10.0, 3), 30.0);
        assert_eq!(Tooth::Planet.mean_stress_factor(), 0.7);
    }
}
