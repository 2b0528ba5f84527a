//! Gearbox description files: what a user writes to model their own gearbox (TOML, read with serde).
//!
//! A description is a chain, as in `torsional`: an optional rotor, stages (planetary: carrier in, sun
//! out, ring fixed or elastically mounted; parallel: gear in, pinion out), an optional generator, and
//! a shaft from each of them to the next. Units are SI, except gear geometry in mm and angles in
//! degrees, as gear data sheets give them (the field names say so). Unknown fields are errors, so a
//! misspelt key is reported with its line instead of being ignored.
//!
//! One job a file: [`schema`] the format (the types serde reads, their defaults), `validation` the
//! checks serde cannot express, [`presets`] the gearboxes shipped with the library (their TOML files
//! under fmus/gearbox6dof/resources/, included once, there).

mod presets;
pub mod schema;
mod validation;

pub use presets::PRESETS;
pub use schema::*;

/// An error reading a description: the file, and serde's line/column/field message.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}: {message}")]
pub struct DescriptionError {
    pub file: String,
    pub message: String,
}

impl Description {
    /// Parses TOML text; `file` names it in errors.
    pub fn parse(text: &str, file: &str) -> Result<Description, DescriptionError> {
        let err = |message: String| DescriptionError {
            file: file.to_string(),
            message,
        };
        let d: Description = toml::from_str(text).map_err(|e| err(e.to_string().trim_end().to_string()))?;
        d.validate().map_err(err)?;
        Ok(d)
    }
}
