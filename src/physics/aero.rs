//! Rotor aerodynamics from an analytic power coefficient, and the gain-scheduled PI pitch control.
//!
//! Power coefficient (Heier; the MathWorks Wind Turbine block), β in degrees:
//! C_p = 0.5176 (116/λ_i − 0.4β − 5) exp(−21/λ_i) + 0.0068 λ, with
//! 1/λ_i = 1/(λ + 0.08β) − 0.035/(β³ + 1); C_p,max = 0.480 at λ = 8.1.
//!
//! Torque T = ½ρπR³V²·C_p/λ. Thrust from momentum theory at the axial induction a that gives this
//! C_p = 4a(1 − a)², then C_T = 4a(1 − a) (a ≤ 1/3, the branch below the Betz optimum).

use serde::{Deserialize, Serialize};

pub const AIR_DENSITY: f64 = 1.225;

/// Heier's power coefficient. Its negative values (a feathered rotor braking) are floored at −0.1
/// (the fit extrapolates wildly at large pitch) and faded out as λ² below λ = 4: divided by a small
/// λ they would otherwise give a standing rotor a large reverse torque it cannot have.
pub fn power_coefficient(lambda: f64, pitch_deg: f64) -> f64 {
    let inv = 1.0 / (lambda + 0.08 * pitch_deg) - 0.035 / (pitch_deg.powi(3) + 1.0);
    let cp = 0.5176 * (116.0 * inv - 0.4 * pitch_deg - 5.0) * (-21.0 * inv).exp() + 0.0068 * lambda;
    if cp < 0.0 {
        cp.max(-0.1) * (lambda / 4.0).min(1.0).powi(2)
    } else {
        cp
    }
}

/// C_T from C_p through momentum theory: the root a ≤ 1/3 of C_p = 4a(1 − a)² (Newton from the
/// small-a guess, which converges monotonically on this concave branch), then C_T = 4a(1 − a).
pub fn thrust_coefficient(cp: f64) -> f64 {
    if cp <= 0.0 {
        return 0.0;
    }
    let cp = cp.min(16.0 / 27.0);
    let mut a = cp / 4.0;
    for _ in 0..30 {
        let f = 4.0 * a * (1.0 - a).powi(2) - cp;
        let df = 4.0 * (1.0 - a) * (1.0 - 3.0 * a);
        if df <= 1e-12 {
            break;
        }
        let next = (a - f / df).min(1.0 / 3.0);
        if (next - a).abs() < 1e-15 {
            a = next;
            break;
        }
        a = next;
    }
    4.0 * a * (1.0 - a)
}

