//! Error metrics of a computed series against a reference, and the extremes they are made of.

/// Largest magnitude.
pub fn peak(x: &[f64]) -> f64 {
    x.iter().map(|v| v.abs()).fold(0.0, f64::max)
}

/// Root mean square.
pub fn rms(x: &[f64]) -> f64 {
    (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
}

/// Largest minus smallest value.
pub fn range(x: &[f64]) -> f64 {
    x.iter().cloned().fold(f64::MIN, f64::max) - x.iter().cloned().fold(f64::MAX, f64::min)
}

/// Largest deviation along the run, relative to the reference's peak (series compared sample by
/// sample, up to the shorter one).
pub fn trajectory_error(x: &[f64], reference: &[f64]) -> f64 {
    x.iter().zip(reference).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max) / peak(reference)
}

/// Relative errors of the peak and of the RMS against the reference's.
pub fn peak_and_rms_errors(x: &[f64], reference: &[f64]) -> (f64, f64) {
    (
        (peak(x) - peak(reference)).abs() / peak(reference),
        (rms(x) - rms(reference)).abs() / rms(reference),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn metrics_of_a_sine_and_a_scaled_copy() {
        let x: Vec<f64> = (0..1000)
            .map(|k| (k as f64 * 0.01 * std::f64::consts::TAU).sin())
            .collect();
        assert!((peak(&x) - 1.0).abs() < 1e-3 && (rms(&x) - 0.5f64.sqrt()).abs() < 1e-3);
        assert!((range(&[3.0, -1.0, 2.0]) - 4.0).abs() < 1e-15);
        let y: Vec<f64> = x.iter().map(|v| 1.01 * v).collect();
        let (p, r) = peak_and_rms_errors(&y, &x);
        assert!((p - 0.01).abs() < 1e-12 && (r - 0.01).abs() < 1e-12, "{p} {r}");
        assert!((trajectory_error(&y, &x) - 0.01).abs() < 1e-12);
        assert_eq!(trajectory_error(&x, &x), 0.0);
    }
}
