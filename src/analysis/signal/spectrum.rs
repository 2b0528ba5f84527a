//! One-sided amplitude spectrum of a uniformly sampled signal: linear trend removed, Hann window,
//! real FFT (realfft), amplitudes corrected for the window's coherent gain so a sine of amplitude A
//! shows a peak of ≈ A.

/// Why a window of a series cannot give a spectrum.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WindowError {
    #[error("the window {from}..{to} s holds {samples} samples; a spectrum needs at least 16")]
    TooShort { from: f64, to: f64, samples: usize },
    #[error("the time steps are not uniform within 0.1 % (decimate or resample first)")]
    NotUniform,
}

/// The samples of times `t` within [from, to] as an index range, with their (uniform) time step.
pub fn window(t: &[f64], from: f64, to: f64) -> Result<(std::ops::Range<usize>, f64), WindowError> {
    let i0 = t.partition_point(|&v| v < from);
    let i1 = t.partition_point(|&v| v <= to);
    if i1 < i0 + 16 {
        return Err(WindowError::TooShort {
            from,
            to,
            samples: i1.saturating_sub(i0),
        });
    }
    let dt = (t[i1 - 1] - t[i0]) / (i1 - 1 - i0) as f64;
    if t[i0..i1].windows(2).any(|w| ((w[1] - w[0]) / dt - 1.0).abs() > 1e-3) {
        return Err(WindowError::NotUniform);
    }
    Ok((i0..i1, dt))
}

/// (frequencies in Hz, amplitudes) of `x` sampled every `dt` seconds.
pub fn amplitude_spectrum(x: &[f64], dt: f64) -> (Vec<f64>, Vec<f64>) {
    let n = x.len();
    if n < 4 {
        return (Vec::new(), Vec::new());
    }
    let nf = n as f64;
    let mean_k = (nf - 1.0) / 2.0;
    let mean_x = x.iter().sum::<f64>() / nf;
    let sxy: f64 = x
        .iter()
        .enumerate()
        .map(|(k, v)| (k as f64 - mean_k) * (v - mean_x))
        .sum();
    let sxx: f64 = (0..n).map(|k| (k as f64 - mean_k).powi(2)).sum();
    let slope = sxy / sxx;
    let mut buf: Vec<f64> = x
        .iter()
        .enumerate()
        .map(|(k, v)| {
            let w = 0.5 - 0.5 * (std::f64::consts::TAU * k as f64 / (nf - 1.0)).cos();
            w * (v - mean_x - slope * (k as f64 - mean_k))
        })
        .collect();
    let plan = realfft::RealFftPlanner::<f64>::new().plan_fft_forward(n);
    let mut spectrum = plan.make_output_vec();
    plan.process(&mut buf, &mut spectrum).expect("sizes from the plan");
    // Hann coherent gain 1/2; one-sided doubling
    let scale = 2.0 / (0.5 * nf);
    let f = (0..spectrum.len()).map(|k| k as f64 / (nf * dt)).collect();
    let a = spectrum.iter().map(|c| c.norm() * scale).collect();
    (f, a)
}

/// Frequency of the largest amplitude above `f_min`, refined by a parabola through the peak bin
/// and its neighbours (on the log amplitude, exact for a Gaussian-like window peak).
pub fn dominant_frequency(f: &[f64], a: &[f64], f_min: f64) -> Option<f64> {
    let k = (1..a.len().saturating_sub(1))
        .filter(|&k| f[k] >= f_min)
        .max_by(|&i, &j| a[i].total_cmp(&a[j]))?;
    Some(refine(f, a, k).0)
}

/// The dominant frequency (above `f_min`) of `x` sampled at times `t` over the window [from, to),
/// with the spectrum it came from: (frequency, frequencies, amplitudes). None when the window holds 16
/// samples or fewer. The sampling step is taken from the first two samples.
pub fn dominant_in_window(t: &[f64], x: &[f64], from: f64, to: f64, f_min: f64) -> Option<(f64, Vec<f64>, Vec<f64>)> {
    let i0 = t.partition_point(|&v| v < from);
    let i1 = t.partition_point(|&v| v < to);
    if i1 <= i0 + 16 {
        return None;
    }
    let (f, amp) = amplitude_spectrum(&x[i0..i1], t[1] - t[0]);
    dominant_frequency(&f, &amp, f_min).map(|d| (d, f, amp))
}

