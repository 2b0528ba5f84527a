//! Hertz line contact (two parallel cylinders, e.g. a roller on a raceway or a gear-tooth pair at
//! the pitch point) and its subsurface stress field on the symmetry axis (McEwen's closed form,
//! plane strain); and Hertz point contact (a ball or a crowned roller on its raceway), whose
//! contact ellipse follows from the complete elliptic integrals. Johnson, *Contact Mechanics*,
//! §4.2–4.3.

/// Effective modulus 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂, Pa.
pub fn effective_modulus(e1: f64, nu1: f64, e2: f64, nu2: f64) -> f64 {
    1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2)
}

/// A loaded line contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineContact {
    /// Contact half-width a (often called b), m.
    pub half_width: f64,
    /// Maximum pressure p_max, Pa.
    pub max_pressure: f64,
}

impl LineContact {
    /// Load per unit length `w` (N/m) between bodies of effective radius 1/R' = 1/R₁ + 1/R₂ (m; a
    /// concave raceway has a negative radius) and effective modulus `e_star` (Pa).
    pub fn new(w: f64, r_eff: f64, e_star: f64) -> Self {
        let half_width = (4.0 * w * r_eff / (std::f64::consts::PI * e_star)).sqrt();
        Self {
            half_width,
            max_pressure: 2.0 * w / (std::f64::consts::PI * half_width),
        }
    }

    /// Principal stresses (σ_x, σ_y, σ_z) at depth z below the centre of the contact, Pa
    /// (compression negative; σ_y = ν(σ_x + σ_z) in plane strain).
    pub fn stresses_at_depth(&self, z: f64, nu: f64) -> (f64, f64, f64) {
        let (a, p) = (self.half_width, self.max_pressure);
        let root = (a * a + z * z).sqrt();
        let sx = -p / a * ((a * a + 2.0 * z * z) / root - 2.0 * z);
        let sz = -p * a / root;
        (sx, nu * (sx + sz), sz)
    }

    /// Maximum shear stress (Tresca) at depth z, Pa.
    pub fn max_shear_at_depth(&self, z: f64, nu: f64) -> f64 {
        tresca(self.stresses_at_depth(z, nu))
    }

    /// von Mises equivalent stress at depth z, Pa.
    pub fn von_mises_at_depth(&self, z: f64, nu: f64) -> f64 {
        let (sx, sy, sz) = self.stresses_at_depth(z, nu);
        (0.5 * ((sx - sy).powi(2) + (sy - sz).powi(2) + (sz - sx).powi(2))).sqrt()
    }

    /// Largest value of `f(z)` along the depth and where it occurs, by a fine scan to 3a refined
    /// by golden-section search: (value, depth).
    pub fn peak_along_depth(&self, f: impl Fn(f64) -> f64) -> (f64, f64) {
        peak_along(f, 3.0 * self.half_width, 3000, 100)
    }
}

/// The largest shear (Tresca) of three principal stresses.
fn tresca((sx, sy, sz): (f64, f64, f64)) -> f64 {
    0.5 * (sx.max(sy).max(sz) - sx.min(sy).min(sz))
}

/// Largest value of `f(z)` for depths 0 to `limit` and where it occurs: a scan of `points`
/// intervals, refined by `refine` golden-section steps around the best: (value, depth).
fn peak_along(f: impl Fn(f64) -> f64, limit: f64, points: usize, refine: usize) -> (f64, f64) {
    let h = limit / points as f64;
    let (mut best, mut at) = (f64::MIN, 0.0);
    for i in 0..=points {
        let z = h * i as f64;
        let v = f(z);
        if v > best {
            (best, at) = (v, z);
        }
    }
    let (mut lo, mut hi) = ((at - h).max(0.0), at + h);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..refine {
        let (z1, z2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if f(z1) > f(z2) { hi = z2 } else { lo = z1 }
    }
    let z = 0.5 * (lo + hi);
    (f(z), z)
}

/// Where the subsurface stresses of a frictionless line contact peak, per unit p_max and per unit
/// half-width: they depend on Poisson's ratio alone, so one scan serves every contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SubsurfacePeaks {
    /// (τ_max / p_max, depth / a)
    pub max_shear: (f64, f64),
    /// (σ_vM / p_max, depth / a)
    pub von_mises: (f64, f64),
}

