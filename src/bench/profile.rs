//! Where an implicit step's time goes, without a profiler: [`Timed`] wraps any model and adds up the
//! wall time spent in the model's own code (forces, tangent, contact pattern), so a bench can print
//! model against solver (the rest of `Driver::advance`: factorisations, solves, the step's
//! bookkeeping). The clock costs ~50 ns per model call, nothing beside a gearbox step's 100 µs.

use crate::solver::system::{Friction, InputLoad, Linearisation, Linearity, Mass, SecondOrderSystem};
use nalgebra::DMatrix;
use std::cell::Cell;
use std::time::{Duration, Instant};

/// A model whose calls are timed; it computes exactly what the model does.
pub struct Timed<'a, S> {
    inner: &'a S,
    model: Cell<Duration>,
}

impl<'a, S: SecondOrderSystem> Timed<'a, S> {
    pub fn new(inner: &'a S) -> Self {
        Self {
            inner,
            model: Cell::new(Duration::ZERO),
        }
    }

    /// Wall time spent in the model's code so far, s.
    pub fn model_s(&self) -> f64 {
        self.model.get().as_secs_f64()
    }

    fn timed<R>(&self, f: impl FnOnce() -> R) -> R {
        let start = Instant::now();
        let r = f();
        self.model.set(self.model.get() + start.elapsed());
        r
    }
}

impl<S: SecondOrderSystem> SecondOrderSystem for Timed<'_, S> {
    fn dofs(&self) -> usize {
        self.inner.dofs()
    }
    fn linearity(&self) -> Linearity {
        self.inner.linearity()
    }
    fn mass(&self) -> Mass<'_> {
        self.inner.mass()
    }
    fn input_loads(&self) -> &[InputLoad] {
        self.inner.input_loads()
    }
    fn internal_forces(&self, t: f64, q: &[f64], v: &[f64], out: &mut [f64]) {
        self.timed(|| self.inner.internal_forces(t, q, v, out))
    }
    fn add_tangent(&self, t: f64, q: &[f64], v: &[f64], c_c: f64, c_k: f64, j: &mut DMatrix<f64>) {
        self.timed(|| self.inner.add_tangent(t, q, v, c_c, c_k, j))
    }
    fn factor_key(&self, t: f64, q: &[f64], key: &mut Vec<u64>) {
        self.timed(|| self.inner.factor_key(t, q, key))
    }
    fn friction(&self, u: &[f64]) -> Option<Friction> {
        self.inner.friction(u)
    }
    fn rigid_mode(&self) -> Option<(&[f64], usize)> {
        self.inner.rigid_mode()
    }
    fn linearise(&self, q: &[f64], v: &[f64]) -> Linearisation {
        self.timed(|| self.inner.linearise(q, v))
    }
}
