//! Factorised iteration matrices J = c_M·M + c_C·C_t + c_K·K_t and what the integrators cache with
//! them, keyed by step size and the model's factorisation key.
//!
//! Which factorisation is chosen from the size and fill of J and from whether it will be reused, by
//! the cross-overs `windrive bench solvers` measures on block-sparse Jacobians of 6-DOF bodies
//! (docs/PERFORMANCE.md):
//! - reused (linear and piecewise-linear systems, cached per step size and contact pattern), where
//!   solves dominate: up to 64 DOFs J⁻¹ kept explicitly (its matrix–vector product is 1.7–3.4×
//!   faster than two triangular solves; the torsional models have 2–20 DOFs), sparse LU (faer) from
//!   128 DOFs at most 20 % fill (its solves are 1.4× faster than dense from 126 DOFs);
//! - refactorised every Newton iteration (smoothly nonlinear systems), where factorising dominates:
//!   never the inverse (4–6× dearer to form than LU), sparse LU from 192 DOFs (factorise + solve
//!   break even with dense there, 4× faster at 288);
//! - otherwise dense LU; or, where the integrator is asked for it ([`Solver::new_with`]: the gearbox
//!   FMU's `linear_solver = sparse`), LU on J's own sparsity pattern ([`pattern_lu`](super::pattern_lu))
//!   when its elimination takes at most half dense LU's multiply–adds (from [`PATTERN_MIN_DOFS`]).

use super::lu::DenseLu;
use super::pattern_lu::{Ordering, PatternLu, pattern};
use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use nalgebra::DMatrix;
use std::sync::Arc;

/// Up to this many DOFs a reused J is inverted explicitly.
pub const EXPLICIT_INVERSE_LIMIT: usize = 64;
/// From this many DOFs a sparse enough reused J is factorised by sparse LU.
pub const SPARSE_MIN_DOFS: usize = 128;
/// From this many DOFs a sparse enough J factorised for one solve is factorised by sparse LU.
pub const SPARSE_MIN_DOFS_ONCE: usize = 192;
/// Largest fraction of non-zero entries for sparse LU.
pub const SPARSE_MAX_FILL: f64 = 0.2;
/// From this many DOFs a J that would go to dense LU goes to LU on its own pattern when that
/// pattern's elimination takes at most half the multiply–adds.
pub const PATTERN_MIN_DOFS: usize = 48;

/// Step sizes this close share one factorisation. Masters that accumulate time pass step sizes that
/// differ in the last bits ((n+1)·h − n·h); treating them as one keeps results independent of that
/// noise and avoids refactorising. The time error it implies is below 1e-15 of a step.
const SAME_STEP: f64 = 1e-12;

pub fn same_step(a: f64, b: f64) -> bool {
    (a - b).abs() <= SAME_STEP * a.abs()
}

/// Entries kept before the cache is emptied (contact patterns of a long run with backlash).
const CACHE_LIMIT: usize = 64;

pub enum Solver {
    /// J⁻¹, column-major: Δ += Σ_j r_j·(column j) vectorises, a row-by-row dot product would not.
    Inverse(Vec<f64>),
    /// Ours: nalgebra's arithmetic in vectorised column loops (`lu.rs`).
    Lu(DenseLu),
    /// On J's own sparsity pattern, without row exchanges (`pattern_lu.rs`).
    Pattern(PatternLu),
    /// Boxed: faer's factors are several hundred bytes inline, the other kinds a pointer or two.
    SparseLu(Box<faer::sparse::linalg::solvers::Lu<usize, f64>>),
}

/// The factorisation `Solver::new` picks for J of `n` DOFs with `nonzeros` non-zero entries.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Inverse,
    DenseLu,
    SparseLu,
    PatternLu,
}

impl Kind {
    /// For J of `n` DOFs with `nonzeros` non-zero entries, `reused` for many solves or not.
    pub fn for_matrix(n: usize, nonzeros: usize, reused: bool) -> Self {
        let sparse = nonzeros as f64 <= SPARSE_MAX_FILL * (n * n) as f64;
        let sparse_from = if reused { SPARSE_MIN_DOFS } else { SPARSE_MIN_DOFS_ONCE };
        if reused && n <= EXPLICIT_INVERSE_LIMIT {
            Self::Inverse
        } else if sparse && n >= sparse_from {
            Self::SparseLu
        } else {
            Self::DenseLu
        }
    }
}

