//! The three components' Kaimal spectra of IEC 61400-1 ed. 3 Annex B.2 (Table B.1):
//! S_k(f) = 4σ_k²(L_k/V) / (1 + 6fL_k/V)^(5/3), the same at every point of the grid.

use crate::physics::turbulence::{kaimal, scale_parameter};

/// One component's spectrum: its standard deviation and integral scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ComponentSpectrum {
    pub sigma: f64,
    pub length: f64,
}

impl ComponentSpectrum {
    /// One-sided density at `f` Hz for mean wind `v_hub`, (m/s)²/Hz.
    pub fn density(&self, f: f64, v_hub: f64) -> f64 {
        kaimal(f, self.sigma, self.length, v_hub)
    }
}

/// u, v and w for σ1 = `sigma` at hub height `hub_height`: σ_v = 0.8σ1, σ_w = 0.5σ1;
/// L_u = 8.1Λ1, L_v = 2.7Λ1, L_w = 0.66Λ1.
pub fn iec_kaimal(sigma: f64, hub_height: f64) -> [ComponentSpectrum; 3] {
    let lambda = scale_parameter(hub_height);
    [(1.0, 8.1), (0.8, 2.7), (0.5, 0.66)].map(|(s, l)| ComponentSpectrum {
        sigma: s * sigma,
        length: l * lambda,
    })
}

/// The coherence scale L_c = 8.1Λ1 (IEC 61400-1 ed. 3 Eq. B.16).
pub fn coherence_length(hub_height: f64) -> f64 {
    8.1 * scale_parameter(hub_height)
}