pub fn subsurface_peaks(nu: f64) -> SubsurfacePeaks {
    let unit = LineContact {
        half_width: 1.0,
        max_pressure: 1.0,
    };
    SubsurfacePeaks {
        max_shear: unit.peak_along_depth(|z| unit.max_shear_at_depth(z, nu)),
        von_mises: unit.peak_along_depth(|z| unit.von_mises_at_depth(z, nu)),
    }
}

/// Complete elliptic integrals of the first and second kind, K(m) and E(m), of parameter m = e²
/// (0 ≤ m < 1), by the arithmetic–geometric mean (Abramowitz & Stegun 17.6.3–4): quadratic
/// convergence, exact to rounding within 40 iterations.
pub fn elliptic_integrals(m: f64) -> (f64, f64) {
    let (mut a, mut b) = (1.0f64, (1.0 - m).sqrt());
    // E = K·(1 − Σ 2^(n−1)·c_n²), c_0² = m
    let (mut sum, mut weight) = (0.5 * m, 0.5);
    for _ in 0..40 {
        let c = 0.5 * (a - b);
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
        weight *= 2.0;
        sum += weight * c * c;
        // c² then lies below the sum's rounding
        if c.abs() <= 1e-15 * a {
            break;
        }
    }
    let k = std::f64::consts::PI / (2.0 * a);
    (k, k * (1.0 - sum))
}

/// The geometry of a Hertz point contact between two bodies whose principal planes coincide: the
/// relative curvatures 1/R_x and 1/R_y in the two planes (1/R = 1/R₁ + 1/R₂, a concave surface's
/// radius negative) and E*. The ellipse's shape depends on the geometry alone, its size on the load
/// (as Q^(1/3)), so the transcendental equation is solved once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EllipticContact {
    /// κ = a/b ≥ 1: the semi-major axis a lies in the plane of less curvature.
    pub aspect: f64,
    /// Σρ = 1/R_x + 1/R_y, 1/m.
    pub curvature_sum: f64,
    pub e_star: f64,
    k: f64,
    e: f64,
}

/// A loaded point contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EllipticLoad {
    /// Semi-axes a ≥ b of the contact ellipse, m.
    pub semi_major: f64,
    pub semi_minor: f64,
    /// p_max = 3Q/(2πab), Pa.
    pub max_pressure: f64,
    /// Approach of the two bodies' distant points, m.
    pub approach: f64,
}

