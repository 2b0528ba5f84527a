//! Reference problems with known answers for the integrator layer, independent of any drivetrain:
//! every method is checked against an analytic solution or a theoretical property, and the solver
//! statistics of each problem are pinned (they change only when the algorithm does).

use nalgebra::{DMatrix, DVector};
use windrive::solver::alpha::Alpha;
use windrive::solver::rk4::stability_limit;
use windrive::solver::system::{Friction, InputLoad, Linearity, Mass, SecondOrderSystem};
use windrive::solver::{Driver, DynState, Method, Statistics};

/// M·a + C·v + K·q = B·u with an optional friction contact (kinetic = u[1], holding = 1.2 × it).
struct Linear {
    mass: Vec<f64>,
    k: DMatrix<f64>,
    c: DMatrix<f64>,
    loads: Vec<InputLoad>,
    friction_dof: Option<usize>,
}

impl Linear {
    fn new(mass: Vec<f64>, k: DMatrix<f64>) -> Self {
        let n = mass.len();
        Self {
            mass,
            k,
            c: DMatrix::zeros(n, n),
            loads: vec![InputLoad {
                input: 0,
                dof: 0,
                gain: 1.0,
            }],
            friction_dof: None,
        }
    }

    /// Springs from each DOF to the next, the first also to ground: K of a fixed–free chain.
    fn chain(mass: Vec<f64>, springs: &[f64]) -> Self {
        let n = mass.len();
        let mut k = DMatrix::zeros(n, n);
        for (i, &s) in springs.iter().enumerate() {
            if i == 0 {
                k[(0, 0)] += s;
            } else {
                k[(i - 1, i - 1)] += s;
                k[(i, i)] += s;
                k[(i - 1, i)] -= s;
                k[(i, i - 1)] -= s;
            }
        }
        Self::new(mass, k)
    }

    fn energy(&self, st: &DynState) -> f64 {
        let q = DVector::from_column_slice(&st.q);
        let kinetic: f64 = self.mass.iter().zip(&st.v).map(|(m, v)| 0.5 * m * v * v).sum();
        kinetic + 0.5 * q.dot(&(&self.k * &q))
    }
}

impl SecondOrderSystem for Linear {
    fn dofs(&self) -> usize {
        self.mass.len()
    }
    fn linearity(&self) -> Linearity {
        Linearity::Linear
    }
    fn mass(&self) -> Mass<'_> {
        Mass::Diagonal(&self.mass)
    }
    fn input_loads(&self) -> &[InputLoad] {
        &self.loads
    }
    fn internal_forces(&self, _: f64, q: &[f64], v: &[f64], out: &mut [f64]) {
        let f = &self.k * DVector::from_column_slice(q) + &self.c * DVector::from_column_slice(v);
        out.copy_from_slice(f.as_slice());
    }
    fn add_tangent(&self, _: f64, _: &[f64], _: &[f64], c_c: f64, c_k: f64, j: &mut DMatrix<f64>) {
        *j += &self.c * c_c + &self.k * c_k;
    }
    fn friction(&self, u: &[f64]) -> Option<Friction> {
        self.friction_dof.map(|dof| Friction {
            dof,
            kinetic: u[1],
            holding: 1.2 * u[1],
        })
    }
}

/// A mass flying at a wall with a Hertzian point contact: F = k·δ^1.5 for δ = q > 0.
struct HertzWall {
    mass: [f64; 1],
    k: f64,
}

impl SecondOrderSystem for HertzWall {
    fn dofs(&self) -> usize {
        1
    }
    fn linearity(&self) -> Linearity {
        Linearity::Nonlinear
    }
    fn mass(&self) -> Mass<'_> {
        Mass::Diagonal(&self.mass)
    }
    fn input_loads(&self) -> &[InputLoad] {
        &[]
    }
    fn internal_forces(&self, _: f64, q: &[f64], _: &[f64], out: &mut [f64]) {
        out[0] = self.k * q[0].max(0.0).powf(1.5);
    }
    fn add_tangent(&self, _: f64, q: &[f64], _: &[f64], _: f64, c_k: f64, j: &mut DMatrix<f64>) {
        j[(0, 0)] += c_k * 1.5 * self.k * q[0].max(0.0).sqrt();
    }
}

/// Runs `steps` communication steps of `h` with constant inputs `u`, calling `each` after each.
fn run<S: SecondOrderSystem>(
    sys: &S,
    method: Method,
    st: &mut DynState,
    h: f64,
    steps: usize,
    u: &[f64],
    mut each: impl FnMut(f64, &DynState),
) -> Statistics {
    let mut driver = Driver::new(method);
    for i in 0..steps {
        let t = i as f64 * h;
        driver
            .advance(sys, st, t, h, h, u.len(), |_, out| out.copy_from_slice(u))
            .unwrap();
        each(t + h, st);
    }
    driver.stats
}