/// The [`Ordering`] for every non-zero pattern J has had so far, and the elimination's zeroed
/// scratch. A J whose pattern is inside the ordering's is factorised on it; one with an entry outside
/// gets a new ordering for the union of both patterns. In a gearbox the roller sets' entries are exact
/// zeros while a set carries no load, so J's own pattern changes with the loads, but within the
/// first pattern's: d-shutdown-6dof's first 20 s make two orderings (an ordering of J's own pattern
/// at each factorisation, 1912 in its first 14 s, cost 5 % of the gearbox's instructions).
/// Which patterns came first decides the ordering, and the ordering the factors' rounding: history,
/// kept and dropped with the factorisations ([`super::alpha::AlphaIntegrator::forget_factorisations`]).
#[derive(Default)]
pub struct Orderings {
    last: Option<Arc<Ordering>>,
    scratch: Vec<f64>,
}

impl Orderings {
    /// An ordering whose pattern holds J's, the kept one when it does.
    pub fn of(&mut self, j: &DMatrix<f64>) -> Arc<Ordering> {
        let mut pattern = pattern(j);
        match &self.last {
            Some(o) if o.covers(&pattern) => o.clone(),
            last => {
                if let Some(o) = last {
                    o.add_pattern_to(&mut pattern);
                }
                let o = Arc::new(Ordering::new(j.nrows(), pattern));
                self.last = Some(o.clone());
                o
            }
        }
    }
}

/// J's non-zero entries, counted from [`SPARSE_MIN_DOFS`] only (no kind below decides by them); the
/// storage slice: a contiguous loop, not nalgebra's strided element iterator.
fn nonzeros(j: &DMatrix<f64>) -> usize {
    let n = j.nrows();
    if n >= SPARSE_MIN_DOFS {
        j.as_slice().iter().filter(|x| **x != 0.0).count()
    } else {
        n * n
    }
}

impl Solver {
    /// Factorises J with the kind its size, fill and reuse call for; None when it is singular.
    pub fn new(j: DMatrix<f64>, reused: bool) -> Option<Self> {
        let kind = Kind::for_matrix(j.nrows(), nonzeros(&j), reused);
        Self::with_kind(j, kind)
    }

    /// [`Self::new`], but where it would choose dense LU (from [`PATTERN_MIN_DOFS`]), LU on J's own
    /// pattern, ordered by `orderings` (which an integrator keeps from one factorisation to the next),
    /// when that ordering needs at most half the multiply–adds; dense LU still when the pattern's
    /// elimination is refused (an unstable pivot).
    pub fn new_with(j: DMatrix<f64>, reused: bool, orderings: &mut Orderings) -> Option<Self> {
        let n = j.nrows();
        let kind = Kind::for_matrix(n, nonzeros(&j), reused);
        if kind == Kind::DenseLu && n >= PATTERN_MIN_DOFS {
            let ordering = orderings.of(&j);
            if 2 * ordering.flops() <= ordering.dense_flops()
                && let Some(s) = Self::on_pattern(&j, ordering, orderings)
            {
                return Some(s);
            }
        }
        Self::with_kind(j, kind)
    }

