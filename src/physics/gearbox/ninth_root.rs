//! x^(1/9) without a libm call, for the line-contact lamina law q = k·δ^(10/9): the roller sets'
//! inner loop evaluates it for every loaded lamina of every force evaluation, and exp(ln x / 9)
//! spent a quarter of the GRC shutdown's run in glibc.
//!
//! x = m·2^e with m in [1, 2): m^(1/9) is a table's value at the start of m's cell (256 cells)
//! times (1 + r)^(1/9) by its binomial series to r⁵ (|r| < 1/256 leaves 5.1e-17), and
//! 2^(e/9) = 2^k·2^(j/9) for e = 9k + j, one table entry per biased exponent (2^k is exact, so
//! the entry 2^(j/9)·2^k gives the bits of multiplying by 2^(j/9) and then by 2^k, with no
//! division by nine per call). Within 6 ulp (7e-16) of `powf` from 2⁻⁴⁰ to 1, the
//! approaches a lamina meets (tests below: two rounded table values, the series and three
//! products, each within half an ulp, and `powf`'s own rounding), far below the Newton iteration's
//! 1e-8; anything but a positive normal number goes to `powf`.

use std::sync::LazyLock;

const CELL_BITS: u32 = 8;
const CELLS: usize = 1 << CELL_BITS;
const BELOW_CELL: u64 = (1 << (52 - CELL_BITS)) - 1;
const EXPONENT_BIAS: i64 = 1023;

/// (1 + r)^(1/9) = Σ C(1/9, n)·rⁿ.
const C1: f64 = 1.0 / 9.0;
const C2: f64 = -4.0 / 81.0;
const C3: f64 = 68.0 / 2187.0;
const C4: f64 = -442.0 / 19683.0;
const C5: f64 = 3094.0 / 177147.0;

/// Biased exponents of the normal numbers: 1..2047.
const EXPONENTS: usize = 2047;

struct Tables {
    /// Per cell [1 + i/256, 1 + (i + 1)/256): its start's ninth root and 2⁻⁵² over its start.
    cells: [(f64, f64); CELLS],
    /// Per biased exponent e + 1023 (e = 9k + j, 0 ≤ j < 9): 2^(j/9)·2^k.
    powers: [f64; EXPONENTS],
}

static TABLES: LazyLock<Tables> = LazyLock::new(|| {
    let mut cells = [(0.0, 0.0); CELLS];
    for (i, c) in cells.iter_mut().enumerate() {
        let start = 1.0 + i as f64 / CELLS as f64;
        *c = (start.powf(1.0 / 9.0), 2f64.powi(-52) / start);
    }
    let ninths: [f64; 9] = std::array::from_fn(|j| (j as f64 / 9.0).exp2());
    let powers = std::array::from_fn(|biased| {
        let e = biased as i64 - EXPONENT_BIAS;
        // 2^k ranges over 2^-114..2^114 here: a normal number, so the product is exact
        ninths[e.rem_euclid(9) as usize] * f64::from_bits(((e.div_euclid(9) + EXPONENT_BIAS) as u64) << 52)
    });
    Tables { cells, powers }
});

/// x^(1/9).
#[inline]
pub fn ninth_root(x: f64) -> f64 {
    NinthRoots::get().of(x)
}

