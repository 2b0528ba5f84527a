//! Sparse rows: how one scalar deflection (a bearing direction, a mesh slice) depends on the DOFs.

/// g with deflection δ = g·q; a few (index, coefficient) pairs, indices unique.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Row {
    pub idx: Vec<usize>,
    pub val: Vec<f64>,
}

impl Row {
    pub fn add(&mut self, i: usize, v: f64) {
        if v == 0.0 {
            return;
        }
        match self.idx.iter().position(|&j| j == i) {
            Some(k) => self.val[k] += v,
            None => {
                self.idx.push(i);
                self.val.push(v);
            }
        }
    }

    pub fn dot(&self, x: &[f64]) -> f64 {
        self.idx.iter().zip(&self.val).map(|(&i, v)| v * x[i]).sum()
    }

    /// (g·q, g·v) in one pass over the row: each sum [`Self::dot`]'s, term by term in the same order
    /// from the same start, so the same bits. A force reads a deflection and its rate together, and
    /// a pass per vector read the row's indices and coefficients twice (the rows' products and sums were
    /// about a quarter of a force evaluation with linear bearings, callgrind).
    #[inline]
    pub fn dot2(&self, q: &[f64], v: &[f64]) -> (f64, f64) {
        // where `dot`'s `sum` starts (the standard library's neutral element of a float sum: −0.0)
        let start: f64 = std::iter::empty::<f64>().sum();
        self.idx
            .iter()
            .zip(&self.val)
            .fold((start, start), |(sq, sv), (&i, c)| (sq + c * q[i], sv + c * v[i]))
    }

    /// out += c·g
    pub fn axpy(&self, c: f64, out: &mut [f64]) {
        for (&i, v) in self.idx.iter().zip(&self.val) {
            out[i] += c * v;
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
    }
}

/// j += c·(a·bᵀ + b·aᵀ)/2·2 = c·(a bᵀ + b aᵀ) when `a` ≠ `b`; c·a aᵀ when the same row is passed twice.
pub fn add_outer(j: &mut nalgebra::DMatrix<f64>, c: f64, a: &Row, b: &Row) {
    if c == 0.0 {
        return;
    }
    for (&ia, va) in a.idx.iter().zip(&a.val) {
        for (&ib, vb) in b.idx.iter().zip(&b.val) {
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
                    row.idx.push(i);
                    row.val.push(value(&mut rng));
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
