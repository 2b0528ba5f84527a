//! Damage-equivalent load: the constant-amplitude range that, repeated N_eq = f_eq · T times, does the
//! damage of the counted cycles under a Wöhler curve of slope m (Palmgren–Miner):
//! DEL = (Σ n_i S_i^m / N_eq)^(1/m).

use crate::analysis::fatigue::rainflow::{Counter, Cycle};
use crate::analysis::signal::series::{Extent, SeriesError, stream_channel};
use std::path::Path;

/// Σ n_i S_i^m for several Wöhler slopes, accumulated one cycle at a time, so a streaming count
/// needs no cycle list.
#[derive(Debug, Clone)]
pub struct DamageSums {
    slopes: Vec<f64>,
    sums: Vec<f64>,
    /// When every slope is a whole number up to 16 (3, 6, 9, ...): (multiplications since the
    /// previous slope, slope index, running sum) in ascending slope order, so one run of
    /// multiplications S, S², S³, ... serves all slopes (powi per slope costs 10 % more instructions
    /// over the whole count, powf far more).
    whole: Option<Vec<(u32, usize, f64)>>,
}

impl DamageSums {
    pub fn new(slopes: &[f64]) -> Self {
        let whole = slopes
            .iter()
            .all(|&m| m.fract() == 0.0 && (1.0..=16.0).contains(&m))
            .then(|| {
                let mut order: Vec<usize> = (0..slopes.len()).collect();
                order.sort_by(|&a, &b| slopes[a].total_cmp(&slopes[b]));
                let mut previous = 0;
                order
                    .into_iter()
                    .map(|i| {
                        let m = slopes[i] as u32;
                        let steps = m - previous;
                        previous = m;
                        (steps, i, 0.0)
                    })
                    .collect()
            });
        Self {
            slopes: slopes.to_vec(),
            sums: vec![0.0; slopes.len()],
            whole,
        }
    }

    #[inline]
    pub fn add(&mut self, c: &Cycle) {
        match &mut self.whole {
            Some(terms) => {
                let mut p = 1.0;
                for (steps, _, sum) in terms.iter_mut() {
                    for _ in 0..*steps {
                        p *= c.range;
                    }
                    *sum += c.count * p;
                }
            }
            None => {
                for (sum, &m) in self.sums.iter_mut().zip(&self.slopes) {
                    *sum += c.count * c.range.powf(m);
                }
            }
        }
    }

    /// Σ n_i S_i^m per slope, in the order the slopes were given.
    pub fn sums(&self) -> Vec<f64> {
        let mut sums = self.sums.clone();
        for &(_, i, sum) in self.whole.iter().flatten() {
            sums[i] = sum;
        }
        sums
    }

    /// One DEL per slope, for N_eq equivalent cycles.
    pub fn dels(&self, equivalent_cycles: f64) -> Vec<f64> {
        self.sums()
            .iter()
            .zip(&self.slopes)
            .map(|(sum, m)| (sum / equivalent_cycles).powf(1.0 / m))
            .collect()
    }
}

/// Goodman mean-stress correction as in MLife (Hayman 2012): the range that does the same damage at
/// the fixed mean L_MF as `c.range` at its own mean, L_RF = L_R·(L_ult − |L_MF|)/(L_ult − |L_M|).
/// Errors when a cycle's mean reaches the ultimate load (the correction is undefined there).
pub fn goodman(c: &Cycle, ultimate: f64, fixed_mean: f64) -> Result<Cycle, String> {
    if c.mean.abs() >= ultimate {
        return Err(format!(
            "a cycle's mean {} reaches the ultimate load {ultimate}: Goodman's correction is undefined",
            c.mean
        ));
    }
    Ok(Cycle {
        range: c.range * (ultimate - fixed_mean.abs()) / (ultimate - c.mean.abs()),
        mean: fixed_mean,
        ..*c
    })
}

pub fn damage_equivalent_load(cycles: &[Cycle], m: f64, equivalent_cycles: f64) -> f64 {
    let mut sums = DamageSums::new(&[m]);
    cycles.iter().for_each(|c| sums.add(c));
    sums.dels(equivalent_cycles)[0]
}

/// The damage sums at the slopes `m` of one CSV channel, counted in one streaming pass from the file
/// (no series, no cycle list), each cycle first Goodman-corrected to `goodman_to` = (ultimate load,
/// fixed mean) when given; with the channel's extent, and why the correction refused its first cycle.
pub fn stream_damage(
    path: &Path,
    channel: &str,
    m: &[f64],
    goodman_to: Option<(f64, f64)>,
) -> Result<(DamageSums, Extent, Option<String>), SeriesError> {
    let mut sums = DamageSums::new(m);
    let mut counter = Counter::new();
    let mut bad = None;
    let mut add = |c: Cycle| match goodman_to {
        None => sums.add(&c),
        Some((ultimate, fixed_mean)) => match goodman(&c, ultimate, fixed_mean) {
            Ok(c) => sums.add(&c),
            Err(e) => bad = bad.take().or(Some(e)),
        },
    };
    let extent = stream_channel(path, channel, |_, v| counter.push(v, &mut add))?;
    counter.finish(&mut add);
    Ok((sums, extent, bad))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::fatigue::rainflow::cycles;

    /// MLife's Goodman correction: a cycle at mean 0 with fixed mean 0 is unchanged; at mean L_ult/2
    /// it counts double; the DEL then follows the corrected ranges.
    #[test]
    fn goodman_correction() {
        let c = Cycle {
            range: 10.0,
            mean: 50.0,
            count: 1.0,
            start: 0,
            end: 1,
        };
        assert_eq!(goodman(&Cycle { mean: 0.0, ..c }, 100.0, 0.0).unwrap().range, 10.0);
        assert!((goodman(&c, 100.0, 0.0).unwrap().range - 20.0).abs() < 1e-12);
        assert!((goodman(&c, 100.0, 50.0).unwrap().range - 10.0).abs() < 1e-12);
        assert!(
            goodman(&Cycle { mean: -100.0, ..c }, 100.0, 0.0)
                .unwrap_err()
                .contains("ultimate")
        );
    }

    /// Both accumulation paths equal the direct formula Σ n S^m to 1e-12.
    #[test]
    fn streamed_sums_equal_the_direct_formula() {
        let series: Vec<f64> = (0..5000)
            .map(|i| (i as f64 * 0.37).sin() * (1.0 + (i % 7) as f64))
            .collect();
        let c = cycles(&series);
        for slopes in [vec![9.0, 3.0, 6.0], vec![3.5, 6.0]] {
            let mut sums = DamageSums::new(&slopes);
            c.iter().for_each(|x| sums.add(x));
            for (del, m) in sums.dels(100.0).iter().zip(&slopes) {
                let direct = (c.iter().map(|x| x.count * x.range.powf(*m)).sum::<f64>() / 100.0).powf(1.0 / m);
                assert!((del / direct - 1.0).abs() < 1e-12, "m = {m}: {del} vs {direct}");
            }
        }
    }
}
