//! Hertz line contact (two parallel cylinders, e.g. a roller on a raceway or a gear-tooth pair at
//! the pitch point) and its subsurface stress field on the symmetry axis (McEwen's closed form,
//! plane strain). Johnson, *Contact Mechanics*, §4.2–4.3.

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
        let (sx, sy, sz) = self.stresses_at_depth(z, nu);
        0.5 * (sx.max(sy).max(sz) - sx.min(sy).min(sz))
    }

    /// von Mises equivalent stress at depth z, Pa.
    pub fn von_mises_at_depth(&self, z: f64, nu: f64) -> f64 {
        let (sx, sy, sz) = self.stresses_at_depth(z, nu);
        (0.5 * ((sx - sy).powi(2) + (sy - sz).powi(2) + (sz - sx).powi(2))).sqrt()
    }

    /// Largest value of `f(z)` along the depth and where it occurs, by a fine scan to 3a refined
    /// by golden-section search: (value, depth).
    pub fn peak_along_depth(&self, f: impl Fn(f64) -> f64) -> (f64, f64) {
        let a = self.half_width;
        let n = 3000;
        let (mut best, mut at) = (f64::MIN, 0.0);
        for i in 0..=n {
            let z = 3.0 * a * i as f64 / n as f64;
            let v = f(z);
            if v > best {
                (best, at) = (v, z);
            }
        }
        let (mut lo, mut hi) = ((at - 3.0 * a / n as f64).max(0.0), at + 3.0 * a / n as f64);
        let g = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..100 {
            let (z1, z2) = (hi - g * (hi - lo), lo + g * (hi - lo));
            if f(z1) > f(z2) { hi = z2 } else { lo = z1 }
        }
        let z = 0.5 * (lo + hi);
        (f(z), z)
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Johnson, Contact Mechanics §4.2: for a frictionless line contact the largest shear stress is
    /// 0.300 p_max at 0.786 a below the surface; von Mises (ν = 0.3) peaks at 0.557 p_max at 0.704 a
    /// (REFERENCE-DATA.md §4, computed). Tolerance 0.5 % of the printed three digits.
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

    /// REFERENCE-DATA.md §4 worked example: Ø40 roller on Ø200 race (R' = 16.67 mm), steel/steel,
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
}
