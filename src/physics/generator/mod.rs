//! The generator as the drivetrain sees it: the torque it puts on the generator shaft at a speed,
//! and the electrical side behind it. Kinds:
//!
//! - `spring`: the thesis's fixed-speed generator (K_gen spring to the synchronous field);
//! - `fixed`: grid-connected squirrel-cage induction machine ([`induction`], v_r = 0);
//! - `dfig`: doubly fed induction machine with rotor-current control ([`induction`]);
//! - `pmg`: permanent-magnet machine with full converter ([`pmg`]).
//!
//! `dfig` and `pmg` get their torque demand from a [`control::TorqueControl`] fed by the low-pass
//! filtered speed. Tripped (grid connection lost), every kind's torque decays as exp(−t/τ_trip).
//! States integrate with RK4 sub-steps of at most half the fastest time constant (the current
//! loop's 1/α), the speed following the master's input polynomial inside the step.

pub mod control;
pub mod induction;
pub mod pmg;
pub mod presets;
pub mod spring;

use control::TorqueControl;
use induction::Induction;
use nalgebra::{DMatrix, DVector};
use pmg::Pmg;
use serde::{Deserialize, Serialize};
pub use spring::SpringGenerator;

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Machine {
    Spring(SpringGenerator),
    Induction(Induction),
    Pmg(Pmg),
}

/// Number of state variables: 4 for the machine (ψ_r or i_dq, and the current-loop integrals),
/// the filtered speed and the speed regulator's integral.
pub const N: usize = 6;

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Generator {
    pub machine: Machine,
    /// Mechanical speed that is 1 pu (synchronous for induction machines, rated for the PMG), rad/s.
    pub base_speed: f64,
    /// Rated power S_b, W; the base torque is S_b / base_speed.
    pub base_power: f64,
    pub control: Option<TorqueControl>,
    /// Corner frequency of the controller's speed filter, rad/s.
    pub filter_corner: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct GenState {
    pub x: [f64; N],
    /// 1 while connected; decays after a trip.
    pub connected_fraction: f64,
}

/// Everything the FMU reports at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Outputs {
    /// Electromagnetic torque on the shaft, positive opposing rotation (generating), N·m.
    pub torque: f64,
    pub electrical_power: f64,
    pub torque_demand: f64,
    /// (ω_sync − ω)/ω_sync: negative when generating above synchronous speed.
    pub slip: f64,
    pub stator_current: f64,
    pub rotor_current: f64,
    pub load_angle: f64,
}

impl Generator {
    pub fn base_torque(&self) -> f64 {
        self.base_power / self.base_speed
    }

    /// Torque demand of the controller (N·m, generating positive) at state x.
    pub fn demand(&self, x: &[f64; N]) -> f64 {
        self.control.map_or(0.0, |c| c.demand(x[4], x[5]))
    }

    /// Motor-convention per-unit torque demand handed to the machine model.
    fn te_demand(&self, x: &[f64; N]) -> f64 {
        -self.demand(x) / self.base_torque()
    }

    /// Shaft torque (connected), N·m, positive opposing rotation.
    fn machine_torque(&self, x: &[f64; N], omega: f64) -> f64 {
        let w = omega / self.base_speed;
        match &self.machine {
            Machine::Spring(s) => s.torque(x[0], omega),
            Machine::Induction(m) => -m.terminal(x, w, self.te_demand(x)).torque * self.base_torque(),
            Machine::Pmg(m) => -m.torque(x) * self.base_torque(),
        }
    }

    pub fn derivative(&self, x: &[f64; N], omega: f64) -> [f64; N] {
        let w = omega / self.base_speed;
        let m = match &self.machine {
            Machine::Spring(s) => [omega - s.synchronous_speed, 0.0, 0.0, 0.0],
            Machine::Induction(m) => m.derivative(x, w, self.te_demand(x)),
            Machine::Pmg(m) => m.derivative(x, w, self.te_demand(x)),
        };
        let (filter, integral) = match &self.control {
            None => (0.0, 0.0),
            Some(c) => (self.filter_corner * (omega - x[4]), c.integral_rate(x[4], x[5])),
        };
        [m[0], m[1], m[2], m[3], filter, integral]
    }

    /// Equilibrium at speed `omega`: the spring twisted to `initial_torque`, the machines in
    /// electrical steady state with the controller's demand at that speed (the speed regulator's
    /// integral set so its demand is `initial_torque`).
    pub fn initial_state(&self, omega: f64, initial_torque: f64) -> GenState {
        let mut x = [0.0; N];
        x[4] = omega;
        if let Some(c) = &self.control {
            x[5] = c.integral_for(omega, initial_torque);
        }
        let te = self.te_demand(&x);
        let w = omega / self.base_speed;
        let m = match &self.machine {
            Machine::Spring(s) => [s.initial_angle(initial_torque), 0.0, 0.0, 0.0],
            Machine::Induction(m) => m.steady_state(w, te),
            Machine::Pmg(m) => m.steady_state(te),
        };
        x[..4].copy_from_slice(&m);
        GenState {
            x,
            connected_fraction: 1.0,
        }
    }

