//! Dense LU with partial pivoting for iteration matrices factorised about once a step: the 6-DOF
//! gearbox with roller sets (84 DOFs) changes its contact pattern every step, and nalgebra's LU,
//! which walks its generic strided views one scalar at a time, took 23 % of the GRC shutdown's
//! instructions (callgrind, docs/PERFORMANCE.md).
//!
//! The arithmetic is nalgebra's `LU::new` and `LU::solve_mut`, operation for operation: the pivot is
//! the first entry of largest magnitude, the column below it is scaled by the pivot's reciprocal,
//! every update is y + (−u)·l, the lower solve divides by its unit diagonal, the upper solve by U's.
//! So the factors and solutions are identical to the bit (tests below), and the gearbox's results do
//! not move. What changes is the shape: every update is a contiguous column loop the compiler
//! vectorises, with AVX where the CPU has it (picked at run time) and SSE2 otherwise; Rust never
//! fuses a multiply and an add, so both give the same bits.

use nalgebra::DMatrix;

/// P·J = L·U of a square J, column-major: L below the diagonal (its unit diagonal implied), U on
/// and above it.
#[derive(Debug, Clone)]
pub struct DenseLu {
    n: usize,
    lu: Vec<f64>,
    /// Step i swapped rows i and `pivots[i]`.
    pivots: Vec<usize>,
}

impl DenseLu {
    /// Factorises `j`; None when a pivot is zero (J singular).
    pub fn new(j: DMatrix<f64>) -> Option<Self> {
        let n = j.nrows();
        assert_eq!(n, j.ncols(), "LU of a non-square matrix");
        let mut lu = j.as_slice().to_vec();
        let pivots = factorise(&mut lu, n)?;
        Some(Self { n, lu, pivots })
    }

    /// b ← J⁻¹·b
    pub fn solve_in_place(&self, b: &mut [f64]) {
        assert_eq!(b.len(), self.n);
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx") {
            // SAFETY: the CPU has AVX.
            return unsafe { self.substitute_avx(b) };
        }
        self.substitute(b)
    }

    /// `substitute` compiled for AVX.
    ///
    /// # Safety
    /// The CPU has AVX.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn substitute_avx(&self, b: &mut [f64]) {
        self.substitute(b)
    }

    /// The row swaps, then forward substitution with L and back substitution with U, column by column.
    #[inline(always)]
    fn substitute(&self, b: &mut [f64]) {
        let n = self.n;
        for (i, &p) in self.pivots.iter().enumerate() {
            b.swap(i, p);
        }
        for i in 0..n.saturating_sub(1) {
            // nalgebra divides by the unit diagonal: exact, left out
            let coeff = b[i];
            axpy(-coeff, &self.lu[i * n + i + 1..(i + 1) * n], &mut b[i + 1..]);
        }
        for i in (0..n).rev() {
            let coeff = b[i] / self.lu[i * n + i];
            b[i] = coeff;
            axpy(-coeff, &self.lu[i * n..i * n + i], &mut b[..i]);
        }
    }
}

/// Factorises the column-major n×n `a` in place; the pivot rows, or None at a zero pivot.
fn factorise(a: &mut [f64], n: usize) -> Option<Vec<usize>> {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the CPU has AVX.
        return unsafe { factorise_avx(a, n) };
    }
    eliminate(a, n)
}

/// `eliminate` compiled for AVX.
///
/// # Safety
/// The CPU has AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
unsafe fn factorise_avx(a: &mut [f64], n: usize) -> Option<Vec<usize>> {
    eliminate(a, n)
}

/// Gaussian elimination with partial pivoting, right-looking: per column, pivot, swap the whole
/// rows, scale L's column, and update the columns to its right by y + (−u)·l, four at a time.
#[inline(always)]
fn eliminate(a: &mut [f64], n: usize) -> Option<Vec<usize>> {
    let mut pivots = Vec::with_capacity(n);
    for i in 0..n {
        let piv = i + first_largest(&a[i * n + i..(i + 1) * n]);
        let diag = a[i * n + piv];
        if diag == 0.0 {
            return None;
        }
        if piv != i {
            for column in a.chunks_exact_mut(n) {
                column.swap(i, piv);
            }
        }
        pivots.push(piv);
        let inv_diag = 1.0 / diag;
        for x in &mut a[i * n + i + 1..(i + 1) * n] {
            *x *= inv_diag;
        }
        let (left, right) = a.split_at_mut((i + 1) * n);
        let l = &left[i * n + i + 1..];
        let mut quads = right.chunks_exact_mut(4 * n);
        for quad in &mut quads {
            update_four(l, i, n, quad);
        }
        for column in quads.into_remainder().chunks_exact_mut(n) {
            let u = column[i];
            axpy(-u, l, &mut column[i + 1..]);
        }
    }
    Some(pivots)
}

