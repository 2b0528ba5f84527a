//! Classical explicit RK4 for any [`SecondOrderSystem`]. Stable only for h·ω_max ≤ 2.785 (the RK4
//! stability interval on the imaginary axis), which gear-mesh modes push to a fraction of a
//! millisecond; the driver refuses a larger step with the limit named instead of returning garbage.
//!
//! The friction contact slips with ± its kinetic capacity; when its DOF's speed crosses zero within
//! a step it is set to rest and held while the holding force stays within the static capacity
//! (first-order event location, as OpenFAST's HSS brake: the implicit integrators solve
//! stick–slip exactly and are the default).

use super::state::{DynState, Statistics, same_bits};
use super::system::{Friction, Mass, SecondOrderSystem, SparseColumns, external_forces};

/// Largest stable RK4 step is STABILITY_BOUND / ω_max (2√2 on the imaginary axis).
pub const STABILITY_BOUND: f64 = 2.785;

pub fn stability_limit(omega_max: f64) -> f64 {
    STABILITY_BOUND / omega_max
}

/// Scratch memory for one RK4 integrator.
#[derive(Debug, Clone, Default)]
pub struct Rk4 {
    k_q: [Vec<f64>; 4],
    k_v: [Vec<f64>; 4],
    q: Vec<f64>,
    v: Vec<f64>,
    q0: Vec<f64>,
    v0: Vec<f64>,
    f: Vec<f64>,
    fi: Vec<f64>,
    mass: MassSolver,
}

/// Solves M·x = f. A dense M (the 6-DOF gearbox's 6×6 blocks and planet-orbit coupling) keeps its
/// Cholesky factor between calls, refactorised only when the matrix differs from the one factorised:
/// a communication step's consistent accelerations then cost a back-substitution, not a factorisation.
#[derive(Debug, Clone, Default)]
pub struct MassSolver {
    matrix: Option<nalgebra::DMatrix<f64>>,
    factor: Option<nalgebra::Cholesky<f64, nalgebra::Dyn>>,
    /// The factor's nonzero entries below its diagonal, for a [`Mass::Sparse`] solve.
    below: SparseColumns,
    /// (dof, M⁻¹ e_dof at that dof) of the last friction DOF asked for.
    compliance: Option<(usize, f64)>,
    /// The nonzero entries of `matrix` when it came as a [`Mass::Sparse`]: they decide it.
    entries: Option<SparseColumns>,
}

impl MassSolver {
    /// The Cholesky factor of `m`, refactorised only when `m` changed; `entries` are its nonzero
    /// entries when it is a [`Mass::Sparse`].
    fn factor(
        &mut self,
        m: &nalgebra::DMatrix<f64>,
        entries: Option<&SparseColumns>,
    ) -> Option<&nalgebra::Cholesky<f64, nalgebra::Dyn>> {
        // compared as bytes: nalgebra's matrix equality walks generic strided views and took 6 % of
        // the GRC shutdown's instructions at one comparison per communication step, and an f64
        // comparison per entry still 4 % of a kept-factorisation step; equal bytes are the same
        // matrix (a −0 for a 0 only refactorises). A sparse mass is compared by its nonzero entries,
        // which are all of it (the GRC's 94 of 7056: the bytes' comparison was 1.5 % of a step); a
        // mass that changes kind is factorised afresh
        let same = match (&self.matrix, &self.entries, entries) {
            (Some(f), Some(mine), Some(e)) => f.shape() == m.shape() && mine == e,
            (Some(f), None, None) => f.shape() == m.shape() && same_bits(f.as_slice(), m.as_slice()),
            _ => false,
        };
        if !same {
            self.entries = entries.cloned();
            self.factor = m.clone().cholesky();
            self.below = match &self.factor {
                Some(c) => SparseColumns::below_diagonal(c.l_dirty()),
                None => SparseColumns::default(),
            };
            self.matrix = Some(m.clone());
            self.compliance = None;
        }
        self.factor.as_ref()
    }