    /// Longest RK4 sub-step: half the current loop's time constant, or for the cage machine half
    /// the rotor-flux time constant shortened by the slip rotation.
    fn max_substep(&self) -> f64 {
        match &self.machine {
            Machine::Spring(_) => f64::INFINITY,
            Machine::Induction(m) => match m.current_bandwidth {
                Some(alpha) => 0.5 / alpha,
                None => {
                    let l_r = m.l_lr + m.l_m;
                    let l_r_transient = l_r - m.l_m * m.l_m / (m.l_ls + m.l_m);
                    0.5 / (m.omega_base * (m.r_r / l_r_transient + 0.05))
                }
            },
            Machine::Pmg(m) => 0.5 / m.current_bandwidth,
        }
    }

    /// RK4 sub-steps `advance` takes over a step of `h` (0 for the spring, integrated exactly).
    pub fn substeps(&self, h: f64) -> f64 {
        match self.machine {
            Machine::Spring(_) => 0.0,
            _ => (h / self.max_substep()).ceil().max(1.0),
        }
    }

    /// Advances by `h` with the speed ω(τ) = w[0] + w[1]·τ + w[2]·τ²/2.
    pub fn advance(&self, st: &mut GenState, w: [f64; 3], h: f64, connected: bool, trip_time_constant: f64) {
        if let Machine::Spring(s) = &self.machine {
            st.x[0] = s.advance(st.x[0], w, h);
        } else {
            let n = self.substeps(h) as usize;
            let dt = h / n as f64;
            let speed = |tau: f64| w[0] + w[1] * tau + w[2] * tau * tau / 2.0;
            for i in 0..n {
                let t0 = i as f64 * dt;
                st.x = self.rk4(&st.x, dt, [speed(t0), speed(t0 + dt / 2.0), speed(t0 + dt)]);
            }
        }
        if !connected {
            st.connected_fraction *= if trip_time_constant > 0.0 {
                (-h / trip_time_constant).exp()
            } else {
                0.0
            };
        }
    }

