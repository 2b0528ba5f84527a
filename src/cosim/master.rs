//! The co-simulation algorithms: fixed-step Jacobi and Gauss–Seidel with input extrapolation of
//! order 0–2, iterative coupling with rollback, and an adaptive macro step with rollback.
//!
//! Every algorithm is built from one *sweep*: give each unit its inputs over [t, t+h] as a
//! polynomial a0 + a1·τ + a2·τ²/2, then step it. A source's polynomial is
//! - extrapolated from its history (order 0, 1, 2) while its value at t+h is unknown,
//! - interpolated between t and t+h once it is known (a Gauss–Seidel predecessor, or the previous
//!   iterate of an iterative step); order 0 then holds the end value.
//!
//! FMUs that declare canInterpolateInputs receive a0 and the derivatives through
//! fmi2SetRealInputDerivatives; the others receive the polynomial's mean over the step, which
//! keeps the exchanged impulse (∫u dt) of the polynomial.

use super::acceleration::{Acceleration, Accelerator};
use super::system::System;
use super::unit::{DiscreteInputs, Unit};
use crate::fmi2::host::error::ImportError;
use crate::fmi2::values::first_non_finite;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Algorithm {
    Jacobi,
    GaussSeidel,
    Iterative,
    Adaptive,
}

impl Algorithm {
    pub const NAMES: &'static str = "jacobi, gauss-seidel, iterative, adaptive";

    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "jacobi" => Some(Self::Jacobi),
            "gauss-seidel" | "gs" => Some(Self::GaussSeidel),
            "iterative" => Some(Self::Iterative),
            "adaptive" => Some(Self::Adaptive),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Jacobi => "jacobi",
            Self::GaussSeidel => "gauss-seidel",
            Self::Iterative => "iterative",
            Self::Adaptive => "adaptive",
        }
    }
}

#[derive(Debug, Clone)]
pub struct Options {
    pub algorithm: Algorithm,
    /// Macro step (the initial one for the adaptive algorithm), s.
    pub step: f64,
    pub stop_time: f64,
    /// Order of the input polynomial: 0 hold, 1 linear, 2 quadratic.
    pub order: usize,
    /// Coupling tolerance of the iterative and adaptive algorithms: |Δy| ≤ abs + rel·max(|y|, peak),
    /// peak = the largest |y| the variable has had, so a signal passing through zero (or starting
    /// there) is held to its own scale, not to abs alone.
    pub rel_tol: f64,
    pub abs_tol: f64,
    pub max_iterations: usize,
    /// How the iterative algorithm picks its next iterate (none: plain fixed-point iteration).
    pub acceleration: Acceleration,
    pub min_step: f64,
    pub max_step: f64,
    /// Worker threads for the Jacobi sweep (1 = on the calling thread).
    pub threads: usize,
    /// Growth of a coupled variable's amplitude that stops the run as a diverging coupling
    /// ([`super::divergence`]); infinity disables the check.
    pub divergence_growth: f64,
}

impl Options {
    pub fn new(algorithm: Algorithm, step: f64, stop_time: f64) -> Self {
        Self {
            algorithm,
            step,
            stop_time,
            // interpolation between iterates, and the adaptive error estimate, need order 1
            order: usize::from(matches!(algorithm, Algorithm::Iterative | Algorithm::Adaptive)),
            rel_tol: 1e-6,
            abs_tol: 1e-9,
            max_iterations: 10,
            acceleration: Acceleration::None,
            min_step: step * 1e-3,
            max_step: step * 100.0,
            threads: 1,
            divergence_growth: super::divergence::DEFAULT_GROWTH,
        }
    }
}

#[derive(Debug, Clone, Default)]
pub struct Stats {
    pub steps: u64,
    pub rejected: u64,
    /// Sweeps of all units (one per step for the fixed-step algorithms).
    pub sweeps: u64,
    /// Iterative steps that hit the iteration cap before the tolerance.
    pub unconverged: u64,
    pub final_time: f64,
    pub min_step_taken: f64,
    pub max_step_taken: f64,
    /// Set when the stop time is not a whole number of steps and an FMU cannot shorten its last step.
    pub stopped_early: bool,
}