    /// Factorises J as `kind` says (the benchmark compares the kinds on one matrix).
    pub fn with_kind(j: DMatrix<f64>, kind: Kind) -> Option<Self> {
        let n = j.nrows();
        match kind {
            Kind::Inverse => {
                let inv = j.try_inverse()?;
                inv.iter()
                    .all(|x| x.is_finite())
                    .then(|| Self::Inverse(inv.as_slice().to_vec()))
            }
            Kind::DenseLu => DenseLu::new(j).map(Self::Lu),
            Kind::PatternLu => {
                let mut orderings = Orderings::default();
                let ordering = orderings.of(&j);
                Self::on_pattern(&j, ordering, &mut orderings)
            }
            Kind::SparseLu => {
                let mut triplets = Vec::new();
                for c in 0..n {
                    for r in 0..n {
                        let x = j[(r, c)];
                        if x != 0.0 {
                            triplets.push(Triplet::new(r, c, x));
                        }
                    }
                }
                let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &triplets).ok()?;
                let lu = a.sp_lu().ok()?;
                // faer reports no singularity for a numerically singular J: probe with a solve
                let mut probe = faer::Mat::<f64>::from_fn(n, 1, |_, _| 1.0);
                lu.solve_in_place(probe.as_mut());
                (0..n)
                    .all(|i| probe[(i, 0)].is_finite())
                    .then(|| Self::SparseLu(Box::new(lu)))
            }
        }
    }

    /// LU on `ordering` (from `orderings`, for J's pattern), with their scratch; None where refused.
    pub fn on_pattern(j: &DMatrix<f64>, ordering: Arc<Ordering>, orderings: &mut Orderings) -> Option<Self> {
        PatternLu::new(j, ordering, &mut orderings.scratch).map(Self::Pattern)
    }

    /// x += J⁻¹·r
    pub fn add_solution(&self, r: &[f64], x: &mut [f64]) {
        match self {
            Self::Inverse(inv) => {
                let n = x.len();
                for (column, ri) in inv.chunks_exact(n).zip(r) {
                    for (xi, a) in x.iter_mut().zip(column) {
                        *xi += a * ri;
                    }
                }
            }
            Self::Lu(lu) => {
                let mut b = r.to_vec();
                lu.solve_in_place(&mut b);
                for (xi, bi) in x.iter_mut().zip(&b) {
                    *xi += bi;
                }
            }
            Self::Pattern(lu) => lu.add_solution(r, x),
            Self::SparseLu(lu) => {
                let mut b = faer::Mat::<f64>::from_fn(r.len(), 1, |i, _| r[i]);
                lu.solve_in_place(b.as_mut());
                for (i, xi) in x.iter_mut().enumerate() {
                    *xi += b[(i, 0)];
                }
            }
        }
    }

    pub fn kind(&self) -> Kind {
        match self {
            Self::Inverse(_) => Kind::Inverse,
            Self::Lu(_) => Kind::DenseLu,
            Self::Pattern(_) => Kind::PatternLu,
            Self::SparseLu(_) => Kind::SparseLu,
        }
    }

    /// J⁻¹ e_dof, the response to a unit force on one DOF.
    pub fn unit_response(&self, n: usize, dof: usize) -> Vec<f64> {
        let mut e = vec![0.0; n];
        e[dof] = 1.0;
        let mut x = vec![0.0; n];
        self.add_solution(&e, &mut x);
        x
    }
}

/// One cached factorisation.
pub struct Factor {
    pub key: Vec<u64>,
    /// The step size the matrices were built for.
    pub h: f64,
    pub solver: Solver,
    /// J⁻¹ e_f for the friction DOF, when the system has one.
    pub friction_response: Option<(usize, Vec<f64>)>,
    /// Linear systems only: Δ = W·[x; v; a; u] + (friction), W = [W_q | W_v | W_a | J⁻¹B] (n × (3n +
    /// inputs), column-major, rows padded to `padded(n)`; J⁻¹B the response to each unit input):
    /// one product replaces the force sweep and the solve.
    pub step_map: Option<Vec<f64>>,
}

/// A small cache of factorisations; the last hit is tried first.
#[derive(Default)]
pub struct Cache {
    entries: Vec<Factor>,
    last: usize,
}

/// Key equality without calling memcmp for empty keys: glibc's AVX-512 memcmp reads a zero-length
/// slice at the dangling address of an empty Vec with a masked load, and the fault suppression of
/// that load costs a microcode assist (measured: a third of a linear step's time).
pub fn same_key(a: &[u64], b: &[u64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x == y)
}

impl Cache {
    #[inline]
    pub fn find(&mut self, key: &[u64], h: f64) -> Option<usize> {
        if let Some(f) = self.entries.get(self.last)
            && same_step(f.h, h)
            && same_key(&f.key, key)
        {
            return Some(self.last);
        }
        let i = self
            .entries
            .iter()
            .position(|f| same_step(f.h, h) && same_key(&f.key, key))?;
        self.last = i;
        Some(i)
    }

