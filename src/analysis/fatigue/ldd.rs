//! Load duration distribution (the paper's LDD, as ISO 6336-6 uses it for gear life): how long the
//! load dwelt in each load bin, and how many revolutions (load cycles of a tooth) it did there,
//! n_i = Σ_j t_j·|ω_j|/2π over the samples j of bin i.

use crate::analysis::fatigue::matrix::Bins;

#[derive(Debug, Clone, PartialEq)]
pub struct LoadDuration {
    pub bins: Bins,
    /// Seconds per bin.
    pub seconds: Vec<f64>,
    /// Revolutions per bin.
    pub revolutions: Vec<f64>,
}

/// Each sample's time step and the revolutions |ω_j|·t_j/2π turned in it (the sample holds until the
/// next one; the last gets none).
pub fn sample_revolutions<'a>(time: &'a [f64], speed: &'a [f64]) -> impl Iterator<Item = (f64, f64)> + 'a {
    time.windows(2).zip(speed).map(|(t, w)| {
        let dt = t[1] - t[0];
        (dt, dt * w.abs() / std::f64::consts::TAU)
    })
}

/// The LDD of `load` sampled at `time` with shaft speed `speed` (rad/s) in `n` bins over the load's
/// extent. Each sample holds until the next one (the last sample gets no time).
pub fn load_duration(time: &[f64], load: &[f64], speed: &[f64], n: usize) -> LoadDuration {
    let bins = Bins::spanning(load.iter().copied(), n);
    let mut seconds = vec![0.0; bins.n];
    let mut revolutions = vec![0.0; bins.n];
    for (j, (dt, revs)) in sample_revolutions(time, speed).enumerate() {
        let i = bins.index(load[j]);
        seconds[i] += dt;
        revolutions[i] += revs;
    }
    LoadDuration {
        bins,
        seconds,
        revolutions,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square wave of load 1 / 3 at 10 rad/s, half the time each: 5 s and 5·10/2π revolutions in
    /// each end bin, nothing between; the totals are the duration and ∫ω dt/2π.
    #[test]
    fn square_wave_dwells_half_the_time_at_each_level() {
        let time: Vec<f64> = (0..=1000).map(|i| i as f64 * 0.01).collect();
        let load: Vec<f64> = time
            .iter()
            .map(|t| if (t * 2.0).floor() as i64 % 2 == 0 { 1.0 } else { 3.0 })
            .collect();
        let speed = vec![10.0; time.len()];
        let l = load_duration(&time, &load, &speed, 4);
        assert!(
            (l.seconds[0] - 5.0).abs() < 1e-9 && (l.seconds[3] - 5.0).abs() < 1e-9,
            "{:?}",
            l.seconds
        );
        assert_eq!(l.seconds[1] + l.seconds[2], 0.0);
        let revs = 5.0 * 10.0 / (2.0 * std::f64::consts::PI);
        assert!((l.revolutions[0] - revs).abs() < 1e-9);
        assert!((l.seconds.iter().sum::<f64>() - 10.0).abs() < 1e-9);
    }
}