#[derive(Debug, thiserror::Error)]
pub enum MasterError {
    #[error("{component} failed at t = {time} s: {error}")]
    Step {
        component: String,
        time: f64,
        error: ImportError,
    },
    #[error("{component}.{variable} = {value} at t = {time} s (not finite)")]
    NonFinite {
        component: String,
        variable: String,
        time: f64,
        value: f64,
    },
    #[error(
        "the coupling {variable} -> {consumers} diverges at t = {time} s: its amplitude grew from {from:.4e} to {to:.4e} \
         over the last {steps} macro steps of {step} s, geometrically, as a partitioned scheme does beyond its \
         stability limit. Remedies: a smaller --step (the coupling is stable when the macro step times the \
         angular frequency of the fastest mode it carries stays well below 1), --order 0, or --algorithm iterative \
         --acceleration iqn-ils, which converges the coupling every step; every row so far is kept \
         (--divergence-growth inf turns this check off)"
    )]
    Diverged {
        variable: String,
        consumers: String,
        time: f64,
        from: f64,
        to: f64,
        steps: usize,
        step: f64,
    },
    #[error("{0}")]
    Unsupported(String),
    #[error("writing results: {0}")]
    Record(#[from] std::io::Error),
}

/// Everything a master keeps between steps, besides the units' own current values.
pub struct Master<'s> {
    sys: &'s mut System,
    opts: Options,
    /// Values at the start of the current step, per unit.
    start: Vec<Vec<f64>>,
    /// Two earlier communication points (newest first) for extrapolation.
    hist_t: [f64; 2],
    hist: [Vec<Vec<f64>>; 2],
    hist_len: usize,
    /// Coupled sources (unit, index), where the iterative and adaptive tolerances apply.
    coupled: Vec<(usize, usize)>,
    previous_iterate: Vec<f64>,
    /// The iterative algorithm's acceleration and its current iterate and image.
    accelerator: Accelerator,
    iterate_x: Vec<f64>,
    iterate_g: Vec<f64>,
    /// Largest |y| of each coupled variable so far (its scale for the tolerance).
    peak: Vec<f64>,
    known: Vec<bool>,
    a: Vec<[f64; 3]>,
    pool: Option<rayon::ThreadPool>,
    watch: super::divergence::Watch,
    pub stats: Stats,
}

/// `with_recorded`: the step's row is kept, read the recorder's variables with the coupled outputs.
fn step_unit(unit: &mut Unit, t: f64, h: f64, with_recorded: bool) -> Result<(), MasterError> {
    timed(unit, |c| &mut c.step, |unit| step_and_fetch(unit, t, h, with_recorded))
}

/// `work` on `unit`, its wall time added to the part of the unit's clock `part` picks when it has one.
#[inline(always)]
fn timed<R>(
    unit: &mut Unit,
    part: impl FnOnce(&mut super::unit::Clock) -> &mut std::time::Duration,
    work: impl FnOnce(&mut Unit) -> R,
) -> R {
    if unit.clock.is_none() {
        return work(unit);
    }
    let start = std::time::Instant::now();
    let r = work(unit);
    let elapsed = start.elapsed();
    if let Some(clock) = &mut unit.clock {
        *part(clock) += elapsed;
    }
    r
}

fn step_and_fetch(unit: &mut Unit, t: f64, h: f64, with_recorded: bool) -> Result<(), MasterError> {
    let fail = |error| MasterError::Step {
        component: unit.name.clone(),
        time: t,
        error,
    };
    let start = unit.clock.is_some().then(std::time::Instant::now);
    unit.instance.do_step(t, h).map_err(fail)?;
    if let (Some(start), Some(clock)) = (start, &mut unit.clock) {
        clock.do_step += start.elapsed();
    }
    let fetched = if with_recorded {
        timed(unit, |c| &mut c.recorded_with_step, Unit::fetch_with_recorded)
    } else {
        unit.fetch()
    };
    fetched.map_err(|error| MasterError::Step {
        component: unit.name.clone(),
        time: t + h,
        error,
    })?;
    if let Some(i) = first_non_finite(&unit.values) {
        return Err(MasterError::NonFinite {
            component: unit.name.clone(),
            variable: unit.fetch_names[i].clone(),
            time: t + h,
            value: unit.values[i],
        });
    }
    Ok(())
}