    /// out = M⁻¹·f (NaN when a dense M is not positive definite).
    pub fn solve(&mut self, mass: Mass<'_>, f: &[f64], out: &mut [f64]) {
        match mass {
            Mass::Diagonal(m) => {
                for ((o, fi), mi) in out.iter_mut().zip(f).zip(m) {
                    *o = fi / mi;
                }
            }
            Mass::Dense(m) | Mass::Sparse(m, _) => {
                self.factor(m, sparse_entries(mass));
                match &self.factor {
                    Some(c) => {
                        out.copy_from_slice(f);
                        if matches!(mass, Mass::Sparse(..)) {
                            cholesky_solve_sparse(c.l_dirty(), &self.below, out);
                        } else {
                            cholesky_solve(c.l_dirty(), out);
                        }
                    }
                    None => out.iter_mut().for_each(|x| *x = f64::NAN),
                }
            }
        }
    }

    /// The friction force that keeps DOF `dof` from accelerating under the free accelerations `a`:
    /// its share of M⁻¹ decides how much force one unit of acceleration takes.
    pub fn holding_force(&mut self, mass: Mass<'_>, a: &[f64], dof: usize) -> f64 {
        match mass {
            Mass::Diagonal(m) => -m[dof] * a[dof],
            Mass::Dense(m) | Mass::Sparse(m, _) => {
                self.factor(m, sparse_entries(mass));
                let compliance = match self.compliance {
                    Some((d, c)) if d == dof => c,
                    _ => {
                        let n = m.nrows();
                        let mut e = vec![0.0; n];
                        e[dof] = 1.0;
                        let mut column = vec![0.0; n];
                        self.solve(mass, &e, &mut column);
                        self.compliance = Some((dof, column[dof]));
                        column[dof]
                    }
                };
                -a[dof] / compliance
            }
        }
    }
}

/// A sparse mass's nonzero entries.
fn sparse_entries<'a>(mass: Mass<'a>) -> Option<&'a SparseColumns> {
    match mass {
        Mass::Sparse(_, entries) => Some(entries),
        _ => None,
    }
}

/// x = (L·Lᵀ)⁻¹·b in place, L the lower triangle of `l` (its upper part is not read): nalgebra's
/// `Cholesky::solve_mut` operation for operation (the forward sweep's column updates, the backward
/// sweep's dot products in its eight running sums and their order), so the bits are its bits, on
/// contiguous column slices instead of its generic views (an 84-DOF solve took 81 k instructions).
fn cholesky_solve(l: &nalgebra::DMatrix<f64>, x: &mut [f64]) {
    let n = l.nrows();
    let data = l.as_slice();
    let column = |i: usize| &data[i * n..(i + 1) * n];
    for i in 0..n {
        let c = column(i);
        let coeff = x[i] / c[i];
        x[i] = coeff;
        let a = -coeff;
        for (y, li) in x[i + 1..].iter_mut().zip(&c[i + 1..]) {
            *y += a * li;
        }
    }
    for i in (0..n).rev() {
        let c = column(i);
        let dot = nalgebra_dot(&c[i + 1..], &x[i + 1..]);
        x[i] = (x[i] - dot) / c[i];
    }
}

/// [`cholesky_solve`] over the factor's nonzero entries below its diagonal (`below`): each update and
/// each of the dot product's running sums takes the nonzero terms the dense sweep takes, in its
/// order, so the same bits (a skipped term is ±0, which changes no sum but the sign of an exact zero).
fn cholesky_solve_sparse(l: &nalgebra::DMatrix<f64>, below: &SparseColumns, x: &mut [f64]) {
    let n = l.nrows();
    let diagonal = |i: usize| l.as_slice()[i * n + i];
    for i in 0..n {
        let coeff = x[i] / diagonal(i);
        x[i] = coeff;
        let a = -coeff;
        for &(r, li) in below.column(i) {
            x[r] += a * li;
        }
    }
    for i in (0..n).rev() {
        let column = below.column(i);
        if column.is_empty() {
            // the running sums of no terms add up to +0.0, and x − (+0.0) is x to the bit (−0 too): most
            // columns of a gearbox's mass factor hold no entry below the diagonal
            x[i] /= diagonal(i);
            continue;
        }
        // nalgebra_dot over rows i + 1 … n − 1: position p = r − i − 1 goes to running sum p mod 8
        // in the blocks of eight, the tail after them is added in order
        let blocked = i + 1 + (n - i - 1) / 8 * 8;
        let mut acc = [0.0f64; 8];
        let split = column.partition_point(|&(r, _)| r < blocked);
        for &(r, li) in &column[..split] {
            acc[(r - i - 1) % 8] += li * x[r];
        }
        let mut dot = 0.0;
        dot += acc[0] + acc[4];
        dot += acc[1] + acc[5];
        dot += acc[2] + acc[6];
        dot += acc[3] + acc[7];
        for &(r, li) in &column[split..] {
            dot += li * x[r];
        }
        x[i] = (x[i] - dot) / diagonal(i);
    }
}

