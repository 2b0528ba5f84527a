//! Steady blade-element momentum (BEM) rotor: torque, thrust and per-element loads for one
//! (wind, rotor speed, pitch).
//!
//! Each station solves one residual in the inflow angle φ (Ning 2014, doi:10.1002/we.1636, the
//! formulation CCBlade uses) by a bracketed root search, so it always returns: with the axial and
//! tangential induction a, a' written as functions of φ, the residual is
//!
//!   R(φ) = V_y·sin φ/(1 − a) − V_x·cos φ·(1 − κ')       (momentum and Buhl region, φ > 0)
//!   R(φ) = V_y·sin φ·(1 − κ) − V_x·cos φ·(1 − κ')       (propeller brake region, φ < 0)
//!
//! with κ = σ'c_n/(4F sin²φ), κ' = σ'c_t/(4F sin φ cos φ), σ' = Bc/(2πr), F the product of Prandtl's tip
//! and hub losses, a = κ/(1 + κ) up to a = 0.4 and Buhl's empirical thrust curve above it. It is Ning's
//! residual multiplied by V_y: the same roots, but no division by the rotor speed, so one formula
//! holds at standstill (V_y = 0) and in reverse rotation (V_y < 0). V_x·cos φ·κ' is evaluated as
//! V_x·σ'c_t/(4F sin φ), finite at φ = 90° where a parked blade sits.
//!
//! Loads per unit span N' = c_n·½ρW²c (out of plane), T' = c_t·½ρW²c (in plane, driving); the rotor
//! integrates them with the trapezoidal rule between the hub radius and the tip, where they vanish.
//! No dynamic inflow, no skew: the wind is steady per call, uniform over the disc in [`BemRotor::loads`],
//! per element in [`BemRotor::element_in`] (what the rotationally sampled rotor, [`super::blades`], calls).

use super::blade::{Blade, Polar, Station};
use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// Which corrections the BEM applies (all on by default; CCBlade's options of the same names).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct BemOptions {
    pub tip_loss: bool,
    pub hub_loss: bool,
    /// Tangential induction a' (wake rotation).
    pub wake_rotation: bool,
    /// Drag in the induction (it is always in the loads).
    pub use_cd: bool,
}

impl Default for BemOptions {
    fn default() -> Self {
        Self {
            tip_loss: true,
            hub_loss: true,
            wake_rotation: true,
            use_cd: true,
        }
    }
}

/// The solution at one station.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct ElementLoads {
    /// m
    pub radius: f64,
    /// Inflow angle φ, rad (90° = wind straight along the axis).
    pub inflow: f64,
    /// Angle of attack, rad.
    pub alpha: f64,
    pub axial_induction: f64,
    pub tangential_induction: f64,
    pub cl: f64,
    pub cd: f64,
    /// Relative wind speed, m/s.
    pub relative_wind: f64,
    /// Out-of-plane (thrust-wise) force per unit span, N/m.
    pub normal_n_per_m: f64,
    /// In-plane force per unit span, positive in the direction of rotation, N/m.
    pub tangential_n_per_m: f64,
    /// False when no bracket held a root and the element fell back to the inflow without induction
    /// (no wind, or the momentum balance has no solution in any branch).
    pub converged: bool,
}

/// Rotor totals with the element loads.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct RotorLoads {
    /// N·m, positive driving.
    pub torque: f64,
    /// N
    pub thrust: f64,
    pub elements: Vec<ElementLoads>,
}

/// Power, torque and thrust coefficients: C_P = P/(½ρV³A), C_Q = Q/(½ρV²AR), C_T = T/(½ρV²A).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Coefficients {
    pub cp: f64,
    pub cq: f64,
    pub ct: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BemRotor {
    pub blade: Blade,
    pub stations: Vec<Station>,
    /// kg/m³
    pub air_density: f64,
    pub options: BemOptions,
}

/// What one station needs besides φ.
struct Element<'a> {
    station: &'a Station,
    polar: &'a Polar,
    /// local solidity σ' = Bc/(2πr)
    solidity: f64,
    blades: f64,
    hub: f64,
    tip: f64,
    /// twist + pitch, rad
    theta: f64,
    vx: f64,
    vy: f64,
    options: BemOptions,
}

/// Everything the residual computes at one φ (the loads need it again at the root).
struct State {
    residual: f64,
    a: f64,
    /// κ'·cos φ (finite at φ = 90°)
    kp_cos: f64,
    cl: f64,
    cd: f64,
}

