//! Operating hours per wind-speed bin from a Weibull or Rayleigh distribution, and the time factor
//! that scales a simulated load case to those hours (thesis Ch. 5.4 and 7.2.4).

use crate::physics::turbulence::{TurbulenceModel, iec_sigma};

/// Hours a year, as thesis Table 7.1 counts them.
pub const HOURS_PER_YEAR: f64 = 8760.0;

/// A long-term distribution of the hub-height mean wind speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WindDistribution {
    /// Rayleigh with mean speed V̄: F(v) = 1 − exp(−π/4·(v/V̄)²) (Weibull k = 2).
    Rayleigh { mean: f64 },
    /// Weibull with shape k and scale C: F(v) = 1 − exp(−(v/C)^k).
    Weibull { shape: f64, scale: f64 },
}

impl WindDistribution {
    pub fn cdf(&self, v: f64) -> f64 {
        if v <= 0.0 {
            return 0.0;
        }
        match *self {
            Self::Rayleigh { mean } => 1.0 - (-std::f64::consts::FRAC_PI_4 * (v / mean).powi(2)).exp(),
            Self::Weibull { shape, scale } => 1.0 - (-(v / scale).powf(shape)).exp(),
        }
    }

    /// Hours in each bin (v − width, v] of `total_hours`, for bins named by their upper edge
    /// (the convention that reproduces thesis Table 7.1).
    pub fn hours_per_bin(&self, upper_edges: &[f64], width: f64, total_hours: f64) -> Vec<f64> {
        upper_edges
            .iter()
            .map(|&v| total_hours * (self.cdf(v) - self.cdf(v - width)))
            .collect()
    }
}

/// One DLC 1.2 wind bin: simulated at `speed`, standing for the hub-height wind in [lo, hi].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct WindBin {
    pub speed: f64,
    pub lo: f64,
    pub hi: f64,
    /// Of the hub-height wind lying in [lo, hi].
    pub probability: f64,
}

/// A DLC 1.2 bin as a campaign weighs it: its hours in the design life and the IEC normal turbulence
/// model's intensity σ1 / V_hub at its speed.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Dlc12Bin {
    #[serde(flatten)]
    pub bin: WindBin,
    pub hours: f64,
    pub ntm_turbulence_intensity: f64,
}

impl WindDistribution {
    /// [`Self::dlc_bins`] with each bin's hours over `years` (8760 h a year) and the NTM intensity of the
    /// IEC turbulence class with reference intensity `i_ref` (A 0.16, B 0.14, C 0.12).
    pub fn dlc12_bins(&self, cut_in: f64, cut_out: f64, width: f64, years: f64, i_ref: f64) -> Vec<Dlc12Bin> {
        self.dlc_bins(cut_in, cut_out, width)
            .into_iter()
            .map(|bin| Dlc12Bin {
                hours: bin.probability * HOURS_PER_YEAR * years,
                ntm_turbulence_intensity: iec_sigma(TurbulenceModel::Ntm, bin.speed, i_ref, 50.0) / bin.speed,
                bin,
            })
            .collect()
    }

    /// The DLC 1.2 bins of a campaign: speeds cut_in, cut_in + w, cut_in + 2w, … (w = `width`); bin j
    /// covers [v_j − w/2, v_j + w/2] clipped to [cut_in, cut_out], so the bins tile cut-in to cut-out
    /// and their probabilities add up to F(cut_out) − F(cut_in). A last bin cut short by cut_out is
    /// simulated at cut_out, never above it.
    pub fn dlc_bins(&self, cut_in: f64, cut_out: f64, width: f64) -> Vec<WindBin> {
        let mut edges = vec![cut_in];
        let mut e = cut_in + width / 2.0;
        while e < cut_out - 1e-9 * width {
            // no sliver bin from rounding
            edges.push(e);
            e += width;
        }
        edges.push(cut_out);
        edges
            .windows(2)
            .enumerate()
            .map(|(j, lh)| WindBin {
                speed: (cut_in + j as f64 * width).min(cut_out),
                lo: lh[0],
                hi: lh[1],
                probability: self.cdf(lh[1]) - self.cdf(lh[0]),
            })
            .collect()
    }
}