/// The elimination's update of four adjacent columns (`quad`, 4·n entries) below row i: L's column
/// is loaded once for four columns instead of once per column. Each entry gets the same y + (−u)·l
/// as in `axpy`.
#[inline(always)]
fn update_four(l: &[f64], i: usize, n: usize, quad: &mut [f64]) {
    let (c0, rest) = quad.split_at_mut(n);
    let (c1, rest) = rest.split_at_mut(n);
    let (c2, c3) = rest.split_at_mut(n);
    let a = [-c0[i], -c1[i], -c2[i], -c3[i]];
    let rows = c0[i + 1..]
        .iter_mut()
        .zip(&mut c1[i + 1..])
        .zip(&mut c2[i + 1..])
        .zip(&mut c3[i + 1..])
        .zip(l);
    for ((((y0, y1), y2), y3), lk) in rows {
        *y0 += a[0] * lk;
        *y1 += a[1] * lk;
        *y2 += a[2] * lk;
        *y3 += a[3] * lk;
    }
}

/// Index of the first entry of largest magnitude (nalgebra's `icamax`: a NaN is never picked after the first entry).
#[inline(always)]
fn first_largest(x: &[f64]) -> usize {
    let mut best = (0, x[0].abs());
    for (i, v) in x.iter().enumerate().skip(1) {
        if v.abs() > best.1 {
            best = (i, v.abs());
        }
    }
    best.0
}

/// y ← y + a·x, element by element (nalgebra's a·x·1 + 1·y, the same bits).
#[inline(always)]
fn axpy(a: f64, x: &[f64], y: &mut [f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += a * xi;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DVector;

    /// A seeded matrix whose entries span six decades, so pivoting happens at most columns.
    fn random(n: usize, seed: u64) -> DMatrix<f64> {
        let mut s = seed;
        DMatrix::from_fn(n, n, |_, _| {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 10f64.powi(((s >> 7) % 7) as i32 - 3)
        })
    }

    /// Factors, pivots and solutions equal nalgebra's to the bit, on the dispatched path (AVX where
    /// the CPU has it) and the baseline one, at sizes around the gearbox's.
    #[test]
    fn identical_to_nalgebra_to_the_bit() {
        for (n, seed) in [(1, 1), (2, 2), (7, 3), (30, 4), (84, 5), (85, 6), (130, 7)] {
            let j = random(n, seed);
            let reference = j.clone().lu();
            let ours = DenseLu::new(j.clone()).unwrap();
            assert_eq!(ours.lu, reference.lu_internal().as_slice(), "n = {n}: factors");
            let mut baseline = j.as_slice().to_vec();
            assert_eq!(eliminate(&mut baseline, n).unwrap(), ours.pivots, "n = {n}: pivots");
            assert_eq!(baseline, ours.lu, "n = {n}: baseline path");
            let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
            let mut expected = DVector::from_column_slice(&b);
            assert!(reference.solve_mut(&mut expected));
            let mut x = b.clone();
            ours.solve_in_place(&mut x);
            assert_eq!(x, expected.as_slice(), "n = {n}: solution");
            let mut x = b.clone();
            ours.substitute(&mut x);
            assert_eq!(x, expected.as_slice(), "n = {n}: baseline solution");
        }
    }

    /// P·J = L·U: the residual of a solve is at the rounding level.
    #[test]
    fn solves_to_rounding() {
        for (n, seed) in [(5, 11), (84, 12), (200, 13)] {
            let j = random(n, seed) + DMatrix::identity(n, n) * (1e3 * n as f64);
            let b: Vec<f64> = (0..n).map(|i| 1.0 + (i as f64).cos()).collect();
            let mut x = b.clone();
            DenseLu::new(j.clone()).unwrap().solve_in_place(&mut x);
            let residual = &j * DVector::from_column_slice(&x) - DVector::from_column_slice(&b);
            assert!(
                residual.amax() < 1e-10 * n as f64,
                "n = {n}: residual {}",
                residual.amax()
            );
        }
    }

    /// A zero column leaves no pivot: refused.
    #[test]
    fn singular_is_refused() {
        let mut j = random(20, 9);
        j.column_mut(13).fill(0.0);
        assert!(DenseLu::new(j).is_none());
    }
}
