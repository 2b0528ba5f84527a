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
            Mass::Dense(m) => {
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
            Mass::Dense(m) => m.nrows(),
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
    use super::add_dense_product;

    /// The vectorised product gives what the entry-by-entry sum in column order gives, to the bit.
    #[test]
    fn a_dense_product_on_wide_vectors_keeps_the_bits() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
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
}
