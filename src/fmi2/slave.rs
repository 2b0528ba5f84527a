//! The contract between a physics model and the FMI export adapter: a plain Rust trait with no raw
//! pointers. The adapter (export.rs) owns the state machine, argument checks and logging.

use super::variables::{VarType, Variable};
use serde::{Serialize, de::DeserializeOwned};
use std::path::Path;

/// An error a model reports; the adapter logs the message and answers fmi2Error.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct SlaveError(pub String);

impl SlaveError {
    pub fn new(msg: impl Into<String>) -> Self {
        Self(msg.into())
    }
}

pub type SlaveResult<T> = Result<T, SlaveError>;

/// What a model may say through the host's logger while it works.
pub trait Log {
    /// A warning (category logStatusWarning); the call that emits it answers fmi2Warning.
    fn warning(&mut self, msg: &str);
    /// A model event such as a brake locking (category logEvents).
    fn event(&mut self, msg: &str);
}

/// A Co-Simulation model. Value references reaching these methods already exist in `VARIABLES`
/// with the right type, and the call is legal in the current FMI state; Real values are finite.
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
    fn set_real(&mut self, vr: u32, value: f64, log: &mut dyn Log) -> SlaveResult<()>;
    fn get_integer(&mut self, vr: u32) -> SlaveResult<i32>;
    fn set_integer(&mut self, vr: u32, value: i32, log: &mut dyn Log) -> SlaveResult<()>;
    fn get_boolean(&mut self, vr: u32) -> SlaveResult<bool>;
    fn set_boolean(&mut self, vr: u32, value: bool, log: &mut dyn Log) -> SlaveResult<()>;
    fn get_string(&mut self, vr: u32) -> SlaveResult<String>;
    fn set_string(&mut self, vr: u32, value: &str, log: &mut dyn Log) -> SlaveResult<()>;

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

/// Applies every start value of the model's XML table to a fresh model (importers do not apply them),
/// so code and XML cannot disagree. A start value the model refuses is left at its default.
pub fn apply_start_values<S: Slave>(model: &mut S) {
    struct Quiet;
    impl Log for Quiet {
        fn warning(&mut self, _: &str) {}
        fn event(&mut self, _: &str) {}
    }
    use super::variables::Start;
    for v in S::VARIABLES {
        let _ = match v.start {
            Start::Real(x) => model.set_real(v.vr, x, &mut Quiet),
            Start::Integer(x) => model.set_integer(v.vr, x, &mut Quiet),
            Start::Boolean(x) => model.set_boolean(v.vr, x, &mut Quiet),
            Start::String(x) => model.set_string(v.vr, x, &mut Quiet),
            Start::None => Ok(()),
        };
    }
}