const NEWMARK: Method = Method::Implicit(Alpha::NEWMARK);

fn rk4(limit: f64) -> Method {
    Method::Rk4 { stability_limit: limit }
}

/// Error at t = 9/8 s of x'' = −ω²x, x(0) = 1 (exact: cos ωt, ω = 2π), for step h. At 9/8 of a
/// period the phase error shows at first order in x (at a whole period it would be squared).
fn oscillator_error(method: Method, h: f64) -> f64 {
    let w = std::f64::consts::TAU;
    let sys = Linear::new(vec![1.0], DMatrix::from_element(1, 1, w * w));
    let mut st = DynState::new(vec![1.0], vec![0.0]);
    let end = 1.125;
    let steps = (end / h).round() as usize;
    run(&sys, method, &mut st, h, steps, &[0.0], |_, _| {});
    (st.q[0] - (w * end).cos()).abs()
}

/// Observed order p = log2(e(h) / e(h/2)), the median of three halvings.
fn observed_order(method: Method) -> f64 {
    let hs = [1.0 / 64.0, 1.0 / 128.0, 1.0 / 256.0, 1.0 / 512.0];
    let e: Vec<f64> = hs.iter().map(|&h| oscillator_error(method, h)).collect();
    let mut p: Vec<f64> = e.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    p.sort_by(f64::total_cmp);
    p[1]
}

/// Newmark, HHT-α and generalised-α are second order, RK4 fourth (tolerance ±0.1: the asymptotic
/// range is reached at 50 steps per period).
#[test]
fn single_dof_oscillator_converges_at_the_methods_orders() {
    for (name, method, order) in [
        ("newmark", NEWMARK, 2.0),
        ("hht 0.8", Method::Implicit(Alpha::hht(0.8).unwrap()), 2.0),
        (
            "generalised 0.5",
            Method::Implicit(Alpha::generalised(0.5).unwrap()),
            2.0,
        ),
        ("rk4", rk4(1.0), 4.0),
    ] {
        let p = observed_order(method);
        assert!((p - order).abs() < 0.1, "{name}: observed order {p}, expected {order}");
    }
}

/// An undamped two-inertia chain keeps its energy to 1e-9 under Newmark (the trapezoidal rule
/// conserves the quadratic energy of a linear system exactly; only rounding remains), over 10⁴
/// steps at a step that resolves neither mode well. One factorisation serves every step.
#[test]
fn undamped_two_inertia_chain_conserves_energy() {
    let sys = Linear::chain(vec![2.0, 0.5], &[1e4, 4e4]);
    let mut st = DynState::new(vec![1e-3, -2e-3], vec![0.3, 0.0]);
    let e0 = sys.energy(&st);
    let mut worst: f64 = 0.0;
    let stats = run(&sys, NEWMARK, &mut st, 0.01, 10_000, &[0.0], |_, st| {
        worst = worst.max((sys.energy(st) / e0 - 1.0).abs());
    });
    assert!(worst < 1e-9, "energy drift {worst:e}");
    assert_eq!(
        stats,
        Statistics {
            steps: 10_000,
            newton_iterations: 10_000,
            factorizations: 1,
            halvings: 0,
            // all but the first, whose accelerations are not yet consistent with any inputs
            plain_steps: 9_999,
            newton_restarts: 0,
            newton_rattle_steps: 0,
        }
    );
}

/// Γ(0.4), Γ(0.5), Γ(0.9) (Abramowitz & Stegun table 6.1).
const GAMMA_04: f64 = 2.218_159_543_757_688;
const GAMMA_05: f64 = 1.772_453_850_905_516;
const GAMMA_09: f64 = 1.068_628_702_119_319;

