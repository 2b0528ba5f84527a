//! The gearboxes shipped inside the library, by name, and loading a description by preset name or
//! file path.

use super::{Description, DescriptionError};

/// The presets shipped inside the library (each also a file users can copy: `fmus/gearbox6dof/resources/`).
pub const PRESETS: [(&str, &str); 5] = [
    (
        "grc750",
        include_str!("../../../../fmus/gearbox6dof/resources/grc750.toml"),
    ),
    (
        "nrel5mw",
        include_str!("../../../../fmus/gearbox6dof/resources/nrel5mw.toml"),
    ),
    ("c2mw", include_str!("../../../../fmus/gearbox6dof/resources/c2mw.toml")),
    (
        "paper1p5mw",
        include_str!("../../../../fmus/gearbox6dof/resources/paper1p5mw.toml"),
    ),
    (
        "planetary-spur",
        include_str!("../../../../fmus/gearbox6dof/resources/planetary-spur.toml"),
    ),
];

impl Description {
    /// A preset by name (case-insensitive) or a path to a TOML file.
    pub fn load(name_or_path: &str) -> Result<Description, DescriptionError> {
        let key = name_or_path.trim().to_ascii_lowercase();
        if let Some((name, text)) = PRESETS.iter().find(|(n, _)| *n == key) {
            return Description::parse(text, &format!("preset {name}"));
        }
        let text = std::fs::read_to_string(name_or_path).map_err(|e| DescriptionError {
            file: name_or_path.to_string(),
            message: format!(
                "cannot read it ({e}); presets are {}",
                PRESETS.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
            ),
        })?;
        Description::parse(&text, name_or_path)
    }
}
