//! Where the rollers sit round the cage.

use std::f64::consts::TAU;

/// The rollers' places round the cage, φ_j = 2πj/z: cos φ_j and sin φ_j, each from its own
/// `sin_cos`. A quantity p·cos ψ + q·sin ψ at the rollers' angles ψ_j = ψ_c + φ_j (the cage's angle
/// ψ_c) is P·cos φ_j + Q·sin φ_j ([`Places::turned`]): two products and a sum per roller to screen it,
/// instead of a rotation carried from roller to roller (serial, and it rounds differently as it goes).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Places {
    cos: Vec<f64>,
    sin: Vec<f64>,
}

impl Places {
    pub(super) fn new(count: usize) -> Self {
        let (sin, cos) = (0..count).map(|j| (TAU * j as f64 / count as f64).sin_cos()).unzip();
        Self { cos, sin }
    }

    pub(super) fn count(&self) -> usize {
        self.cos.len()
    }

    /// (cos φ_j, sin φ_j) of every roller.
    #[inline(always)]
    pub(super) fn iter(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.cos.iter().copied().zip(self.sin.iter().copied())
    }

    /// (P, Q) of p·cos ψ + q·sin ψ with the cage at (sin ψ_c, cos ψ_c) = `cage`:
    /// P = p·cos ψ_c + q·sin ψ_c, Q = q·cos ψ_c − p·sin ψ_c.
    #[inline(always)]
    pub(super) fn turned((p, q): (f64, f64), (sc, cc): (f64, f64)) -> (f64, f64) {
        (p * cc + q * sc, q * cc - p * sc)
    }

    /// (cos ψ_j, sin ψ_j) of the roller at (cos φ_j, sin φ_j) with the cage at (sin ψ_c, cos ψ_c).
    #[inline(always)]
    pub(super) fn unit((c, s): (f64, f64), (sc, cc): (f64, f64)) -> (f64, f64) {
        (cc * c - sc * s, sc * c + cc * s)
    }
}
