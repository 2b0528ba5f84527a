//! One instantiated component as the master sees it: the values it fetches after every step, the
//! inputs it receives and where they come from, and its saved FMU state for rollback.

use crate::fmi2::host::description::ScalarVariable;
use crate::fmi2::host::error::ImportError;
use crate::fmi2::host::import::{Fmu, Instance};
use crate::fmi2::host::state::SavedState;
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

/// Variables read together into a slice of `Unit::values`: Real first, then Integer, then Boolean.
#[derive(Debug, Default)]
pub struct VarGroup {
    pub real: Vec<u32>,
    pub integer: Vec<u32>,
    pub boolean: Vec<u32>,
    /// Where the group starts in `Unit::values`.
    pub offset: usize,
}

impl VarGroup {
    pub fn len(&self) -> usize {
        self.real.len() + self.integer.len() + self.boolean.len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Reads the group into `values[offset..offset + len]`.
    fn read(
        &self,
        instance: &mut Instance,
        values: &mut [f64],
        ints: &mut Vec<i32>,
        bools: &mut Vec<bool>,
    ) -> Result<(), ImportError> {
        let nr = self.real.len();
        if nr > 0 {
            instance.get_real(&self.real, &mut values[self.offset..self.offset + nr])?;
        }
        if self.len() > nr {
            self.read_discrete(instance, values, ints, bools)?;
        }
        Ok(())
    }

    /// Reads the group's Integer and Boolean variables into their places in `values`.
    #[inline]
    fn read_discrete(
        &self,
        instance: &mut Instance,
        values: &mut [f64],
        ints: &mut Vec<i32>,
        bools: &mut Vec<bool>,
    ) -> Result<(), ImportError> {
        let (nr, ni) = (self.real.len(), self.integer.len());
        let out = &mut values[self.offset..self.offset + self.len()];
        if ni > 0 {
            ints.resize(ni, 0);
            instance.get_integer(&self.integer, ints)?;
            for (v, i) in out[nr..nr + ni].iter_mut().zip(ints.iter()) {
                *v = f64::from(*i);
            }
        }
        if !self.boolean.is_empty() {
            bools.resize(self.boolean.len(), false);
            instance.get_boolean(&self.boolean, bools)?;
            for (v, b) in out[nr + ni..].iter_mut().zip(bools.iter()) {
                *v = f64::from(u8::from(*b));
            }
        }
        Ok(())
    }
}

/// One instantiated component.
pub struct Unit {
    pub name: String,
    pub instance: Instance,
    pub fmu: Arc<Fmu>,
    pub can_interpolate_inputs: bool,
    pub can_get_set_state: bool,
    pub can_vary_step: bool,
    /// Outputs other units read: fetched after every step.
    pub coupled: VarGroup,
    /// Variables only the recorder reads: fetched when it keeps a row (after `coupled` in `values`).
    pub recorded_only: VarGroup,
    /// The coupled Reals, then the recorder's: [`Unit::fetch_with_recorded`]'s one fmi2GetReal.
    pub joined_real: Vec<u32>,
    /// Scratch for the joined read.
    pub joined_values: Vec<f64>,
    /// Whether `values` holds the recorder's variables of the last step already (read with the
    /// coupled outputs, [`Unit::fetch_with_recorded`]), so that the recorder does not read them again.
    pub recorded_fresh: bool,
    /// Name of every entry of `values`.
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
    /// The Integer and Boolean input values the FMU holds, and scratch to gather the next ones.
    pub discrete_held: DiscreteInputs,
    pub discrete_scratch: DiscreteInputs,
    /// Wall time this unit spent, when a bench or `run --profile` asks for it (None: not timed; the
    /// clock costs two readings per call timed).
    pub clock: Option<Clock>,
}

/// A unit's wall time, split by what the master asked of it.
#[derive(Debug, Clone, Copy, Default)]
pub struct Clock {
    /// doStep and the coupled outputs' getters after it.
    pub step: std::time::Duration,
    /// Of `step`, the doStep calls alone (the rest are the coupled outputs' getters).
    pub do_step: std::time::Duration,
    /// The getters of the variables only the recorder reads, when the recorder calls them.
    pub recorded: std::time::Duration,
    /// Of `step`, the joined getters after a step whose row is kept ([`Unit::fetch_with_recorded`]):
    /// the coupled outputs' and the recorder's variables together, counted as recorded reads.
    pub recorded_with_step: std::time::Duration,
}

impl Clock {
    pub fn total(&self) -> std::time::Duration {
        self.step + self.recorded
    }

