//! The contract every integrated model implements: a second-order system
//!
//! ```text
//! M(q)·a + f_int(t, q, v) = B·u(t) + e_f·T_friction
//! ```
//!
//! with the external loads linear in the model's inputs `u` (the master sets those), and at most one
//! Coulomb friction contact on a DOF whose force T is set-valued (stick: whatever holds the DOF at
//! rest up to the static capacity; slip: the kinetic capacity against the motion). The integrators
//! in this module are written once against [`SecondOrderSystem`]; a model only states its physics.

use nalgebra::DMatrix;

/// How the tangent Jacobian depends on the state: it decides how much Newton work a step needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Linearity {
    /// Constant M, C, K: one linear solve per step, and a cached step map when the step size repeats.
    Linear,
    /// Linear within each pattern named by [`SecondOrderSystem::factor_key`] (contacts open or shut,
    /// single or double tooth contact): the Newton iteration has converged exactly when the pattern
    /// at the new iterate is the pattern the Jacobian was built for.
    PiecewiseLinear,
    /// Piecewise linear as above, plus small smooth terms the tangent leaves out (a rotating frame's
    /// Coriolis and centripetal forces, gyroscopic moments, gravity turning with a carrier): the
    /// pattern's cached Jacobian is reused (modified Newton), converged when the pattern repeats and
    /// the increment is small.
    NearlyPiecewiseLinear,
    /// Smoothly nonlinear (Hertzian contacts): converged when the increment and the residual are
    /// small; the Jacobian is assembled at each iterate.
    Nonlinear,
}

/// The mass matrix, in the form the model has it.
#[derive(Debug, Clone, Copy)]
pub enum Mass<'a> {
    /// Lumped inertias: a mass solve is a division.
    Diagonal(&'a [f64]),
    /// Full (6×6 body blocks): symmetric positive definite.
    Dense(&'a DMatrix<f64>),
    /// Symmetric positive definite and mostly zeros (the 6-DOF gearbox: six inertias a body and its
    /// planets' orbits coupled to their carriers' spin, 94 of 7056 entries for the GRC): products and
    /// solves visit the nonzero entries alone, in the dense loops' order, so they give the dense loops'
    /// bits (a skipped product is ±0, which changes no sum but the sign of an exact zero).
    Sparse(&'a DMatrix<f64>, &'a SparseColumns),
}

/// The nonzero entries of a matrix column after column, rows ascending.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SparseColumns {
    /// Column j's entries are `entries[start[j]..start[j + 1]]`.
    start: Vec<usize>,
    entries: Vec<(usize, f64)>,
    /// Each entry's column, beside `entries`: a product over all of them walks one list instead of
    /// slicing the entries column after column (most of the GRC's 84 mass columns hold one entry, and
    /// the slicing was two thirds of a product's instructions, callgrind).
    columns: Vec<usize>,
}

impl SparseColumns {
    /// The nonzero entries of `m` in rows `rows(j)` of each column j.
    fn select(m: &DMatrix<f64>, rows: impl Fn(usize) -> std::ops::Range<usize>) -> Self {
        let mut start = vec![0];
        let mut entries = Vec::new();
        let mut columns = Vec::new();
        for j in 0..m.ncols() {
            entries.extend(rows(j).map(|i| (i, m[(i, j)])).filter(|&(_, v)| v != 0.0));
            start.push(entries.len());
            columns.resize(entries.len(), j);
        }
        SparseColumns {
            start,
            entries,
            columns,
        }
    }

    /// Every entry as (row, column, value), column after column, rows ascending.
    pub fn each_entry(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        self.entries.iter().zip(&self.columns).map(|(&(i, v), &j)| (i, j, v))
    }

    /// Every nonzero entry of `m`.
    pub fn of(m: &DMatrix<f64>) -> Self {
        Self::select(m, |_| 0..m.nrows())
    }

    /// The nonzero entries of `l` strictly below its diagonal (a Cholesky factor's, whose upper part
    /// holds what the factorisation left there).
    pub fn below_diagonal(l: &DMatrix<f64>) -> Self {
        Self::select(l, |j| j + 1..l.nrows())
    }

    /// Column j's (row, value) pairs, rows ascending.
    pub fn column(&self, j: usize) -> &[(usize, f64)] {
        &self.entries[self.start[j]..self.start[j + 1]]
    }

    pub fn nonzeros(&self) -> usize {
        self.entries.len()
    }
}

/// y += c·M·x for a dense M stored column after column, on the CPU's widest vectors (AVX where it has
/// it): every entry of y takes the same products in the same order either way, so the same bits.
/// A Newton iteration's residual takes one such product (84 DOFs: 7056 entries).
fn add_dense_product(m: &[f64], c: f64, x: &[f64], y: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the CPU has AVX.
        return unsafe { add_dense_product_avx(m, c, x, y) };
    }
    add_dense_columns(m, c, x, y)
}

