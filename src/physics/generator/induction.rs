//! Induction machine in per unit, synchronous reference frame, motor convention, with the stator
//! transients neglected (the "third-order" model of power-system and wind-turbine studies: the
//! stator flux follows the grid, the rotor flux ψ_r is the state):
//!
//!   v_s = R_s·i_s + j·ψ_s,   (1/ω_b)·dψ_r/dt = v_r − R_r·i_r − j·s·ψ_r,   s = 1 − ω_r
//!   ψ_s = L_s·i_s + L_m·i_r,  ψ_r = L_r·i_r + L_m·i_s,   T_e = Im(ψ_s*·i_s)
//!
//! with L_s = L_ls + L_m, L_r = L_lr + L_m, v_s = 1. Kind `fixed` (squirrel cage, v_r = 0) and kind
//! `dfig` (v_r from the rotor-side converter): a PI rotor-current loop in the stator-flux frame,
//! tuned by internal model control to a first-order closed loop of bandwidth α
//! (K_p = α·L_r'/ω_b, K_i = α·R_r, L_r' = L_r − L_m²/L_s) with the back-EMF j·s·ψ_r fed forward.
//! References: i_qr from the torque demand, i_dr = |ψ_s|/L_m (unity stator power factor).

use realfft::num_complex::Complex64 as C;
use serde::{Deserialize, Serialize};

const J: C = C { re: 0.0, im: 1.0 };

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Induction {
    /// Electrical base frequency ω_b = 2πf, rad/s.
    pub omega_base: f64,
    pub r_s: f64,
    pub r_r: f64,
    /// Stator leakage plus the line (grid) inductance in series with it.
    pub l_ls: f64,
    pub l_lr: f64,
    pub l_m: f64,
    /// Rotor-current loop bandwidth α, rad/s; `None` for a squirrel-cage machine.
    pub current_bandwidth: Option<f64>,
}

/// What the machine shows at a state: per-unit motor-convention quantities.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Terminal {
    pub torque: f64,
    pub i_s: C,
    pub i_r: C,
    pub v_r: C,
    pub psi_s: C,
}

impl Induction {
    fn l_s(&self) -> f64 {
        self.l_ls + self.l_m
    }
    fn l_r(&self) -> f64 {
        self.l_lr + self.l_m
    }
    /// Stator transient inductance L_s' = L_s − L_m²/L_r.
    fn l_s_transient(&self) -> f64 {
        self.l_s() - self.l_m * self.l_m / self.l_r()
    }
    /// Rotor transient inductance L_r' = L_r − L_m²/L_s.
    fn l_r_transient(&self) -> f64 {
        self.l_r() - self.l_m * self.l_m / self.l_s()
    }

    /// Rotor-current reference in the synchronous frame for motor torque `te` at stator flux ψ_s.
    fn current_reference(&self, psi_s: C, te: f64) -> C {
        let (mag, angle) = psi_s.to_polar();
        let mag = mag.max(1e-6);
        C::new(mag / self.l_m, -te * self.l_s() / (self.l_m * mag)) * C::from_polar(1.0, angle)
    }

    /// Currents, fluxes and rotor voltage at state x = [Re ψ_r, Im ψ_r, Re ξ, Im ξ] (ξ: the current
    /// controller's integral), rotor speed ω_r (pu) and motor-torque demand `te_demand` (pu).
    pub fn terminal(&self, x: &[f64], w_r: f64, te_demand: f64) -> Terminal {
        let psi_r = C::new(x[0], x[1]);
        let k_r = self.l_m / self.l_r();
        let i_s = (C::new(1.0, 0.0) - J * k_r * psi_r) / C::new(self.r_s, self.l_s_transient());
        let i_r = (psi_r - self.l_m * i_s) / self.l_r();
        let psi_s = self.l_s() * i_s + self.l_m * i_r;
        let v_r = match self.current_bandwidth {
            None => C::new(0.0, 0.0),
            Some(alpha) => {
                let e = self.current_reference(psi_s, te_demand) - i_r;
                let kp = alpha * self.l_r_transient() / self.omega_base;
                kp * e + C::new(x[2], x[3]) + J * (1.0 - w_r) * psi_r
            }
        };
        Terminal {
            torque: (psi_s.conj() * i_s).im,
            i_s,
            i_r,
            v_r,
            psi_s,
        }
    }

    /// dx/dt at state x, rotor speed ω_r (pu) and motor-torque demand (pu).
    pub fn derivative(&self, x: &[f64], w_r: f64, te_demand: f64) -> [f64; 4] {
        let t = self.terminal(x, w_r, te_demand);
        let psi_r = C::new(x[0], x[1]);
        let d = self.omega_base * (t.v_r - self.r_r * t.i_r - J * (1.0 - w_r) * psi_r);
        let integral = match self.current_bandwidth {
            None => C::new(0.0, 0.0),
            Some(alpha) => alpha * self.r_r * (self.current_reference(t.psi_s, te_demand) - t.i_r),
        };
        [d.re, d.im, integral.re, integral.im]
    }

