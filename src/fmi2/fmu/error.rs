//! What a slave's call answers when it cannot do what it was asked: the message the export adapter
//! logs with fmi2Error, and the parameter errors that name the variable and the accepted values.

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

/// A [`SlaveError`] with this message.
pub fn err(msg: impl Into<String>) -> SlaveError {
    SlaveError::new(msg)
}

/// Parameters a model refuses: the XML's range, a value the model does not know, a combination
/// that does not go together, or what the physics said. Faces build their models with it; it
/// crosses to the adapter as a [`SlaveError`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParameterError {
    #[error("parameter {name} = {value} is below its minimum {min}")]
    BelowMinimum { name: &'static str, value: f64, min: f64 },
    #[error("parameter {name} = {value} is above its maximum {max}")]
    AboveMaximum { name: &'static str, value: f64, max: f64 },
    /// `value` as the user gave it (strings quoted).
    #[error("parameter {name} = {value}: {reason}")]
    Invalid {
        name: &'static str,
        value: String,
        reason: String,
    },
    /// Parameters that do not go together; the message names them.
    #[error("{0}")]
    Conflict(String),
    /// The physics refused the parameters; the message says why.
    #[error("{0}")]
    Model(String),
}

impl ParameterError {
    /// A value of parameter `name` the model does not accept, with what it accepts.
    pub fn invalid(name: &'static str, value: &impl std::fmt::Debug, reason: impl Into<String>) -> Self {
        Self::Invalid {
            name,
            value: format!("{value:?}"),
            reason: reason.into(),
        }
    }

    /// Checks a Real or Integer parameter against the XML's min and max (generated setters call it).
    pub fn check_range(name: &'static str, value: f64, min: Option<f64>, max: Option<f64>) -> Result<(), Self> {
        if let Some(min) = min.filter(|m| value < *m) {
            return Err(Self::BelowMinimum { name, value, min });
        }
        if let Some(max) = max.filter(|m| value > *m) {
            return Err(Self::AboveMaximum { name, value, max });
        }
        Ok(())
    }
}

impl From<ParameterError> for SlaveError {
    fn from(e: ParameterError) -> Self {
        Self(e.to_string())
    }
}