    pub fn insert(&mut self, f: Factor) -> usize {
        if self.entries.len() >= CACHE_LIMIT {
            self.entries.clear();
        }
        self.entries.push(f);
        self.last = self.entries.len() - 1;
        self.last
    }

    /// Whether `i` names an entry (the cache is emptied when full).
    pub fn holds(&self, i: usize) -> bool {
        i < self.entries.len()
    }

    pub fn get(&self, i: usize) -> &Factor {
        &self.entries[i]
    }

    pub fn get_mut(&mut self, i: usize) -> &mut Factor {
        &mut self.entries[i]
    }
}

/// Rows of the step map are padded to a multiple of this (one SSE2 register holds two f64).
pub const LANES: usize = 2;

pub fn padded(n: usize) -> usize {
    n.div_ceil(LANES) * LANES
}

/// y += Σ A_k·x_k for column-major blocks A_k whose columns have y.len() rows (a multiple of
/// LANES): every column of every block is accumulated into registers holding all of y at once
/// (register blocking), so y is loaded and stored once per step. On x86_64 this uses AVX where the CPU
/// has it (checked at run time; four rows per register) and SSE2 otherwise (part of the x86_64
/// baseline, so the FMU still runs on every x86_64 CPU); elsewhere it is plain Rust. Every path adds
/// the same products in the same order without fused multiply–adds: the result is the same to the bit.
pub fn axpy_columns<const B: usize>(blocks: [(&[f64], &[f64]); B], y: &mut [f64]) {
    columns::<false, B>(blocks, y)
}

/// y = Σ A_k·x_k, the sum [`axpy_columns`] accumulates into a zeroed y, to the bit: the registers
/// start at +0.0 instead of loading y, and y need not be zeroed first (a linear step's increment).
pub fn set_columns<const B: usize>(blocks: [(&[f64], &[f64]); B], y: &mut [f64]) {
    columns::<true, B>(blocks, y)
}

/// [`axpy_columns`] (`FROM_ZERO` false) or [`set_columns`] (true).
fn columns<const FROM_ZERO: bool, const B: usize>(blocks: [(&[f64], &[f64]); B], y: &mut [f64]) {
    let rows = y.len();
    assert!(rows.is_multiple_of(LANES));
    for (a, x) in blocks {
        assert_eq!(a.len(), rows * x.len());
    }
    #[cfg(target_arch = "x86_64")]
    {
        // SAFETY (all arms): the asserts above guarantee every block holds rows × x.len() values and
        // y holds rows values; the kernels read and write exactly those, and the AVX kernels run only
        // on a CPU that has AVX.
        if std::arch::is_x86_feature_detected!("avx") {
            match rows / 2 {
                1 => return unsafe { avx_kernel::<0, 1, FROM_ZERO, B>(blocks, y) },
                2 => return unsafe { avx_kernel::<1, 0, FROM_ZERO, B>(blocks, y) },
                3 => return unsafe { avx_kernel::<1, 1, FROM_ZERO, B>(blocks, y) },
                4 => return unsafe { avx_kernel::<2, 0, FROM_ZERO, B>(blocks, y) },
                5 => return unsafe { avx_kernel::<2, 1, FROM_ZERO, B>(blocks, y) },
                6 => return unsafe { avx_kernel::<3, 0, FROM_ZERO, B>(blocks, y) },
                7 => return unsafe { avx_kernel::<3, 1, FROM_ZERO, B>(blocks, y) },
                8 => return unsafe { avx_kernel::<4, 0, FROM_ZERO, B>(blocks, y) },
                _ => {}
            }
        }
        if let Some(()) = sse2_columns::<FROM_ZERO, B>(blocks, y) {
            return;
        }
    }
    plain_columns::<FROM_ZERO, B>(blocks, y)
}

/// [`columns`] in plain Rust: the order of operations every kernel keeps.
fn plain_columns<const FROM_ZERO: bool, const B: usize>(blocks: [(&[f64], &[f64]); B], y: &mut [f64]) {
    if FROM_ZERO {
        y.fill(0.0);
    }
    let rows = y.len();
    for (a, x) in blocks {
        for (column, &s) in a.chunks_exact(rows).zip(x) {
            for (yi, ai) in y.iter_mut().zip(column) {
                *yi += ai * s;
            }
        }
    }
}