/// nalgebra's dot product of two dynamic vectors (`Matrix::dot`): eight running sums over blocks of
/// eight, added pairwise in its order, then the tail.
fn nalgebra_dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0f64; 8];
    let blocks = a.len() / 8;
    for (x, y) in a.chunks_exact(8).zip(b.chunks_exact(8)) {
        for k in 0..8 {
            acc[k] += x[k] * y[k];
        }
    }
    let mut res = 0.0;
    res += acc[0] + acc[4];
    res += acc[1] + acc[5];
    res += acc[2] + acc[6];
    res += acc[3] + acc[7];
    for k in blocks * 8..a.len() {
        res += a[k] * b[k];
    }
    res
}

/// Accelerations at (q, v) into `out`; returns the friction force used (on its DOF).
#[allow(clippy::too_many_arguments)]
fn accelerations<S: SecondOrderSystem>(
    sys: &S,
    t: f64,
    q: &[f64],
    v: &[f64],
    u: &[f64],
    friction: Option<Friction>,
    locked: bool,
    w: &mut Rk4,
    out: &mut [f64],
) -> f64 {
    external_forces(sys, u, &mut w.f);
    sys.internal_forces(t, q, v, &mut w.fi);
    for (f, fi) in w.f.iter_mut().zip(&w.fi) {
        *f -= fi;
    }
    let Some(fr) = friction else {
        w.mass.solve(sys.mass(), &w.f, out);
        return 0.0;
    };
    let force = if locked {
        w.mass.solve(sys.mass(), &w.f, out);
        w.mass.holding_force(sys.mass(), out, fr.dof)
    } else if v[fr.dof] != 0.0 {
        -fr.kinetic * v[fr.dof].signum()
    } else {
        0.0
    };
    w.f[fr.dof] += force;
    w.mass.solve(sys.mass(), &w.f, out);
    if locked {
        out[fr.dof] = 0.0;
    }
    force
}

impl Rk4 {
    fn fit(&mut self, n: usize) {
        if self.q.len() != n {
            let z = vec![0.0; n];
            self.k_q = std::array::from_fn(|_| z.clone());
            self.k_v = std::array::from_fn(|_| z.clone());
            self.q = z.clone();
            self.v = z.clone();
            self.q0 = z.clone();
            self.v0 = z.clone();
            self.f = z.clone();
            self.fi = z;
        }
    }