/// Reads every unit's recorder-only variables at `time` (a kept row), refusing non-finite ones.
pub fn read_recorded(sys: &mut System, time: f64) -> Result<(), MasterError> {
    for unit in &mut sys.units {
        if unit.recorded_only.is_empty() {
            continue;
        }
        if unit.recorded_fresh {
            // read with the step's coupled outputs and checked there
            unit.recorded_fresh = false;
            continue;
        }
        timed(unit, |c| &mut c.recorded, Unit::fetch_recorded).map_err(|error| MasterError::Step {
            component: unit.name.clone(),
            time,
            error,
        })?;
        let range = unit.recorded_only.offset..unit.values.len();
        if let Some(i) = first_non_finite(&unit.values[range.clone()]) {
            let i = range.start + i;
            return Err(MasterError::NonFinite {
                component: unit.name.clone(),
                variable: unit.fetch_names[i].clone(),
                time,
                value: unit.values[i],
            });
        }
    }
    Ok(())
}

/// [`read_recorded`] for an observer that keeps every row, telling the master so
/// ([`System::record_next`]): from the next step on each FMU's recorder-only variables come with its
/// coupled outputs (Jacobi and Gauss–Seidel) and this reads nothing more.
pub fn read_every_row(sys: &mut System, time: f64) -> Result<(), MasterError> {
    read_recorded(sys, time)?;
    sys.record_next = true;
    Ok(())
}

impl<'s> Master<'s> {
    pub fn new(sys: &'s mut System, opts: Options) -> Result<Self, MasterError> {
        if !(opts.step.is_finite() && opts.step > 0.0) {
            return Err(MasterError::Unsupported(format!(
                "step size {} must be positive",
                opts.step
            )));
        }
        if !(opts.stop_time.is_finite() && opts.stop_time > sys.start_time) {
            return Err(MasterError::Unsupported(format!(
                "stop time {} must be after the start time {}",
                opts.stop_time, sys.start_time
            )));
        }
        if opts.order > 2 {
            return Err(MasterError::Unsupported(format!(
                "extrapolation order {} (0, 1 or 2)",
                opts.order
            )));
        }
        let rollback = matches!(opts.algorithm, Algorithm::Iterative | Algorithm::Adaptive);
        for u in &sys.units {
            if rollback && !u.can_get_set_state {
                return Err(MasterError::Unsupported(format!(
                    "the {} algorithm rolls steps back, but {} ({}) declares canGetAndSetFMUstate=false; use jacobi or gauss-seidel",
                    opts.algorithm.name(),
                    u.name,
                    u.fmu.description.model_name
                )));
            }
            if opts.algorithm == Algorithm::Adaptive && !u.can_vary_step {
                return Err(MasterError::Unsupported(format!(
                    "the adaptive algorithm changes the step, but {} declares canHandleVariableCommunicationStepSize=false",
                    u.name
                )));
            }
        }
        let mut coupled: Vec<(usize, usize)> = sys
            .units
            .iter()
            .flat_map(|u| u.real_in.links.iter().map(|l| (l.src_unit, l.src)))
            .collect();
        coupled.sort_unstable();
        coupled.dedup();
        let start: Vec<Vec<f64>> = sys.units.iter().map(|u| u.values.clone()).collect();
        let peak = coupled.iter().map(|&(u, i)| start[u][i].abs()).collect();
        let coupled_len = coupled.len();
        let pool = if opts.threads > 1 && opts.algorithm == Algorithm::Jacobi {
            Some(
                rayon::ThreadPoolBuilder::new()
                    .num_threads(opts.threads)
                    .build()
                    .map_err(|e| MasterError::Unsupported(format!("cannot start {} threads: {e}", opts.threads)))?,
            )
        } else {
            None
        };
        let n = sys.units.len();
        let stats = Stats {
            final_time: sys.start_time,
            min_step_taken: f64::INFINITY,
            ..Stats::default()
        };
        Ok(Self {
            sys,
            hist: [start.clone(), start.clone()],
            start,
            hist_t: [0.0; 2],
            hist_len: 0,
            previous_iterate: vec![0.0; coupled.len()],
            accelerator: Accelerator::default(),
            iterate_x: Vec::new(),
            iterate_g: Vec::new(),
            peak,
            coupled,
            known: vec![false; n],
            a: Vec::new(),
            pool,
            // windows count steps: under the adaptive algorithm's growing steps a power law in time
            // grows geometrically per step, and that algorithm bounds its coupling error itself
            watch: super::divergence::Watch::new(
                coupled_len,
                if opts.algorithm == Algorithm::Adaptive {
                    f64::INFINITY
                } else {
                    opts.divergence_growth
                },
                1e3 * opts.abs_tol,
            ),
            opts,
            stats,
        })
    }