/// Scales a simulated load case to real time: hours · 3600 / simulated seconds.
pub fn time_factor(hours: f64, simulated_seconds: f64) -> f64 {
    hours * 3600.0 / simulated_seconds
}

#[cfg(test)]
mod tests {
    /// 4 to 25 m/s in 2 m/s bins: 4 (4–5), 6 (5–7), …, 24 (23–25): eleven bins that tile the range,
    /// their probabilities adding up to F(25) − F(4); a cut-out of 23.5 simulates the last bin at 23.5.
    #[test]
    fn dlc_bins_tile_cut_in_to_cut_out() {
        let w = super::WindDistribution::Weibull {
            shape: 2.0,
            scale: 11.0,
        };
        let bins = w.dlc_bins(4.0, 25.0, 2.0);
        assert_eq!(bins.len(), 11);
        assert_eq!((bins[0].speed, bins[0].lo, bins[0].hi), (4.0, 4.0, 5.0));
        assert_eq!((bins[10].speed, bins[10].lo, bins[10].hi), (24.0, 23.0, 25.0));
        let total: f64 = bins.iter().map(|b| b.probability).sum();
        approx::assert_relative_eq!(total, w.cdf(25.0) - w.cdf(4.0), max_relative = 1e-12);
        assert!(bins.windows(2).all(|p| p[0].hi == p[1].lo));
        assert_eq!(w.dlc_bins(4.0, 23.5, 2.0).last().unwrap().speed, 23.5);
    }

    use super::*;

    /// Thesis Table 7.1 (20 years = 175 200 h, cut-in 4, cut-out 25 m/s): a Rayleigh distribution with
    /// mean 10.0 m/s and bins (v − 1, v] reproduces every bin to the table's rounding (whole hours,
    /// so within 0.6 h), and the 161 950 h in operation to 0.05 %.
    #[test]
    fn rayleigh_10_m_s_reproduces_thesis_table_7_1() {
        let table = [
            (4, 8733.0),
            (5, 10545.0),
            (6, 11916.0),
            (7, 12817.0),
            (8, 13251.0),
            (9, 13247.0),
            (10, 12856.0),
            (11, 12146.0),
            (12, 11194.0),
            (13, 10080.0),
            (14, 8878.0),
            (15, 7655.0),
            (16, 6467.0),
            (17, 5356.0),
            (18, 4351.0),
            (19, 3468.0),
            (20, 2713.0),
            (21, 2084.0),
            (22, 1573.0),
            (23, 1165.0),
            (24, 848.0),
            (25, 607.0),
        ];
        let edges: Vec<f64> = table.iter().map(|(v, _)| *v as f64).collect();
        let hours = WindDistribution::Rayleigh { mean: 10.0 }.hours_per_bin(&edges, 1.0, 175_200.0);
        for ((v, expected), h) in table.iter().zip(&hours) {
            assert!((h - expected).abs() < 0.6, "{v} m/s: {h:.2} h vs {expected} h");
        }
        let total: f64 = hours.iter().sum();
        assert!((total / 161_950.0 - 1.0).abs() < 5e-4, "{total}");
        // the table's time factor for 8 m/s over a 20 s simulation: 2 385 178
        assert!((time_factor(13251.0, 20.0) / 2_385_178.0 - 1.0).abs() < 1e-4);
    }

    /// The bins tile the operating range: their sum is the hours between cut-in and cut-out, and a
    /// Rayleigh is the Weibull with k = 2, C = 2 V̄ / √π.
    #[test]
    fn bins_add_up_and_rayleigh_is_weibull_2() {
        let weibull = WindDistribution::Weibull {
            shape: 2.0,
            scale: 2.0 * 8.5 / std::f64::consts::PI.sqrt(),
        };
        let rayleigh = WindDistribution::Rayleigh { mean: 8.5 };
        let edges: Vec<f64> = (4..=25).map(f64::from).collect();
        let sum: f64 = weibull.hours_per_bin(&edges, 1.0, 1000.0).iter().sum();
        assert!((sum - 1000.0 * (weibull.cdf(25.0) - weibull.cdf(3.0))).abs() < 1e-9);
        for v in [1.0, 5.0, 12.5, 30.0] {
            assert!((weibull.cdf(v) - rayleigh.cdf(v)).abs() < 1e-14);
        }
    }
}
