//! The nearly piecewise-linear class's modified Newton iteration (`Newton { keep, predict }`): on the
//! GRC gearbox with lamina bearings it converges to the default iteration's answer within the Newton
//! tolerance with fewer factorisations; on a model whose tangent leaves out too much stiffness it
//! hands the step back to the default iteration (counted as a restart), and a step neither way can
//! take still ends in `NewtonDiverged`.

use nalgebra::DMatrix;
use windrive::bench::solvers::gearbox_matrix;
use windrive::physics::gearbox::Gearbox;
use windrive::physics::gearbox::description::{BearingModel, Description};
use windrive::physics::gearbox::statics::equilibrium;
use windrive::solver::alpha::{Alpha, AlphaIntegrator, Newton, Span};
use windrive::solver::factor::{Kind, Orderings, Solver};
use windrive::solver::{
    Driver, DynState, InputLoad, Linearity, Mass, Method, SecondOrderSystem, SolverError, Statistics,
};

const KEPT: Newton = Newton {
    keep: true,
    predict: false,
    ..Newton::PATTERN
};
const KEPT_PREDICTED: Newton = Newton {
    keep: true,
    predict: true,
    ..Newton::PATTERN
};
/// The same with J solved on its sparsity pattern (`linear_solver = sparse`): other rounding, the
/// same answer within the tolerance.
const KEPT_PREDICTED_SPARSE: Newton = Newton {
    sparse: true,
    ..KEPT_PREDICTED
};

/// The GRC at rated torque and speed, lamina bearings, 35 slices; its rotor torque drops by a fifth
/// at t = 0 and the brake stays open: `steps` steps of 1 ms with HHT-α (ρ∞ = 0.8, the FMU's default),
/// in internal steps of `h`.
fn grc_run(newton: Newton, steps: usize, h: f64) -> (Gearbox, DynState, Statistics) {
    let mut d = Description::load("grc750").unwrap();
    d.model.bearings = BearingModel::Lamina;
    let g = Gearbox::new(&d).unwrap();
    let t = g.rated_rotor_torque.unwrap();
    let speed = d.rated_rotor_speed_rpm.unwrap() * std::f64::consts::TAU / 60.0;
    let (q, v) = equilibrium(&g, &[t, t / g.gear_ratio, 0.0], speed).unwrap();
    let u = [0.8 * t, t / g.gear_ratio, 0.0];
    let mut st = DynState::new(q, v);
    let mut driver = Driver::new(Method::Implicit(Alpha::hht(0.8).unwrap()));
    driver.set_newton(newton);
    for k in 0..steps {
        driver
            .advance(&g, &mut st, k as f64 * 1e-3, 1e-3, h, 3, |_, out| {
                out.copy_from_slice(&u)
            })
            .unwrap();
    }
    (g, st, driver.stats)
}

fn largest(x: impl Iterator<Item = f64>) -> f64 {
    x.fold(0.0f64, |m, v| m.max(v.abs()))
}

