//! Allowable stresses the thesis checks against (its §7.2; σ_Hlim, σ_Flim from ISO 6336-5): IEC 61400-4
//! maximum Hertz pressure of gearbox bearings and ISO 6336-5 limits of case-carburised gears.

/// σ_Hlim of case-carburised 18CrNiMo7-6 (Eh), quality MQ (ISO 6336-5), Pa.
pub const CONTACT_LIMIT_EH_MQ: f64 = 1.5e9;
/// σ_Flim of the same steel, Pa (σ_FE = 2 σ_Flim).
pub const BENDING_LIMIT_EH_MQ: f64 = 0.5e9;

/// (component, limit in Pa, what it limits, source)
pub const LIMITS: [(&str, f64, &str, &str); 6] = [
    ("planet bearing", 1.5e9, "max Hertz pressure", "IEC 61400-4"),
    ("intermediate bearing", 1.65e9, "max Hertz pressure", "IEC 61400-4"),
    ("high-speed bearing", 1.3e9, "max Hertz pressure", "IEC 61400-4"),
    (
        "gear flank (thesis)",
        1.45e9,
        "contact stress",
        "ISO 6336-5 as used in the thesis",
    ),
    (
        "gear flank, σ_Hlim MQ",
        CONTACT_LIMIT_EH_MQ,
        "contact endurance limit",
        "ISO 6336-5, 18CrNiMo7-6 Eh",
    ),
    (
        "gear root, σ_Flim MQ",
        BENDING_LIMIT_EH_MQ,
        "bending endurance limit (σ_FE = 2 σ_Flim)",
        "ISO 6336-5, 18CrNiMo7-6 Eh",
    ),
];

/// Limit of a named component (the table's first column).
pub fn limit(component: &str) -> Option<f64> {
    LIMITS.iter().find(|l| l.0 == component).map(|l| l.1)
}