    /// Steady state at speed ω_r: for the cage machine the ψ_r that zeroes dψ_r/dt (one complex
    /// linear equation); for the DFIG the state whose rotor current equals its reference for the
    /// demand (a fixed point in ψ_s, converging in a few iterations since ψ_s hardly moves).
    pub fn steady_state(&self, w_r: f64, te_demand: f64) -> [f64; 4] {
        let z = C::new(self.r_s, self.l_s_transient());
        let k_r = self.l_m / self.l_r();
        match self.current_bandwidth {
            None => {
                // ψ_r (R_r/L_r + j·R_r·k_r²/Z + j·s) = R_r·k_r·v_s/Z
                let a = self.r_r / self.l_r() + J * self.r_r * k_r * k_r / z + J * (1.0 - w_r);
                let psi_r = self.r_r * k_r / z / a;
                [psi_r.re, psi_r.im, 0.0, 0.0]
            }
            Some(_) => {
                let zs = C::new(self.r_s, self.l_s());
                let mut i_r = C::new(1.0 / self.l_m, 0.0);
                let mut i_s = C::new(0.0, 0.0);
                for _ in 0..50 {
                    i_s = (C::new(1.0, 0.0) - J * self.l_m * i_r) / zs;
                    let psi_s = self.l_s() * i_s + self.l_m * i_r;
                    i_r = self.current_reference(psi_s, te_demand);
                }
                let psi_r = self.l_r() * i_r + self.l_m * i_s;
                // integral = the voltage the loop must supply beyond the feed-forward: R_r·i_r
                let xi = self.r_r * i_r;
                [psi_r.re, psi_r.im, xi.re, xi.im]
            }
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A 60 Hz MW-class machine with typical per-unit data; a current-loop bandwidth makes it a DFIG.
    pub(crate) fn typical_machine(current_bandwidth: Option<f64>) -> Induction {
        Induction {
            omega_base: 2.0 * std::f64::consts::PI * 60.0,
            r_s: 0.01,
            r_r: 0.01,
            l_ls: 0.2,
            l_lr: 0.1,
            l_m: 3.0,
            current_bandwidth,
        }
    }

    /// AWT-27 Thevenin induction generator (OpenFAST r-test's AWT_YFix_WSt, ServoDyn's TEC model), in per unit
    /// on Z_b = 1 Ω so the machine data are the published ohms: the steady torque of the
    /// third-order model equals OpenFAST's closed-form A0·V²·s/(C0 + C1·s + C2·s²) — the same
    /// equivalent circuit solved a different way.
    #[test]
    fn cage_steady_torque_matches_openfast_thevenin_formula() {
        let (rs, rr, xs, xr, xm) = (0.0185, 0.017, 0.034, 0.005, 0.775);
        let m = Induction {
            omega_base: 2.0 * std::f64::consts::PI * 60.0,
            r_s: rs,
            r_r: rr,
            l_ls: xs,
            l_lr: xr,
            l_m: xm,
            current_bandwidth: None,
        };
        // OpenFAST with V_LL = √3 (phase voltage 1, the pu stator voltage), ω_syn = 1
        let d = rs * rs + (xs + xm).powi(2);
        let re1 = rs * xm * xm / d;
        let xe1 = xm * (rs * rs + xs * (xs + xm)) / d;
        let (k1, k2) = ((xe1 + xr).powi(2), xm * xm / d);
        let (a0, c0, c1, c2) = (rr * k2, rr * rr, -2.0 * re1 * rr, re1 * re1 + k1);
        for slip_gen in [0.001, 0.01, 0.03, 0.1] {
            // generator slip in OpenFAST's sign: s = (ω − ω_syn)/ω_syn > 0
            let openfast = a0 * 3.0 * slip_gen / (c0 + c1 * slip_gen + c2 * slip_gen * slip_gen);
            let x = m.steady_state(1.0 + slip_gen, 0.0);
            let ours = -m.terminal(&x, 1.0 + slip_gen, 0.0).torque;
            // per-phase pu torque vs OpenFAST's three-phase sum: factor 3
            assert!(
                (3.0 * ours - openfast).abs() < 1e-9 * openfast.abs(),
                "s = {slip_gen}: {} vs {openfast}",
                3.0 * ours
            );
            let dx = m.derivative(&x, 1.0 + slip_gen, 0.0);
            assert!(dx.iter().all(|v| v.abs() < 1e-9), "{dx:?}");
        }
    }

    /// DFIG in steady state: the rotor current equals its reference, the torque equals the demand,
    /// the stator power factor is one, and nothing moves.
    #[test]
    fn dfig_steady_state_delivers_the_demand() {
        let m = typical_machine(Some(1000.0));
        for (w, te) in [(0.93, -0.9), (1.1, -1.0), (0.8, -0.3)] {
            let x = m.steady_state(w, te);
            let t = m.terminal(&x, w, te);
            assert!((t.torque - te).abs() < 1e-9, "{} vs {te}", t.torque);
            let q = (C::new(1.0, 0.0) * t.i_s.conj()).im;
            assert!(q.abs() < 1e-9, "stator reactive power {q}");
            let dx = m.derivative(&x, w, te);
            assert!(dx.iter().all(|v| v.abs() < 1e-9), "{dx:?}");
        }
    }
}
