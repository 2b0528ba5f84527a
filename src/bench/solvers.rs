//! `windrive bench solvers`: the three factorisations of `solver::factor` on block-sparse iteration
//! matrices of 6-DOF bodies (each coupled to the next and to a carrier): factorise + one solve (what a
//! Newton iteration with a fresh Jacobian costs) and one solve with a kept factorisation (a step with a
//! cached one), and the kind the automatic choice takes.

use crate::solver::factor::{Kind, Solver, block_sparse};
use std::fmt;

/// Seconds per call of `f`, the best of three 0.1 s batches (the machine is shared).
fn seconds_per_call(mut f: impl FnMut()) -> f64 {
    (0..3)
        .map(|_| {
            let t = std::time::Instant::now();
            let mut calls = 0u32;
            while t.elapsed().as_secs_f64() < 0.1 {
                f();
                calls += 1;
            }
            t.elapsed().as_secs_f64() / f64::from(calls)
        })
        .fold(f64::MAX, f64::min)
}

/// The kinds timed, in the order of [`Row`]'s arrays.
pub const KINDS: [Kind; 3] = [Kind::DenseLu, Kind::Inverse, Kind::SparseLu];

/// One matrix size.
pub struct Row {
    pub dofs: usize,
    /// Non-zero share of the matrix, %.
    pub fill_percent: f64,
    /// Per kind of [`KINDS`]: factorise + one solve, and one solve, s per call.
    pub factor_solve: [f64; 3],
    pub solve: [f64; 3],
    /// The automatic choice with the factorisation reused, and used once.
    pub chosen_reused: Kind,
    pub chosen_once: Kind,
}

/// The head of the table; each [`Row`] displays as one of its rows.
pub fn head() -> String {
    format!(
        "block-sparse iteration matrices of 6-DOF bodies; times per call, ratios against dense LU (> 1: faster)\n\
         {:>5} {:>6} {:>13} {:>10} {:>10} {:>12} {:>10} {:>10}  chosen (reused / once)",
        "DOFs", "fill", "LU f+s / µs", "inverse", "sparse", "LU s / µs", "inverse", "sparse"
    )
}

/// Times per call, and ratios against dense LU (> 1: faster).
impl fmt::Display for Row {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        let (fs, s) = (&self.factor_solve, &self.solve);
        write!(
            f,
            "{:>5} {:>5.1}% {:>13.1} {:>10.2} {:>10.2} {:>12.2} {:>10.2} {:>10.2}  {:?} / {:?}",
            self.dofs,
            self.fill_percent,
            fs[0] * 1e6,
            fs[0] / fs[1],
            fs[0] / fs[2],
            s[0] * 1e6,
            s[0] / s[1],
            s[0] / s[2],
            self.chosen_reused,
            self.chosen_once
        )
    }
}

/// Every size from 2 to 64 bodies; `row` after each.
pub fn run(mut row: impl FnMut(&Row)) {
    for bodies in [2, 4, 8, 11, 16, 21, 24, 32, 48, 64] {
        let j = block_sparse(bodies, 1);
        let n = j.nrows();
        let nonzeros = j.iter().filter(|x| **x != 0.0).count();
        let r: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let mut x = vec![0.0; n];
        let mut factor_solve = [0.0; 3];
        let mut solve = [0.0; 3];
        for (k, kind) in KINDS.into_iter().enumerate() {
            factor_solve[k] = seconds_per_call(|| {
                let s = Solver::with_kind(j.clone(), kind).expect("the reference matrix is regular");
                s.add_solution(&r, &mut x);
            });
            let s = Solver::with_kind(j.clone(), kind).expect("the reference matrix is regular");
            solve[k] = seconds_per_call(|| s.add_solution(&r, &mut x));
        }
        row(&Row {
            dofs: n,
            fill_percent: 100.0 * nonzeros as f64 / (n * n) as f64,
            factor_solve,
            solve,
            chosen_reused: Kind::for_matrix(n, nonzeros, true),
            chosen_once: Kind::for_matrix(n, nonzeros, false),
        });
    }
}