    /// Advances `st` from t by h with the inputs held at `u` (their value at t + h).
    pub fn step<S: SecondOrderSystem>(
        &mut self,
        sys: &S,
        st: &mut DynState,
        t: f64,
        h: f64,
        u: &[f64],
        stats: &mut Statistics,
    ) {
        let n = sys.dofs();
        self.fit(n);
        let friction = sys.friction(u).filter(|f| f.kinetic > 0.0 || f.holding > 0.0);
        // a stuck contact lets go when the force to hold it exceeds its static capacity
        if let Some(fr) = friction
            && st.locked
        {
            let mut k0 = std::mem::take(&mut self.k_v[0]);
            let hold = accelerations(sys, t, &st.q, &st.v, u, friction, true, self, &mut k0);
            self.k_v[0] = k0;
            st.locked = hold.abs() <= fr.holding;
        }
        let locked = st.locked && friction.is_some();
        let w = self;
        w.q0.copy_from_slice(&st.q);
        w.v0.copy_from_slice(&st.v);
        w.q.copy_from_slice(&st.q);
        w.v.copy_from_slice(&st.v);
        let mut force = 0.0;
        for stage in 0..4 {
            let c = match stage {
                0 => 0.0,
                3 => h,
                _ => 0.5 * h,
            };
            if stage > 0 {
                for d in 0..n {
                    w.q[d] = w.q0[d] + c * w.k_q[stage - 1][d];
                    w.v[d] = w.v0[d] + c * w.k_v[stage - 1][d];
                }
            }
            w.k_q[stage].copy_from_slice(&w.v);
            let (q, v) = (std::mem::take(&mut w.q), std::mem::take(&mut w.v));
            let mut k = std::mem::take(&mut w.k_v[stage]);
            let used = accelerations(sys, t + c, &q, &v, u, friction, locked, w, &mut k);
            (w.q, w.v, w.k_v[stage]) = (q, v, k);
            if stage == 0 {
                force = used;
            }
        }
        for d in 0..n {
            st.q[d] = w.q0[d] + h / 6.0 * (w.k_q[0][d] + 2.0 * w.k_q[1][d] + 2.0 * w.k_q[2][d] + w.k_q[3][d]);
            st.v[d] = w.v0[d] + h / 6.0 * (w.k_v[0][d] + 2.0 * w.k_v[1][d] + 2.0 * w.k_v[2][d] + w.k_v[3][d]);
        }
        if let Some(fr) = friction {
            let f = fr.dof;
            if locked {
                st.v[f] = 0.0;
                st.q[f] = w.q0[f];
            } else if fr.kinetic > 0.0 && w.v0[f] * st.v[f] <= 0.0 && w.v0[f] != 0.0 {
                // the friction would reverse the DOF: it stops instead (as OpenFAST's FixHSSBrTq)
                st.v[f] = 0.0;
                st.locked = true;
            }
        } else {
            st.locked = false;
        }
        st.friction_force = force;
        // RK4 keeps no accelerations: the next step recomputes them from the inputs
        st.applied.clear();
        stats.steps += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::{Mass, MassSolver, SparseColumns, cholesky_solve, cholesky_solve_sparse, nalgebra_dot, same_bits};
    use nalgebra::{DMatrix, DVector};

    /// A seeded sequence in (−1, 1).
    fn numbers(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s = s
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }

    #[test]
    fn the_cholesky_solve_gives_nalgebras_bits() {
        for n in (1..=40).chain([63, 64, 65, 84, 130]) {
            let mut r = numbers(n as u64);
            let a = DMatrix::from_fn(n, n, |_, _| r());
            // symmetric positive definite, entries of mixed magnitude as a 6-DOF mass matrix has
            let m =
                &a * a.transpose() + DMatrix::from_fn(n, n, |i, j| if i == j { 1e3 * (1.0 + i as f64) } else { 0.0 });
            let chol = m.clone().cholesky().unwrap();
            for k in 0..3 {
                let b: Vec<f64> = (0..n).map(|i| r() * 10f64.powi((i % 7) as i32 - 3 + k)).collect();
                let expected = chol.solve(&DVector::from_column_slice(&b));
                let mut x = b.clone();
                cholesky_solve(chol.l_dirty(), &mut x);
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&x), bits(expected.as_slice()), "n = {n}");
            }
        }
    }

    /// Over the factor's nonzero entries the solve gives the dense sweep's bits: sparse symmetric
    /// positive definite matrices (a diagonal, couplings of every sixth DOF to one, as the gearbox's
    /// planets to their carrier, and a few random pairs), every size around the dot product's blocks
    /// of eight.
    #[test]
    fn the_sparse_cholesky_solve_gives_the_dense_sweeps_bits() {
        for n in (1..=40).chain([63, 64, 65, 84, 130]) {
            let mut r = numbers(1000 + n as u64);
            let mut m = DMatrix::from_fn(n, n, |i, j| if i == j { 1e3 * (2.0 + r()) } else { 0.0 });
            let hub = n / 3;
            for k in (0..n).step_by(6).filter(|&k| k != hub) {
                let v = 20.0 * r();
                (m[(k, hub)], m[(hub, k)]) = (v, v);
            }
            for _ in 0..n / 4 {
                let (i, j) = (
                    ((r() + 1.0) * 0.5 * n as f64) as usize % n,
                    ((r() + 1.0) * 0.5 * n as f64) as usize % n,
                );
                if i != j {
                    let v = 5.0 * r();
                    (m[(i, j)], m[(j, i)]) = (v, v);
                }
            }
            let chol = m.clone().cholesky().unwrap();
            let below = SparseColumns::below_diagonal(chol.l_dirty());
            assert!(
                n < 12 || below.nonzeros() < n * n / 4,
                "n = {n}: the test matrix should be sparse"
            );
            for k in 0..3 {
                let b: Vec<f64> = (0..n).map(|i| r() * 10f64.powi((i % 7) as i32 - 3 + k)).collect();
                let (mut dense, mut sparse) = (b.clone(), b);
                cholesky_solve(chol.l_dirty(), &mut dense);
                cholesky_solve_sparse(chol.l_dirty(), &below, &mut sparse);
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&sparse), bits(&dense), "n = {n}");
            }
        }
    }

    #[test]
    fn the_dot_product_is_nalgebras() {
        for n in 0..40 {
            let mut r = numbers(100 + n as u64);
            let (a, b): (Vec<f64>, Vec<f64>) = (0..n).map(|_| (r() * 1e5, r() * 1e-3)).unzip();
            let expected = DVector::from_column_slice(&a).dot(&DVector::from_column_slice(&b));
            assert_eq!(nalgebra_dot(&a, &b).to_bits(), expected.to_bits(), "n = {n}");
        }
    }

    /// A sparse mass is refactorised when one of its nonzero entries changes or it turns dense with
    /// other bits, and its solves are then the new matrix's; the same entries keep the factor.
    #[test]
    fn a_sparse_mass_is_refactorised_when_its_entries_change() {
        let mut m = DMatrix::from_fn(5, 5, |i, j| if i == j { 2.0 + i as f64 } else { 0.0 });
        (m[(0, 4)], m[(4, 0)]) = (0.5, 0.5);
        let b = [1.0, -2.0, 0.5, 3.0, -1.0];
        let solve = |solver: &mut MassSolver, mass: Mass<'_>| {
            let mut x = [0.0; 5];
            solver.solve(mass, &b, &mut x);
            x
        };
        let fresh = |mass: Mass<'_>| solve(&mut MassSolver::default(), mass);
        let mut solver = MassSolver::default();
        let entries = SparseColumns::of(&m);
        let first = solve(&mut solver, Mass::Sparse(&m, &entries));
        assert_eq!(first, fresh(Mass::Sparse(&m, &entries)));
        assert_eq!(solve(&mut solver, Mass::Sparse(&m, &entries)), first);
        let mut changed = m.clone();
        (changed[(0, 4)], changed[(4, 0)]) = (0.25, 0.25);
        let changed_entries = SparseColumns::of(&changed);
        let second = solve(&mut solver, Mass::Sparse(&changed, &changed_entries));
        assert_ne!(second, first);
        assert_eq!(second, fresh(Mass::Sparse(&changed, &changed_entries)));
        changed[(2, 2)] = 7.0;
        assert_eq!(solve(&mut solver, Mass::Dense(&changed)), fresh(Mass::Dense(&changed)));
        assert_eq!(solve(&mut solver, Mass::Sparse(&m, &entries)), first);
    }

    #[test]
    fn matrices_are_the_same_only_with_the_same_bits() {
        assert!(same_bits(&[1.0, 2.5], &[1.0, 2.5]));
        assert!(!same_bits(&[1.0, 2.5], &[1.0, 2.5000000000000004]));
        assert!(!same_bits(&[0.0], &[-0.0]));
        assert!(!same_bits(&[1.0], &[1.0, 1.0]));
        assert!(same_bits(&[], &[]));
    }
}
