//! Factorised iteration matrices J = c_M·M + c_C·C_t + c_K·K_t and what the integrators cache with
//! them, keyed by step size and the model's factorisation key.
//!
//! Small systems keep J⁻¹ explicitly: a matrix–vector product with it vectorises and is cheaper
//! than two triangular solves up to a few dozen DOFs (the torsional models have 2–20). Larger ones
//! keep the LU factors.

use nalgebra::{DMatrix, DVector};

/// Up to this many DOFs J is inverted explicitly; above it, LU-factorised.
pub const EXPLICIT_INVERSE_LIMIT: usize = 64;

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
    Lu(nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>),
}

impl Solver {
    /// Factorises J; None when it is singular.
    pub fn new(j: DMatrix<f64>) -> Option<Self> {
        if j.nrows() <= EXPLICIT_INVERSE_LIMIT {
            let inv = j.try_inverse()?;
            if inv.iter().all(|x| x.is_finite()) {
                return Some(Self::Inverse(inv.as_slice().to_vec()));
            }
            return None;
        }
        let lu = j.lu();
        lu.is_invertible().then_some(Self::Lu(lu))
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
                let mut b = DVector::from_column_slice(r);
                lu.solve_mut(&mut b);
                for (xi, bi) in x.iter_mut().zip(b.iter()) {
                    *xi += bi;
                }
            }
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
    /// J⁻¹·B, one column per input (the response to each unit input), rows padded to `padded(n)`
    /// so the step kernel takes it as one more block.
    pub input_response: Vec<f64>,
    /// J⁻¹ e_f for the friction DOF, when the system has one.
    pub friction_response: Option<(usize, Vec<f64>)>,
    /// Linear systems only: Δ = W·[x; v; a] + J⁻¹·f, W = [W_q | W_v | W_a] (n × 3n, column-major,
    /// rows padded to `padded(n)`): one product replaces the force sweep and the solve.
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

    pub fn get(&self, i: usize) -> &Factor {
        &self.entries[i]
    }

    pub fn get_mut(&mut self, i: usize) -> &mut Factor {
        &mut self.entries[i]
    }

    pub fn clear(&mut self) {
        self.entries.clear();
        self.last = 0;
    }
}

/// Rows of the step map are padded to a multiple of this (one SSE2 register holds two f64).
pub const LANES: usize = 2;

pub fn padded(n: usize) -> usize {
    n.div_ceil(LANES) * LANES
}

/// y += Σ A_k·x_k for column-major blocks A_k whose columns have y.len() rows (a multiple of
/// LANES): every column of every block is accumulated into registers holding all of y at once
/// (register blocking), so y is loaded and stored once per step. On x86_64 this uses SSE2, part of
/// the x86_64 baseline, so the FMU still runs on every x86_64 CPU; elsewhere it is plain Rust.
pub fn axpy_columns<const B: usize>(blocks: [(&[f64], &[f64]); B], y: &mut [f64]) {
    let rows = y.len();
    assert!(rows.is_multiple_of(LANES));
    for (a, x) in blocks {
        assert_eq!(a.len(), rows * x.len());
    }
    #[cfg(target_arch = "x86_64")]
    {
        // SAFETY (all arms): the asserts above guarantee every block holds rows × x.len() values and
        // y holds rows values; the kernel reads and writes exactly those.
        match rows / 2 {
            1 => return unsafe { sse2_kernel::<1, B>(blocks, y) },
            2 => return unsafe { sse2_kernel::<2, B>(blocks, y) },
            3 => return unsafe { sse2_kernel::<3, B>(blocks, y) },
            4 => return unsafe { sse2_kernel::<4, B>(blocks, y) },
            5 => return unsafe { sse2_kernel::<5, B>(blocks, y) },
            6 => return unsafe { sse2_kernel::<6, B>(blocks, y) },
            7 => return unsafe { sse2_kernel::<7, B>(blocks, y) },
            8 => return unsafe { sse2_kernel::<8, B>(blocks, y) },
            _ => {}
        }
    }
    for (a, x) in blocks {
        for (column, &s) in a.chunks_exact(rows).zip(x) {
            for (yi, ai) in y.iter_mut().zip(column) {
                *yi += ai * s;
            }
        }
    }
}

/// `axpy_columns` for 2·P rows held in P SSE2 registers.
///
/// # Safety
/// `y` has 2·P entries and every block's matrix has 2·P × x.len() entries.
#[cfg(target_arch = "x86_64")]
unsafe fn sse2_kernel<const P: usize, const B: usize>(blocks: [(&[f64], &[f64]); B], y: &mut [f64]) {
    use std::arch::x86_64::{__m128d, _mm_add_pd, _mm_loadu_pd, _mm_mul_pd, _mm_set1_pd, _mm_storeu_pd};
    unsafe {
        let out = y.as_mut_ptr();
        let mut acc: [__m128d; P] = std::array::from_fn(|k| _mm_loadu_pd(out.add(2 * k)));
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Explicit inverse and LU give the same solution (seeded SPD matrices at both sides of the
    /// cross-over), checked by the residual.
    #[test]
    fn inverse_and_lu_solve_alike() {
        let mut seed = 7u64;
        let mut rand = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for n in [3, EXPLICIT_INVERSE_LIMIT, EXPLICIT_INVERSE_LIMIT + 5] {
            let a = DMatrix::from_fn(n, n, |_, _| rand());
            let j = &a * a.transpose() + DMatrix::identity(n, n) * n as f64;
            let r: Vec<f64> = (0..n).map(|_| rand()).collect();
            let mut x = vec![0.0; n];
            Solver::new(j.clone()).unwrap().add_solution(&r, &mut x);
            let res = &j * DVector::from_column_slice(&x) - DVector::from_column_slice(&r);
            assert!(res.amax() < 1e-12 * n as f64, "n = {n}: residual {}", res.amax());
        }
    }
}
