//! The co-simulation master on the d-grid-step scene (drivetrain D, 2-mass, undamped, on the grid
//! through the generator FMU's electrical spring): trajectories against the exact modal solution,
//! convergence orders, and where each algorithm goes unstable. Every run is deterministic (same
//! calls, same bits), so the thresholds below are margins around measured values, not noise bands.

use crate::common;

use windrive::cosim::{Algorithm, Options};
use windrive::reference::grid_step::compare as run_grid_step;

fn error(algorithm: Algorithm, order: usize, step: f64, stop: f64) -> Option<f64> {
    let (_guard, dir) = common::scene_copy("d-grid-step");
    let mut opts = Options::new(algorithm, step, stop);
    opts.order = order;
    let o = run_grid_step(&dir, opts).unwrap();
    o.error.filter(|e| *e < 1.0)
}

/// Error at 1 ms over 2 s, and the order observed between 2 ms and 1 ms. Measured: GS p0 1.6e-3
/// (order 1.05), GS p1 1.5e-4 (2.00), Jacobi p1 3.8e-4 (2.01), Jacobi p2 1.3e-5 (2.98),
/// iterative p1 7.5e-5 (2.00). Bounds: 1.5× the measured error, order within 0.25 of the theory
/// (hold = first order; linear = second; quadratic = third).
#[test]
fn every_algorithm_converges_to_the_modal_solution_at_its_order() {
    for (algorithm, order, bound, expected) in [
        (Algorithm::GaussSeidel, 0, 2.4e-3, 1.0),
        (Algorithm::GaussSeidel, 1, 2.3e-4, 2.0),
        (Algorithm::Jacobi, 1, 5.7e-4, 2.0),
        (Algorithm::Jacobi, 2, 2.0e-5, 3.0),
        (Algorithm::Iterative, 1, 1.2e-4, 2.0),
    ] {
        let coarse = error(algorithm, order, 2e-3, 2.0).unwrap();
        let fine = error(algorithm, order, 1e-3, 2.0).unwrap();
        let observed = (coarse / fine).log2();
        assert!(fine < bound, "{algorithm:?} p{order}: error {fine:.3e} at 1 ms");
        assert!(
            (observed - expected).abs() < 0.25,
            "{algorithm:?} p{order}: observed order {observed:.2}, expected {expected}"
        );
    }
}

/// Where the methods fail on this stiff coupling (5.89 Hz generator mode, ω = 37 rad/s, no damping):
/// zero-order-hold Jacobi injects energy at any step (growing past the exact peak within 10 s even
/// at H·ω = 0.037); linear extrapolation holds to H·ω ≈ 0.19 and fails by 0.37; Gauss–Seidel with
/// hold stays bounded to H·ω = 1.85; iterative coupling with linear interpolation to 1.85 and fails
/// at 3.7, where its fixed-point iteration no longer contracts. The theory of this split
/// (src/cosim/stability.rs, docs/SPEED-ACCURACY.md) draws the same picture.
#[test]
fn stability_limits_of_the_coupling_algorithms() {
    let stable = |a, p, h| error(a, p, h, 10.0).is_some();
    assert!(
        !stable(Algorithm::Jacobi, 0, 1e-3),
        "ZOH Jacobi must go unstable without damping"
    );
    assert!(stable(Algorithm::Jacobi, 1, 5e-3));
    assert!(!stable(Algorithm::Jacobi, 1, 1e-2));
    assert!(stable(Algorithm::GaussSeidel, 0, 5e-2));
    assert!(!stable(Algorithm::GaussSeidel, 0, 0.1));
    assert!(stable(Algorithm::Iterative, 1, 5e-2));
    assert!(!stable(Algorithm::Iterative, 1, 0.1));
}

