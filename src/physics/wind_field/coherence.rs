//! The IEC 61400-1 ed. 3 exponential coherence of u (Eq. B.16) on a regular grid.
//!
//! Coh(r, f) = exp(−12·√((f·r/V)² + (0.12·r/L_c)²)) = exp(−12·c(f)·r), c(f) = √((f/V)² + (0.12/L_c)²):
//! an exponential kernel in the distance, positive definite for distinct points in the plane, so its
//! matrix has a Cholesky factor at every frequency. On a regular grid the distance between two points
//! depends only on their offset (|Δj|, |Δk|), so a frequency needs ny·nz exponentials, not (ny·nz)².

use crate::physics::turbulence::iec_coherence;
use faer::Mat;

/// The distances of a grid's point offsets, for filling its coherence matrices.
#[derive(Debug, Clone)]
pub struct GridOffsets {
    ny: usize,
    nz: usize,
    /// distance of offset (|Δj|, |Δk|) at index |Δk|·ny + |Δj|
    distance: Vec<f64>,
}

impl GridOffsets {
    pub fn new(ny: usize, nz: usize, dy: f64, dz: f64) -> Self {
        let distance = (0..nz)
            .flat_map(|dk| (0..ny).map(move |dj| ((dj as f64 * dy).powi(2) + (dk as f64 * dz).powi(2)).sqrt()))
            .collect();
        Self { ny, nz, distance }
    }

    /// The coherence matrix at `f` Hz over the points in order p = k·ny + j (lower triangle filled:
    /// the Cholesky factorisation reads no more).
    pub fn matrix(&self, f: f64, v_hub: f64, coherence_length: f64) -> Mat<f64> {
        let table: Vec<f64> = self
            .distance
            .iter()
            .map(|&r| iec_coherence(f, r, v_hub, coherence_length))
            .collect();
        let (ny, n) = (self.ny, self.ny * self.nz);
        Mat::from_fn(n, n, |a, b| {
            if b > a {
                return 0.0;
            }
            let (ka, ja, kb, jb) = (a / ny, a % ny, b / ny, b % ny);
            table[ka.abs_diff(kb) * ny + ja.abs_diff(jb)]
        })
    }
}