/// Smallest |φ| of the brackets: sin φ appears in denominators (as in Ning 2014).
const EPS_PHI: f64 = 1e-6;

impl Element<'_> {
    fn prandtl(&self, sin_phi: f64) -> f64 {
        let factor = |distance: f64, radius: f64| {
            let f = self.blades / 2.0 * distance / (radius * sin_phi.abs());
            2.0 / PI * (-f).exp().clamp(0.0, 1.0).acos()
        };
        let r = self.station.radius;
        let tip = if self.options.tip_loss {
            factor(self.tip - r, r)
        } else {
            1.0
        };
        let hub = if self.options.hub_loss && self.hub > 0.0 {
            factor(r - self.hub, self.hub)
        } else {
            1.0
        };
        tip * hub
    }

    fn state(&self, phi: f64) -> State {
        let (s, c) = phi.sin_cos();
        let (cl, cd) = self.polar.at(phi - self.theta);
        let (cn, ct) = if self.options.use_cd {
            (cl * c + cd * s, cl * s - cd * c)
        } else {
            (cl * c, cl * s)
        };
        let f = self.prandtl(s);
        let k = self.solidity * cn / (4.0 * f * s * s);
        let kp_cos = if self.options.wake_rotation {
            self.solidity * ct / (4.0 * f * s)
        } else {
            0.0
        };
        let swirl = self.vx * (c - kp_cos);
        let (a, residual) = if phi > 0.0 {
            let a = if k <= 2.0 / 3.0 { k / (1.0 + k) } else { buhl(k, f) };
            (a, self.vy * s / (1.0 - a) - swirl)
        } else {
            // propeller brake: a = κ/(κ − 1) (unused beyond the loads' relative wind)
            let a = if k > 1.0 { k / (k - 1.0) } else { 0.0 };
            (a, self.vy * s * (1.0 - k) - swirl)
        };
        State {
            residual,
            a,
            kp_cos,
            cl,
            cd,
        }
    }

    /// Bracketed roots in the order the flow suggests; the first bracket with a sign change wins.
    fn solve(&self) -> Option<f64> {
        let (lo, hi, brake) = ((EPS_PHI, FRAC_PI_2), (FRAC_PI_2, PI - EPS_PHI), (-FRAC_PI_4, -EPS_PHI));
        // Ning's order for a turning rotor; when the wind dominates the blade speed (a parked or rocking
        // rotor) the two brackets beside 90° come first, so the solution does not jump to the propeller
        // brake branch as the speed changes sign.
        let order = if self.vy.abs() < self.vx {
            if self.vy >= 0.0 {
                [lo, hi, brake]
            } else {
                [hi, lo, brake]
            }
        } else if self.vy > 0.0 {
            [lo, brake, hi]
        } else {
            [hi, lo, brake]
        };
        let f = |phi: f64| self.state(phi).residual;
        order.into_iter().find_map(|(a, b)| {
            let (fa, fb) = (f(a), f(b));
            let bracketed = fa.is_finite() && fb.is_finite() && fa * fb <= 0.0;
            // Ning accepts a propeller-brake root of a turning rotor only where the residual rises
            // through it (fzero(−π/4) < 0 < fzero(−ε)); the other crossing is not a physical state
            let rising = !(a < 0.0 && self.vy > 0.0) || (fa < 0.0 && fb > 0.0);
            (bracketed && rising).then(|| brent(f, a, b, fa, fb, 1e-12))
        })
    }

    fn loads(&self, air_density: f64) -> ElementLoads {
        let (vx, vy) = (self.vx, self.vy);
        let root = if vx > 0.0 { self.solve() } else { None };
        let (phi, a, ap, cl, cd) = match root {
            Some(phi) => {
                let st = self.state(phi);
                let c = phi.cos();
                // a' = κ'/(1 − κ'), with κ' recovered from κ'·cos φ away from φ = 90°
                let kp = if c.abs() > 1e-12 { st.kp_cos / c } else { f64::INFINITY };
                let ap = if self.options.wake_rotation {
                    kp / (1.0 - kp)
                } else {
                    0.0
                };
                (phi, st.a, ap, st.cl, st.cd)
            }
            None => {
                let phi = vx.atan2(vy);
                let (cl, cd) = self.polar.at(phi - self.theta);
                (phi, 0.0, 0.0, cl, cd)
            }
        };
        let (s, c) = phi.sin_cos();
        // At the root tan φ = V_x(1 − a)/(V_y(1 + a')); take W from the component that stays finite
        // (a' is unbounded at standstill, a near the propeller-brake limit).
        let w = if !ap.is_finite() || ap.abs() > 10.0 {
            vx * (1.0 - a) / s
        } else if a.abs() > 10.0 {
            vy * (1.0 + ap) / c
        } else {
            (vx * (1.0 - a)).hypot(vy * (1.0 + ap))
        }
        .abs();
        let q = 0.5 * air_density * w * w * self.station.chord;
        ElementLoads {
            radius: self.station.radius,
            inflow: phi,
            alpha: phi - self.theta,
            axial_induction: a,
            tangential_induction: ap,
            cl,
            cd,
            relative_wind: w,
            normal_n_per_m: (cl * c + cd * s) * q,
            tangential_n_per_m: (cl * s - cd * c) * q,
            converged: root.is_some(),
        }
    }
}