/// Tip-speed ratio and C_p at the maximum of C_p(λ, β) over λ (golden-section search on [2, 15],
/// where the curve is unimodal): (8.10, 0.480) at β = 0.
pub fn optimum(pitch_deg: f64) -> (f64, f64) {
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (2.0, 15.0);
    for _ in 0..80 {
        let (c, d) = (b - g * (b - a), a + g * (b - a));
        if power_coefficient(c, pitch_deg) > power_coefficient(d, pitch_deg) {
            b = d;
        } else {
            a = c;
        }
    }
    let l = 0.5 * (a + b);
    (l, power_coefficient(l, pitch_deg))
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Rotor {
    pub radius: f64,
    /// Smallest tip-speed ratio used in C_p (keeps T = ½ρπR³V²C_p/λ finite at standstill).
    pub lambda_min: f64,
}

impl Rotor {
    pub fn tip_speed_ratio(&self, omega: f64, wind: f64) -> f64 {
        if wind <= 0.0 {
            f64::INFINITY
        } else {
            (omega * self.radius / wind).max(self.lambda_min)
        }
    }

    /// Aerodynamic torque on the rotor, N·m, positive driving.
    pub fn torque(&self, omega: f64, wind: f64, pitch_deg: f64) -> f64 {
        if wind <= 0.0 {
            return 0.0;
        }
        let lambda = self.tip_speed_ratio(omega, wind);
        let cp = power_coefficient(lambda, pitch_deg);
        0.5 * AIR_DENSITY * std::f64::consts::PI * self.radius.powi(3) * wind * wind * cp / lambda
    }

    /// Rotor thrust, N.
    pub fn thrust(&self, omega: f64, wind: f64, pitch_deg: f64) -> f64 {
        if wind <= 0.0 {
            return 0.0;
        }
        let cp = power_coefficient(self.tip_speed_ratio(omega, wind), pitch_deg);
        0.5 * AIR_DENSITY * std::f64::consts::PI * self.radius.powi(2) * wind * wind * thrust_coefficient(cp)
    }
}

/// Gain-scheduled PI pitch control (the NREL/OpenFAST form the paper uses): GK = 1/(1 + β/β_K),
/// β = GK·(K_P·e + K_I·∫e), the integral clamped so β stays in [β_min, β_max] (anti-windup), the
/// pitch rate limited. The error e is the caller's: the generator-side speed error (rad/s) for a
/// variable-speed turbine, or the per-unit power error for a fixed-speed one, whose speed the grid
/// holds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PitchController {
    pub kp: f64,
    pub ki: f64,
    /// β_K, rad: pitch at which the gain has halved.
    pub gain_halving_pitch: f64,
    pub min_pitch: f64,
    pub max_pitch: f64,
    /// rad/s
    pub max_rate: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct PitchState {
    /// rad
    pub pitch: f64,
    pub integral: f64,
}

impl PitchController {
    /// Advances the controller by `h` with error `e` (positive: pitch more); returns the pitch (rad).
    pub fn step(&self, st: &mut PitchState, e: f64, h: f64) -> f64 {
        let gk = 1.0 / (1.0 + st.pitch / self.gain_halving_pitch);
        st.integral += e * h;
        // anti-windup: the integral alone may not command beyond the pitch limits
        // max/min rather than clamp: a limit pair the owner failed to check must not panic
        if self.ki > 0.0 {
            let lo = self.min_pitch / (gk * self.ki);
            let hi = self.max_pitch / (gk * self.ki);
            st.integral = st.integral.max(lo).min(hi);
        }
        let target = (gk * (self.kp * e + self.ki * st.integral))
            .max(self.min_pitch)
            .min(self.max_pitch);
        let max_change = self.max_rate * h;
        st.pitch += (target - st.pitch).max(-max_change).min(max_change);
        st.pitch
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Heier's coefficients give C_p,max = 0.4800 at λ = 8.10, β = 0 (docs/SOURCES.md §Derived values).
    #[test]
    fn heier_maximum() {
        let (mut best, mut at) = (0.0, 0.0);
        for i in 0..2000 {
            let l = 2.0 + i as f64 * 0.005;
            let cp = power_coefficient(l, 0.0);
            if cp > best {
                (best, at) = (cp, l);
            }
        }
        assert!(
            (best - 0.4800).abs() < 5e-4 && (at - 8.10).abs() < 0.02,
            "{best} at {at}"
        );
        let (l, cp) = optimum(0.0);
        assert!((l - at).abs() < 0.01 && (cp - best).abs() < 1e-6, "{l} {cp}");
        // pitching to feather kills the power
        assert!(power_coefficient(8.1, 30.0) < 0.05);
    }

    /// Momentum theory: the Betz optimum C_p = 16/27 needs a = 1/3, C_T = 8/9.
    #[test]
    fn thrust_at_betz() {
        // C_p is flat at its maximum, so a (and C_T) is found only to √ε there
        assert!((thrust_coefficient(16.0 / 27.0) - 8.0 / 9.0).abs() < 1e-6);
        // C_p = 0.48 = 4a(1 − a)² at a = 0.17729, C_T = 4a(1 − a) = 0.58344
        assert!((thrust_coefficient(0.48) - 0.58344).abs() < 1e-4);
    }

    #[test]
    fn pitch_controller_respects_rate_and_limits() {
        let c = PitchController {
            kp: 0.0335,
            ki: 0.0089,
            gain_halving_pitch: 0.11,
            min_pitch: 0.0,
            max_pitch: 1.5,
            max_rate: 0.14,
        };
        let mut st = PitchState::default();
        // far over speed for 1 s at 10 ms: the rate limit binds
        for _ in 0..100 {
            c.step(&mut st, 100.0, 0.01);
        }
        assert!((st.pitch - 0.14).abs() < 1e-9);
        // under speed: back to the minimum pitch, never below
        for _ in 0..10_000 {
            c.step(&mut st, -50.0, 0.01);
        }
        assert_eq!(st.pitch, 0.0);
    }
}
