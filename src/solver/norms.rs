//! The largest magnitude of a vector, the norm every convergence test here takes.

/// max |x| over `xs`, NaN entries left out (as `f64::max` leaves them), 0 for none: what
/// `xs.iter().fold(0.0, |m, x| m.max(x.abs()))` gives, to the bit, in four running maxima the compiler
/// keeps in vector registers (the fold's `max` keeps its NaN rule one value at a time; in the 6-DOF
/// gearbox's Newton iteration with linear bearings those folds were a third of the integrator's own
/// instructions, 4 % of a step, callgrind).
/// A maximum is exact, so neither the order nor the lanes change the answer.
#[inline]
pub fn max_abs(xs: &[f64]) -> f64 {
    // `a > m` is false for a NaN a: the lane keeps its value, as `m.max(NaN)` does
    let larger = |m: f64, x: f64| {
        let a = x.abs();
        if a > m { a } else { m }
    };
    let mut lanes = [0.0f64; 4];
    let mut quads = xs.chunks_exact(4);
    for quad in &mut quads {
        for (m, &x) in lanes.iter_mut().zip(quad) {
            *m = larger(*m, x);
        }
    }
    let tail = quads.remainder().iter().fold(0.0, |m, &x| larger(m, x));
    lanes.into_iter().fold(tail, larger)
}

#[cfg(test)]
mod tests {
    use super::max_abs;
    use crate::xorshift::Xorshift;

    /// The fold it replaces, to the bit, over lengths around the lanes, signs, zeros of both signs,
    /// NaNs, infinities and subnormals.
    #[test]
    fn the_largest_magnitude_is_the_folds_to_the_bit() {
        let fold = |xs: &[f64]| xs.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let mut rng = Xorshift::new(7);
        let special = [
            0.0,
            -0.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            5e-324,
            -f64::MAX,
            1.0,
        ];
        for n in 0..40 {
            for round in 0..200 {
                let xs: Vec<f64> = (0..n)
                    .map(|_| {
                        let r = rng.unit();
                        if round % 3 == 0 && r < 0.3 {
                            special[(rng.unit() * special.len() as f64) as usize % special.len()]
                        } else {
                            (r - 0.5) * 10f64.powi((rng.unit() * 20.0) as i32 - 10)
                        }
                    })
                    .collect();
                assert_eq!(max_abs(&xs).to_bits(), fold(&xs).to_bits(), "{xs:?}");
            }
        }
        assert_eq!(max_abs(&[]).to_bits(), 0.0f64.to_bits());
        assert_eq!(max_abs(&[f64::NAN; 9]).to_bits(), 0.0f64.to_bits());
        assert_eq!(max_abs(&[-0.0; 5]).to_bits(), 0.0f64.to_bits());
    }
}