/// Buhl's high-induction correction (NREL/TP-500-36834): the empirical C_T(a) = 8/9 + (4F − 40/9)a +
/// (50/9 − 4F)a² that meets momentum theory C_T = 4Fa(1 − a) at a = 0.4, solved for a with
/// C_T = 4Fκ(1 − a)², the blade-element thrust. At the double root (2Fκ = 25/9 − 2F) the quadratic's
/// leading coefficient vanishes and a = 1 − 1/(2√g₂), its limit.
fn buhl(k: f64, f: f64) -> f64 {
    let g1 = 2.0 * f * k - (10.0 / 9.0 - f);
    let g2 = 2.0 * f * k - f * (4.0 / 3.0 - f);
    let g3 = 2.0 * f * k - (25.0 / 9.0 - 2.0 * f);
    if g3.abs() < 1e-9 {
        1.0 - 1.0 / (2.0 * g2.sqrt())
    } else {
        (g1 - g2.sqrt()) / g3
    }
}

/// Brent's root finder on [a, b] with f(a)·f(b) ≤ 0: inverse quadratic or secant steps while they
/// make progress, bisection otherwise; converges to |Δx| ≤ tol whatever the function's shape.
fn brent(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64, mut fa: f64, mut fb: f64, tol: f64) -> f64 {
    if fa == 0.0 {
        return a;
    }
    let (mut c, mut fc) = (a, fa);
    let (mut d, mut e) = (b - a, b - a);
    for _ in 0..200 {
        if fb == 0.0 {
            return b;
        }
        if (fb > 0.0) == (fc > 0.0) {
            // keep the root between b and c
            (c, fc) = (a, fa);
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            (a, fa) = (b, fb);
            (b, fb) = (c, fc);
            (c, fc) = (a, fa);
        }
        let tol1 = 2.0 * f64::EPSILON * b.abs() + 0.5 * tol;
        let m = 0.5 * (c - b);
        if m.abs() <= tol1 {
            return b;
        }
        if e.abs() >= tol1 && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q) = if a == c {
                (2.0 * m * s, 1.0 - s)
            } else {
                let (qq, r) = (fa / fc, fb / fc);
                (
                    s * (2.0 * m * qq * (qq - r) - (b - a) * (r - 1.0)),
                    (qq - 1.0) * (r - 1.0) * (s - 1.0),
                )
            };
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tol1 * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        } else {
            d = m;
            e = m;
        }
        (a, fa) = (b, fb);
        b += if d.abs() > tol1 { d } else { tol1.copysign(m) };
        fb = f(b);
    }
    b
}

impl BemRotor {
    pub fn new(blade: Blade, air_density: f64) -> Self {
        Self {
            stations: blade.stations(),
            blade,
            air_density,
            options: BemOptions::default(),
        }
    }

    /// Tip radius, m.
    pub fn radius(&self) -> f64 {
        self.blade.tip_radius()
    }

    fn element(&self, i: usize, wind: f64, omega: f64, pitch: f64) -> ElementLoads {
        self.element_in(i, wind, omega * self.stations[i].radius, pitch)
    }

    /// Station `i`'s loads in a local inflow of its own: `vx` (m/s) along the rotor axis, `vy` (m/s)
    /// in the rotor plane against the blade's motion (ω·r plus the in-plane wind the blade runs into).
    /// A rotor sampling a non-uniform field calls this per element and blade.
    pub fn element_in(&self, i: usize, vx: f64, vy: f64, pitch: f64) -> ElementLoads {
        let st = &self.stations[i];
        Element {
            station: st,
            polar: &self.blade.polars[st.airfoil],
            solidity: f64::from(self.blade.blades) * st.chord / (2.0 * PI * st.radius),
            blades: f64::from(self.blade.blades),
            hub: self.blade.hub_radius,
            tip: self.radius(),
            theta: st.twist + pitch,
            vx,
            vy,
            options: self.options,
        }
        .loads(self.air_density)
    }