/// [`add_dense_columns`] compiled for AVX.
///
/// # Safety
/// The CPU has AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
unsafe fn add_dense_product_avx(m: &[f64], c: f64, x: &[f64], y: &mut [f64]) {
    add_dense_columns(m, c, x, y)
}

/// Column by column over the storage, not m[(i, j)] with its bounds check per entry.
#[inline(always)]
fn add_dense_columns(m: &[f64], c: f64, x: &[f64], y: &mut [f64]) {
    if y.is_empty() {
        return;
    }
    for (column, xj) in m.chunks_exact(y.len()).zip(x) {
        for (yi, mij) in y.iter_mut().zip(column) {
            *yi += c * mij * xj;
        }
    }
}

impl Mass<'_> {
    /// y += c·M·x
    pub fn add_product(&self, c: f64, x: &[f64], y: &mut [f64]) {
        match self {
            Mass::Diagonal(m) => {
                for ((yi, mi), xi) in y.iter_mut().zip(*m).zip(x) {
                    *yi += c * mi * xi;
                }
            }
            Mass::Dense(m) => {
                assert_eq!((m.nrows(), m.ncols()), (y.len(), x.len()));
                add_dense_product(m.as_slice(), c, x, y);
            }
            Mass::Sparse(m, columns) => {
                assert_eq!((m.nrows(), m.ncols()), (y.len(), x.len()));
                // column after column as the dense loop, the same c·m_ij·x_j
                for (i, j, mij) in columns.each_entry() {
                    y[i] += c * mij * x[j];
                }
            }
        }
    }

    /// j += c·M
    pub fn add_to(&self, c: f64, j: &mut DMatrix<f64>) {
        match self {
            Mass::Diagonal(m) => {
                for (i, mi) in m.iter().enumerate() {
                    j[(i, i)] += c * mi;
                }
            }
            // in place: `*j += *m * c` built the product as a temporary matrix every factorisation
            Mass::Dense(m) | Mass::Sparse(m, _) => {
                assert_eq!(j.shape(), m.shape());
                for (x, mi) in j.as_mut_slice().iter_mut().zip(m.as_slice()) {
                    *x += mi * c;
                }
            }
        }
    }

    pub fn to_matrix(&self) -> DMatrix<f64> {
        let n = match self {
            Mass::Diagonal(m) => m.len(),
            Mass::Dense(m) | Mass::Sparse(m, _) => m.nrows(),
        };
        let mut j = DMatrix::zeros(n, n);
        self.add_to(1.0, &mut j);
        j
    }
}

/// Input `input` acts on DOF `dof` with `gain`: f_ext[dof] += gain·u[input].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct InputLoad {
    pub input: usize,
    pub dof: usize,
    pub gain: f64,
}

/// A Coulomb friction contact between DOF `dof` and the ground at one instant (the HSS brake disk).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Friction {
    pub dof: usize,
    /// Kinetic capacity while slipping, ≥ 0 (N·m or N).
    pub kinetic: f64,
    /// What a contact that was stuck at the start of the step can hold, ≥ 0.
    pub holding: f64,
}

impl Friction {
    /// The most the contact can hold in a step that starts stuck (`locked`) or slipping.
    pub fn hold(&self, locked: bool) -> f64 {
        if locked { self.holding } else { self.kinetic }
    }
}

/// The constant-coefficient linearisation {M, C, K} about a state: what modal analysis, frequency
/// response and Campbell diagrams work on, for any model.
#[derive(Debug, Clone, PartialEq)]
pub struct Linearisation {
    pub mass: DMatrix<f64>,
    pub damping: DMatrix<f64>,
    pub stiffness: DMatrix<f64>,
}

/// A second-order system M(q)·a + f_int(t, q, v) = f_ext(t) as the integrators see it.
///
/// Implementations are plain Rust over slices; they never allocate in `internal_forces` or
/// `factor_key`, which run every step.
pub trait SecondOrderSystem {
    fn dofs(&self) -> usize;

    fn linearity(&self) -> Linearity;

    fn mass(&self) -> Mass<'_>;

    /// How the inputs load the DOFs (f_ext = B·u). Input count = 1 + the largest `input` index.
    fn input_loads(&self) -> &[InputLoad];

    /// Sets `out` to f_int(t, q, v): every elastic, damping and state-dependent force.
    fn internal_forces(&self, t: f64, q: &[f64], v: &[f64], out: &mut [f64]);

    /// Adds c_C·C_t + c_K·K_t, the tangent damping and stiffness at (t, q, v), to `j`. The
    /// integrator adds the mass term itself.
    fn add_tangent(&self, t: f64, q: &[f64], v: &[f64], c_c: f64, c_k: f64, j: &mut DMatrix<f64>);