/// The tables taken once, for a caller that takes many roots: each [`ninth_root`] checks that the
/// lazy tables are built (an atomic load and a branch, 0.8 % of the GRC's normal step).
#[derive(Clone, Copy)]
pub struct NinthRoots(&'static Tables);

impl NinthRoots {
    pub fn get() -> Self {
        NinthRoots(&TABLES)
    }

    /// x^(1/9), as [`ninth_root`].
    #[inline(always)]
    pub fn of(self, x: f64) -> f64 {
        let bits = x.to_bits();
        let biased = biased_exponent(bits);
        if !(1..2047).contains(&biased) {
            return x.powf(1.0 / 9.0);
        }
        let (root, r) = self.cell(bits);
        root * series(r) * self.0.powers[biased as usize]
    }

    /// Two roots at once, each as [`Self::of`]: the series of both in one pair of lanes.
    #[inline(always)]
    pub fn of_two(self, x: [f64; 2]) -> [f64; 2] {
        let bits = x.map(f64::to_bits);
        let biased = bits.map(biased_exponent);
        if !biased.iter().all(|b| (1..2047).contains(b)) {
            return x.map(|x| self.of(x));
        }
        let cells = bits.map(|b| self.cell(b));
        let series = cells.map(|(_, r)| series(r));
        [0, 1].map(|i| cells[i].0 * series[i] * self.0.powers[biased[i] as usize])
    }

    /// A positive normal number's cell: the ninth root of its start, and r, the mantissa past the
    /// start over the start.
    #[inline(always)]
    fn cell(self, bits: u64) -> (f64, f64) {
        let (root, inverse) = self.0.cells[((bits >> (52 - CELL_BITS)) as usize) & (CELLS - 1)];
        // m minus its cell's start is the mantissa's bits below the cell's, times 2⁻⁵² (exact)
        (root, (bits & BELOW_CELL) as f64 * inverse)
    }
}

/// The biased exponent; the sign bit makes a negative number's 2048 or more.
#[inline(always)]
fn biased_exponent(bits: u64) -> i64 {
    (bits >> 52) as i64
}

/// (1 + r)^(1/9) to r⁵ by Estrin's scheme: three dependent multiply-adds instead of Horner's five.
#[inline(always)]
fn series(r: f64) -> f64 {
    let r2 = r * r;
    (1.0 + C1 * r) + r2 * ((C2 + C3 * r) + r2 * (C4 + C5 * r))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::xorshift::Xorshift;

    /// Ulps between a and b (same sign, finite).
    fn ulps(a: f64, b: f64) -> u64 {
        a.to_bits().abs_diff(b.to_bits())
    }

    #[test]
    fn within_six_ulp_of_powf_over_every_binade_a_lamina_meets() {
        // a seeded walk over the mantissas of approaches from 1e-12 m to 1 m, every cell's edges
        // and the powers of two themselves
        let mut worst = 0;
        let mut random = Xorshift::new(0x9e37_79b9_7f4a_7c15);
        for e in -40..=0 {
            let base = 2f64.powi(e);
            for i in 0..CELLS {
                for x in [
                    base * (1.0 + i as f64 / CELLS as f64),
                    base * (1.0 + (i + 1) as f64 / CELLS as f64),
                ] {
                    worst = worst.max(ulps(ninth_root(x), x.powf(1.0 / 9.0)));
                }
            }
            for _ in 0..2000 {
                let x = base * (1.0 + random.unit());
                worst = worst.max(ulps(ninth_root(x), x.powf(1.0 / 9.0)));
            }
        }
        assert!(worst <= 6, "{worst} ulp");
        assert_eq!(ninth_root(1.0), 1.0);
        assert_eq!(ninth_root(512.0), 2.0);
    }

    /// What the function computed before its exponents were tabulated: the cell's root times the
    /// series, times 2^(j/9), times 2^k.
    fn two_step(x: f64) -> f64 {
        let bits = x.to_bits();
        let biased = (bits >> 52) as i64;
        let cell = ((bits >> (52 - CELL_BITS)) as usize) & (CELLS - 1);
        let start = 1.0 + cell as f64 / CELLS as f64;
        let (root, inverse) = (start.powf(1.0 / 9.0), 2f64.powi(-52) / start);
        let r = (bits & BELOW_CELL) as f64 * inverse;
        let r2 = r * r;
        let series = (1.0 + C1 * r) + r2 * ((C2 + C3 * r) + r2 * (C4 + C5 * r));
        let e = biased - EXPONENT_BIAS;
        let ninth = (e.rem_euclid(9) as f64 / 9.0).exp2();
        root * series * ninth * f64::from_bits(((e.div_euclid(9) + EXPONENT_BIAS) as u64) << 52)
    }

    #[test]
    fn one_table_for_the_exponent_gives_the_bits_of_two_factors() {
        // every biased exponent from the smallest normal to the largest finite, at seeded mantissas
        let mut random = Xorshift::new(0x2545_f491_4f6c_dd1d);
        for biased in 1..2047u64 {
            for _ in 0..64 {
                let x = f64::from_bits(biased << 52 | (random.next_u64() >> 12));
                assert_eq!(ninth_root(x).to_bits(), two_step(x).to_bits(), "{x:e}");
            }
        }
    }

    #[test]
    fn two_at_once_give_the_bits_of_one_at_a_time() {
        // normal numbers over every exponent a lamina meets and far beyond, paired with each other
        // and with what takes powf's path (zero, negative, subnormal, infinite, NaN)
        let roots = NinthRoots::get();
        let odd = [0.0, -1.0, f64::MIN_POSITIVE / 4.0, f64::INFINITY, f64::NAN];
        let mut random = Xorshift::new(0x9e37_79b9_7f4a_7c15);
        let mut next = || {
            let state = random.next_u64();
            f64::from_bits((1 + state % 2046) << 52 | (state >> 12))
        };
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        for k in 0..20_000 {
            let x = [next(), if k % 10 == 0 { odd[k / 10 % odd.len()] } else { next() }];
            for pair in [x, [x[1], x[0]]] {
                let two = roots.of_two(pair);
                assert!(
                    same(two[0], roots.of(pair[0])) && same(two[1], roots.of(pair[1])),
                    "{pair:?}"
                );
            }
        }
    }

    #[test]
    fn anything_else_is_powfs() {
        for x in [0.0, -1.0, f64::MIN_POSITIVE / 4.0, f64::INFINITY, f64::NAN] {
            let (a, b) = (ninth_root(x), x.powf(1.0 / 9.0));
            assert!(
                a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()),
                "{x}: {a} vs {b}"
            );
        }
    }
}