    /// The weights of [`Self::integrate`]'s trapezoidal rule per station (½ the distance between the
    /// neighbours, the hub and tip radii standing for the ends): ∫ f dr ≈ Σ wᵢ·f(rᵢ).
    pub fn span_weights(&self) -> Vec<f64> {
        let n = self.stations.len();
        let r = |i: isize| match i {
            -1 => self.blade.hub_radius,
            i if i as usize == n => self.radius(),
            i => self.stations[i as usize].radius,
        };
        (0..n as isize).map(|i| 0.5 * (r(i + 1) - r(i - 1))).collect()
    }

    /// Trapezoidal integral over [hub, stations…, tip] of per-station values that vanish at both ends.
    fn integrate(&self, values: impl Iterator<Item = (f64, f64)>) -> f64 {
        let (mut sum, mut prev) = (0.0, (self.blade.hub_radius, 0.0));
        for (r, v) in values.chain(std::iter::once((self.radius(), 0.0))) {
            sum += 0.5 * (prev.1 + v) * (r - prev.0);
            prev = (r, v);
        }
        sum
    }

    /// Torque (N·m, positive driving) and thrust (N) at wind speed `wind` (m/s), rotor speed `omega`
    /// (rad/s, negative = reverse) and pitch (rad, positive towards feather), with the element loads.
    pub fn loads(&self, wind: f64, omega: f64, pitch: f64) -> RotorLoads {
        let elements: Vec<ElementLoads> = (0..self.stations.len())
            .map(|i| self.element(i, wind, omega, pitch))
            .collect();
        let (torque, thrust) = self.totals(&elements);
        RotorLoads {
            torque,
            thrust,
            elements,
        }
    }

    fn totals(&self, elements: &[ElementLoads]) -> (f64, f64) {
        let b = f64::from(self.blade.blades);
        let torque = self.integrate(elements.iter().map(|e| (e.radius, e.tangential_n_per_m * e.radius)));
        let thrust = self.integrate(elements.iter().map(|e| (e.radius, e.normal_n_per_m)));
        (b * torque, b * thrust)
    }

    /// Torque and thrust only (what the FMU needs every step).
    pub fn torque_thrust(&self, wind: f64, omega: f64, pitch: f64) -> (f64, f64) {
        let mut buf = [ElementLoads::default(); 64];
        if self.stations.len() <= buf.len() {
            for (i, e) in buf.iter_mut().enumerate().take(self.stations.len()) {
                *e = self.element(i, wind, omega, pitch);
            }
            self.totals(&buf[..self.stations.len()])
        } else {
            let l = self.loads(wind, omega, pitch);
            (l.torque, l.thrust)
        }
    }