/// Hertzian impact without damping is elastic: the mass leaves the wall at its impact speed
/// (restitution 1; to 1e-6 at 1 µs steps), after the analytic contact time
/// t_c = 2·(δ_max/v)·(1/2.5)·B(0.4, 0.5), δ_max = (5mv²/4k)^(2/5) (to 0.1 %: one step in ~900).
#[test]
fn hertzian_impact_rebounds_at_its_impact_speed() {
    let (m, k, v0) = (1.0, 1e9, 1.0);
    let sys = HertzWall { mass: [m], k };
    let mut st = DynState::new(vec![-1e-4], vec![v0]);
    let h = 1e-6;
    let (mut touch, mut left) = (None, None);
    let mut previous = st.q[0];
    let stats = run(&sys, NEWMARK, &mut st, h, 2000, &[], |t, st| {
        if previous <= 0.0 && st.q[0] > 0.0 {
            // linear interpolation of the crossing inside the step
            touch.get_or_insert(t - h * st.q[0] / (st.q[0] - previous));
        }
        if previous > 0.0 && st.q[0] <= 0.0 && left.is_none() {
            left = Some((t - h * st.q[0] / (st.q[0] - previous), st.v[0]));
        }
        previous = st.q[0];
    });
    let (touch, (left, rebound)) = (touch.unwrap(), left.unwrap());
    assert!((rebound + v0).abs() < 1e-6 * v0, "rebound speed {rebound}");
    let delta_max = (5.0 * m * v0 * v0 / (4.0 * k)).powf(0.4);
    let beta = GAMMA_04 * GAMMA_05 / GAMMA_09;
    let t_c = 2.0 * delta_max / v0 * beta / 2.5;
    assert!(
        ((left - touch) / t_c - 1.0).abs() < 1e-3,
        "contact {} s vs {t_c} s",
        left - touch
    );
    // pinned: 2000 steps; in free flight the second iteration confirms the first (a zero increment),
    // in contact full Newton takes 3–4
    assert_eq!((stats.steps, stats.halvings), (2000, 0));
    assert_eq!(stats.newton_iterations, 4801);
}

/// A mass sliding under Coulomb friction stops after m·v₀/F exactly (uniform deceleration) and then
/// holds bit-exactly while a load below the static capacity pulls at it; a load above it breaks it
/// free. For every implicit method.
#[test]
fn stick_slip_stops_on_time_and_holds_bit_exactly() {
    for (name, method) in [
        ("newmark", NEWMARK),
        ("hht 0.7", Method::Implicit(Alpha::hht(0.7).unwrap())),
    ] {
        let mut sys = Linear::new(vec![2.0], DMatrix::zeros(1, 1));
        sys.friction_dof = Some(0);
        // v0 puts the stop in the middle of a step (0.6005 s)
        let (v0, kinetic, h) = (3.0025, 10.0, 1e-3);
        let mut st = DynState::new(vec![0.0], vec![v0]);
        let mut stopped = None;
        run(&sys, method, &mut st, h, 1000, &[0.0, kinetic], |t, st| {
            if st.locked && stopped.is_none() {
                stopped = Some(t);
            }
        });
        let t_stop = 2.0 * v0 / kinetic;
        let stopped = stopped.expect("the friction stops the mass");
        assert!(
            stopped >= t_stop - 1e-12 && stopped < t_stop + h,
            "stopped at {stopped} s, expected {t_stop} s"
        );
        // sliding, every method of the family is exact (constant acceleration); in the step that
        // stops, the force is just what stops the mass at its end, which places it within a·h²/8 of
        // the exact stop for Newmark; HHT-α mixes α_f of the start's kinetic force into that step,
        // so it may be off by up to twice that
        let x_stop = 0.5 * v0 * t_stop;
        let decel = kinetic / 2.0;
        let bound = if name == "newmark" { 0.125 } else { 0.25 } * decel * h * h;
        assert!(
            (st.q[0] - x_stop).abs() <= bound + 1e-12,
            "{name}: stopped at x = {} vs {x_stop}",
            st.q[0]
        );
        // a pull of 1.1 × kinetic (below the holding 1.2 ×) leaves every bit in place
        let held = st.q[0].to_bits();
        run(&sys, method, &mut st, h, 1000, &[1.1 * kinetic, kinetic], |_, st| {
            assert_eq!(st.q[0].to_bits(), held);
            assert_eq!(st.v[0], 0.0);
            assert!(st.locked);
        });
        // 1.3 × kinetic breaks it free and it accelerates at (1.3 − 1)·F/m
        run(&sys, method, &mut st, h, 100, &[1.3 * kinetic, kinetic], |_, _| {});
        assert!(!st.locked);
        let expected = 0.3 * kinetic / 2.0 * 0.1;
        assert!(
            (st.v[0] / expected - 1.0).abs() < 0.02,
            "speed {} vs {expected}",
            st.v[0]
        );
    }
}

/// `Linear` as the gearbox presents itself to the integrators: nonlinear (the Newton path, with
/// HHT-α's start-of-step forces) and with a dense mass matrix (the friction's accelerations solved).
struct DenseNonlinear(Linear, DMatrix<f64>);

