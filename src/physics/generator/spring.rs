//! The thesis's fixed-speed generator: an electrical torsional spring (and damper) between the
//! generator rotor and the field that turns at synchronous speed, T = K_gen·δ + D_gen·(ω − ω_sync),
//! δ = δ0 + ∫(ω − ω_sync) dt with δ0 = T0/K_gen.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpringGenerator {
    /// K_gen, N·m/rad at the generator shaft.
    pub stiffness: f64,
    /// D_gen, N·m·s/rad.
    pub damping: f64,
    pub synchronous_speed: f64,
}

impl SpringGenerator {
    /// δ0 that makes the torque `initial_torque` at synchronous speed.
    pub fn initial_angle(&self, initial_torque: f64) -> f64 {
        if self.stiffness > 0.0 {
            initial_torque / self.stiffness
        } else {
            0.0
        }
    }

    /// Torque at load angle δ and speed ω, positive opposing rotation.
    pub fn torque(&self, delta: f64, omega: f64) -> f64 {
        self.stiffness * delta + self.damping * (omega - self.synchronous_speed)
    }

    /// Load angle after `h` with the speed ω(τ) = w[0] + w[1]·τ + w[2]·τ²/2, integrated exactly.
    pub fn advance(&self, delta: f64, w: [f64; 3], h: f64) -> f64 {
        delta + (w[0] - self.synchronous_speed) * h + w[1] * h * h / 2.0 + w[2] * h * h * h / 6.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn load_angle_integrates_the_speed_polynomial_exactly() {
        let g = SpringGenerator {
            stiffness: 2.81e4,
            damping: 0.0,
            synchronous_speed: 150.0,
        };
        // ω(τ) = 151 + 2τ + 3τ²/2 over 0.5 s: ∫(ω − 150) = 0.5 + 0.25 + 0.0625
        let d = g.advance(g.initial_angle(0.0), [151.0, 2.0, 3.0], 0.5);
        assert!((d - 0.8125).abs() < 1e-15);
        assert!((g.torque(d, 151.0) - 2.81e4 * 0.8125).abs() < 1e-9);
    }
}
