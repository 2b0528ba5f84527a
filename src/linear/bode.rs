//! Bode data of a complex frequency response: magnitude, phase and the resonance peaks, on a
//! log-spaced frequency grid.

/// `points` frequencies from `lo` to `hi` (both included), evenly spaced in log frequency.
pub fn log_spaced(lo: f64, hi: f64, points: usize) -> Vec<f64> {
    let (a, b) = (lo.ln(), hi.ln());
    (0..points)
        .map(|i| (a + (b - a) * i as f64 / (points.max(2) - 1) as f64).exp())
        .collect()
}

#[derive(Debug, Clone, PartialEq)]
pub struct Bode {
    pub frequency_hz: Vec<f64>,
    pub magnitude: Vec<f64>,
    pub phase_deg: Vec<f64>,
}

impl Bode {
    /// From the complex response (re, im) at each frequency.
    pub fn new(frequency_hz: Vec<f64>, response: &[(f64, f64)]) -> Self {
        Self {
            frequency_hz,
            magnitude: response.iter().map(|(a, b)| a.hypot(*b)).collect(),
            phase_deg: response.iter().map(|(a, b)| b.atan2(*a).to_degrees()).collect(),
        }
    }

    /// Indices of the resonance peaks: local maxima of the magnitude.
    pub fn peaks(&self) -> Vec<usize> {
        let m = &self.magnitude;
        (1..m.len().saturating_sub(1))
            .filter(|&i| m[i] > m[i - 1] && m[i] >= m[i + 1])
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A single-DOF oscillator 1/(k − ω²m + jωc) peaks at its natural frequency with phase −90°.
    #[test]
    fn one_resonance_at_the_natural_frequency() {
        let f = log_spaced(0.1, 10.0, 2001);
        assert!((f[0] - 0.1).abs() < 1e-15 && (f[2000] - 10.0).abs() < 1e-12);
        let (k, m, c) = (4.0 * std::f64::consts::PI.powi(2), 1.0, 0.05);
        let h: Vec<(f64, f64)> = f
            .iter()
            .map(|f| {
                let w = std::f64::consts::TAU * f;
                let (re, im) = (k - w * w * m, w * c);
                let d = re * re + im * im;
                (re / d, -im / d)
            })
            .collect();
        let b = Bode::new(f, &h);
        let p = b.peaks();
        assert_eq!(p.len(), 1);
        assert!((b.frequency_hz[p[0]] - 1.0).abs() < 3e-3, "{}", b.frequency_hz[p[0]]);
        assert!((b.phase_deg[p[0]] + 90.0).abs() < 2.0, "{}", b.phase_deg[p[0]]);
    }
}
