//! Involute helical gear-pair geometry (ISO 21771 relations) and the ISO 6336-1 mesh stiffness.
//!
//! Lengths in metres; the tooth-count, module and shift relations are the standard ones:
//! tan α_t = tan α_n / cos β, tan β_b = tan β·cos α_t, d = m_n·z / cos β, d_b = d·cos α_t,
//! inv α_wt = inv α_t + 2 tan α_n (x₁ ± x₂)/(z₂ ± z₁) (+ external, − internal), ε_β = b sin β/(π m_n).

use std::f64::consts::PI;

/// One pair's geometry as the mesh force element needs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairGeometry {
    /// Transverse operating pressure angle α_wt, rad.
    pub pressure_angle: f64,
    /// Base helix angle β_b, rad.
    pub base_helix: f64,
    /// Operating centre distance, m.
    pub centre_distance: f64,
    /// Base radii of wheel 1 and 2, m (the ring's for an internal pair).
    pub base_radius: [f64; 2],
    /// Operating pitch radii, m.
    pub pitch_radius: [f64; 2],
    /// Transverse contact ratio ε_α and overlap ratio ε_β.
    pub contact_ratio: f64,
    pub overlap_ratio: f64,
    /// Transverse base pitch p_bt, m.
    pub base_pitch: f64,
    /// Wheel 2 is a ring (internal teeth).
    pub internal: bool,
}

/// A gear pair's defining data. `internal` makes wheel 2 a ring (internal teeth).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pair {
    pub teeth: [u32; 2],
    pub shift: [f64; 2],
    /// Normal module, m.
    pub module: f64,
    /// Normal pressure angle and helix angle, rad.
    pub pressure_angle: f64,
    pub helix_angle: f64,
    /// Face width, m.
    pub face_width: f64,
    /// Addendum and dedendum of the basic rack, in modules (1.0 and 1.25 by default).
    pub addendum: f64,
    pub dedendum: f64,
    pub internal: bool,
    /// Operating centre distance, m; None = from the profile shifts.
    pub centre_distance: Option<f64>,
}

fn involute(a: f64) -> f64 {
    a.tan() - a
}

/// The α with inv α = y (Newton from the Cheng-style starting value; y up to ≈ 0.5).
fn inverse_involute(y: f64) -> f64 {
    let mut a = (3.0 * y).cbrt().min(1.4);
    for _ in 0..50 {
        let f = involute(a) - y;
        let df = a.tan().powi(2);
        let next = a - f / df.max(1e-300);
        if (next - a).abs() < 1e-15 {
            return next;
        }
        a = next.clamp(1e-6, 1.5);
    }
    a
}

impl Pair {
    pub fn transverse_pressure_angle(&self) -> f64 {
        (self.pressure_angle.tan() / self.helix_angle.cos()).atan()
    }

    pub fn transverse_module(&self) -> f64 {
        self.module / self.helix_angle.cos()
    }

    /// Reference radius of wheel i.
    pub fn reference_radius(&self, i: usize) -> f64 {
        0.5 * self.transverse_module() * f64::from(self.teeth[i])
    }

    pub fn base_radius(&self, i: usize) -> f64 {
        self.reference_radius(i) * self.transverse_pressure_angle().cos()
    }

