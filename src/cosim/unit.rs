//! One instantiated component as the master sees it: the values it fetches after every step, the
//! inputs it receives and where they come from, and its saved FMU state for rollback.

use crate::fmi2::description::ScalarVariable;
use crate::fmi2::import::{Fmu, ImportError, Instance, SavedState};
use std::sync::Arc;

/// Kinds of values a master moves between FMUs. Enumerations travel as Integer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Kind {
    Real,
    Integer,
    Boolean,
}

pub(super) fn kind_of(v: &ScalarVariable) -> Option<Kind> {
    match v.type_name() {
        "Real" => Some(Kind::Real),
        "Integer" | "Enumeration" => Some(Kind::Integer),
        "Boolean" => Some(Kind::Boolean),
        _ => None,
    }
}

/// One connected input: where its value comes from and the linear transformation on the way.
#[derive(Debug, Clone, Copy)]
pub struct Link {
    pub src_unit: usize,
    /// Index into the source unit's fetched values.
    pub src: usize,
    pub factor: f64,
    pub offset: f64,
}

/// Inputs of one kind a unit receives: value references, their sources and the values set.
#[derive(Debug, Default)]
pub struct Inputs {
    pub vr: Vec<u32>,
    pub links: Vec<Link>,
}

/// One instantiated component.
pub struct Unit {
    pub name: String,
    pub instance: Instance,
    pub fmu: Arc<Fmu>,
    pub can_interpolate_inputs: bool,
    pub can_get_set_state: bool,
    pub can_vary_step: bool,
    /// Variables read after every step, Real first, then Integer, then Boolean: `values` holds
    /// them in that order.
    pub fetch_real: Vec<u32>,
    pub fetch_integer: Vec<u32>,
    pub fetch_boolean: Vec<u32>,
    pub fetch_names: Vec<String>,
    pub values: Vec<f64>,
    pub real_in: Inputs,
    pub integer_in: Inputs,
    pub boolean_in: Inputs,
    /// Scratch for inputs and non-real fetches, reused every step.
    pub u_real: Vec<f64>,
    pub du1: Vec<f64>,
    pub du2: Vec<f64>,
    pub scratch_int: Vec<i32>,
    pub scratch_bool: Vec<bool>,
    pub saved: Option<SavedState>,
}

impl Drop for Unit {
    fn drop(&mut self) {
        if let Some(s) = self.saved.take() {
            let _ = self.instance.free_state(s);
        }
    }
}

impl Unit {
    /// Reads every fetched variable into `values`.
    pub fn fetch(&mut self) -> Result<(), ImportError> {
        let nr = self.fetch_real.len();
        let ni = self.fetch_integer.len();
        if nr > 0 {
            self.instance.get_real(&self.fetch_real, &mut self.values[..nr])?;
        }
        if ni > 0 {
            self.scratch_int.resize(ni, 0);
            self.instance.get_integer(&self.fetch_integer, &mut self.scratch_int)?;
            for (v, i) in self.values[nr..nr + ni].iter_mut().zip(&self.scratch_int) {
                *v = f64::from(*i);
            }
        }
        if !self.fetch_boolean.is_empty() {
            self.scratch_bool.resize(self.fetch_boolean.len(), false);
            self.instance.get_boolean(&self.fetch_boolean, &mut self.scratch_bool)?;
            for (v, b) in self.values[nr + ni..].iter_mut().zip(&self.scratch_bool) {
                *v = f64::from(u8::from(*b));
            }
        }
        Ok(())
    }

    /// Saves the FMU state, reusing the previous snapshot's memory.
    pub fn save_state(&mut self) -> Result<(), ImportError> {
        match &mut self.saved {
            Some(s) => self.instance.update_state(s),
            None => {
                self.saved = Some(self.instance.get_state()?);
                Ok(())
            }
        }
    }

    pub fn restore_state(&mut self) -> Result<(), ImportError> {
        match &self.saved {
            Some(s) => self.instance.set_state(s),
            None => unreachable!("restore_state before save_state"),
        }
    }

    /// Index in `values` of a fetched variable.
    pub fn value_index(&self, name: &str) -> Option<usize> {
        self.fetch_names.iter().position(|n| n == name)
    }
}

/// Integer and Boolean inputs of one unit: always the source's current value.
pub struct DiscreteInputs {
    integers: Vec<i32>,
    booleans: Vec<bool>,
}

impl DiscreteInputs {
    pub fn of(units: &[Unit], u: usize) -> Self {
        let value = |l: &Link| units[l.src_unit].values[l.src];
        Self {
            integers: units[u].integer_in.links.iter().map(|l| value(l) as i32).collect(),
            booleans: units[u].boolean_in.links.iter().map(|l| value(l) != 0.0).collect(),
        }
    }

    pub fn set(&self, unit: &mut Unit) -> Result<(), ImportError> {
        if !self.integers.is_empty() {
            unit.instance.set_integer(&unit.integer_in.vr, &self.integers)?;
        }
        if !self.booleans.is_empty() {
            unit.instance.set_boolean(&unit.boolean_in.vr, &self.booleans)?;
        }
        Ok(())
    }
}
