//! Checks on the values that cross the boundary, the same on both sides.

/// Index of the first value that is NaN or infinite, if any. The common answer (every value finite) comes
/// from one pass without a branch per value, which the compiler turns into vector compares (a row of 52
/// recorded values cost 8 instructions a value searched one by one, callgrind); the search for the
/// culprit runs only when there is one.
#[inline]
pub fn first_non_finite(values: &[f64]) -> Option<usize> {
    if values.iter().fold(true, |finite, v| finite & v.is_finite()) {
        return None;
    }
    values.iter().position(|v| !v.is_finite())
}

#[cfg(test)]
mod tests {
    use super::first_non_finite;

    #[test]
    fn finds_the_first_nan_or_infinity_at_any_position() {
        assert_eq!(first_non_finite(&[]), None);
        for n in [1, 3, 4, 7, 8, 52, 67] {
            let mut v: Vec<f64> = (0..n).map(|i| i as f64 - 2.5).collect();
            assert_eq!(first_non_finite(&v), None, "{n} finite values");
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                for at in [0, n / 2, n - 1] {
                    let kept = v[at];
                    v[at] = bad;
                    assert_eq!(first_non_finite(&v), Some(at), "{bad} at {at} of {n}");
                    v[at] = kept;
                }
            }
        }
        assert_eq!(first_non_finite(&[1.0, f64::NAN, f64::INFINITY]), Some(1));
        assert_eq!(first_non_finite(&[f64::MAX, f64::MIN_POSITIVE, -0.0]), None);
    }
}