    /// Coefficients at tip-speed ratio `tsr` and pitch (rad) in wind `wind` (the result depends on the
    /// wind speed only through the Reynolds number, which this model ignores).
    pub fn coefficients(&self, tsr: f64, pitch: f64, wind: f64) -> Coefficients {
        let r = self.radius();
        let (torque, thrust) = self.torque_thrust(wind, tsr * wind / r, pitch);
        let q_area = 0.5 * self.air_density * wind * wind * PI * r * r;
        Coefficients {
            cp: torque * tsr * wind / r / (q_area * wind),
            cq: torque / (q_area * r),
            ct: thrust / q_area,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::blade::{Node, Polar};

    /// A thin-airfoil blade: C_l = 2πα within ±10°, flat-plate beyond (C_l = sin 2α, C_d = 2 sin²α).
    fn plate_blade(wake: bool) -> BemRotor {
        let mut alpha = Vec::new();
        for i in -180..=180 {
            alpha.push(f64::from(i).to_radians());
        }
        let cl = alpha
            .iter()
            .map(|&a: &f64| {
                if a.abs() <= 0.1745 {
                    2.0 * PI * a
                } else {
                    (2.0 * a).sin()
                }
            })
            .collect();
        let cd = alpha.iter().map(|&a: &f64| 0.01 + 2.0 * a.sin().powi(2)).collect();
        let polar = Polar {
            name: "plate".into(),
            alpha,
            cl,
            cd,
        };
        let nodes = (0..20)
            .map(|i| {
                let x = f64::from(i) / 19.0;
                Node {
                    span: 1.0 + 38.0 * x,
                    chord: 3.0 - 2.0 * x,
                    twist: (12.0 - 12.0 * x).to_radians(),
                    airfoil: 0,
                }
            })
            .collect();
        let blade = Blade {
            name: "plate".into(),
            hub_radius: 1.0,
            tip: None,
            blades: 3,
            nodes,
            polars: vec![polar],
        };
        let mut r = BemRotor::new(blade, 1.225);
        r.options.wake_rotation = wake;
        r
    }

    #[test]
    fn brent_finds_roots_to_tolerance() {
        let f = |x: f64| x.powi(3) - 2.0 * x - 5.0;
        let x = brent(f, 2.0, 3.0, f(2.0), f(3.0), 1e-14);
        assert!((x - 2.094_551_481_542_327).abs() < 1e-12, "{x}");
    }

    /// Each converged station satisfies the momentum balance it was solved from: tan φ =
    /// V_x(1 − a)/(V_y(1 + a')), and in the momentum region a = κ/(1 + κ).
    #[test]
    fn converged_stations_satisfy_the_inflow_relation() {
        let rotor = plate_blade(true);
        for (tsr, pitch) in [(3.0, 0.0), (7.0, 0.0), (9.0, 5.0), (12.0, -2.0)] {
            let v = 10.0;
            let omega = tsr * v / rotor.radius();
            for e in rotor.loads(v, omega, f64::to_radians(pitch)).elements {
                assert!(e.converged);
                let lhs = e.inflow.tan();
                let rhs = v * (1.0 - e.axial_induction) / (omega * e.radius * (1.0 + e.tangential_induction));
                assert!(
                    (lhs / rhs - 1.0).abs() < 1e-8,
                    "tsr {tsr} r {}: {lhs} vs {rhs}",
                    e.radius
                );
            }
        }
    }

    /// Standstill: no tangential blade speed. Without wake rotation the inflow is exactly 90° and there
    /// is no induction from it; the torque is then the blade-element integral B∫½ρV²c·c_t(α)·r dr.
    #[test]
    fn standstill_sees_the_wind_at_90_degrees() {
        let rotor = plate_blade(false);
        let pitch = 80f64.to_radians();
        let l = rotor.loads(12.0, 0.0, pitch);
        for e in &l.elements {
            assert!(e.converged && (e.inflow - FRAC_PI_2).abs() < 1e-9, "{e:?}");
        }
        // with wake rotation the swirl tilts the inflow slightly but the torque changes little
        let with = plate_blade(true).loads(12.0, 0.0, pitch);
        assert!(with.elements.iter().all(|e| e.converged));
        assert!(
            (with.torque / l.torque - 1.0).abs() < 0.05,
            "{} vs {}",
            with.torque,
            l.torque
        );
    }

    /// Across Ω = 0 the torque is continuous and falls with speed (aerodynamic damping), forward and
    /// reverse, feathered and at fine pitch; every station converges.
    #[test]
    fn torque_is_continuous_through_standstill_and_reverse() {
        let rotor = plate_blade(true);
        for pitch_deg in [0.0, 30.0, 60.0, 90.0] {
            let pitch = f64::to_radians(pitch_deg);
            let q = |w: f64| rotor.torque_thrust(15.0, w, pitch).0;
            let (qm, q0, qp) = (q(-1e-3), q(0.0), q(1e-3));
            assert!(qm > q0 && q0 > qp, "pitch {pitch_deg}: {qm} {q0} {qp}");
            // one-sided slopes agree: no jump of the solution branch at Ω = 0
            let (sm, sp) = (q0 - qm, qp - q0);
            assert!((sm / sp - 1.0).abs() < 0.05, "pitch {pitch_deg}: slopes {sm} {sp}");
            for w in [-2.0, -0.5, 0.5, 2.0] {
                assert!(rotor.loads(15.0, w, pitch).elements.iter().all(|e| e.converged));
            }
        }
    }

    #[test]
    fn buhl_meets_momentum_at_a_equal_0_4() {
        for f in [0.3, 0.7, 1.0] {
            let k = 2.0 / 3.0;
            assert!((buhl(k + 1e-12, f) - 0.4).abs() < 1e-9, "F = {f}");
        }
        // the double root's limit is the value beside it
        let f = 0.8;
        let k0 = (25.0 / 9.0 - 2.0 * f) / (2.0 * f);
        assert!((buhl(k0, f) - buhl(k0 + 1e-6, f)).abs() < 1e-5);
    }
}
