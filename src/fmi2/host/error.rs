//! What opening, loading or calling an FMU can answer, with the FMU's own last messages attached,
//! and the form those messages are kept in.

use crate::fmi2::types::Fmi2Status;
use std::path::PathBuf;

/// One logged message: (status, category, text).
pub type LogRecord = (Fmi2Status, String, String);

#[derive(Debug, thiserror::Error)]
pub enum ImportError {
    #[error("{path}: {message}")]
    Archive { path: PathBuf, message: String },
    #[error("{path}: modelDescription.xml: {message}")]
    Description { path: PathBuf, message: String },
    #[error("{path}: cannot load: {message}")]
    Library { path: PathBuf, message: String },
    #[error("{path}: missing FMI function {symbol}")]
    MissingSymbol { path: PathBuf, symbol: String },
    #[error("{instance}: fmi2Instantiate returned NULL{}", log_suffix(.log))]
    Instantiate { instance: String, log: Vec<String> },
    #[error("{instance}: {function} returned {status}{}", log_suffix(.log))]
    Call {
        instance: String,
        function: &'static str,
        status: &'static str,
        log: Vec<String>,
    },
    #[error("{model}: no variable named {name}")]
    UnknownVariable { model: String, name: String },
    #[error("{instance}: its process ended during {calls}: {how}")]
    Crashed {
        instance: String,
        calls: String,
        how: String,
    },
    #[error("{instance}: {message}")]
    Isolation { instance: String, message: String },
}

/// The FMU's messages after an error: the last few, which say what went wrong.
fn log_suffix(log: &[String]) -> String {
    const SHOWN: usize = 8;
    match log.len() {
        0 => String::new(),
        n if n <= SHOWN => format!(": {}", log.join(" | ")),
        n => format!(
            ": ({} earlier messages not shown) {}",
            n - SHOWN,
            log[n - SHOWN..].join(" | ")
        ),
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn an_error_shows_the_last_few_messages_not_a_thousand() {
        let texts: Vec<String> = (0..1_000).map(|k| format!("m{k}")).collect();
        let suffix = super::log_suffix(&texts);
        assert!(
            suffix.starts_with(": (992 earlier messages not shown) m992 | "),
            "{suffix}"
        );
    }
}
