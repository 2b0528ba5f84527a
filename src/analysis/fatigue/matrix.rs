//! Rainflow matrices: counts binned by (range, mean) or by (from, to) level, the forms load spectra
//! are exchanged in (Markov / from–to matrices of the FVA and of MLife's output).

use crate::analysis::fatigue::rainflow::Cycle;

/// `n` equal bins over [lo, hi]; values outside are put in the end bins.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bins {
    pub lo: f64,
    pub hi: f64,
    pub n: usize,
}

impl Bins {
    /// Bins spanning the values' extent (a single value gets a bin of width 1 around it).
    pub fn spanning(values: impl Iterator<Item = f64>, n: usize) -> Bins {
        let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
        let (lo, hi) = if !lo.is_finite() {
            (0.0, 1.0)
        } else if hi > lo {
            (lo, hi)
        } else {
            (lo - 0.5, hi + 0.5)
        };
        Bins { lo, hi, n: n.max(1) }
    }

    pub fn width(&self) -> f64 {
        (self.hi - self.lo) / self.n as f64
    }

    pub fn index(&self, v: f64) -> usize {
        (((v - self.lo) / self.width()).floor().max(0.0) as usize).min(self.n - 1)
    }

    pub fn centre(&self, i: usize) -> f64 {
        self.lo + (i as f64 + 0.5) * self.width()
    }
}

/// Cycle counts in rows × columns bins.
#[derive(Debug, Clone, PartialEq)]
pub struct Matrix {
    pub rows: Bins,
    pub cols: Bins,
    /// Row-major, rows.n × cols.n.
    pub counts: Vec<f64>,
}

impl Matrix {
    fn new(rows: Bins, cols: Bins) -> Self {
        Matrix {
            rows,
            cols,
            counts: vec![0.0; rows.n * cols.n],
        }
    }

    fn add(&mut self, r: f64, c: f64, count: f64) {
        let k = self.rows.index(r) * self.cols.n + self.cols.index(c);
        self.counts[k] += count;
    }

    pub fn at(&self, row: usize, col: usize) -> f64 {
        self.counts[row * self.cols.n + col]
    }

    pub fn total(&self) -> f64 {
        self.counts.iter().sum()
    }
}

/// Range (rows, from 0) × mean (columns) matrix with the given numbers of bins.
pub fn range_mean(cycles: &[Cycle], range_bins: usize, mean_bins: usize) -> Matrix {
    let max_range = cycles.iter().map(|c| c.range).fold(0.0, f64::max);
    let rows = Bins {
        lo: 0.0,
        hi: if max_range > 0.0 { max_range } else { 1.0 },
        n: range_bins.max(1),
    };
    let cols = Bins::spanning(cycles.iter().map(|c| c.mean), mean_bins);
    let mut m = Matrix::new(rows, cols);
    for c in cycles {
        m.add(c.range, c.mean, c.count);
    }
    m
}

/// From (rows) × to (columns) level matrix over the series' extent; a cycle goes from the value at
/// its first reversal to the value at its second (`series` is what was counted).
pub fn from_to(cycles: &[Cycle], series: &[f64], bins: usize) -> Matrix {
    let levels = Bins::spanning(series.iter().copied(), bins);
    let mut m = Matrix::new(levels, levels);
    for c in cycles {
        m.add(series[c.start], series[c.end], c.count);
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::fatigue::rainflow::cycles;

    /// The ASTM E1049 example (the `rainflow` package's test vector −2, 1, −3, 5, −1, 3, −4, 4, −2):
    /// ranges 3: 0.5, 4: 1.5, 6: 0.5, 8: 1.0, 9: 0.5. Nine range bins of width 1 over [0, 9] put each
    /// in its own row; counts are conserved.
    #[test]
    fn astm_example_in_a_range_mean_matrix() {
        let x = [-2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0];
        let c = cycles(&x);
        let m = range_mean(&c, 9, 1);
        let per_row: Vec<f64> = (0..9).map(|r| m.at(r, 0)).collect();
        // range r falls in bin floor(r), the maximum (9) in the last
        assert_eq!(per_row, vec![0.0, 0.0, 0.0, 0.5, 1.5, 0.0, 0.5, 0.0, 1.5]);
        assert_eq!(m.total(), c.iter().map(|c| c.count).sum::<f64>());
        let ft = from_to(&c, &x, 9);
        assert_eq!(ft.total(), m.total());
        // the 8-range cycle −4 → 4 (or 4 → −4) sits off the diagonal at the extremes
        let (lo, hi) = (ft.rows.index(-4.0), ft.rows.index(4.0));
        assert!(ft.at(lo, hi) + ft.at(hi, lo) >= 1.0);
    }
}
