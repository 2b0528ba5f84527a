//! Sparse rows: how one scalar deflection (a bearing direction, a mesh slice) depends on the DOFs.

/// g with deflection δ = g·q; a few (index, coefficient) pairs, indices unique.
///
/// The entries are private so that `reach` always bounds them: the products read the vectors
/// without a bounds check per entry once `reach` is checked against their lengths (the two checks
/// per entry were a third of the instructions of a sparse row's product, and the rows' products a
/// seventh of the 6-DOF gearbox's step with lamina bearings, a quarter with linear ones, callgrind).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Row {
    idx: Vec<usize>,
    val: Vec<f64>,
    /// One past the largest index (0 for an empty row): the shortest vector the row may read.
    reach: usize,
}

impl Row {
    pub fn add(&mut self, i: usize, v: f64) {
        if v == 0.0 {
            return;
        }
        match self.idx.iter().position(|&j| j == i) {
            Some(k) => self.val[k] += v,
            None => self.push(i, v),
        }
    }

    /// A new entry (index not yet in the row), zero or not.
    fn push(&mut self, i: usize, v: f64) {
        self.idx.push(i);
        self.val.push(v);
        self.reach = self.reach.max(i + 1);
    }

    /// The entries' indices, in the order they were added.
    pub fn indices(&self) -> &[usize] {
        &self.idx
    }

    /// The entries' coefficients, in the order of [`Self::indices`].
    pub fn values(&self) -> &[f64] {
        &self.val
    }

    /// (index, coefficient) of each entry in order.
    pub fn entries(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.idx.iter().copied().zip(self.val.iter().copied())
    }

    /// Every coefficient times `c`.
    pub fn scale(&mut self, c: f64) {
        self.val.iter_mut().for_each(|v| *v *= c);
    }

    /// The row's entries in lockstep; panics if a vector of length `len` is too short for the row,
    /// after which every index is below `len`.
    #[inline(always)]
    fn checked(&self, len: usize) -> (&[usize], &[f64]) {
        assert!(
            self.reach <= len,
            "a row reaching index {} read from a vector of {len}",
            self.reach - 1
        );
        let n = self.idx.len();
        (&self.idx[..n], &self.val[..n])
    }

    pub fn dot(&self, x: &[f64]) -> f64 {
        let (idx, val) = self.checked(x.len());
        // SAFETY: every index is below `reach` (kept by `push` and `compact`), `reach` <= x.len() (checked)
        idx.iter()
            .zip(val)
            .map(|(&i, v)| v * unsafe { *x.get_unchecked(i) })
            .sum()
    }

    /// (g·q, g·v) in one pass over the row: each sum [`Self::dot`]'s, term by term in the same order
    /// from the same start, so the same bits. A force reads a deflection and its rate together, and
    /// a pass per vector read the row's indices and coefficients twice (the rows' products and sums were
    /// about a quarter of a force evaluation with linear bearings, callgrind).
    #[inline]
    pub fn dot2(&self, q: &[f64], v: &[f64]) -> (f64, f64) {
        let (idx, val) = self.checked(q.len().min(v.len()));
        // where `dot`'s `sum` starts (the standard library's neutral element of a float sum: −0.0)
        let start: f64 = std::iter::empty::<f64>().sum();
        idx.iter().zip(val).fold((start, start), |(sq, sv), (&i, c)| {
            // SAFETY: every index is below `reach` <= both lengths (checked)
            let (qi, vi) = unsafe { (*q.get_unchecked(i), *v.get_unchecked(i)) };
            (sq + c * qi, sv + c * vi)
        })
    }

    /// out += c·g
    pub fn axpy(&self, c: f64, out: &mut [f64]) {
        let (idx, val) = self.checked(out.len());
        for (&i, v) in idx.iter().zip(val) {
            // SAFETY: every index is below `reach` <= out.len() (checked)
            unsafe { *out.get_unchecked_mut(i) += c * v };
        }
    }

    pub fn is_empty(&self) -> bool {
        self.idx.is_empty()
    }

    /// Drops coefficients that cancelled (a carrier's spin against its own frame).
    pub fn compact(&mut self) {
        let mut k = 0;
        while k < self.idx.len() {
            if self.val[k].abs() < 1e-300 {
                self.idx.swap_remove(k);
                self.val.swap_remove(k);
            } else {
                k += 1;
            }
        }
        self.reach = self.idx.iter().map(|&i| i + 1).max().unwrap_or(0);
    }
}

/// j += c·(a·bᵀ + b·aᵀ)/2·2 = c·(a bᵀ + b aᵀ) when `a` ≠ `b`; c·a aᵀ when the same row is passed twice.
pub fn add_outer(j: &mut nalgebra::DMatrix<f64>, c: f64, a: &Row, b: &Row) {
    if c == 0.0 {
        return;
    }
    for (ia, va) in a.entries() {
        for (ib, vb) in b.entries() {
            j[(ia, ib)] += c * va * vb;
        }
    }
}

/// j += c·(a bᵀ + b aᵀ)
pub fn add_symmetric(j: &mut nalgebra::DMatrix<f64>, c: f64, a: &Row, b: &Row) {
    add_outer(j, c, a, b);
    add_outer(j, c, b, a);
}

#[cfg(test)]
mod tests {
    use super::Row;
    use crate::xorshift::Xorshift;

    /// `dot2` is two `dot`s to the bit: rows of 0–13 entries with magnitudes over twenty decades, zeros of
    /// both signs in the vectors (an empty row's sum and a row of −0 products keep `dot`'s sign).
    #[test]
    fn one_pass_over_a_row_is_two_dots_to_the_bit() {
        let mut rng = Xorshift::new(11);
        let value = |rng: &mut Xorshift| match (rng.unit() * 8.0) as u32 {
            0 => 0.0,
            1 => -0.0,
            _ => rng.symmetric() * 10f64.powi((rng.unit() * 20.0) as i32 - 10),
        };
        for _ in 0..2000 {
            let n = 30;
            let q: Vec<f64> = (0..n).map(|_| value(&mut rng)).collect();
            let v: Vec<f64> = (0..n).map(|_| value(&mut rng)).collect();
            let mut row = Row::default();
            for _ in 0..(rng.unit() * 14.0) as usize {
                let i = (rng.unit() * n as f64) as usize % n;
                if !row.idx.contains(&i) {
                    row.push(i, value(&mut rng));
                }
            }
            let (dq, dv) = row.dot2(&q, &v);
            assert_eq!(
                (dq.to_bits(), dv.to_bits()),
                (row.dot(&q).to_bits(), row.dot(&v).to_bits()),
                "{row:?}"
            );
        }
        let empty = Row::default();
        assert_eq!(empty.dot2(&[1.0], &[1.0]).0.to_bits(), empty.dot(&[1.0]).to_bits());
    }
}
