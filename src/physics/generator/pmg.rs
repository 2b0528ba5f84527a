//! Permanent-magnet synchronous generator behind a full converter, in per unit, rotor (dq) frame,
//! motor convention, non-salient (L_d = L_q = L):
//!
//!   (L/ω_b)·di_d/dt = v_d − R·i_d + ω_r·L·i_q
//!   (L/ω_b)·di_q/dt = v_q − R·i_q − ω_r·(L·i_d + ψ_m),      T_e = ψ_m·i_q
//!
//! The base frequency is the electrical frequency at rated speed and ψ_m = 1, so the back-EMF is
//! 1 pu at rated speed. Field-oriented control: i_d = 0, i_q = T_demand/ψ_m, PI current loops tuned
//! by internal model control to bandwidth α (K_p = α·L/ω_b, K_i = α·R) with the cross-coupling and
//! back-EMF fed forward.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Pmg {
    pub omega_base: f64,
    pub r_s: f64,
    /// Synchronous inductance L = L_m + L_ls (pu).
    pub l: f64,
    pub psi_m: f64,
    pub current_bandwidth: f64,
}

impl Pmg {
    /// Stator voltage (v_d, v_q) the controller applies at state x = [i_d, i_q, ξ_d, ξ_q].
    pub fn voltage(&self, x: &[f64], w_r: f64, te_demand: f64) -> (f64, f64) {
        let kp = self.current_bandwidth * self.l / self.omega_base;
        let (e_d, e_q) = (-x[0], te_demand / self.psi_m - x[1]);
        (
            kp * e_d + x[2] - w_r * self.l * x[1],
            kp * e_q + x[3] + w_r * (self.l * x[0] + self.psi_m),
        )
    }

    pub fn torque(&self, x: &[f64]) -> f64 {
        self.psi_m * x[1]
    }

    pub fn derivative(&self, x: &[f64], w_r: f64, te_demand: f64) -> [f64; 4] {
        let (v_d, v_q) = self.voltage(x, w_r, te_demand);
        let g = self.omega_base / self.l;
        let ki = self.current_bandwidth * self.r_s;
        [
            g * (v_d - self.r_s * x[0] + w_r * self.l * x[1]),
            g * (v_q - self.r_s * x[1] - w_r * (self.l * x[0] + self.psi_m)),
            ki * -x[0],
            ki * (te_demand / self.psi_m - x[1]),
        ]
    }

    /// Currents on their references, integrals holding the resistive drop.
    pub fn steady_state(&self, te_demand: f64) -> [f64; 4] {
        let i_q = te_demand / self.psi_m;
        [0.0, i_q, 0.0, self.r_s * i_q]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A step in torque demand: with the feed-forward exact, i_q follows a first-order lag of time
    /// constant 1/α (IMC design), so after 1/α the torque has covered 1 − e⁻¹ of the step.
    #[test]
    fn current_loop_is_first_order_with_its_bandwidth() {
        let m = Pmg {
            omega_base: 2.0 * std::f64::consts::PI * 42.9,
            r_s: 0.01,
            l: 0.96,
            psi_m: 1.0,
            current_bandwidth: 1000.0,
        };
        let mut x = m.steady_state(-0.5);
        let h = 1e-6;
        for _ in 0..1000 {
            // 1 ms = 1/α; RK4 at 1 µs is exact to far below the tolerance
            let k1 = m.derivative(&x, 1.0, -1.0);
            let a: Vec<f64> = (0..4).map(|i| x[i] + 0.5 * h * k1[i]).collect();
            let k2 = m.derivative(&a, 1.0, -1.0);
            let b: Vec<f64> = (0..4).map(|i| x[i] + 0.5 * h * k2[i]).collect();
            let k3 = m.derivative(&b, 1.0, -1.0);
            let c: Vec<f64> = (0..4).map(|i| x[i] + h * k3[i]).collect();
            let k4 = m.derivative(&c, 1.0, -1.0);
            for i in 0..4 {
                x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        let expected = -0.5 - 0.5 * (1.0 - (-1.0f64).exp());
        assert!((m.torque(&x) - expected).abs() < 1e-9, "{} vs {expected}", m.torque(&x));
        assert!(x[0].abs() < 1e-9);
    }
}