    /// The steps less the joined getters, and every getter of the recorder's variables.
    pub fn steps_and_reads(&self) -> (std::time::Duration, std::time::Duration) {
        let joined = self.recorded_with_step.min(self.step);
        (self.step - joined, self.recorded + joined)
    }
}

impl Drop for Unit {
    fn drop(&mut self) {
        if let Some(s) = self.saved.take() {
            let _ = self.instance.free_state(s);
        }
    }
}

impl Unit {
    /// Reads the coupled outputs into `values`.
    pub fn fetch(&mut self) -> Result<(), ImportError> {
        self.recorded_fresh = false;
        self.coupled.read(
            &mut self.instance,
            &mut self.values,
            &mut self.scratch_int,
            &mut self.scratch_bool,
        )
    }

    /// Reads the coupled outputs and the recorder's variables, the Reals of both in one fmi2GetReal:
    /// after a step whose row the recorder keeps. The values [`Unit::fetch`] and
    /// [`Unit::fetch_recorded`] would read, with one call across the FMI boundary less per step (on
    /// an FMU of ours a call costs about 260 instructions besides its values, callgrind; through
    /// `--isolate` a round trip to the FMU's process).
    pub fn fetch_with_recorded(&mut self) -> Result<(), ImportError> {
        if self.recorded_only.is_empty() {
            return self.fetch();
        }
        let (c, r) = (&self.coupled, &self.recorded_only);
        let (nc, nr) = (c.real.len(), r.real.len());
        if c.len() == nc {
            // no discrete coupled outputs: both groups' Reals lie side by side in `values`
            self.instance
                .get_real(&self.joined_real, &mut self.values[c.offset..r.offset + nr])?;
        } else {
            self.joined_values.resize(nc + nr, 0.0);
            self.instance.get_real(&self.joined_real, &mut self.joined_values)?;
            self.values[c.offset..c.offset + nc].copy_from_slice(&self.joined_values[..nc]);
            self.values[r.offset..r.offset + nr].copy_from_slice(&self.joined_values[nc..]);
            c.read_discrete(
                &mut self.instance,
                &mut self.values,
                &mut self.scratch_int,
                &mut self.scratch_bool,
            )?;
        }
        if r.len() > nr {
            r.read_discrete(
                &mut self.instance,
                &mut self.values,
                &mut self.scratch_int,
                &mut self.scratch_bool,
            )?;
        }
        self.recorded_fresh = true;
        Ok(())
    }

    /// Reads the variables only the recorder needs.
    pub fn fetch_recorded(&mut self) -> Result<(), ImportError> {
        self.recorded_only.read(
            &mut self.instance,
            &mut self.values,
            &mut self.scratch_int,
            &mut self.scratch_bool,
        )
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
        self.discrete_held.held = false;
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

/// What a unit's Integer and Boolean inputs were last set to, so that an unchanged value (a brake
/// command, a mode switch: they change a few times per run) costs no call. Forgotten when the FMU's
/// state is restored: a restored state holds the inputs it was taken with (FMI 2.0 §2.1.8), and an
/// FMU that gets this wrong must not be left with a value nobody sent (one call per restore).
#[derive(Debug, Default)]
pub struct DiscreteInputs {
    integers: Vec<i32>,
    booleans: Vec<bool>,
    /// Whether `integers` and `booleans` are what the FMU holds.
    held: bool,
}

impl DiscreteInputs {
    /// Sets unit `u`'s Integer and Boolean inputs to their sources' current values, calling the FMU
    /// only for a kind whose values changed.
    pub fn send(units: &mut [Unit], u: usize) -> Result<(), ImportError> {
        let mut next = std::mem::take(&mut units[u].discrete_scratch);
        next.integers.clear();
        next.booleans.clear();
        let value = |l: &Link| units[l.src_unit].values[l.src];
        next.integers
            .extend(units[u].integer_in.links.iter().map(|l| value(l) as i32));
        next.booleans
            .extend(units[u].boolean_in.links.iter().map(|l| value(l) != 0.0));
        let unit = &mut units[u];
        let result = unit.set_discrete(&next);
        unit.discrete_scratch = next;
        result
    }
}

impl Unit {
    fn set_discrete(&mut self, next: &DiscreteInputs) -> Result<(), ImportError> {
        let held = &mut self.discrete_held;
        if !next.integers.is_empty() && (!held.held || held.integers != next.integers) {
            held.held = false;
            self.instance.set_integer(&self.integer_in.vr, &next.integers)?;
            held.integers.clone_from(&next.integers);
        }
        if !next.booleans.is_empty() && (!held.held || held.booleans != next.booleans) {
            held.held = false;
            self.instance.set_boolean(&self.boolean_in.vr, &next.booleans)?;
            held.booleans.clone_from(&next.booleans);
        }
        held.integers.resize(next.integers.len(), 0);
        held.booleans.resize(next.booleans.len(), false);
        held.held = true;
        Ok(())
    }
}