/// Where plain iteration fails (H·ω = 3.7: the fixed-point map amplifies instead of contracting),
/// Aitken relaxation and IQN-ILS converge at every step, both to the same answer: the implicit
/// coupling's own (error 1.48e-1 against the exact solution at 100 ms, 4.67e-2 at 50 ms: second
/// order, ratio 3.2), in 4 sweeps per step where plain iteration spends its 10-sweep cap at 50 ms.
/// At 1 ms, where plain iteration contracts, they take the same sweeps to the same answer (within
/// the coupling tolerance: the iterates after the first differ).
#[test]
fn accelerated_iteration_converges_where_plain_iteration_diverges() {
    use windrive::cosim::Acceleration;
    let (_guard, dir) = common::scene_copy("d-grid-step");
    let run = |acceleration, step| {
        let mut opts = Options::new(Algorithm::Iterative, step, 10.0);
        opts.acceleration = acceleration;
        run_grid_step(&dir, opts).unwrap()
    };
    let plain = run(Acceleration::None, 0.1);
    assert!(
        plain.failure.is_some(),
        "plain iteration was expected to diverge at H·ω = 3.7"
    );
    let mut errors = Vec::new();
    for acceleration in [Acceleration::Aitken, Acceleration::IqnIls] {
        let coarse = run(acceleration, 0.1);
        let fine = run(acceleration, 0.05);
        for (o, steps) in [(&coarse, 100), (&fine, 200)] {
            assert!(o.failure.is_none(), "{acceleration:?}: {:?}", o.failure);
            assert_eq!(o.stats.unconverged, 0, "{acceleration:?}");
            assert!(
                o.stats.sweeps <= 4 * steps,
                "{acceleration:?}: {} sweeps",
                o.stats.sweeps
            );
        }
        let (e1, e2) = (coarse.error.unwrap(), fine.error.unwrap());
        assert!(
            (e1 - 0.1477).abs() < 2e-3 && (e2 - 0.04672).abs() < 1e-3,
            "{acceleration:?}: {e1} {e2}"
        );
        errors.push(e1);
    }
    assert!((errors[0] - errors[1]).abs() < 1e-6 * errors[0], "{errors:?}");
    // where plain iteration contracts, acceleration costs nothing
    let (a, b) = (run(Acceleration::None, 1e-3), run(Acceleration::IqnIls, 1e-3));
    let (ea, eb) = (a.error.unwrap(), b.error.unwrap());
    assert!((ea - eb).abs() < 1e-6 * ea, "{ea} {eb}");
    assert_eq!(a.stats.sweeps, b.stats.sweeps);
}

/// The adaptive step meets a tighter tolerance with a smaller error: measured 2.4e-2, 1.8e-3 and
/// 1.2e-4 for 1e-3, 1e-4, 1e-5 over 10 s. Rejected steps are rolled back (counted), not kept.
#[test]
fn adaptive_step_error_follows_the_tolerance() {
    let (_guard, dir) = common::scene_copy("d-grid-step");
    let mut errors = Vec::new();
    for tol in [1e-3, 1e-4, 1e-5] {
        let mut opts = Options::new(Algorithm::Adaptive, 1e-3, 10.0);
        opts.rel_tol = tol;
        let o = run_grid_step(&dir, opts).unwrap();
        assert!(o.stats.rejected > 0 && o.stats.steps > 0);
        errors.push(o.error.unwrap());
    }
    assert!(errors[0] < 4e-2 && errors[1] < 3e-3 && errors[2] < 2e-4, "{errors:?}");
    assert!(errors[0] > errors[1] && errors[1] > errors[2]);
}

/// Jacobi on worker threads computes exactly what it computes on one: each FMU's step depends only
/// on the inputs set before the sweep.
#[test]
fn threaded_jacobi_is_bit_identical() {
    let (_guard, dir) = common::scene_copy("d-grid-step");
    let run = |threads| {
        let mut opts = Options::new(Algorithm::Jacobi, 1e-3, 1.0);
        opts.order = 1;
        opts.threads = threads;
        run_grid_step(&dir, opts).unwrap().error.unwrap()
    };
    assert_eq!(run(1).to_bits(), run(2).to_bits());
}