/// [`columns`] with SSE2 for up to 16 rows; None (nothing done) for more.
#[cfg(target_arch = "x86_64")]
fn sse2_columns<const FROM_ZERO: bool, const B: usize>(blocks: [(&[f64], &[f64]); B], y: &mut [f64]) -> Option<()> {
    let rows = y.len();
    assert!(rows.is_multiple_of(LANES));
    for (a, x) in blocks {
        assert_eq!(a.len(), rows * x.len());
    }
    // SAFETY (all arms): checked just above, as in `columns`.
    match rows / 2 {
        1 => unsafe { sse2_kernel::<1, FROM_ZERO, B>(blocks, y) },
        2 => unsafe { sse2_kernel::<2, FROM_ZERO, B>(blocks, y) },
        3 => unsafe { sse2_kernel::<3, FROM_ZERO, B>(blocks, y) },
        4 => unsafe { sse2_kernel::<4, FROM_ZERO, B>(blocks, y) },
        5 => unsafe { sse2_kernel::<5, FROM_ZERO, B>(blocks, y) },
        6 => unsafe { sse2_kernel::<6, FROM_ZERO, B>(blocks, y) },
        7 => unsafe { sse2_kernel::<7, FROM_ZERO, B>(blocks, y) },
        8 => unsafe { sse2_kernel::<8, FROM_ZERO, B>(blocks, y) },
        _ => return None,
    }
    Some(())
}

/// [`columns`] for 2·P rows held in P SSE2 registers, which start from y or (`FROM_ZERO`) from +0.0.
///
/// # Safety
/// `y` has 2·P entries and every block's matrix has 2·P × x.len() entries.
#[cfg(target_arch = "x86_64")]
unsafe fn sse2_kernel<const P: usize, const FROM_ZERO: bool, const B: usize>(
    blocks: [(&[f64], &[f64]); B],
    y: &mut [f64],
) {
    use std::arch::x86_64::{
        __m128d, _mm_add_pd, _mm_loadu_pd, _mm_mul_pd, _mm_set1_pd, _mm_setzero_pd, _mm_storeu_pd,
    };
    unsafe {
        let out = y.as_mut_ptr();
        let start = |k: usize| {
            if FROM_ZERO {
                _mm_setzero_pd()
            } else {
                _mm_loadu_pd(out.add(2 * k))
            }
        };
        let mut acc: [__m128d; P] = std::array::from_fn(start);
        for (a, x) in blocks {
            let mut column = a.as_ptr();
            for &s in x {
                let sv = _mm_set1_pd(s);
                for (k, r) in acc.iter_mut().enumerate() {
                    *r = _mm_add_pd(*r, _mm_mul_pd(_mm_loadu_pd(column.add(2 * k)), sv));
                }
                column = column.add(2 * P);
            }
        }
        for (k, r) in acc.iter().enumerate() {
            _mm_storeu_pd(out.add(2 * k), *r);
        }
    }
}