#[test]
fn kept_factorisations_reach_the_default_iterations_answer_with_fewer_factorisations() {
    let steps = 300;
    let (g, reference, pattern) = grc_run(Newton::default(), steps, 1e-3);
    let n = g.dofs();
    let forces = |st: &DynState| {
        let mut f = vec![0.0; n];
        g.internal_forces(0.0, &st.q, &st.v, &mut f);
        f
    };
    let f_ref = forces(&reference);
    let scale_f = largest(f_ref.iter().copied());
    let scale_v = largest(reference.v.iter().copied());
    // the internal forces carry the deflections (positions are absolute angles of tens of radians)
    let differences = |st: &DynState| {
        (
            largest(forces(st).iter().zip(&f_ref).map(|(a, b)| a - b)) / scale_f,
            largest(st.v.iter().zip(&reference.v).map(|(a, b)| a - b)) / scale_v,
        )
    };
    // what the step itself costs: the default iteration at half the step
    let (step_f, step_v) = differences(&grc_run(Newton::default(), steps, 5e-4).1);
    // and the gearbox FMU's defaults: the same with its looser tolerance and its motion floor
    let params = windrive::slaves::gearbox6dof::Params::default();
    let fmu_defaults = Newton {
        tolerance: params.newton_tolerance,
        motion_floor: params.newton_motion_floor,
        ..KEPT_PREDICTED_SPARSE
    };
    for newton in [KEPT, KEPT_PREDICTED, KEPT_PREDICTED_SPARSE, fmu_defaults] {
        let (_, st, stats) = grc_run(newton, steps, 1e-3);
        let (df, dv) = differences(&st);
        println!(
            "{newton:?}: forces {df:.1e}, speeds {dv:.1e} of their largest (0.5 ms: {step_f:.1e}, {step_v:.1e}); per \
             step: {:.2} iterations, {:.3} factorisations, {} restarts (default: {:.2}, {:.3})",
            stats.newton_iterations as f64 / steps as f64,
            stats.factorizations as f64 / steps as f64,
            stats.newton_restarts,
            pattern.newton_iterations as f64 / steps as f64,
            pattern.factorizations as f64 / steps as f64,
        );
        assert!(
            df < step_f / 10.0 && dv < step_v / 10.0,
            "{newton:?}: forces {df:e}, speeds {dv:e} against the step's {step_f:e}, {step_v:e}"
        );
        assert_eq!(stats.steps, pattern.steps);
        assert!(
            2 * stats.factorizations < pattern.factorizations,
            "{newton:?}: {} factorisations, default {}",
            stats.factorizations,
            pattern.factorizations
        );
    }
}

/// The GRC's and the 2 MW gearbox's iteration matrices go to LU on their pattern when asked (its
/// elimination is far below half dense LU's, and the probe passes: no silent fallback to dense LU),
/// and that LU solves them as dense LU does within rounding.
#[test]
fn gearbox_iteration_matrices_factorise_on_their_pattern() {
    for preset in ["grc750", "c2mw"] {
        let j = gearbox_matrix(preset);
        let n = j.nrows();
        let pattern = Solver::new_with(j.clone(), true, &mut Orderings::default()).unwrap();
        assert_eq!(pattern.kind(), Kind::PatternLu, "{preset}");
        let dense = Solver::new(j.clone(), true).unwrap();
        assert_eq!(dense.kind(), Kind::DenseLu, "{preset}: the default stays dense");
        let r: Vec<f64> = (0..n).map(|i| (0.3 * i as f64).cos()).collect();
        let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
        pattern.add_solution(&r, &mut a);
        dense.add_solution(&r, &mut b);
        let scale = largest(b.iter().copied());
        let apart = largest(a.iter().zip(&b).map(|(x, y)| x - y));
        assert!(apart <= 1e-10 * scale, "{preset}: {apart:e} of {scale:e}");
    }
}

/// One mass on a spring k whose tangent reports only `reported` of k: the modified Newton iteration
/// on it contracts by |1 − J_true/J| per iteration. From `stiff_until` (s) on, the spring is what the
/// tangent reports.
struct Understated {
    mass: [f64; 1],
    k: f64,
    reported: f64,
    stiff_until: f64,
}

impl SecondOrderSystem for Understated {
    fn dofs(&self) -> usize {
        1
    }
    fn linearity(&self) -> Linearity {
        Linearity::NearlyPiecewiseLinear
    }
    fn mass(&self) -> Mass<'_> {
        Mass::Diagonal(&self.mass)
    }
    fn input_loads(&self) -> &[InputLoad] {
        &[]
    }
    fn internal_forces(&self, t: f64, q: &[f64], _: &[f64], out: &mut [f64]) {
        out[0] = if t < self.stiff_until { self.k } else { self.reported } * q[0];
    }
    fn add_tangent(&self, _: f64, _: &[f64], _: &[f64], _: f64, c_k: f64, j: &mut DMatrix<f64>) {
        j[(0, 0)] += c_k * self.reported;
    }
}

fn understated_run(sys: &Understated, newton: Newton, steps: usize) -> Result<(DynState, Statistics), SolverError> {
    let mut st = DynState::new(vec![1e-3], vec![0.0]);
    let mut driver = Driver::new(Method::Implicit(Alpha::NEWMARK));
    driver.set_newton(newton);
    for k in 0..steps {
        driver.advance(sys, &mut st, k as f64 * 1e-3, 1e-3, 1e-3, 0, |_, _| {})?;
    }
    Ok((st, driver.stats))
}

