//! The variable table build.rs generates from each modelDescription XML.

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VarType {
    Real,
    Integer,
    Boolean,
    String,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Causality {
    Parameter,
    CalculatedParameter,
    Input,
    Output,
    Local,
    Independent,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variability {
    Constant,
    Fixed,
    Tunable,
    Discrete,
    Continuous,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Start {
    None,
    Real(f64),
    Integer(i32),
    Boolean(bool),
    String(&'static str),
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Variable {
    pub name: &'static str,
    pub vr: u32,
    pub ty: VarType,
    pub causality: Causality,
    pub variability: Variability,
    pub start: Start,
    pub min: Option<f64>,
    pub max: Option<f64>,
}

/// Finds a variable by type and value reference (value references are unique per type).
pub fn lookup(table: &'static [Variable], ty: VarType, vr: u32) -> Option<&'static Variable> {
    table.iter().find(|v| v.ty == ty && v.vr == vr)
}
