//! The generator as the drivetrain sees it. `SpringGenerator` is the thesis's fixed-speed generator:
//! an electrical torsional spring (and damper) between the generator rotor and the field that turns
//! at synchronous speed, T = T0 + K_gen·δ + D_gen·(ω − ω_sync), δ = ∫(ω − ω_sync) dt. Tripped, its
//! torque decays exponentially to zero.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpringGenerator {
    /// K_gen, N·m/rad at the generator shaft.
    pub stiffness: f64,
    /// D_gen, N·m·s/rad.
    pub damping: f64,
    pub synchronous_speed: f64,
}

/// What changes in time: the load angle and how much of the torque survives a trip.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct SpringState {
    /// δ, rad: rotor angle ahead of the field (including the initial δ0 = T0/K).
    pub load_angle: f64,
    /// 1 while connected; decays after a trip.
    pub connected_fraction: f64,
}

impl SpringGenerator {
    pub fn initial_state(&self, initial_torque: f64) -> SpringState {
        SpringState {
            load_angle: if self.stiffness > 0.0 {
                initial_torque / self.stiffness
            } else {
                0.0
            },
            connected_fraction: 1.0,
        }
    }

    /// Electromagnetic torque at speed `omega`.
    pub fn torque(&self, st: &SpringState, omega: f64) -> f64 {
        st.connected_fraction * (self.stiffness * st.load_angle + self.damping * (omega - self.synchronous_speed))
    }

    /// Advances by `h` with the speed given as ω(τ) = w[0] + w[1]·τ + w[2]·τ²/2: the load angle
    /// integrates that polynomial exactly.
    pub fn advance(&self, st: &mut SpringState, w: [f64; 3], h: f64, connected: bool, trip_time_constant: f64) {
        st.load_angle += (w[0] - self.synchronous_speed) * h + w[1] * h * h / 2.0 + w[2] * h * h * h / 6.0;
        if !connected {
            st.connected_fraction *= if trip_time_constant > 0.0 {
                (-h / trip_time_constant).exp()
            } else {
                0.0
            };
        }
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
        let mut st = g.initial_state(0.0);
        // ω(τ) = 151 + 2τ + 3τ²/2 over 0.5 s: ∫(ω − 150) = 0.5 + 0.25 + 0.0625
        g.advance(&mut st, [151.0, 2.0, 3.0], 0.5, true, 0.05);
        assert!((st.load_angle - 0.8125).abs() < 1e-15);
        assert!((g.torque(&st, 151.0) - 2.81e4 * 0.8125).abs() < 1e-9);
    }

    #[test]
    fn trip_decays_the_torque_with_its_time_constant() {
        let g = SpringGenerator {
            stiffness: 1e4,
            damping: 0.0,
            synchronous_speed: 100.0,
        };
        let mut st = g.initial_state(5000.0);
        for _ in 0..100 {
            g.advance(&mut st, [100.0, 0.0, 0.0], 1e-3, false, 0.05);
        }
        // 0.1 s = 2 time constants
        assert!((g.torque(&st, 100.0) / 5000.0 - (-2.0f64).exp()).abs() < 1e-12);
    }
}