    /// Geometry at the operating centre distance. Err names the inconsistency.
    pub fn geometry(&self) -> Result<PairGeometry, String> {
        let at = self.transverse_pressure_angle();
        let (z1, z2) = (f64::from(self.teeth[0]), f64::from(self.teeth[1]));
        let sign = if self.internal { -1.0 } else { 1.0 };
        let mt = self.transverse_module();
        let reference_distance = 0.5 * mt * (z2 + sign * z1);
        if reference_distance <= 0.0 {
            return Err(format!(
                "teeth {} and {} do not make an {} pair",
                self.teeth[0],
                self.teeth[1],
                if self.internal { "internal" } else { "external" }
            ));
        }
        let (awt, a) = match self.centre_distance {
            Some(a) => {
                let c = reference_distance * at.cos() / a;
                if c.is_nan() || c.abs() >= 1.0 {
                    return Err(format!("centre distance {:.4} m cannot be reached by these teeth", a));
                }
                (c.acos(), a)
            }
            None => {
                let inv = involute(at)
                    + 2.0 * self.pressure_angle.tan() * (self.shift[1] + sign * self.shift[0]) / (z2 + sign * z1);
                let awt = inverse_involute(inv);
                (awt, reference_distance * at.cos() / awt.cos())
            }
        };
        let rb = [self.base_radius(0), self.base_radius(1)];
        // tip radii from the shifted reference profile (tip shortening ignored: a documented simplification)
        let m = self.module;
        let ra1 = self.reference_radius(0) + m * (self.addendum + self.shift[0]);
        let ra2 = if self.internal {
            self.reference_radius(1) - m * (self.addendum - self.shift[1])
        } else {
            self.reference_radius(1) + m * (self.addendum + self.shift[1])
        };
        let pbt = PI * mt * at.cos();
        let approach = (ra1 * ra1 - rb[0] * rb[0]).max(0.0).sqrt();
        let other = (ra2 * ra2 - rb[1] * rb[1]).max(0.0).sqrt();
        let eps_a = if self.internal {
            (approach - other + a * awt.sin()) / pbt
        } else {
            (approach + other - a * awt.sin()) / pbt
        };
        if eps_a.is_nan() || eps_a <= 1.0 {
            return Err(format!(
                "transverse contact ratio {eps_a:.3} ≤ 1: the teeth lose contact"
            ));
        }
        let base_helix = (self.helix_angle.tan() * at.cos()).atan();
        let pitch = [rb[0] / awt.cos(), rb[1] / awt.cos()];
        Ok(PairGeometry {
            pressure_angle: awt,
            base_helix,
            centre_distance: a,
            base_radius: rb,
            pitch_radius: pitch,
            contact_ratio: eps_a,
            overlap_ratio: self.face_width * self.helix_angle.sin().abs() / (PI * m),
            base_pitch: pbt,
            internal: self.internal,
        })
    }

    /// ISO 6336-1 method B single stiffness c′ and mesh stiffness c_γα, N/(mm·µm) = N/m per m·1e-? (returned
    /// in N/m per metre of face width, i.e. N/m²: multiply by the face width for N/m).
    pub fn iso_stiffness(&self, contact_ratio: f64) -> (f64, f64) {
        let bb = (self.helix_angle.tan() * self.transverse_pressure_angle().cos()).atan();
        let zn = |z: u32| f64::from(z) / (bb.cos().powi(2) * self.helix_angle.cos());
        let (zn1, zn2) = (zn(self.teeth[0]), zn(self.teeth[1]));
        // an internal gear behaves as a wheel of infinite teeth in the ISO flexibility fit
        let inv_zn2 = if self.internal { 0.0 } else { 1.0 / zn2 };
        let (x1, x2) = (self.shift[0], self.shift[1]);
        let q = 0.04723 + 0.15551 / zn1 + 0.25791 * inv_zn2
            - 0.00635 * x1
            - 0.11654 * x1 / zn1
            - 0.00193 * x2
            - 0.24188 * x2 * inv_zn2
            + 0.00529 * x1 * x1
            + 0.00182 * x2 * x2;
        let c_th = 1.0 / q;
        let c_m = 0.8;
        let c_r = 1.0;
        let c_b = (1.0 + 0.5 * (1.2 - self.dedendum)) * (1.0 - 0.02 * (20.0 - self.pressure_angle.to_degrees()));
        let c_single = c_th * c_m * c_r * c_b * self.helix_angle.cos();
        let c_gamma = c_single * (0.75 * contact_ratio + 0.25);
        // N/(mm·µm) → N/m per m of face width: 1 N/(mm·µm) = 1e9 N/m²
        (c_single * 1e9, c_gamma * 1e9)
    }
}

/// Rolled teeth of a wheel: the mesh phase in teeth of wheel `teeth` turned by `angle` rad.
pub fn teeth_rolled(teeth: u32, angle: f64) -> f64 {
    f64::from(teeth) * angle / (2.0 * PI)
}

/// Tooth pairs in contact at roll position s (in base pitches) for contact ratio ε.
pub fn pairs_in_contact(s: f64, contact_ratio: f64) -> u32 {
    let whole = contact_ratio.floor();
    let part = contact_ratio - whole;
    let f = s - s.floor();
    whole as u32 + u32::from(f < part)
}