    pub fn system(&self) -> &System {
        self.sys
    }

    /// Runs from the start to the stop time, calling `observe(time, system)` after initialization
    /// and after every accepted step (call [`read_recorded`] there before reading variables that
    /// only the recorder uses). On an error, everything observed so far stands.
    pub fn run(
        &mut self,
        mut observe: impl FnMut(f64, &mut System) -> Result<(), MasterError>,
    ) -> Result<(), MasterError> {
        let t0 = self.sys.start_time;
        let stop = self.opts.stop_time;
        observe(t0, self.sys)?;
        let can_shorten = self.sys.units.iter().all(|u| u.can_vary_step);
        let mut t = t0;
        let mut h = self.opts.step;
        let mut k: u64 = 0;
        // a step shorter than this fraction of h at the end is rounding, not a step
        let eps = 1e-9 * self.opts.step;
        while stop - t > eps {
            let adaptive = self.opts.algorithm == Algorithm::Adaptive;
            // fixed steps: t_k = t0 + k·h, so 10⁶ steps accumulate no round-off
            let mut h_k = if adaptive { h.min(stop - t) } else { self.opts.step };
            if !adaptive && t0 + (k + 1) as f64 * h_k > stop + eps {
                if !can_shorten {
                    self.stats.stopped_early = true;
                    break;
                }
                h_k = stop - t;
            }
            match self.opts.algorithm {
                // neither retakes a step: a kept row's variables are read with the coupled outputs
                Algorithm::Jacobi => self.sweep(t, h_k, false, false, self.sys.record_next)?,
                Algorithm::GaussSeidel => self.sweep(t, h_k, true, false, self.sys.record_next)?,
                Algorithm::Iterative => self.iterate(t, h_k)?,
                Algorithm::Adaptive => {
                    let (taken, next) = self.adaptive(t, h_k)?;
                    h_k = taken;
                    h = next;
                }
            }
            k += 1;
            t = if !adaptive && h_k == self.opts.step {
                t0 + k as f64 * h_k
            } else {
                t + h_k
            };
            if stop - t <= eps {
                t = stop;
            }
            self.accept(t, h_k);
            observe(t, self.sys)?;
            let units = &self.sys.units;
            if let Some(d) = self
                .watch
                .observe(self.coupled.iter().map(|&(u, i)| units[u].values[i]))
            {
                return Err(self.diverged(d, t, h_k));
            }
        }
        Ok(())
    }

    /// The error naming a diverging coupling: its source variable and the units that read it.
    fn diverged(&self, d: super::divergence::Diverged, t: f64, h: f64) -> MasterError {
        let (su, si) = self.coupled[d.variable];
        let units = &self.sys.units;
        let consumers: Vec<&str> = units
            .iter()
            .filter(|u| u.real_in.links.iter().any(|l| l.src_unit == su && l.src == si))
            .map(|u| u.name.as_str())
            .collect();
        MasterError::Diverged {
            variable: format!("{}.{}", units[su].name, units[su].fetch_names[si]),
            consumers: consumers.join(", "),
            time: t,
            from: d.from,
            to: d.to,
            steps: d.steps,
            step: h,
        }
    }

    fn accept(&mut self, t: f64, h: f64) {
        self.stats.steps += 1;
        self.stats.final_time = t;
        self.stats.min_step_taken = self.stats.min_step_taken.min(h);
        self.stats.max_step_taken = self.stats.max_step_taken.max(h);
        if self.opts.order > 0 {
            // shift history: hist[1] <- hist[0] <- start (values at t - h)
            self.hist.swap(0, 1);
            std::mem::swap(&mut self.hist[0], &mut self.start);
            self.hist_t[1] = self.hist_t[0];
            self.hist_t[0] = t - h;
            self.hist_len = (self.hist_len + 1).min(2);
        }
        for (s, u) in self.start.iter_mut().zip(&self.sys.units) {
            s.copy_from_slice(&u.values);
        }
        for (p, &(u, i)) in self.peak.iter_mut().zip(&self.coupled) {
            *p = p.max(self.sys.units[u].values[i].abs());
        }
    }

