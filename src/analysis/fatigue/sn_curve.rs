//! Life and damage: S-N curves with Palmgren–Miner summation, and ISO 281 basic bearing life.

use crate::analysis::fatigue::rainflow::Cycle;

/// A Wöhler (S-N) curve N(S) = N_ref·(S_ref/S)^m, optionally with a second slope m₂ below the knee
/// (the paper's two-slope curve uses m₂ = 2m − 1, Haibach).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SnCurve {
    pub slope: f64,
    /// Stress range at the knee, and its number of cycles.
    pub knee_range: f64,
    pub knee_cycles: f64,
    /// Slope below the knee; None = single slope throughout.
    pub second_slope: Option<f64>,
}

impl SnCurve {
    /// Cycles to failure at stress range `s`.
    pub fn cycles_to_failure(&self, s: f64) -> f64 {
        let m = match self.second_slope {
            Some(m2) if s < self.knee_range => m2,
            _ => self.slope,
        };
        self.knee_cycles * (self.knee_range / s).powf(m)
    }

    /// Palmgren–Miner damage Σ n_i / N_i of counted cycles, times `scale` (e.g. hours·3600/simulated s).
    pub fn miner_damage(&self, cycles: &[Cycle], scale: f64) -> f64 {
        cycles
            .iter()
            .filter(|c| c.range > 0.0)
            .map(|c| c.count / self.cycles_to_failure(c.range))
            .sum::<f64>()
            * scale
    }
}

/// ISO 281 basic rating life L10 in millions of revolutions: (C/P)^p with p = 10/3 for roller
/// bearings and 3 for ball bearings.
pub fn bearing_l10(dynamic_capacity: f64, equivalent_load: f64, roller: bool) -> f64 {
    let p = if roller { 10.0 / 3.0 } else { 3.0 };
    (dynamic_capacity / equivalent_load).powf(p)
}

/// L10 in hours at `rpm`.
pub fn bearing_l10_hours(dynamic_capacity: f64, equivalent_load: f64, roller: bool, rpm: f64) -> f64 {
    bearing_l10(dynamic_capacity, equivalent_load, roller) * 1e6 / (60.0 * rpm)
}

/// Miner damage of a bearing over a load spectrum: Σ revolutions_i / L10(P_i) with L10 in
/// revolutions (ISO 281 basic rating life; 10 % failure probability). `spectrum` holds
/// (equivalent dynamic load P_i, revolutions at it), e.g. an LDD of the bearing load.
pub fn bearing_damage(dynamic_capacity: f64, spectrum: &[(f64, f64)], roller: bool) -> f64 {
    spectrum
        .iter()
        .filter(|(p, n)| *p > 0.0 && *n > 0.0)
        .map(|(p, n)| n / (bearing_l10(dynamic_capacity, *p, roller) * 1e6))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::fatigue::rainflow::cycles;

    /// Miner over a spectrum equals one L10 at the spectrum's equivalent load
    /// P_eq = (Σ n_i P_i^p / Σ n_i)^(1/p), the ISO 281 rule for variable load.
    #[test]
    fn bearing_miner_equals_the_equivalent_load() {
        let spectrum = [(80e3, 2e8), (120e3, 5e7), (200e3, 1e6)];
        let p = 10.0 / 3.0;
        let n: f64 = spectrum.iter().map(|s| s.1).sum();
        let p_eq = (spectrum.iter().map(|&(l, k): &(f64, f64)| k * l.powf(p)).sum::<f64>() / n).powf(1.0 / p);
        let d = bearing_damage(1.2e6, &spectrum, true);
        assert!((d / (n / (bearing_l10(1.2e6, p_eq, true) * 1e6)) - 1.0).abs() < 1e-12);
    }

    /// Thesis §7.1 (Eqs. 7.1–7.2): a UW bearing carrying 1.6× the DW load lives 1.6^(10/3) = 4.79× shorter.
    #[test]
    fn load_ratio_to_life_ratio() {
        let ratio = bearing_l10(5500e3, 100e3, true) / bearing_l10(5500e3, 160e3, true);
        assert!((ratio - 4.79).abs() < 0.005, "{ratio}");
        // ball bearings: cube law
        assert!((bearing_l10(2.0, 1.0, false) - 8.0).abs() < 1e-12);
        assert!((bearing_l10_hours(10.0, 1.0, false, 1000.0) - 1e3 * 1e6 / 60_000.0).abs() < 1e-6);
    }

    /// Miner's sum of a constant-amplitude history is n/N; the two-slope curve switches at the knee.
    #[test]
    fn miner_sum_adds_up() {
        let curve = SnCurve {
            slope: 6.0,
            knee_range: 100.0,
            knee_cycles: 1e7,
            second_slope: Some(11.0),
        };
        let history: Vec<f64> = (0..2001).map(|i| if i % 2 == 0 { 0.0 } else { 200.0 }).collect();
        let c = cycles(&history);
        let n: f64 = c.iter().map(|c| c.count).sum();
        let expected = n / (1e7 * (100.0f64 / 200.0).powi(6));
        assert!((curve.miner_damage(&c, 1.0) / expected - 1.0).abs() < 1e-12);
        assert!((curve.cycles_to_failure(50.0) / (1e7 * 2f64.powi(11)) - 1.0).abs() < 1e-12);
        assert!((curve.miner_damage(&c, 3.0) / curve.miner_damage(&c, 1.0) - 3.0).abs() < 1e-12);
    }
}