/// [`columns`] for 4·Q + 2·R rows (R = 0 or 1) held in Q AVX registers and R SSE register, which
/// start from y or (`FROM_ZERO`) from +0.0: half the multiplies and adds of the SSE2 kernel for the
/// same products.
///
/// # Safety
/// The CPU has AVX; `y` has 4·Q + 2·R entries and every block's matrix has that many × x.len() entries.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
unsafe fn avx_kernel<const Q: usize, const R: usize, const FROM_ZERO: bool, const B: usize>(
    blocks: [(&[f64], &[f64]); B],
    y: &mut [f64],
) {
    use std::arch::x86_64::{
        __m128d, __m256d, _mm_add_pd, _mm_loadu_pd, _mm_mul_pd, _mm_set1_pd, _mm_setzero_pd, _mm_storeu_pd,
        _mm256_add_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_set1_pd, _mm256_setzero_pd, _mm256_storeu_pd,
    };
    unsafe {
        let out = y.as_mut_ptr();
        let rows = 4 * Q + 2 * R;
        let start = |k: usize| {
            if FROM_ZERO {
                _mm256_setzero_pd()
            } else {
                _mm256_loadu_pd(out.add(4 * k))
            }
        };
        let start_tail = |_| {
            if FROM_ZERO {
                _mm_setzero_pd()
            } else {
                _mm_loadu_pd(out.add(4 * Q))
            }
        };
        let mut acc: [__m256d; Q] = std::array::from_fn(start);
        let mut tail: [__m128d; R] = std::array::from_fn(start_tail);
        for (a, x) in blocks {
            let mut column = a.as_ptr();
            for &s in x {
                let sv = _mm256_set1_pd(s);
                for (k, r) in acc.iter_mut().enumerate() {
                    *r = _mm256_add_pd(*r, _mm256_mul_pd(_mm256_loadu_pd(column.add(4 * k)), sv));
                }
                for r in tail.iter_mut() {
                    *r = _mm_add_pd(*r, _mm_mul_pd(_mm_loadu_pd(column.add(4 * Q)), _mm_set1_pd(s)));
                }
                column = column.add(rows);
            }
        }
        for (k, r) in acc.iter().enumerate() {
            _mm256_storeu_pd(out.add(4 * k), *r);
        }
        for r in tail.iter() {
            _mm_storeu_pd(out.add(4 * Q), *r);
        }
    }
}

