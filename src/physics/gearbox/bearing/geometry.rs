//! How a roller's laminae approach their races: a row's approach round the cage and a lamina's
//! approach gradient on the five relative coordinates, shared by the force evaluation and the kink
//! margin ([`super::tangent`]).

use super::{Places, RollerBearing, RollerRow};

/// The approach of a row's rollers round the cage: at the row's centre and its change per metre
/// along the axis (the tilt, cos α·(x₄ cos ψ − x₃ sin ψ)), both p·cos ψ + q·sin ψ + constant in the
/// roller's angle ψ, turned to the cage ([`Places::turned`]).
pub(super) struct RowApproach {
    centre: (f64, f64),
    spread: (f64, f64),
    constant: f64,
}

impl RowApproach {
    /// The approach at the roller's centre and its change along the axis, for the roller at `place`.
    #[inline(always)]
    pub(super) fn at(&self, (c, s): (f64, f64)) -> (f64, f64) {
        (
            self.centre.0 * c + self.centre.1 * s + self.constant,
            self.spread.0 * c + self.spread.1 * s,
        )
    }
}

/// A lamina at z along the roller's axis has the approach gradient u + z·w on the five relative
/// coordinates (w is zero on the three translations): the roller's sums over its laminae give its
/// force and tangent without a 5×5 product per lamina. With the rates u·ẋ and w·(ẋ₃, ẋ₄).
pub(super) struct Gradient {
    pub(super) u: [f64; 5],
    pub(super) w: [f64; 2],
    pub(super) rate_u: f64,
    pub(super) rate_w: f64,
}

impl RollerBearing {
    /// (p, q) of a roller's approach round `row` at `z` along the axis from the row's centre,
    /// p·cos ψ + q·sin ψ in the roller's angle ψ without the axial part sin α·x₂ and the gap: the
    /// approach is cos α·(x₀ cos ψ + x₁ sin ψ + z·(x₄ cos ψ − x₃ sin ψ)) + sin α·(x₂ + r·(x₃ sin ψ −
    /// x₄ cos ψ)) − gap.
    #[inline(always)]
    pub(super) fn approach_round_the_row(&self, row: &RollerRow, x: &[f64; 5], z: f64) -> (f64, f64) {
        let (ca, sa, r) = (row.cos, row.sin, self.pitch_radius);
        (
            ca * (x[0] + z * x[4]) - sa * r * x[4],
            ca * (x[1] - z * x[3]) + sa * r * x[3],
        )
    }

    /// How the rollers of `row` approach their races round the cage at (sin ψ_c, cos ψ_c) = `cage`.
    #[inline(always)]
    pub(super) fn row_approach(&self, row: &RollerRow, x: &[f64; 5], cage: (f64, f64)) -> RowApproach {
        let gap = row.cos * 0.5 * self.clearance + row.sin.abs() * 0.5 * self.axial_clearance;
        RowApproach {
            centre: Places::turned(self.approach_round_the_row(row, x, row.z), cage),
            spread: Places::turned((row.cos * x[4], -row.cos * x[3]), cage),
            constant: row.sin * x[2] - gap,
        }
    }

    /// The gradient of a lamina's approach of the roller of `row` at (cos ψ, sin ψ) = `unit` on the
    /// five relative coordinates, and the rates at `xd`.
    #[inline(always)]
    pub(super) fn gradient(&self, row: &RollerRow, (cs, sn): (f64, f64), xd: &[f64; 5]) -> Gradient {
        let sin_r = row.sin * self.pitch_radius;
        let u = [row.cos * cs, row.cos * sn, row.sin, sin_r * sn, -sin_r * cs];
        let w = [-row.cos * sn, row.cos * cs];
        Gradient {
            u,
            w,
            rate_u: u[0] * xd[0] + u[1] * xd[1] + u[2] * xd[2] + u[3] * xd[3] + u[4] * xd[4],
            rate_w: w[0] * xd[3] + w[1] * xd[4],
        }
    }
}