    fn rk4(&self, x: &[f64; N], dt: f64, omega: [f64; 3]) -> [f64; N] {
        let axpy = |a: &[f64; N], s: f64, k: &[f64; N]| std::array::from_fn(|i| a[i] + s * k[i]);
        let k1 = self.derivative(x, omega[0]);
        let k2 = self.derivative(&axpy(x, dt / 2.0, &k1), omega[1]);
        let k3 = self.derivative(&axpy(x, dt / 2.0, &k2), omega[1]);
        let k4 = self.derivative(&axpy(x, dt, &k3), omega[2]);
        std::array::from_fn(|i| x[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
    }

    pub fn outputs(&self, st: &GenState, omega: f64) -> Outputs {
        let x = &st.x;
        let f = st.connected_fraction;
        let w = omega / self.base_speed;
        let torque = f * self.machine_torque(x, omega);
        let mut out = Outputs {
            torque,
            electrical_power: torque * omega,
            torque_demand: self.demand(x),
            slip: 1.0 - w,
            ..Outputs::default()
        };
        match &self.machine {
            Machine::Spring(s) => {
                out.load_angle = x[0];
                out.slip = 1.0 - omega / s.synchronous_speed;
                out.torque_demand = torque;
            }
            Machine::Induction(m) => {
                let t = m.terminal(x, w, self.te_demand(x));
                // absorbed power Re(v_s·i_s*) + Re(v_r·i_r*) with v_s = 1
                let p = t.i_s.re + (t.v_r * t.i_r.conj()).re;
                out.electrical_power = -f * p * self.base_power;
                out.stator_current = t.i_s.norm();
                out.rotor_current = t.i_r.norm();
                if self.control.is_none() {
                    out.torque_demand = torque;
                }
            }
            Machine::Pmg(m) => {
                let (v_d, v_q) = m.voltage(x, w, self.te_demand(x));
                out.electrical_power = -f * (v_d * x[0] + v_q * x[1]) * self.base_power;
                out.stator_current = x[0].hypot(x[1]);
                out.slip = 0.0;
            }
        }
        out
    }

    /// Linearised torque–angle stiffness K and damping D at the state `st` and speed `omega`,
    /// for a shaft oscillation at `frequency` (rad/s): ΔT = (K + jΩD)·Δθ, from the transfer
    /// function G(jΩ) = C(jΩI − A)⁻¹B + D of ΔT/Δω with A, B, C, D by central differences.
    /// For the spring this returns (K_gen, D_gen) at every frequency.
    pub fn equivalent_stiffness_damping(&self, st: &GenState, omega: f64, frequency: f64) -> (f64, f64) {
        let x0 = st.x;
        let eps_w = 1e-6 * omega.abs().max(1.0);
        let perturb = |j: usize, s: f64| {
            let mut x = x0;
            let e = 1e-6 * x0[j].abs().max(1e-3);
            x[j] += s * e;
            (x, e)
        };
        let mut a = DMatrix::zeros(2 * N, 2 * N);
        let mut b = DVector::zeros(2 * N);
        let mut c = [0.0; N];
        for j in 0..N {
            let (xp, e) = perturb(j, 1.0);
            let (xm, _) = perturb(j, -1.0);
            let (fp, fm) = (self.derivative(&xp, omega), self.derivative(&xm, omega));
            for i in 0..N {
                let aij = (fp[i] - fm[i]) / (2.0 * e);
                a[(i, j)] = -aij;
                a[(N + i, N + j)] = -aij;
            }
            c[j] = (self.machine_torque(&xp, omega) - self.machine_torque(&xm, omega)) / (2.0 * e);
        }
        for i in 0..N {
            a[(i, N + i)] = -frequency;
            a[(N + i, i)] = frequency;
        }
        let (fp, fm) = (self.derivative(&x0, omega + eps_w), self.derivative(&x0, omega - eps_w));
        for i in 0..N {
            b[i] = (fp[i] - fm[i]) / (2.0 * eps_w);
        }
        let d = (self.machine_torque(&x0, omega + eps_w) - self.machine_torque(&x0, omega - eps_w)) / (2.0 * eps_w);
        let Some(y) = a.lu().solve(&b) else {
            return (f64::NAN, f64::NAN);
        };
        let g_re: f64 = d + (0..N).map(|j| c[j] * y[j]).sum::<f64>();
        let g_im: f64 = (0..N).map(|j| c[j] * y[N + j]).sum();
        // ΔT/Δθ = jΩ·G
        (-frequency * g_im * st.connected_fraction, g_re * st.connected_fraction)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spring() -> Generator {
        Generator {
            machine: Machine::Spring(SpringGenerator {
                stiffness: 2.81e4,
                damping: 30.0,
                synchronous_speed: 157.0,
            }),
            base_speed: 157.0,
            base_power: 750e3,
            control: None,
            filter_corner: 1.0,
        }
    }

    #[test]
    fn spring_equivalent_is_its_own_stiffness_and_damping() {
        let g = spring();
        let st = g.initial_state(157.0, 4000.0);
        for f in [0.5, 2.6, 20.0] {
            let (k, d) = g.equivalent_stiffness_damping(&st, 157.0, 2.0 * std::f64::consts::PI * f);
            assert!(
                (k / 2.81e4 - 1.0).abs() < 1e-6 && (d / 30.0 - 1.0).abs() < 1e-6,
                "{k} {d}"
            );
        }
    }

    #[test]
    fn trip_decays_the_torque_with_its_time_constant() {
        let g = spring();
        let mut st = g.initial_state(157.0, 5000.0);
        for _ in 0..100 {
            g.advance(&mut st, [157.0, 0.0, 0.0], 1e-3, false, 0.05);
        }
        // 0.1 s = 2 time constants
        assert!((g.outputs(&st, 157.0).torque / 5000.0 - (-2.0f64).exp()).abs() < 1e-12);
    }

    /// A cage machine at constant speed: a quasi-static slope dT/dω (damping) and, because the
    /// rotor flux lags, a stiffness that grows with frequency as D_s·Ω²τ/(1 + Ω²τ²).
    #[test]
    fn cage_machine_is_mostly_a_damper() {
        let g = Generator {
            machine: Machine::Induction(induction::tests::typical_machine(None)),
            base_speed: 188.5,
            base_power: 2e6,
            control: None,
            filter_corner: 1.0,
        };
        let st = g.initial_state(188.5 * 1.005, 0.0);
        let (k0, d0) = g.equivalent_stiffness_damping(&st, 188.5 * 1.005, 1e-3);
        // quasi-static slope: the steady torque–speed curve's derivative
        let t = |w: f64| g.outputs(&g.initial_state(w, 0.0), w).torque;
        let slope = (t(188.5 * 1.006) - t(188.5 * 1.004)) / (188.5 * 0.002);
        assert!((d0 / slope - 1.0).abs() < 1e-3, "{d0} vs {slope}");
        assert!(k0.abs() < 1e-3 * slope, "{k0}");
        let (k, _) = g.equivalent_stiffness_damping(&st, 188.5 * 1.005, 2.0 * std::f64::consts::PI * 2.5);
        assert!(k > 0.0);
    }

    /// Sub-stepped RK4 against the same model at 1 µs: the DFIG's torque after a demand step.
    #[test]
    fn substeps_resolve_the_current_loop() {
        let g = presets::build("C", presets::Kind::Dfig, &presets::Overrides::default()).expect("C");
        let w = 165.0;
        let mut coarse = g.initial_state(w, 0.0);
        coarse.x[4] = 0.95 * w; // a filtered-speed jump changes the demand
        let mut fine = coarse;
        for _ in 0..20 {
            g.advance(&mut coarse, [w, 0.0, 0.0], 1e-3, true, 0.05);
            for _ in 0..1000 {
                g.advance(&mut fine, [w, 0.0, 0.0], 1e-6, true, 0.05);
            }
        }
        let (a, b) = (g.outputs(&coarse, w).torque, g.outputs(&fine, w).torque);
        assert!((a - b).abs() < 1e-4 * b.abs(), "{a} vs {b}");
    }
}
