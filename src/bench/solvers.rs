//! `windrive bench solvers`: the four factorisations of `solver::factor` on block-sparse iteration
//! matrices of 6-DOF bodies (each coupled to the next and to a carrier) and on the iteration matrices
//! of the GRC and 2 MW gearboxes: factorise + one solve (what a Newton iteration with a fresh Jacobian
//! costs) and one solve with a kept factorisation (a step with a cached one), and the kind the
//! automatic choice takes. LU on J's pattern is timed as an integrator runs it, its ordering made once
//! beforehand (it is kept while J's pattern stays within it).

use crate::physics::gearbox::Gearbox;
use crate::physics::gearbox::description::Description;
use crate::physics::gearbox::statics::equilibrium;
use crate::solver::SecondOrderSystem;
use crate::solver::factor::{Kind, Orderings, Solver, block_sparse};
use nalgebra::DMatrix;
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
pub const KINDS: [Kind; 4] = [Kind::DenseLu, Kind::Inverse, Kind::SparseLu, Kind::PatternLu];

/// One matrix.
pub struct Row {
    /// `blocks` for the block-sparse reference, else the gearbox preset.
    pub matrix: &'static str,
    pub dofs: usize,
    /// Non-zero share of the matrix, %.
    pub fill_percent: f64,
    /// Per kind of [`KINDS`]: factorise + one solve, and one solve, s per call.
    pub factor_solve: [f64; 4],
    pub solve: [f64; 4],
    /// The automatic choice with the factorisation reused, and used once.
    pub chosen_reused: Kind,
    pub chosen_once: Kind,
}

/// The head of the table; each [`Row`] displays as one of its rows.
pub fn head() -> String {
    format!(
        "block-sparse iteration matrices of 6-DOF bodies; times per call, ratios against dense LU (> 1: faster)\n\
         {:>8} {:>5} {:>6} {:>13} {:>10} {:>10} {:>10} {:>12} {:>10} {:>10} {:>10}  chosen (reused / once)",
        "matrix",
        "DOFs",
        "fill",
        "LU f+s / µs",
        "inverse",
        "sparse",
        "pattern",
        "LU s / µs",
        "inverse",
        "sparse",
        "pattern"
    )
}

/// Times per call, and ratios against dense LU (> 1: faster).
impl fmt::Display for Row {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        let (fs, s) = (&self.factor_solve, &self.solve);
        write!(
            f,
            "{:>8} {:>5} {:>5.1}% {:>13.1} {:>10.2} {:>10.2} {:>10.2} {:>12.2} {:>10.2} {:>10.2} {:>10.2}  {:?} / {:?}",
            self.matrix,
            self.dofs,
            self.fill_percent,
            fs[0] * 1e6,
            fs[0] / fs[1],
            fs[0] / fs[2],
            fs[0] / fs[3],
            s[0] * 1e6,
            s[0] / s[1],
            s[0] / s[2],
            s[0] / s[3],
            self.chosen_reused,
            self.chosen_once
        )
    }
}

/// The GRC's or another preset's iteration matrix at rated torque and speed, its lamina bearings
/// loaded: M/(β·h²) + γ/(β·h)·C + K with Newmark's β = 1/4, γ = 1/2 at h = 1 ms (the pattern and the
/// scaling of the FMU's HHT-α matrices).
pub fn gearbox_matrix(preset: &str) -> DMatrix<f64> {
    let d = Description::load(preset).expect("a preset");
    let g = Gearbox::new(&d).expect("the preset builds");
    let t = g.rated_rotor_torque.expect("a rated torque");
    let speed = d.rated_rotor_speed_rpm.expect("a rated speed") * std::f64::consts::TAU / 60.0;
    let (q, v) = equilibrium(&g, &[t, t / g.gear_ratio, 0.0], speed).expect("a loaded equilibrium");
    let (n, h) = (g.dofs(), 1e-3);
    let mut j = DMatrix::zeros(n, n);
    g.mass().add_to(4.0 / (h * h), &mut j);
    g.add_tangent(0.0, &q, &v, 2.0 / h, 1.0, &mut j);
    j
}

/// Every size from 2 to 64 bodies, then the GRC's and the 2 MW gearbox's iteration matrices; `row`
/// after each.
pub fn run(mut row: impl FnMut(&Row)) {
    let blocks = [2, 4, 8, 11, 16, 21, 24, 32, 48, 64].map(|bodies| ("blocks", block_sparse(bodies, 1)));
    let gearboxes = ["grc750", "c2mw"].map(|preset| (preset, gearbox_matrix(preset)));
    for (matrix, j) in blocks.into_iter().chain(gearboxes) {
        let n = j.nrows();
        let nonzeros = j.iter().filter(|x| **x != 0.0).count();
        let r: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let mut x = vec![0.0; n];
        let mut factor_solve = [0.0; 4];
        let mut solve = [0.0; 4];
        let mut orderings = Orderings::default();
        let ordering = orderings.of(&j);
        for (k, kind) in KINDS.into_iter().enumerate() {
            let mut factorise = || {
                match kind {
                    // J copied as the other kinds take it (by value)
                    Kind::PatternLu => Solver::on_pattern(&j.clone(), ordering.clone(), &mut orderings),
                    _ => Solver::with_kind(j.clone(), kind),
                }
                .expect("the reference matrix is regular")
            };
            factor_solve[k] = seconds_per_call(|| factorise().add_solution(&r, &mut x));
            let s = factorise();
            solve[k] = seconds_per_call(|| s.add_solution(&r, &mut x));
        }
        row(&Row {
            matrix,
            dofs: n,
            fill_percent: 100.0 * nonzeros as f64 / (n * n) as f64,
            factor_solve,
            solve,
            chosen_reused: Kind::for_matrix(n, nonzeros, true),
            chosen_once: Kind::for_matrix(n, nonzeros, false),
        });
    }
}