impl EllipticContact {
    /// From the effective radii in the two principal planes (m, both positive: a point contact)
    /// and E* (Pa). None when a radius is not positive and finite (the bodies conform or separate
    /// in that plane: no point contact), or when the ellipse would be more than 10⁶ times longer
    /// than wide (a line contact in all but name).
    pub fn new(rx: f64, ry: f64, e_star: f64) -> Option<Self> {
        if !(rx > 0.0 && ry > 0.0 && rx.is_finite() && ry.is_finite() && e_star > 0.0) {
            return None;
        }
        let (px, py) = (1.0 / rx, 1.0 / ry);
        let sum = px + py;
        // (B − A)/(A + B) = [(κ² + 1)E(e) − 2K(e)] / [(κ² − 1)E(e)], e² = 1 − 1/κ² (Johnson 4.39,
        // Harris's curvature difference); its right side rises from 0 at κ = 1 to 1
        let difference = (px - py).abs() / sum;
        let side = |kappa: f64| {
            let (k, e) = elliptic_integrals(1.0 - 1.0 / (kappa * kappa));
            ((kappa * kappa + 1.0) * e - 2.0 * k) / ((kappa * kappa - 1.0) * e)
        };
        let aspect = if difference < 1e-12 {
            1.0
        } else {
            // bisection on ln κ from just above 1 to 10⁶ (a roller's crown far flatter than any bearing's)
            let top = 6.0 * std::f64::consts::LN_10;
            let (mut lo, mut hi) = (1e-9f64, top);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if side(mid.exp()) < difference {
                    lo = mid;
                } else {
                    hi = mid;
                }
                if hi - lo < 1e-15 {
                    break;
                }
            }
            if hi >= top - 1e-9 {
                return None;
            }
            (0.5 * (lo + hi)).exp()
        };
        let (k, e) = elliptic_integrals(1.0 - 1.0 / (aspect * aspect));
        Some(Self {
            aspect,
            curvature_sum: sum,
            e_star,
            k,
            e,
        })
    }

    /// The contact under load `q` (N).
    pub fn at(&self, q: f64) -> EllipticLoad {
        use std::f64::consts::PI;
        let (kappa, sum) = (self.aspect, self.curvature_sum);
        let scale = (3.0 * q.max(0.0) / (2.0 * sum * self.e_star)).cbrt();
        let semi_major = (2.0 * kappa * kappa * self.e / PI).cbrt() * scale;
        let semi_minor = (2.0 * self.e / (PI * kappa)).cbrt() * scale;
        let approach = 2.0 * self.k / PI * (PI / (2.0 * kappa * kappa * self.e)).cbrt() * scale * scale * 0.5 * sum;
        let max_pressure = if q > 0.0 {
            3.0 * q / (2.0 * PI * semi_major * semi_minor)
        } else {
            0.0
        };
        EllipticLoad {
            semi_major,
            semi_minor,
            max_pressure,
            approach,
        }
    }

    /// c in Q = c·δ^(3/2), N/m^1.5.
    pub fn stiffness(&self) -> f64 {
        self.at(1.0).approach.powf(-1.5)
    }

    /// Where the largest subsurface shear (Tresca) of the contact lies, per unit p_max and per unit
    /// semi-minor axis b: (τ_max/p_max, depth/b). It depends on κ and ν alone: 0.31 at 0.48b for a
    /// circle (ν = 0.3), 0.324 at 0.63b for κ = 2, tending to the line contact's 0.300 at 0.786b as κ
    /// grows. Beyond κ = 200 (within 0.4 % of the line contact there) the line contact's values.
    pub fn max_shear(&self, nu: f64) -> (f64, f64) {
        if self.aspect > 200.0 {
            return subsurface_peaks(nu).max_shear;
        }
        // a coarse scan to 2b: each point is a quadrature over the ellipse
        peak_along(|z| tresca(elliptic_stresses_on_axis(self.aspect, z, nu)), 2.0, 40, 40)
    }
}

