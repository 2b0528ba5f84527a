//! Divergence of a coupling, detected while the run goes on: a partitioned scheme that is unstable at
//! its macro step makes the coupled variables grow geometrically, by a fixed factor per step, until
//! they overflow. Physical transients do not: a brake lock or a torque step jumps once, a resonance
//! grows linearly, a load ramp from rest like a power of time whose growth per window slows down. The
//! watch compares the peak |y| of each coupled variable over windows of [`WINDOW`] macro steps: when
//! every window of a run of them exceeds the one before by at least [`MIN_WINDOW_GROWTH`], the growth
//! does not slow (each window's factor at least [`MIN_ACCELERATION`] of the previous one's), and the
//! run has grown by the stated bound (default [`DEFAULT_GROWTH`]), the coupling diverges. Growth
//! slower than 2 % per step is left to the non-finite check. That is caught hundreds of steps before the values stop being finite, and it
//! names the variable, so the message can name the coupling and the remedy.

/// Macro steps per window.
pub const WINDOW: usize = 20;
/// Least growth of each window's peak over the previous one for the run to continue.
pub const MIN_WINDOW_GROWTH: f64 = 1.5;
/// Geometric growth keeps its factor; a power law t^p from rest loses it ((k+1)^p/k^p falls).
pub const MIN_ACCELERATION: f64 = 0.8;
/// Default total growth of a run of growing windows that counts as divergence.
pub const DEFAULT_GROWTH: f64 = 1e3;

/// What diverged: the coupled variable's index (in the order given to [`Watch::observe`]), the
/// peak where its growth began and the peak now.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Diverged {
    pub variable: usize,
    pub from: f64,
    pub to: f64,
    /// Macro steps the growth took.
    pub steps: usize,
}

#[derive(Debug, Clone)]
pub struct Watch {
    growth: f64,
    /// Peaks below this are noise around zero, not the start of a growth.
    floor: f64,
    steps: usize,
    current: Vec<f64>,
    previous: Vec<f64>,
    /// Per variable: the peak of the window the growth began in, and its length in windows.
    start: Vec<(f64, usize)>,
    /// Per variable: the last window's growth factor.
    factor: Vec<f64>,
}

impl Watch {
    /// A watch over `n` variables; `growth` = ∞ disables it.
    pub fn new(n: usize, growth: f64, floor: f64) -> Self {
        Self {
            growth,
            floor,
            steps: 0,
            current: vec![0.0; n],
            previous: vec![f64::NAN; n],
            start: vec![(0.0, 0); n],
            factor: vec![0.0; n],
        }
    }

    /// Takes the coupled values after an accepted macro step.
    pub fn observe(&mut self, values: impl Iterator<Item = f64>) -> Option<Diverged> {
        if !self.growth.is_finite() {
            return None;
        }
        for (c, v) in self.current.iter_mut().zip(values) {
            *c = c.max(v.abs());
        }
        self.steps += 1;
        if !self.steps.is_multiple_of(WINDOW) {
            return None;
        }
        let mut found = None;
        for k in 0..self.current.len() {
            let (now, before) = (self.current[k], self.previous[k]);
            let (from, windows) = &mut self.start[k];
            let factor = now / before;
            let growing = before > self.floor && factor >= MIN_WINDOW_GROWTH;
            if growing && (*windows == 0 || factor >= MIN_ACCELERATION * self.factor[k]) {
                if *windows == 0 {
                    *from = before;
                }
                *windows += 1;
                if now >= self.growth * *from && found.is_none() {
                    found = Some(Diverged {
                        variable: k,
                        from: *from,
                        to: now,
                        steps: *windows * WINDOW,
                    });
                }
            } else if growing {
                // slowing down: a new run may start from here
                *from = before;
                *windows = 1;
            } else {
                *windows = 0;
            }
            self.factor[k] = factor;
            self.previous[k] = now;
            self.current[k] = 0.0;
        }
        found
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(watch: &mut Watch, series: impl Fn(usize) -> f64, steps: usize) -> Option<(usize, Diverged)> {
        (0..steps).find_map(|k| watch.observe(std::iter::once(series(k))).map(|d| (k, d)))
    }

    /// An oscillation growing 5 % per step (a coupling unstable at its step) is caught after a
    /// thousandfold growth, long before it overflows; one growing 2.5 % per step too, later.
    #[test]
    fn geometric_growth_is_caught() {
        let mut w = Watch::new(1, DEFAULT_GROWTH, 1e-6);
        let (k, d) = run(
            &mut w,
            |k| 1.05f64.powi(k as i32) * if k % 2 == 0 { 1.0 } else { -1.0 },
            100_000,
        )
        .unwrap();
        assert!(d.to / d.from >= 1e3 && k < 200, "{k} {d:?}");
        let mut w = Watch::new(1, DEFAULT_GROWTH, 1e-6);
        let (k, _) = run(&mut w, |k| 1.025f64.powi(k as i32), 100_000).unwrap();
        assert!(k < 400, "{k}");
    }

    /// Physical transients are not divergence: a step from rest, a brake lock's jump, a resonance
    /// growing linearly from small, a decaying oscillation, ramps from rest as t³ and t⁵.
    #[test]
    fn transients_are_not() {
        let cases: [&dyn Fn(usize) -> f64; 6] = [
            &|k| if k < 300 { 0.0 } else { 1e6 },
            &|k| if k < 300 { 1.0 } else { 5.0 },
            &|k| 1e-3 * k as f64 * (k as f64 * 0.3).sin(),
            &|k| (-(k as f64) * 1e-3).exp() * (k as f64 * 0.3).sin(),
            &|k| ((k.min(400)) as f64 * 1e-2).powi(3),
            &|k| ((k.min(1000)) as f64 * 1e-2).powi(5),
        ];
        for (i, c) in cases.iter().enumerate() {
            let mut w = Watch::new(1, DEFAULT_GROWTH, 1e-6);
            assert!(run(&mut w, c, 20_000).is_none(), "case {i}");
        }
    }

    #[test]
    fn an_infinite_bound_disables_it() {
        let mut w = Watch::new(1, f64::INFINITY, 1e-6);
        assert!(run(&mut w, |k| 1.1f64.powi(k as i32), 2000).is_none());
    }
}