    /// The input polynomial (a0, a1, a2) of one source over [t, t+h].
    fn source_polynomial(&self, su: usize, i: usize, t: f64, h: f64) -> [f64; 3] {
        let y0 = self.start[su][i];
        if self.known[su] {
            let end = self.sys.units[su].values[i];
            return if self.opts.order == 0 {
                [end, 0.0, 0.0]
            } else {
                [y0, (end - y0) / h, 0.0]
            };
        }
        match self.opts.order.min(self.hist_len) {
            0 => [y0, 0.0, 0.0],
            1 => {
                let (t1, y1) = (self.hist_t[0], self.hist[0][su][i]);
                [y0, (y0 - y1) / (t - t1), 0.0]
            }
            _ => {
                let (t1, y1) = (self.hist_t[0], self.hist[0][su][i]);
                let (t2, y2) = (self.hist_t[1], self.hist[1][su][i]);
                let f01 = (y0 - y1) / (t - t1);
                let f12 = (y1 - y2) / (t1 - t2);
                let f012 = (f01 - f12) / (t - t2);
                [y0, f01 + f012 * (t - t1), 2.0 * f012]
            }
        }
    }

    /// Gives unit `u` its inputs for the step [t, t+h].
    fn set_inputs(&mut self, u: usize, t: f64, h: f64) -> Result<(), MasterError> {
        let mut a = std::mem::take(&mut self.a);
        a.clear();
        for l in &self.sys.units[u].real_in.links {
            let p = self.source_polynomial(l.src_unit, l.src, t, h);
            a.push([l.factor * p[0] + l.offset, l.factor * p[1], l.factor * p[2]]);
        }
        let order = self.opts.order;
        let unit = &mut self.sys.units[u];
        let interpolate = unit.can_interpolate_inputs && order > 0;
        for (k, p) in a.iter().enumerate() {
            if interpolate {
                unit.u_real[k] = p[0];
                unit.du1[k] = p[1];
                unit.du2[k] = p[2];
            } else {
                // mean of the polynomial over the step
                unit.u_real[k] = p[0] + p[1] * h / 2.0 + p[2] * h * h / 6.0;
            }
        }
        self.a = a;
        let fail = |unit: &Unit, error| MasterError::Step {
            component: unit.name.clone(),
            time: t,
            error,
        };
        if !unit.real_in.vr.is_empty() {
            let r = unit.instance.set_real(&unit.real_in.vr, &unit.u_real);
            r.map_err(|e| fail(unit, e))?;
            if interpolate {
                let r = unit.instance.set_real_input_derivatives(&unit.real_in.vr, 1, &unit.du1);
                r.map_err(|e| fail(unit, e))?;
                if order == 2 {
                    let r = unit.instance.set_real_input_derivatives(&unit.real_in.vr, 2, &unit.du2);
                    r.map_err(|e| fail(unit, e))?;
                }
            }
        }
        DiscreteInputs::send(&mut self.sys.units, u).map_err(|e| fail(&self.sys.units[u], e))
    }

    /// One pass over all units for [t, t+h]. Jacobi: every unit's inputs from the values at t
    /// (or the previous iterate), then all steps, on worker threads if asked. Gauss–Seidel: unit by
    /// unit in the scene's order, each seeing its predecessors' new values.
    /// `ends_known`: every unit's values already hold an estimate at t+h (a previous iterate);
    /// otherwise sources are extrapolated until they step. `with_recorded`: the sweep is final and its
    /// row kept, each unit reads the recorder's variables with its coupled outputs.
    fn sweep(
        &mut self,
        t: f64,
        h: f64,
        gauss_seidel: bool,
        ends_known: bool,
        with_recorded: bool,
    ) -> Result<(), MasterError> {
        self.stats.sweeps += 1;
        self.known.fill(ends_known);
        let n = self.sys.units.len();
        if gauss_seidel {
            for u in 0..n {
                self.set_inputs(u, t, h)?;
                step_unit(&mut self.sys.units[u], t, h, with_recorded)?;
                self.known[u] = true;
            }
        } else {
            for u in 0..n {
                self.set_inputs(u, t, h)?;
            }
            match &self.pool {
                Some(pool) => {
                    use rayon::prelude::*;
                    let units = &mut self.sys.units;
                    pool.install(|| {
                        units
                            .par_iter_mut()
                            .try_for_each(|unit| step_unit(unit, t, h, with_recorded))
                    })?;
                }
                None => {
                    for unit in &mut self.sys.units {
                        step_unit(unit, t, h, with_recorded)?;
                    }
                }
            }
            self.known.fill(true);
        }
        Ok(())
    }

