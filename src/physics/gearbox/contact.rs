//! Contact stress of a loaded gear slice: the Hertz line contact of two cylinders with the flanks'
//! radii of curvature at the pitch point, in the normal section (what ISO 6336-2's Z_H·Z_E·Z_β
//! express), and the subsurface shear under it. A slice carries its load on ε_α contact lines on
//! average; at the pitch point ISO 6336-2's contact-ratio factor Z_ε² gives the share of the most
//! loaded line, so the line load is w = F_n·cos β_b·Z_ε² / b_slice.

use super::involute::PairGeometry;
use crate::physics::hertz::{LineContact, effective_modulus, subsurface_peaks};

/// ISO 6336-2's steel for gears (Z_E = 189.8 √MPa).
const GEAR_E: f64 = 206e9;
const GEAR_NU: f64 = 0.3;

/// What the most loaded slice of a mesh sees.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactStress {
    /// Maximum Hertz pressure, Pa.
    pub pressure: f64,
    /// Largest subsurface shear (Tresca), Pa, and its depth, m.
    pub max_shear: f64,
    pub max_shear_depth: f64,
    /// Half-width of the contact, m.
    pub half_width: f64,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GearContact {
    /// Relative radius of curvature at the pitch point, normal section, m.
    radius: f64,
    /// Contact line per unit slice load: cos β_b·Z_ε² / b_slice (1/m).
    line_load_per_newton: f64,
    e_star: f64,
    /// (τ_max/p_max, depth/a)
    shear: (f64, f64),
}

impl GearContact {
    pub fn new(g: &PairGeometry, face_width: f64, slices: usize) -> Self {
        // transverse radii at the pitch point, ρ = r_w·sin α_wt; in the normal section / cos β_b
        let rho = g.pitch_radius.map(|r| r * g.pressure_angle.sin() / g.base_helix.cos());
        let inverse = if g.internal {
            1.0 / rho[0] - 1.0 / rho[1]
        } else {
            1.0 / rho[0] + 1.0 / rho[1]
        };
        let (ea, eb) = (g.contact_ratio, g.overlap_ratio);
        let z_eps_squared = if eb < 1.0 {
            (4.0 - ea) / 3.0 * (1.0 - eb) + eb / ea
        } else {
            1.0 / ea
        };
        GearContact {
            radius: 1.0 / inverse,
            line_load_per_newton: g.base_helix.cos() * z_eps_squared * slices as f64 / face_width,
            e_star: effective_modulus(GEAR_E, GEAR_NU, GEAR_E, GEAR_NU),
            shear: subsurface_peaks(GEAR_NU).max_shear,
        }
    }

    /// Stress under a slice carrying `load` (N, either flank).
    pub fn at(&self, load: f64) -> ContactStress {
        let w = load.abs() * self.line_load_per_newton;
        if w <= 0.0 {
            return ContactStress::default();
        }
        let c = LineContact::new(w, self.radius, self.e_star);
        ContactStress {
            pressure: c.max_pressure,
            max_shear: self.shear.0 * c.max_pressure,
            max_shear_depth: self.shear.1 * c.half_width,
            half_width: c.half_width,
        }
    }
}
