//! Rainflow cycle counting per ASTM E1049-85 (2011) §5.4.4, in one pass over the series: reversals are
//! extracted as samples arrive and counted on a stack; what is left on the stack at the end is counted
//! as half cycles. The cycle list (order included) equals that of the Python `rainflow` package 3.2
//! (`extract_cycles`), which the test suite checks on the ASTM example and on thousands of random series.

use std::collections::VecDeque;

/// One counted cycle: range, mean, count (1 or 0.5) and the sample indices of its two reversals.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cycle {
    pub range: f64,
    pub mean: f64,
    pub count: f64,
    pub start: usize,
    pub end: usize,
}

impl Cycle {
    fn between(a: (usize, f64), b: (usize, f64), count: f64) -> Self {
        Self {
            range: (a.1 - b.1).abs(),
            mean: 0.5 * (a.1 + b.1),
            count,
            start: a.0,
            end: b.0,
        }
    }
}

/// Turns samples into reversal points: where the slope changes sign; plateaus count once. The first
/// and the last sample are reversals by definition.
#[derive(Debug, Default)]
struct Reversals {
    seen: usize,
    last: f64,
    x: f64,
    slope: f64,
    /// position reported for `x` when it turns out to be a reversal (the `rainflow` package's index)
    index: usize,
}

impl Reversals {
    fn push(&mut self, value: f64, out: &mut impl FnMut((usize, f64))) {
        match self.seen {
            0 => self.last = value,
            1 => {
                self.x = value;
                self.slope = value - self.last;
                out((0, self.last));
            }
            _ => {
                let index = self.seen - 1;
                self.index = index;
                if value != self.x {
                    let slope = value - self.x;
                    if self.slope * slope < 0.0 {
                        out((index, self.x));
                    }
                    self.last = self.x;
                    self.x = value;
                    self.slope = slope;
                }
            }
        }
        self.seen += 1;
    }

    fn finish(&mut self, out: &mut impl FnMut((usize, f64))) {
        // as the reference implementation: a series of two samples has no last reversal
        if self.seen > 2 {
            out((self.index + 1, self.x));
        }
    }
}

/// Streaming rainflow counter: feed samples with [`Counter::push`], then call [`Counter::finish`].
#[derive(Debug, Default)]
pub struct Counter {
    reversals: Reversals,
    stack: VecDeque<(usize, f64)>,
}

impl Counter {
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds one sample; every cycle it closes is handed to `cycle`.
    pub fn push(&mut self, value: f64, cycle: &mut impl FnMut(Cycle)) {
        let stack = &mut self.stack;
        self.reversals
            .push(value, &mut |point| count_point(stack, point, cycle));
    }

    /// Ends the series: counts its last reversal, then the residue as half cycles.
    pub fn finish(mut self, cycle: &mut impl FnMut(Cycle)) {
        let stack = &mut self.stack;
        self.reversals.finish(&mut |point| count_point(stack, point, cycle));
        while stack.len() > 1 {
            cycle(Cycle::between(stack[0], stack[1], 0.5));
            stack.pop_front();
        }
    }
}

/// ASTM E1049-85 §5.4.4 on the newest reversal: X = latest range, Y = the one before it.
fn count_point(stack: &mut VecDeque<(usize, f64)>, point: (usize, f64), cycle: &mut impl FnMut(Cycle)) {
    stack.push_back(point);
    while stack.len() >= 3 {
        let n = stack.len();
        let (x1, x2, x3) = (stack[n - 3].1, stack[n - 2].1, stack[n - 1].1);
        let (x, y) = ((x3 - x2).abs(), (x2 - x1).abs());
        if x < y {
            break;
        } else if n == 3 {
            // Y contains the starting point: half a cycle
            cycle(Cycle::between(stack[0], stack[1], 0.5));
            stack.pop_front();
        } else {
            cycle(Cycle::between(stack[n - 3], stack[n - 2], 1.0));
            let last = stack.pop_back().unwrap_or(point);
            stack.pop_back();
            stack.pop_back();
            stack.push_back(last);
        }
    }
}

/// All cycles of a series, in counting order.
pub fn cycles(series: &[f64]) -> Vec<Cycle> {
    let mut out = Vec::new();
    let mut counter = Counter::new();
    for &x in series {
        counter.push(x, &mut |c| out.push(c));
    }
    counter.finish(&mut |c| out.push(c));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ASTM E1049-85 (2011) Fig. 6 / Table 4: ranges 3 (0.5), 4 (1.5), 6 (0.5), 8 (1.0), 9 (0.5).
    #[test]
    fn astm_example() {
        let c = cycles(&[-2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0]);
        let mut by_range = std::collections::BTreeMap::new();
        for cycle in &c {
            *by_range.entry(cycle.range as i64).or_insert(0.0) += cycle.count;
        }
        let expected: Vec<(i64, f64)> = vec![(3, 0.5), (4, 1.5), (6, 0.5), (8, 1.0), (9, 0.5)];
        assert_eq!(by_range.into_iter().collect::<Vec<_>>(), expected);
    }

    /// Each reversal-to-reversal excursion is counted once: Σ 2·count·range = total variation of the
    /// reversal sequence (half cycles cover one excursion, full cycles two).
    #[test]
    fn cycles_conserve_total_variation() {
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        for _ in 0..200 {
            let mut x = 0.0;
            let series: Vec<f64> = (0..300)
                .map(|_| {
                    x += next();
                    (x * 4.0_f64).round() / 4.0 // plateaus and repeated values
                })
                .collect();
            let mut reversal_values = Vec::new();
            let mut r = Reversals::default();
            for &v in &series {
                r.push(v, &mut |p| reversal_values.push(p.1));
            }
            r.finish(&mut |p| reversal_values.push(p.1));
            let variation: f64 = reversal_values.windows(2).map(|w| (w[1] - w[0]).abs()).sum();
            let counted: f64 = cycles(&series).iter().map(|c| 2.0 * c.count * c.range).sum();
            assert!(
                (variation - counted).abs() <= 1e-9 * variation.max(1.0),
                "{variation} vs {counted}"
            );
        }
    }

    #[test]
    fn short_series() {
        assert!(cycles(&[]).is_empty());
        assert!(cycles(&[1.0]).is_empty());
        assert!(cycles(&[1.0, 2.0]).is_empty());
        assert_eq!(cycles(&[0.0, 2.0, 1.0]).len(), 2);
    }
}