    /// Runs `f` on every unit, naming the unit and time `t` in an error.
    fn each_unit(&mut self, t: f64, f: impl Fn(&mut Unit) -> Result<(), ImportError>) -> Result<(), MasterError> {
        for unit in &mut self.sys.units {
            f(unit).map_err(|error| MasterError::Step {
                component: unit.name.clone(),
                time: t,
                error,
            })?;
        }
        Ok(())
    }

    fn save_all(&mut self, t: f64) -> Result<(), MasterError> {
        self.each_unit(t, Unit::save_state)
    }

    fn restore_all(&mut self, t: f64) -> Result<(), MasterError> {
        self.each_unit(t, |u| u.restore_state())
    }

    /// Largest coupling change relative to the tolerance between `reference` and the current values.
    fn coupling_error(&self, reference: impl Fn(usize, usize, usize) -> f64) -> f64 {
        self.coupled
            .iter()
            .enumerate()
            .map(|(k, &(u, i))| {
                let y = self.sys.units[u].values[i];
                let scale = y.abs().max(self.peak[k]);
                (y - reference(k, u, i)).abs() / (self.opts.abs_tol + self.opts.rel_tol * scale)
            })
            .fold(0.0, f64::max)
    }

    /// Iterative coupling: Gauss–Seidel sweeps from the saved state until the coupled outputs at
    /// t+h change less than the tolerance between two sweeps, at most `max_iterations` sweeps. The
    /// end values each sweep starts from are the previous sweep's outputs, or with an
    /// [`Acceleration`] the accelerated iterate (`acceleration.rs`).
    fn iterate(&mut self, t: f64, h: f64) -> Result<(), MasterError> {
        self.save_all(t)?;
        let kind = self.opts.acceleration;
        let (mut x, mut g) = (std::mem::take(&mut self.iterate_x), std::mem::take(&mut self.iterate_g));
        if kind != Acceleration::None {
            // the first sweep's consumers get the sources' extrapolations: its iterate is their end
            self.known.fill(false);
            x.clear();
            for &(u, i) in &self.coupled {
                let p = self.source_polynomial(u, i, t, h);
                x.push(p[0] + p[1] * h + p[2] * h * h / 2.0);
            }
            let scale: Vec<f64> = (self.coupled.iter().zip(&self.peak))
                .map(|(&(u, i), peak)| self.opts.abs_tol + self.opts.rel_tol * self.start[u][i].abs().max(*peak))
                .collect();
            self.accelerator.start(scale.into_iter());
        }
        self.sweep(t, h, true, false, false)?;
        let result = self.iterate_sweeps(t, h, kind, &mut x, &mut g);
        (self.iterate_x, self.iterate_g) = (x, g);
        result
    }

    fn iterate_sweeps(
        &mut self,
        t: f64,
        h: f64,
        kind: Acceleration,
        x: &mut [f64],
        g: &mut Vec<f64>,
    ) -> Result<(), MasterError> {
        for _ in 1..self.opts.max_iterations {
            g.clear();
            g.extend(self.coupled.iter().map(|&(u, i)| self.sys.units[u].values[i]));
            if kind == Acceleration::None {
                self.previous_iterate.copy_from_slice(g);
            } else {
                self.accelerator.next(kind, x, g);
                self.previous_iterate.copy_from_slice(x);
                for (&(u, i), &v) in self.coupled.iter().zip(x.iter()) {
                    self.sys.units[u].values[i] = v;
                }
            }
            self.restore_all(t)?;
            self.sweep(t, h, true, true, false)?;
            if self.coupling_error(|k, _, _| self.previous_iterate[k]) <= 1.0 {
                return Ok(());
            }
        }
        if self.opts.max_iterations > 1 && !self.coupled.is_empty() {
            self.stats.unconverged += 1;
        }
        Ok(())
    }

