//! The contract between a physics model and the FMI export adapter: a plain Rust trait with no raw
//! pointers. The adapter (export.rs) owns the state machine, argument checks and logging.

use super::error::{SlaveError, SlaveResult, err};
use super::variables::{VarType, Variable};
use serde::{Deserialize, Serialize, de::DeserializeOwned};
use std::path::Path;

/// What setting a parameter or input by value reference changed (generated `set_*` functions).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Changed {
    /// A parameter: whatever was built from the parameters is stale.
    Parameter,
    /// An input value (its derivatives are cleared).
    Input,
}

/// The refusal to set a variable that is neither a parameter nor an input, naming it.
pub fn cannot_set(var: Option<&Variable>, ty: VarType, vr: u32) -> SlaveError {
    match var {
        Some(v) => err(format!("{} ({:?} {ty:?}) cannot be set", v.name, v.causality)),
        None => err(format!("{ty:?} value reference {vr} cannot be set")),
    }
}

/// The refusal to read a variable the model has no getter for, naming it.
pub fn no_getter(var: Option<&Variable>, ty: VarType, vr: u32) -> SlaveError {
    match var {
        Some(v) => err(format!("{} ({:?} {ty:?}) has no getter", v.name, v.causality)),
        None => err(format!("{ty:?} value reference {vr} has no getter")),
    }
}

/// Clamps an input to the XML's min/max, with a warning naming it when it was outside. Inlined into
/// the generated setters (a master sets such an input every step); the warning stays out of line.
#[inline]
pub fn clamp_input(name: &str, value: f64, min: Option<f64>, max: Option<f64>, log: &mut dyn Log) -> f64 {
    let (lo, hi) = (min.unwrap_or(f64::NEG_INFINITY), max.unwrap_or(f64::INFINITY));
    if (lo..=hi).contains(&value) {
        return value;
    }
    clamp_with_warning(name, value, (lo, hi), log)
}

#[cold]
#[inline(never)]
fn clamp_with_warning(name: &str, value: f64, (lo, hi): (f64, f64), log: &mut dyn Log) -> f64 {
    log.warning(&format!("{name} = {value} outside [{lo}, {hi}], clamped"));
    value.clamp(lo, hi)
}

/// One Real input with the time derivatives a master may send (fmi2SetRealInputDerivatives,
/// orders 1 and 2): u(τ) = u + u'·τ + u''·τ²/2 after the communication point. Setting the value
/// clears the derivatives; a step moves the expansion point along the polynomial.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct InputPolynomial(pub [f64; 3]);

impl InputPolynomial {
    pub fn new(value: f64) -> Self {
        Self([value, 0.0, 0.0])
    }

    pub fn value(&self) -> f64 {
        self.0[0]
    }

    pub fn set(&mut self, value: f64) {
        self.0 = [value, 0.0, 0.0];
    }

    pub fn set_derivative(&mut self, order: i32, value: f64) -> SlaveResult<()> {
        match order {
            1 | 2 => {
                self.0[order as usize] = value;
                Ok(())
            }
            _ => Err(err(format!("derivative order {order} not supported (1 or 2)"))),
        }
    }

    /// u(τ)
    pub fn at(&self, tau: f64) -> f64 {
        let w = self.0;
        w[0] + tau * w[1] + 0.5 * tau * tau * w[2]
    }

    /// ∫₀^τ u(s) ds, exact for the polynomial.
    pub fn integral(&self, tau: f64) -> f64 {
        let w = self.0;
        // without a second derivative (a host that sets no derivatives) τ·w₂ is a zero, which the
        // division by 6 leaves as it is: the same bits without the division, whose latency the
        // torsional FMU's step waited for three times (perf)
        let quadratic = if w[2] == 0.0 { tau * w[2] } else { tau * w[2] / 6.0 };
        tau * (w[0] + tau * (w[1] / 2.0 + quadratic))
    }

    /// Moves the expansion point forward by `h`.
    pub fn advance(&mut self, h: f64) {
        let w = self.0;
        self.0 = [self.at(h), w[1] + h * w[2], w[2]];
    }
}

/// What a model may say through the host's logger while it works.
pub trait Log {
    /// A warning (category logStatusWarning); the call that emits it answers fmi2Warning.
    fn warning(&mut self, msg: &str);
    /// A model event such as a brake locking (category logEvents).
    fn event(&mut self, msg: &str);
}

/// A logger that drops everything: for models driven from Rust (tests, the command line).
pub struct NoLog;

impl Log for NoLog {
    fn warning(&mut self, _: &str) {}
    fn event(&mut self, _: &str) {}
}