/// Gauss–Legendre nodes and weights on [0, 1] (Newton on P_n from Chebyshev's guesses).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    use std::f64::consts::PI;
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                // P_n(x) and P_n'(x) by the three-term recurrence
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let k = k as f64;
                    (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let step = p1 / dp;
                x -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            (0.5 * (1.0 - x), 1.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// Principal stresses (σ_x, σ_y, σ_z) at depth z on the axis of a Hertz pressure p_max = 1 over the
/// ellipse of semi-axes κ (along x) and 1 (along y): Boussinesq's point-load field integrated over
/// the ellipse (Johnson §3.2). On the axis the shears vanish by symmetry. In polar coordinates
/// (x, y) = (κ·s·cos φ, s·sin φ) with s = sin θ, which takes the pressure's square root into the
/// weight, Gauss–Legendre in θ clusters nodes at the centre, where the kernel peaks, and the polar
/// angle gets 30κ points a quarter, so the long axis is resolved as finely as the short one: Johnson's
/// closed form on the axis of a circle to 1e-12 of p_max at depths from 0.1b on.
/// κ up to 200 (`EllipticContact::max_shear` takes the line contact beyond): 6000 polar points.
fn elliptic_stresses_on_axis(kappa: f64, z: f64, nu: f64) -> (f64, f64, f64) {
    use std::f64::consts::{FRAC_PI_2, PI};
    static RADIAL: std::sync::OnceLock<Vec<(f64, f64)>> = std::sync::OnceLock::new();
    let radial = RADIAL.get_or_init(|| gauss_legendre(64));
    let np = ((30.0 * kappa.clamp(1.0, 200.0)).ceil() as usize).max(64);
    let polar: Vec<(f64, f64)> = (0..np)
        .map(|j| (FRAC_PI_2 * (j as f64 + 0.5) / np as f64).sin_cos())
        .collect();
    let (mut sx, mut sy, mut sz) = (0.0, 0.0, 0.0);
    for &(t, wt) in radial {
        let (s, c) = (FRAC_PI_2 * t).sin_cos();
        // p·dA = √(1 − s²)·κ·s ds dφ, ds = cos θ dθ, a quarter of the ellipse times four
        let weight_s = 4.0 * c * c * s * kappa * FRAC_PI_2 * wt * FRAC_PI_2 / np as f64;
        for &(sp, cp) in &polar {
            let (x, y) = (kappa * s * cp, s * sp);
            let r2 = x * x + y * y;
            let rho2 = r2 + z * z;
            let rho = rho2.sqrt();
            let rho3 = rho2 * rho;
            let rho5 = rho3 * rho2;
            let common = (1.0 - 2.0 * nu) / r2;
            let lift = 1.0 - z / rho;
            sx += weight_s * (common * (lift * (x * x - y * y) / r2 + z * y * y / rho3) - 3.0 * z * x * x / rho5);
            sy += weight_s * (common * (lift * (y * y - x * x) / r2 + z * x * x / rho3) - 3.0 * z * y * y / rho5);
            sz -= weight_s * 3.0 * z * z * z / rho5;
        }
    }
    let k = 1.0 / (2.0 * PI);
    (k * sx, k * sy, k * sz)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Johnson, Contact Mechanics §4.2: for a frictionless line contact the largest shear stress is
    /// 0.300 p_max at 0.786 a below the surface; von Mises (ν = 0.3) peaks at 0.557 p_max at 0.704 a
    /// (McEwen's field evaluated by hand). Tolerance 0.5 % of the printed three digits.
    #[test]
    fn subsurface_maxima_match_the_textbook() {
        let c = LineContact::new(1e6, 16.67e-3, effective_modulus(210e9, 0.3, 210e9, 0.3));
        let (tau, z_tau) = c.peak_along_depth(|z| c.max_shear_at_depth(z, 0.3));
        assert!(
            (tau / c.max_pressure - 0.300).abs() < 0.0015,
            "{}",
            tau / c.max_pressure
        );
        assert!((z_tau / c.half_width - 0.786).abs() < 0.004, "{}", z_tau / c.half_width);
        let (vm, z_vm) = c.peak_along_depth(|z| c.von_mises_at_depth(z, 0.3));
        assert!((vm / c.max_pressure - 0.557).abs() < 0.003, "{}", vm / c.max_pressure);
        assert!((z_vm / c.half_width - 0.704).abs() < 0.004, "{}", z_vm / c.half_width);
        // the unit contact gives the same ratios
        let p = subsurface_peaks(0.3);
        assert!(
            (p.max_shear.0 - tau / c.max_pressure).abs() < 1e-6 && (p.max_shear.1 - z_tau / c.half_width).abs() < 1e-6
        );
        assert!(
            (p.von_mises.0 - vm / c.max_pressure).abs() < 1e-6 && (p.von_mises.1 - z_vm / c.half_width).abs() < 1e-6
        );
    }

    /// Worked by hand from Johnson's formulas: Ø40 roller on Ø200 race (R' = 16.67 mm), steel/steel,
    /// 1000 N/mm: E* = 115.4 GPa, b = 0.429 mm, p_max = 1484 MPa.
    #[test]
    fn roller_on_race_example() {
        let e = effective_modulus(210e9, 0.3, 210e9, 0.3);
        assert!((e / 115.4e9 - 1.0).abs() < 1e-3);
        let r = 1.0 / (1.0 / 0.020 + 1.0 / 0.100);
        let c = LineContact::new(1e6, r, e);
        assert!((c.half_width / 0.429e-3 - 1.0).abs() < 2e-3, "{}", c.half_width);
        assert!((c.max_pressure / 1484e6 - 1.0).abs() < 2e-3, "{}", c.max_pressure);
        // at the surface the pressure is p_max in both directions
        let (sx, _, sz) = c.stresses_at_depth(0.0, 0.3);
        assert!(
            (sx + c.max_pressure).abs() < 1e-6 * c.max_pressure && (sz + c.max_pressure).abs() < 1e-6 * c.max_pressure
        );
    }

    /// K and E of m = ½ (Abramowitz & Stegun Table 17.1: K = 1.854074677301372, E =
    /// 1.350643881047675) and of m = 0 (both π/2), to rounding.
    #[test]
    fn elliptic_integrals_by_the_agm() {
        let (k, e) = elliptic_integrals(0.5);
        assert!((k - 1.854_074_677_301_372).abs() < 1e-14, "{k}");
        assert!((e - 1.350_643_881_047_675).abs() < 1e-14, "{e}");
        let (k, e) = elliptic_integrals(0.0);
        assert!((k - std::f64::consts::FRAC_PI_2).abs() < 1e-15 && (e - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    }

    /// A sphere on a flat (equal curvatures): Hertz's circle, a = (3QR/4E*)^(1/3), p_max = 3Q/2πa²,
    /// δ = a²/R, to rounding (R the sphere's radius, so 1/R_x = 1/R_y = 1/R).
    #[test]
    fn equal_curvatures_give_hertz_circle() {
        let e_star = effective_modulus(210e9, 0.3, 210e9, 0.3);
        let (r, q) = (0.0127, 5000.0);
        let c = EllipticContact::new(r, r, e_star).unwrap();
        let l = c.at(q);
        let a = (3.0 * q * r / (4.0 * e_star)).cbrt();
        assert!((c.aspect - 1.0).abs() < 1e-12);
        assert!((l.semi_major / a - 1.0).abs() < 1e-12 && (l.semi_minor / a - 1.0).abs() < 1e-12);
        let p = 3.0 * q / (2.0 * std::f64::consts::PI * a * a);
        assert!((l.max_pressure / p - 1.0).abs() < 1e-12);
        assert!((l.approach / (a * a / r) - 1.0).abs() < 1e-12);
        // Q = c·δ^1.5
        assert!((c.stiffness() * l.approach.powf(1.5) / q - 1.0).abs() < 1e-12);
    }

    /// Against Hamrock and Dowson's curve fits (1981; κ = 1.0339·α^0.636, E = 1.0003 + 0.5968/α,
    /// F = 1.5277 + 0.6023·ln α for α = R_y/R_x), an independent approximation of the same theory:
    /// for 2 ≤ α ≤ 25 the fits differ from the exact solution by their own error, largest at α = 2
    /// (a +0.9 %, b −0.4 %, p_max −0.5 %, δ −1.3 %, computed with scipy's ellipk and ellipe); the
    /// tolerances are 1.5 % on the semi-axes and the approach, 1 % on the pressure.
    #[test]
    fn elongated_contacts_agree_with_hamrock_and_dowson() {
        use std::f64::consts::PI;
        let e_star = effective_modulus(210e9, 0.3, 210e9, 0.3);
        let (rx, q) = (0.01, 1e4);
        for alpha in [2.0, 5.0, 10.0, 25.0] {
            let ry = alpha * rx;
            let l = EllipticContact::new(rx, ry, e_star).unwrap().at(q);
            let k = 1.0339 * f64::powf(alpha, 0.636);
            let e = 1.0003 + 0.5968 / alpha;
            let f = 1.5277 + 0.6023 * f64::ln(alpha);
            let r = 1.0 / (1.0 / rx + 1.0 / ry);
            let ep = 2.0 * e_star;
            let a = (6.0 * k * k * e * q * r / (PI * ep)).cbrt();
            let b = (6.0 * e * q * r / (PI * k * ep)).cbrt();
            let delta = f * ((9.0 / (2.0 * e * r)) * (q / (PI * k * ep)).powi(2)).cbrt();
            let p = 3.0 * q / (2.0 * PI * a * b);
            for (name, fit, exact, tolerance) in [
                ("a", a, l.semi_major, 0.015),
                ("b", b, l.semi_minor, 0.015),
                ("p_max", p, l.max_pressure, 0.01),
                ("δ", delta, l.approach, 0.015),
            ] {
                assert!(
                    (fit / exact - 1.0).abs() < tolerance,
                    "α {alpha}: {name} {fit} vs {exact}"
                );
            }
        }
        // no point contact where the bodies conform
        assert!(EllipticContact::new(0.01, -0.5, e_star).is_none());
    }

    /// On the axis of a circular contact (κ = 1) the quadrature gives Johnson's closed form (his
    /// eq. 3.45): σ_z = −p/(1 + z²/a²), σ_r = −p·[(1 + ν)(1 − (z/a)·atan(a/z)) − ½/(1 + z²/a²)], to
    /// 1e-12 of p_max; the largest shear is 0.31·p_max at 0.48·a (ν = 0.3). A long ellipse tends to
    /// the line contact's 0.300·p_max at 0.786·b: κ = 100 within 1 % (0.63 % and 0.03 %), nearer
    /// than κ = 20.
    #[test]
    fn subsurface_stresses_of_a_point_contact() {
        let nu = 0.3;
        for z in [0.1, 0.3, 0.48, 0.8, 1.5] {
            let (sx, sy, sz) = elliptic_stresses_on_axis(1.0, z, nu);
            let szc = -1.0 / (1.0 + z * z);
            let src = -((1.0 + nu) * (1.0 - z * (1.0 / z).atan()) - 0.5 / (1.0 + z * z));
            assert!((sz - szc).abs() < 1e-12, "z {z}: σ_z {sz} vs {szc}");
            assert!(
                (sx - src).abs() < 1e-12 && (sy - src).abs() < 1e-12,
                "z {z}: σ_r {sx} {sy} vs {src}"
            );
        }
        let e_star = effective_modulus(210e9, nu, 210e9, nu);
        let circle = EllipticContact::new(0.01, 0.01, e_star).unwrap().max_shear(nu);
        assert!(
            (circle.0 - 0.31).abs() < 0.005 && (circle.1 - 0.48).abs() < 0.01,
            "{circle:?}"
        );
        let elongated = |aspect| {
            EllipticContact {
                aspect,
                ..EllipticContact::new(0.01, 0.01, e_star).unwrap()
            }
            .max_shear(nu)
        };
        let (long, longer) = (elongated(20.0), elongated(100.0));
        let line = subsurface_peaks(nu).max_shear;
        assert!(
            (longer.0 / line.0 - 1.0).abs() < 0.01 && (longer.1 / line.1 - 1.0).abs() < 0.01,
            "{longer:?} vs {line:?}"
        );
        assert!(
            (long.0 - line.0).abs() > (longer.0 - line.0).abs(),
            "{long:?} {longer:?}"
        );
    }
}