/// The `count` largest local maxima with f_min ≤ f ≤ f_max, as refined (frequency, amplitude),
/// largest first. A maximum must exceed both neighbours; a peak's window side lobes are 31 dB
/// down (Hann) and rarely local maxima above the noise.
pub fn peaks(f: &[f64], a: &[f64], f_min: f64, f_max: f64, count: usize) -> Vec<(f64, f64)> {
    let mut found: Vec<usize> = (1..a.len().saturating_sub(1))
        .filter(|&k| f[k] >= f_min && f[k] <= f_max && a[k] > a[k - 1] && a[k] >= a[k + 1])
        .collect();
    found.sort_by(|&i, &j| a[j].total_cmp(&a[i]));
    found.into_iter().take(count).map(|k| refine(f, a, k)).collect()
}

/// Frequency and amplitude at the vertex of the parabola through the log amplitudes of bin k and its
/// neighbours: corrects most of the window's scalloping loss (up to 15 % for Hann midway between bins).
fn refine(f: &[f64], a: &[f64], k: usize) -> (f64, f64) {
    let (l, c, r) = (
        a[k - 1].max(1e-300).ln(),
        a[k].max(1e-300).ln(),
        a[k + 1].max(1e-300).ln(),
    );
    let denom = l - 2.0 * c + r;
    let shift = if denom.abs() > 0.0 { 0.5 * (l - r) / denom } else { 0.0 };
    let shift = shift.clamp(-0.5, 0.5);
    (f[k] + shift * (f[1] - f[0]), (c - 0.25 * (l - r) * shift).exp())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sine_on_a_ramp_shows_its_frequency_and_amplitude() {
        let dt = 1e-3;
        let x: Vec<f64> = (0..20_000)
            .map(|k| {
                let t = k as f64 * dt;
                3.0 * (std::f64::consts::TAU * 2.51 * t).sin() + 50.0 * t + 7.0
            })
            .collect();
        let (f, a) = amplitude_spectrum(&x, dt);
        let peak = dominant_frequency(&f, &a, 0.3).unwrap();
        assert!((peak - 2.51).abs() < 0.005, "{peak}");
        let amp = a.iter().cloned().fold(0.0, f64::max);
        assert!((amp - 3.0).abs() < 0.1, "{amp}");
    }

    /// A decaying ring after a quiet start: the window picks the ring's frequency, a window of 16
    /// samples or fewer gives none.
    #[test]
    fn dominant_frequency_in_a_window() {
        let dt = 1e-3;
        let t: Vec<f64> = (0..10_000).map(|k| k as f64 * dt).collect();
        let x: Vec<f64> = t
            .iter()
            .map(|&t| {
                if t < 2.0 {
                    0.1 * (std::f64::consts::TAU * 9.0 * t).sin()
                } else {
                    (-(t - 2.0) / 4.0).exp() * (std::f64::consts::TAU * 2.61 * t).sin()
                }
            })
            .collect();
        let (f, _, _) = dominant_in_window(&t, &x, 2.0, f64::INFINITY, 0.3).unwrap();
        assert!((f - 2.61).abs() < 0.01, "{f}");
        let (f, _, _) = dominant_in_window(&t, &x, 0.0, 2.0, 0.3).unwrap();
        assert!((f - 9.0).abs() < 0.01, "{f}");
        assert!(dominant_in_window(&t, &x, 1.0, 1.016, 0.3).is_none());
        assert_eq!(window(&t, 2.0, 2.5).unwrap().0, 2000..2501);
        assert!(matches!(
            window(&t, 2.0, 2.0095),
            Err(WindowError::TooShort { samples: 10, .. })
        ));
        let mut uneven = t.clone();
        uneven[100] += 0.5e-3;
        assert_eq!(window(&uneven, 0.0, 1.0), Err(WindowError::NotUniform));
    }

    /// Two sines and noise-free: the two peaks, largest first, at their frequencies and amplitudes.
    #[test]
    fn two_peaks_in_order() {
        let dt = 1e-3;
        let x: Vec<f64> = (0..20_000)
            .map(|k| {
                let t = k as f64 * dt;
                1.0 * (std::f64::consts::TAU * 7.3 * t).sin() + 4.0 * (std::f64::consts::TAU * 2.2 * t).sin()
            })
            .collect();
        let (f, a) = amplitude_spectrum(&x, dt);
        let p = peaks(&f, &a, 0.5, 50.0, 2);
        assert!((p[0].0 - 2.2).abs() < 0.005 && (p[0].1 - 4.0).abs() < 0.1, "{p:?}");
        assert!((p[1].0 - 7.3).abs() < 0.005 && (p[1].1 - 1.0).abs() < 0.05, "{p:?}");
    }
}
