//! What can go wrong making a scene runnable: an FMU that does not load or answer, a scene that does
//! not check, an algebraic loop, a recording asked for that does not exist.

use crate::fmi2::host::error::ImportError;
use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum SystemError {
    #[error("component {component}: {error}")]
    Load { component: String, error: ImportError },
    #[error("{ssd}:{line}: {message}")]
    Invalid { ssd: PathBuf, line: usize, message: String },
    #[error("algebraic loop through direct-feedthrough outputs: {0}")]
    AlgebraicLoop(String),
    #[error("component {component}: {error}")]
    Call { component: String, error: ImportError },
    #[error("{0}")]
    Record(String),
}