/// A reference iteration matrix shaped like a multibody gearbox's: `bodies` 6×6 blocks, each coupled to the next and
/// to body 0 (a carrier), symmetric and diagonally dominant (seeded).
pub fn block_sparse(bodies: usize, seed: u64) -> DMatrix<f64> {
    let n = 6 * bodies;
    let mut j = DMatrix::zeros(n, n);
    let mut seed = seed;
    let mut rand = move || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut couple = |j: &mut DMatrix<f64>, a: usize, b: usize, w: f64| {
        for i in 0..6 {
            for k in 0..6 {
                let v = w * rand();
                j[(6 * a + i, 6 * b + k)] -= v;
                j[(6 * b + k, 6 * a + i)] -= v;
                j[(6 * a + i, 6 * a + i)] += v;
                j[(6 * b + k, 6 * b + k)] += v;
            }
        }
    };
    for b in 1..bodies {
        couple(&mut j, b - 1, b, 1.0);
        if b > 1 {
            couple(&mut j, 0, b, 0.3);
        }
    }
    for i in 0..n {
        j[(i, i)] += 10.0;
    }
    j
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DVector;

    /// Every kind solves alike at both sides of each cross-over, checked by the residual, and the
    /// automatic choice follows size and fill.
    #[test]
    fn every_kind_solves_alike() {
        for bodies in [1, 11, 12, 30] {
            let j = block_sparse(bodies, 7);
            let n = j.nrows();
            let r: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
            for kind in [Kind::Inverse, Kind::DenseLu, Kind::SparseLu, Kind::PatternLu] {
                let mut x = vec![0.0; n];
                Solver::with_kind(j.clone(), kind).unwrap().add_solution(&r, &mut x);
                let res = &j * DVector::from_column_slice(&x) - DVector::from_column_slice(&r);
                assert!(
                    res.amax() < 1e-12 * n as f64,
                    "n = {n}, {kind:?}: residual {}",
                    res.amax()
                );
            }
        }
        let kind = |bodies, reused| Solver::new(block_sparse(bodies, 1), reused).unwrap().kind();
        let with_pattern = |bodies, reused| {
            Solver::new_with(block_sparse(bodies, 1), reused, &mut Orderings::default())
                .unwrap()
                .kind()
        };
        assert_eq!(kind(10, true), Kind::Inverse); // 60 DOFs
        assert_eq!(kind(10, false), Kind::DenseLu);
        assert_eq!(with_pattern(10, true), Kind::Inverse);
        assert_eq!(with_pattern(10, false), Kind::PatternLu);
        assert_eq!(kind(12, true), Kind::DenseLu); // 72 DOFs
        assert_eq!(with_pattern(12, true), Kind::PatternLu);
        assert_eq!(kind(30, true), Kind::SparseLu); // 180 DOFs, 10 % fill
        assert_eq!(with_pattern(30, true), Kind::SparseLu);
        assert_eq!(kind(30, false), Kind::DenseLu);
        assert_eq!(with_pattern(30, false), Kind::PatternLu);
        // a full J of 72 DOFs: its pattern saves nothing, dense LU
        let full = DMatrix::from_fn(72, 72, |r, c| if r == c { 100.0 } else { 1.0 / (1 + r + c) as f64 });
        assert_eq!(
            Solver::new_with(full, true, &mut Orderings::default()).unwrap().kind(),
            Kind::DenseLu
        );
        assert_eq!(kind(40, false), Kind::SparseLu); // 240 DOFs
        assert_eq!(Kind::for_matrix(200, 200 * 200, true), Kind::DenseLu);
    }

    /// A singular J is refused by every kind.
    #[test]
    fn singular_matrices_are_refused() {
        for n in [10, 100, 200] {
            let mut j = DMatrix::<f64>::identity(n, n);
            j[(n - 1, n - 1)] = 0.0;
            for kind in [Kind::Inverse, Kind::DenseLu, Kind::SparseLu, Kind::PatternLu] {
                assert!(Solver::with_kind(j.clone(), kind).is_none(), "n = {n}, {kind:?}");
            }
        }
    }

    fn bits(x: &[f64]) -> Vec<u64> {
        x.iter().map(|v| v.to_bits()).collect()
    }

    /// Every kernel of the step-map product (AVX where the CPU has it, SSE2, plain Rust) gives the same
    /// bits for every row count, so a model's results do not depend on the CPU that runs it; started
    /// from zero, each gives what it accumulates into a zeroed y (a product of −0.0 included).
    #[test]
    fn product_kernels_agree_to_the_bit() {
        let mut seed = 3u64;
        let mut rand = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 1e3f64.powf(((seed >> 7) % 5) as f64 - 2.0)
        };
        for rows in (2..=20).step_by(2) {
            let (n1, n2) = (rows + 3, 2);
            let a1: Vec<f64> = (0..rows * n1).map(|_| rand()).collect();
            let a2: Vec<f64> = (0..rows * n2).map(|_| rand()).collect();
            let x1: Vec<f64> = (0..n1).map(|_| rand()).collect();
            let x2: Vec<f64> = (0..n2).map(|_| rand()).collect();
            let start: Vec<f64> = (0..rows).map(|_| rand()).collect();
            let blocks = [(&a1[..], &x1[..]), (&a2[..], &x2[..])];
            let mut plain = start.clone();
            plain_columns::<false, 2>(blocks, &mut plain);
            let mut dispatched = start.clone();
            axpy_columns(blocks, &mut dispatched);
            assert_eq!(plain, dispatched, "{rows} rows, dispatched kernel");
            // from zero: what the accumulating kernels give from a zeroed y, whatever y held
            let mut zeroed = vec![0.0; rows];
            plain_columns::<false, 2>(blocks, &mut zeroed);
            let mut set = start.clone();
            set_columns(blocks, &mut set);
            assert_eq!(bits(&zeroed), bits(&set), "{rows} rows, dispatched kernel from zero");
            #[cfg(target_arch = "x86_64")]
            {
                let mut sse2 = start.clone();
                if sse2_columns::<false, 2>(blocks, &mut sse2).is_some() {
                    assert_eq!(plain, sse2, "{rows} rows, SSE2");
                }
                let mut sse2_set = start.clone();
                if sse2_columns::<true, 2>(blocks, &mut sse2_set).is_some() {
                    assert_eq!(bits(&zeroed), bits(&sse2_set), "{rows} rows, SSE2 from zero");
                }
            }
        }
        // every product −0.0: from zero their sum is +0.0, as in a zeroed y, not y's −0.0
        for rows in (2..=20).step_by(2) {
            let (a, x) = (vec![0.0; rows * 3], vec![-1.0; 3]);
            let mut y = vec![-0.0; rows];
            set_columns([(&a[..], &x[..])], &mut y);
            assert!(y.iter().all(|v| v.to_bits() == 0), "{rows} rows: {y:?}");
        }
    }
}