/// Mean tooth pairs in contact over roll positions [s − width/2, s + width/2] (width in base
/// pitches, ≥ 0; 0 gives `pairs_in_contact` at s). A slice of a helical face spans this much roll
/// along its width, so its stiffness follows the share of its contact line on each pair count, and
/// the face's total follows the contact line's length whatever the slice count, instead of switching
/// a whole slice at once.
pub fn mean_pairs_in_contact(s: f64, width: f64, contact_ratio: f64) -> f64 {
    if width <= 0.0 {
        return f64::from(pairs_in_contact(s, contact_ratio));
    }
    let whole = contact_ratio.floor();
    let part = contact_ratio - whole;
    // roll spent with the extra pair from 0 to x: one `part` a base pitch, then the start of the
    // current pitch
    let extra = |x: f64| x.floor() * part + (x - x.floor()).min(part);
    whole + (extra(s + 0.5 * width) - extra(s - 0.5 * width)) / width
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grc_sun_planet() -> Pair {
        Pair {
            teeth: [21, 39],
            shift: [0.0, 0.0],
            module: 0.010,
            pressure_angle: 20f64.to_radians(),
            helix_angle: 7.5f64.to_radians(),
            face_width: 0.1,
            addendum: 1.0,
            dedendum: 1.25,
            internal: false,
            centre_distance: None,
        }
    }

    #[test]
    fn grc_geometry_matches_the_data_sheet() {
        // by hand from the GRC's teeth, modules and helix angles: sun reference Ø 211.8 mm, a = 302.6 mm,
        // ε_α ≈ 1.62, ε_β 0.415 per 100 mm, β_b 7.05°
        let p = grc_sun_planet();
        let g = p.geometry().unwrap();
        assert!((2.0 * p.reference_radius(0) - 0.2118).abs() < 2e-4);
        assert!((g.centre_distance - 0.3026).abs() < 2e-4, "{}", g.centre_distance);
        assert!((g.contact_ratio - 1.62).abs() < 0.02, "{}", g.contact_ratio);
        assert!((g.overlap_ratio - 0.415).abs() < 0.002);
        assert!((g.base_helix.to_degrees() - 7.05).abs() < 0.01);
        // ring–planet ε_α ≈ 1.91
        let r = Pair {
            teeth: [39, 99],
            internal: true,
            ..p
        };
        let gr = r.geometry().unwrap();
        assert!((gr.contact_ratio - 1.91).abs() < 0.03, "{}", gr.contact_ratio);
        assert!((gr.centre_distance - 0.3026).abs() < 2e-4);
    }

    #[test]
    fn nrel_5mw_shifts_give_the_published_centre_distances() {
        // Nejad 2016 Table V: stage 1 x = 0.617/0.802, a_w = 863 mm; stage 3 β 10°, a_w = 861 mm
        let s1 = Pair {
            teeth: [19, 17],
            shift: [0.617, 0.802],
            module: 0.045,
            pressure_angle: 20f64.to_radians(),
            helix_angle: 0.0,
            face_width: 0.491,
            addendum: 1.0,
            dedendum: 1.25,
            internal: false,
            centre_distance: None,
        };
        let a = s1.geometry().unwrap().centre_distance;
        assert!((a - 0.863).abs() < 0.002, "{a}");
        let s3 = Pair {
            teeth: [24, 95],
            shift: [0.480, 0.669],
            module: 0.014,
            helix_angle: 10f64.to_radians(),
            face_width: 0.36,
            ..s1
        };
        let a3 = s3.geometry().unwrap().centre_distance;
        assert!((a3 - 0.861).abs() < 0.002, "{a3}");
    }

    #[test]
    fn iso_single_stiffness_is_the_textbook_value() {
        // ISO 6336-1 by hand: c′ of the GRC sun–planet pair (x = 0, h_fP = 1.25 m_n) ≈ 12.7 N/(mm·µm)
        let p = grc_sun_planet();
        let (c1, cg) = p.iso_stiffness(1.62);
        assert!((c1 / 1e9 - 12.7).abs() < 0.15, "{}", c1 / 1e9);
        assert!((cg / c1 - (0.75 * 1.62 + 0.25)).abs() < 1e-12);
    }

    #[test]
    fn pair_count_alternates_with_the_contact_ratio() {
        let e = 1.5;
        let double: usize = (0..1000)
            .filter(|&i| pairs_in_contact(i as f64 / 1000.0, e) == 2)
            .count();
        assert_eq!(double, 500);
        assert_eq!(pairs_in_contact(-0.2, e), 1);
        // the mean over a width: the point count for none, the contact ratio over whole pitches,
        // the midpoint rule's count inside a zone, and in between across a switch
        assert_eq!(mean_pairs_in_contact(0.3, 0.0, e), 2.0);
        for s in [-1.7, 0.0, 0.35, 2.9] {
            assert!((mean_pairs_in_contact(s, 3.0, e) - e).abs() < 1e-12);
        }
        assert!((mean_pairs_in_contact(0.3, 0.1, e) - 2.0).abs() < 1e-12);
        assert!((mean_pairs_in_contact(0.8, 0.2, e) - 1.0).abs() < 1e-12);
        let p = e - 1.0;
        assert!((mean_pairs_in_contact(p, 0.2, e) - 1.5).abs() < 1e-12);
        assert!((mean_pairs_in_contact(1.0 + p + 0.05, 0.2, e) - 1.25).abs() < 1e-12);
    }
}