    /// Adaptive macro step: a Gauss–Seidel sweep with extrapolated inputs, then the coupling
    /// error = the difference between each coupled output at t+h and the polynomial its consumers
    /// were given. Rejected steps are rolled back and retried shorter; the next step follows the
    /// error with exponent 1/(order+1), growth at most 2×.
    fn adaptive(&mut self, t: f64, mut h: f64) -> Result<(f64, f64), MasterError> {
        let exponent = 1.0 / (self.opts.order as f64 + 1.0);
        let (min_h, max_h) = (self.opts.min_step, self.opts.max_step);
        self.save_all(t)?;
        loop {
            self.known.fill(false);
            let predicted: Vec<f64> = self
                .coupled
                .iter()
                .map(|&(u, i)| {
                    let p = self.source_polynomial(u, i, t, h);
                    p[0] + p[1] * h + p[2] * h * h / 2.0
                })
                .collect();
            self.sweep(t, h, true, false, false)?;
            let err = self.coupling_error(|k, _, _| predicted[k]);
            let factor = if err > 0.0 { 0.9 * err.powf(-exponent) } else { 2.0 };
            if err <= 1.0 || h <= min_h * (1.0 + 1e-12) {
                let next = (h * factor.clamp(0.2, 2.0)).clamp(min_h, max_h);
                return Ok((h, next));
            }
            self.stats.rejected += 1;
            self.restore_all(t)?;
            for (s, u) in self.start.iter().zip(self.sys.units.iter_mut()) {
                u.values.copy_from_slice(s);
            }
            h = (h * factor.clamp(0.2, 0.9)).max(min_h);
        }
    }
}

/// Runs a built scene with Gauss–Seidel at 1 ms from initialisation to `stop` and returns time and the
/// channels, in memory: for analyses that read a few series of a short run.
pub fn run_columns(
    scene: &super::Scene,
    overrides: &[(String, String, String)],
    channels: &[&str],
    stop: Option<f64>,
) -> Result<Vec<Vec<f64>>, Box<dyn std::error::Error + Send + Sync>> {
    let stop = stop
        .or(scene.experiment.stop_time)
        .ok_or_else(|| format!("scene {}: no stop time", scene.name))?;
    let opts = Options::new(Algorithm::GaussSeidel, 1e-3, stop);
    Ok(run_columns_with(scene, overrides, channels, opts)?.columns)
}

/// A scene run kept in memory: time and the channels, what stepping it cost and the master's counts.
pub struct ColumnRun {
    pub columns: Vec<Vec<f64>>,
    /// CPU time of the calling thread from the first to the last macro step (loading and
    /// initialising the FMUs left out), s.
    pub cpu_s: f64,
    pub stats: Stats,
}

/// As [`run_columns`] with the master's options given (algorithm, macro step, order, stop time).
pub fn run_columns_with(
    scene: &super::Scene,
    overrides: &[(String, String, String)],
    channels: &[&str],
    opts: Options,
) -> Result<ColumnRun, Box<dyn std::error::Error + Send + Sync>> {
    let names: Vec<String> = channels.iter().map(|c| c.to_string()).collect();
    let mut system = super::System::build(scene, overrides, &super::Record::Only(names))?;
    system.initialize(Some(opts.stop_time))?;
    let mut out: Vec<Vec<f64>> = vec![Vec::new(); channels.len() + 1];
    let mut master = Master::new(&mut system, opts)?;
    let start = thread_cpu_seconds();
    master.run(|time, sys| {
        read_every_row(sys, time)?;
        out[0].push(time);
        for (k, (_, u, i)) in sys.recorded.iter().enumerate() {
            out[k + 1].push(sys.units[*u].values[*i]);
        }
        Ok(())
    })?;
    let cpu_s = thread_cpu_seconds() - start;
    let stats = master.stats.clone();
    system.terminate();
    Ok(ColumnRun {
        columns: out,
        cpu_s,
        stats,
    })
}

/// CPU time every thread of this process has used, s (the calling thread's and any worker's, a
/// results writer's for one).
pub fn process_cpu_seconds() -> f64 {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: clock_gettime writes into the timespec we own; CLOCK_PROCESS_CPUTIME_ID exists on Linux.
    unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// CPU time the calling thread has used, s: what a run costs, unlike wall time not counting the
/// neighbours that share the machine.
pub fn thread_cpu_seconds() -> f64 {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: clock_gettime writes into the timespec we own; CLOCK_THREAD_CPUTIME_ID exists on Linux.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}
