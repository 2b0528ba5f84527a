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