impl SecondOrderSystem for DenseNonlinear {
    fn dofs(&self) -> usize {
        self.0.dofs()
    }
    fn linearity(&self) -> Linearity {
        Linearity::Nonlinear
    }
    fn mass(&self) -> Mass<'_> {
        Mass::Dense(&self.1)
    }
    fn input_loads(&self) -> &[InputLoad] {
        self.0.input_loads()
    }
    fn internal_forces(&self, t: f64, q: &[f64], v: &[f64], out: &mut [f64]) {
        self.0.internal_forces(t, q, v, out)
    }
    fn add_tangent(&self, t: f64, q: &[f64], v: &[f64], c_c: f64, c_k: f64, j: &mut DMatrix<f64>) {
        self.0.add_tangent(t, q, v, c_c, c_k, j)
    }
    fn friction(&self, u: &[f64]) -> Option<Friction> {
        self.0.friction(u)
    }
}

/// HHT-α needs the internal forces at each step's start; the driver hands it those it evaluated
/// for the consistent accelerations at the communication point. Through sliding, sticking and
/// breaking free (the friction's accelerations solved with a dense mass), every bit is as when
/// they are evaluated afresh.
#[test]
fn reusing_the_communication_points_forces_changes_no_bit() {
    let mut chain = Linear::chain(vec![2.0, 1.0], &[400.0, 900.0]);
    chain.friction_dof = Some(1);
    chain.c = DMatrix::from_row_slice(2, 2, &[0.5, -0.2, -0.2, 0.3]);
    let mass = DMatrix::from_row_slice(2, 2, &[2.0, 0.1, 0.1, 1.0]);
    let sys = DenseNonlinear(chain, mass);
    let method = Method::Implicit(Alpha::hht(0.8).unwrap());
    let trajectory = |reuse: bool| {
        let mut driver = Driver::new(method);
        driver.reuse_start_forces = reuse;
        let mut st = DynState::new(vec![0.0, 0.0], vec![1.0, 2.0]);
        let (mut out, mut locked) = (Vec::new(), 0);
        for i in 0..3000 {
            // a pull that sticks the friction DOF for a while and then breaks it free
            let u = [40.0 * (i as f64 * 2e-3).sin(), 5.0];
            driver
                .advance(&sys, &mut st, i as f64 * 1e-3, 1e-3, 1e-3, 2, |_, o| {
                    o.copy_from_slice(&u)
                })
                .unwrap();
            locked += st.locked as usize;
            out.extend(st.q.iter().chain(&st.v).chain(&st.a).map(|x| x.to_bits()));
        }
        (out, locked)
    };
    let (fresh, locked) = trajectory(false);
    assert!(
        locked > 100 && locked < 2900,
        "the contact sticks and slips: {locked} steps locked"
    );
    assert!(
        trajectory(true).0 == fresh,
        "reusing the start forces changed the trajectory"
    );
}

/// The spectral radius of the HHT-α amplification matrix for an undamped oscillator at Ω = h·ω,
/// from the method's defining equations (Hilber, Hughes, Taylor 1977), not from the integrator:
/// the state (x, h·v, h²·a) maps to the next by A = L⁻¹·R.
fn hht_spectral_radius(p: &Alpha, omega_h: f64) -> f64 {
    let (a, b, g) = (p.alpha_f, p.beta, p.gamma);
    let w2 = omega_h * omega_h;
    // unknowns (x₁, v₁, a₁), scaled by h
    // x₁ − β a₁ = x + v + (½ − β) a
    // v₁ − γ a₁ = v + (1 − γ) a
    // a₁ + (1 − α) Ω² x₁ = −α Ω² x
    let l = DMatrix::from_row_slice(3, 3, &[1.0, 0.0, -b, 0.0, 1.0, -g, (1.0 - a) * w2, 0.0, 1.0]);
    let r = DMatrix::from_row_slice(3, 3, &[1.0, 1.0, 0.5 - b, 0.0, 1.0, 1.0 - g, -a * w2, 0.0, 0.0]);
    let amp = l.try_inverse().unwrap() * r;
    amp.complex_eigenvalues().iter().map(|z| z.norm()).fold(0.0, f64::max)
}