    /// Writes into `key` a pattern that identifies the tangent at (t, q) among those already
    /// factorised (which contacts touch, which meshes are in double contact), of any length.
    /// Systems that are [`Linearity::Linear`] leave it empty.
    fn factor_key(&self, t: f64, q: &[f64], key: &mut Vec<u64>) {
        let _ = (t, q);
        key.clear();
    }

    /// The friction contact for these inputs, if any acts.
    fn friction(&self, u: &[f64]) -> Option<Friction> {
        let _ = u;
        None
    }

    /// A rigid-body mode r (K·r = 0) and the DOF it is normalised to (r[dof] = 1). The linear step
    /// then forms K·q as K·(q − r·q[dof]): absolute angles grow to thousands of radians while
    /// elastic deflections are micro-radians, and the difference keeps their digits.
    fn rigid_mode(&self) -> Option<(&[f64], usize)> {
        None
    }

    /// The linearisation about (q, v) at time 0 (t matters only for time-varying stiffness).
    fn linearise(&self, q: &[f64], v: &[f64]) -> Linearisation {
        let n = self.dofs();
        let mut damping = DMatrix::zeros(n, n);
        let mut stiffness = DMatrix::zeros(n, n);
        self.add_tangent(0.0, q, v, 1.0, 0.0, &mut damping);
        self.add_tangent(0.0, q, v, 0.0, 1.0, &mut stiffness);
        Linearisation {
            mass: self.mass().to_matrix(),
            damping,
            stiffness,
        }
    }
}

/// f_ext = B·u into `out` (overwritten).
pub fn external_forces<S: SecondOrderSystem + ?Sized>(system: &S, u: &[f64], out: &mut [f64]) {
    out.iter_mut().for_each(|x| *x = 0.0);
    for l in system.input_loads() {
        out[l.dof] += l.gain * u[l.input];
    }
}

/// Number of inputs the system reads.
pub fn input_count<S: SecondOrderSystem + ?Sized>(system: &S) -> usize {
    system.input_loads().iter().map(|l| l.input + 1).max().unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::{Mass, SparseColumns, add_dense_product};
    use nalgebra::DMatrix;

    /// The vectorised product gives what the entry-by-entry sum in column order gives, to the bit.
    #[test]
    fn a_dense_product_on_wide_vectors_keeps_the_bits() {
        let mut random = crate::xorshift::Xorshift::new(0x2545_f491_4f6c_dd1d);
        let mut next = || random.symmetric();
        for n in 1..=90 {
            let m: Vec<f64> = (0..n * n).map(|_| next() * 1e3).collect();
            let x: Vec<f64> = (0..n).map(|_| next()).collect();
            let start: Vec<f64> = (0..n).map(|_| next() * 1e-3).collect();
            let c = 0.7 + next();
            let mut fast = start.clone();
            add_dense_product(&m, c, &x, &mut fast);
            let mut plain = start.clone();
            for (j, xj) in x.iter().enumerate() {
                for (i, yi) in plain.iter_mut().enumerate() {
                    *yi += c * m[j * n + i] * xj;
                }
            }
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&fast), bits(&plain), "n = {n}");
        }
    }

    /// A sparse mass's product visits its nonzero entries alone and gives the dense product's bits
    /// (6×6 diagonal blocks and orbit couplings, as the gearbox's, and a random fifth of the entries).
    #[test]
    fn a_sparse_product_gives_the_dense_products_bits() {
        let mut random = crate::xorshift::Xorshift::new(0x9e37_79b9_7f4a_7c15);
        let mut next = move || random.symmetric();
        for n in [1, 6, 12, 84, 90] {
            for dense_fraction in [0.0, 0.2] {
                let mut m = DMatrix::from_fn(n, n, |i, j| if i == j { 1e3 * (1.0 + next().abs()) } else { 0.0 });
                for k in (0..n).step_by(6).skip(1) {
                    // a planet's translations coupled to a carrier's spin, both ways
                    let v = 50.0 * next();
                    (m[(k, 5)], m[(5.min(n - 1), k)]) = (v, v);
                }
                for i in 0..n {
                    for j in 0..n {
                        if next().abs() < dense_fraction {
                            m[(i, j)] = next();
                        }
                    }
                }
                let entries = SparseColumns::of(&m);
                assert_eq!(entries.nonzeros(), m.iter().filter(|v| **v != 0.0).count());
                let x: Vec<f64> = (0..n).map(|_| next()).collect();
                let start: Vec<f64> = (0..n).map(|_| next() * 1e-3).collect();
                let (mut dense, mut sparse) = (start.clone(), start);
                Mass::Dense(&m).add_product(-1.0, &x, &mut dense);
                Mass::Sparse(&m, &entries).add_product(-1.0, &x, &mut sparse);
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&sparse), bits(&dense), "n = {n}");
            }
        }
    }
}