#[test]
fn a_kept_iteration_that_stalls_is_retaken_the_default_way_and_divergence_stays_an_error() {
    // J = c_m·m = 4e6 at 1 ms (Newmark); the spring adds 4e4 (θ = 0.01: one J throughout) or 2.4e6
    // (θ = 0.6: refreshed, the fresh J no better, the step retaken; the default way takes some 36
    // iterations, so the next RATTLE_RUN steps go that way at once, then the kept J is tried again
    // on step 17 and fails again: 2 restarts, 18 steps the default way at once, one fresh J each restart)
    let steps = 20;
    for (k, restarts, rattle_steps, factorizations) in [(4e4, 0, 0, 1), (2.4e6, 2, 18, 3)] {
        let sys = Understated {
            mass: [1.0],
            k,
            reported: 0.0,
            stiff_until: f64::INFINITY,
        };
        let (default, _) = understated_run(&sys, Newton::default(), steps).unwrap();
        let (kept, stats) = understated_run(&sys, KEPT, steps).unwrap();
        assert_eq!(stats.newton_restarts, restarts, "k = {k}");
        assert_eq!(stats.newton_rattle_steps, rattle_steps, "k = {k}");
        assert_eq!(stats.factorizations, factorizations, "k = {k}");
        // both within 1e-8 of the step's motion (q ≈ 1e-3 m)
        let error = (kept.q[0] - default.q[0]).abs();
        assert!(error < 1e-9, "k = {k}: {} vs {}", kept.q[0], default.q[0]);
    }
    // 4e7: |1 − J_true/J| = 10 (4.5 with the default way's halved increments), neither way converges;
    // one step of the integrator
    // itself (the driver would halve the step until it does)
    let sys = Understated {
        mass: [1.0],
        k: 4e7,
        reported: 0.0,
        stiff_until: f64::INFINITY,
    };
    for newton in [Newton::default(), KEPT, KEPT_PREDICTED] {
        let mut integrator = AlphaIntegrator::new(Alpha::NEWMARK);
        integrator.newton = newton;
        let mut st = DynState::new(vec![1e-3], vec![0.0]);
        st.a[0] = -sys.k * st.q[0];
        let span = Span {
            t: 0.0,
            h: 1e-3,
            u0: &[],
            u1: &[],
            fi0: None,
        };
        let mut stats = Statistics::default();
        match integrator.step(&sys, &mut st, &span, &mut stats) {
            Err(SolverError::NewtonDiverged { .. }) => {}
            other => panic!("{newton:?}: {other:?}"),
        }
        assert_eq!(stats.newton_restarts, u64::from(newton.keep), "{newton:?}");
    }
}

/// After a restart the steps go the default way at once (RATTLE_ITERATIONS), and the first of them that
/// converges fast hands the next step back to the kept iteration: a spring the tangent understates
/// until 5 ms (each step forced at its end, t + h: four such steps), then one it reports exactly.
#[test]
fn steps_go_the_default_way_after_a_restart_until_one_converges_fast() {
    let sys = Understated {
        mass: [1.0],
        k: 2.4e6,
        reported: 4e4,
        stiff_until: 4.5e-3,
    };
    let steps = 20;
    let (kept, stats) = understated_run(&sys, KEPT, steps).unwrap();
    let (default, _) = understated_run(&sys, Newton::default(), steps).unwrap();
    // the first step restarts; the three hard ones after it and the first soft one go the default way
    assert_eq!(stats.newton_restarts, 1);
    assert_eq!(stats.newton_rattle_steps, 4);
    // then the kept iteration takes every step on one J (the restart's fresh J, exact from 5 ms on)
    let (_, after) = understated_run(&sys, KEPT, 5).unwrap();
    assert_eq!(
        stats.newton_iterations - after.newton_iterations,
        2 * (steps as u64 - 5),
        "two iterations a step on the exact J"
    );
    assert_eq!(stats.factorizations, after.factorizations);
    assert!(
        (kept.q[0] - default.q[0]).abs() < 1e-9,
        "{} vs {}",
        kept.q[0],
        default.q[0]
    );
}