/// A Co-Simulation model. Value references reaching these methods already exist in `VARIABLES`
/// with the right type, and the call is legal in the current FMI state; Real values are finite.
/// What most FMUs refuse (types they have no variable of, setting outputs) has a default that
/// refuses by the variable's name; parameters and inputs are dispatched by the generated
/// `models::<name>::{get_*, set_*}` functions.
pub trait Slave: Sized + Clone + Send + Serialize + DeserializeOwned + 'static {
    const MODEL_IDENTIFIER: &'static str;
    const GUID: &'static str;
    const MODEL_DESCRIPTION_XML: &'static str;
    const VARIABLES: &'static [Variable];

    /// The variable with this type and value reference (generated O(1) lookup).
    fn variable(ty: VarType, vr: u32) -> Option<&'static Variable>;

    /// A new instance with every start value of the XML applied (importers do not apply them).
    fn instantiate(resources: Option<&Path>) -> Self;

    fn get_real(&mut self, vr: u32) -> SlaveResult<f64>;
    /// Several Real values at once, `out[k]` for `vrs[k]` (one fmi2GetReal with an array: a master
    /// reads a row of recorded variables in one call). By default [`Slave::get_real`] for each; a
    /// model overrides it to check its state and compute what the values share once per call. It
    /// must answer exactly what `get_real` answers value by value; on an error the adapter asks again
    /// value by value for the message, so the error need not name anything.
    fn get_reals(&mut self, vrs: &[u32], out: &mut [f64]) -> SlaveResult<()> {
        for (r, o) in vrs.iter().zip(out) {
            *o = self.get_real(*r)?;
        }
        Ok(())
    }
    fn set_real(&mut self, vr: u32, value: f64, log: &mut dyn Log) -> SlaveResult<()>;
    fn get_integer(&mut self, vr: u32) -> SlaveResult<i32> {
        Err(no_getter(Self::variable(VarType::Integer, vr), VarType::Integer, vr))
    }
    fn set_integer(&mut self, vr: u32, value: i32, log: &mut dyn Log) -> SlaveResult<()> {
        let _ = (value, log);
        Err(cannot_set(Self::variable(VarType::Integer, vr), VarType::Integer, vr))
    }
    fn get_boolean(&mut self, vr: u32) -> SlaveResult<bool> {
        Err(no_getter(Self::variable(VarType::Boolean, vr), VarType::Boolean, vr))
    }
    fn set_boolean(&mut self, vr: u32, value: bool, log: &mut dyn Log) -> SlaveResult<()> {
        let _ = (value, log);
        Err(cannot_set(Self::variable(VarType::Boolean, vr), VarType::Boolean, vr))
    }
    fn get_string(&mut self, vr: u32) -> SlaveResult<String> {
        Err(no_getter(Self::variable(VarType::String, vr), VarType::String, vr))
    }
    fn set_string(&mut self, vr: u32, value: &str, log: &mut dyn Log) -> SlaveResult<()> {
        let _ = (value, log);
        Err(cannot_set(Self::variable(VarType::String, vr), VarType::String, vr))
    }

    /// What fmi2GetFMUstate keeps: by default the whole slave. A slave with a workspace (an
    /// integrator's cached factorisations) leaves it out: a state holds only what changes.
    fn snapshot(&self) -> Self {
        self.clone()
    }

    /// Overwrites an earlier snapshot (fmi2GetFMUstate on a non-null state); slaves that can reuse
    /// its allocations do, so the master's state at every macro step allocates nothing.
    fn snapshot_into(&self, into: &mut Self) {
        *into = self.snapshot();
    }

    /// Returns to a snapshot (fmi2SetFMUstate): by default a copy of it. A slave with a workspace
    /// keeps its own while the model is the same: its caches serve the restored state as well, and
    /// results stay bit-identical (a cached factorisation is the one a rebuild would compute).
    fn restore(&mut self, snap: &Self) {
        *self = snap.clone();
    }

    /// Called when fmi2GetFMUstate has taken a state: a slave whose next steps would depend on history
    /// the state leaves out (factorisations assembled at earlier points) drops it here, as its `restore`
    /// does, so the run that goes on and every run restored from the state take the same path.
    fn state_taken(&mut self) {}

    /// Checks the parameters and builds the model; called by fmi2ExitInitializationMode.
    fn initialize(&mut self, start_time: f64, log: &mut dyn Log) -> SlaveResult<()>;

    /// The `order`-th time derivative of a Real input, used to interpolate it during the next steps.
    fn set_input_derivative(&mut self, vr: u32, order: i32, value: f64) -> SlaveResult<()> {
        let _ = (vr, order, value);
        Err(SlaveError::new(
            "this FMU cannot interpolate inputs (canInterpolateInputs=false)",
        ))
    }

    /// Advances from `t` to `t + h`; `t` already matches the model's time.
    fn do_step(&mut self, t: f64, h: f64, log: &mut dyn Log) -> SlaveResult<()>;
}