/// A stiff two-mode chain (1 Hz and ≈ 5 kHz) stepped at 1 ms: HHT-α damps the top mode per step by
/// the spectral radius theory gives at its h·ω (→ ρ∞ as h·ω → ∞; to 1 %), and leaves the lowest
/// mode's amplitude within 1e-4 over one period; Newmark keeps both.
#[test]
fn hht_damps_the_stiff_mode_by_theory_and_spares_the_low_one() {
    let rho = 0.8;
    let p = Alpha::hht(rho).unwrap();
    assert!((hht_spectral_radius(&p, 1e6) - rho).abs() < 1e-6);
    let (m1, m2) = (1.0, 1e-6);
    let k1 = (std::f64::consts::TAU).powi(2) * (m1 + m2);
    let k2 = 1e3;
    let sys = Linear::chain(vec![m1, m2], &[k1, k2]);
    // modes from the symmetric eigenproblem (M diagonal)
    let m_half: Vec<f64> = sys.mass.iter().map(|m| m.sqrt()).collect();
    let a = DMatrix::from_fn(2, 2, |i, j| sys.k[(i, j)] / (m_half[i] * m_half[j]));
    let eig = nalgebra::SymmetricEigen::new(a);
    let order = if eig.eigenvalues[0] < eig.eigenvalues[1] {
        [0, 1]
    } else {
        [1, 0]
    };
    let w: Vec<f64> = order.iter().map(|&i| eig.eigenvalues[i].sqrt()).collect();
    let shape = |mode: usize| -> Vec<f64> { (0..2).map(|d| eig.eigenvectors[(d, order[mode])] / m_half[d]).collect() };
    // modal amplitude sqrt(q_m² + (v_m/ω)²) with q_m = φᵀ M q (φ M-orthonormal)
    let amplitude = |st: &DynState, mode: usize| {
        let phi = shape(mode);
        let qm: f64 = (0..2).map(|d| phi[d] * sys.mass[d] * st.q[d]).sum();
        let vm: f64 = (0..2).map(|d| phi[d] * sys.mass[d] * st.v[d]).sum();
        qm.hypot(vm / w[mode])
    };
    let h = 1e-3;
    let (low, high) = (shape(0), shape(1));
    let start = DynState::new((0..2).map(|d| 1e-3 * (low[d] + high[d])).collect(), vec![0.0, 0.0]);
    let a_low = amplitude(&start, 0);
    let steps = (1.0 / (w[0] / std::f64::consts::TAU) / h).round() as usize;
    const FIT: usize = 100;
    for (method, damps) in [(Method::Implicit(p), true), (NEWMARK, false)] {
        let mut st = start.clone();
        // ln(amplitude) of the top mode over the first FIT steps: the numerical oscillation at
        // h·ω ≈ 32 beats against the sampling every ≈ 43 steps, so the decay rate is the slope of a
        // least-squares line, not the ratio of two samples
        let mut log_amplitude = vec![amplitude(&st, 1).ln()];
        run(&sys, method, &mut st, h, steps, &[0.0], |_, st| {
            if log_amplitude.len() <= FIT {
                log_amplitude.push(amplitude(st, 1).ln());
            }
        });
        let low_change = (amplitude(&st, 0) / a_low - 1.0).abs();
        assert!(low_change < 1e-4, "low mode amplitude changed by {low_change:e}");
        let n = log_amplitude.len() as f64;
        let mean_x = (n - 1.0) / 2.0;
        let mean_y = log_amplitude.iter().sum::<f64>() / n;
        let (sxy, sxx) = log_amplitude.iter().enumerate().fold((0.0, 0.0), |(sxy, sxx), (i, y)| {
            let dx = i as f64 - mean_x;
            (sxy + dx * (y - mean_y), sxx + dx * dx)
        });
        let per_step = (sxy / sxx).exp();
        if damps {
            let theory = hht_spectral_radius(&p, w[1] * h);
            assert!(
                (per_step / theory - 1.0).abs() < 0.01,
                "top mode decays {per_step}/step, theory {theory}"
            );
        } else {
            assert!(
                (per_step - 1.0).abs() < 1e-3,
                "Newmark changed the top mode by {per_step}/step"
            );
        }
    }
}

/// RK4 refuses a step above the stability limit it is given, with the limit in the error.
#[test]
fn rk4_refuses_steps_above_its_stability_limit() {
    let sys = Linear::new(vec![1.0], DMatrix::from_element(1, 1, 1e6));
    let limit = stability_limit(1e3);
    let mut st = DynState::new(vec![1.0], vec![0.0]);
    let mut driver = Driver::new(rk4(limit));
    let e = driver
        .advance(&sys, &mut st, 0.0, 2.0 * limit, 2.0 * limit, 1, |_, u| u[0] = 0.0)
        .unwrap_err();
    assert!(e.to_string().contains("stability limit"), "{e}");
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(
            driver
                .advance(&sys, &mut st, 0.0, bad, 1e-3, 1, |_, u| u[0] = 0.0)
                .is_err()
        );
    }
}
