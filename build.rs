//! Reads every `modelDescription/<name>.xml`, checks its ModelStructure against its variables and
//! generates `$OUT_DIR/model_<name>.rs`: value-reference constants, the variable table with start
//! values, the GUID and the final XML. The binary and the XML therefore cannot drift apart.
//! Per FMU it also generates the typed `Parameters` struct (every causality="parameter" variable,
//! `Default` = the XML's start values, get/set by value reference within the XML's min/max), the
//! `Inputs` struct (Real inputs as input polynomials) and `get_*`/`set_*` functions that dispatch a
//! value reference to either, so a face only writes its outputs and its model. Read the result in
//! `$OUT_DIR/model_<name>.rs`.
//! With the `cli` feature it also compiles the master's C logger shim.

use quick_xml::events::{BytesStart, Event};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

struct Var {
    name: String,
    vr: u32,
    ty: String,
    causality: String,
    variability: String,
    initial: Option<String>,
    start: Option<String>,
    min: Option<String>,
    max: Option<String>,
    description: Option<String>,
    unit: Option<String>,
}

struct Model {
    identifier: String,
    vars: Vec<Var>,
    outputs: Vec<usize>,
    initial_unknowns: Vec<usize>,
}

fn attrs(e: &BytesStart) -> BTreeMap<String, String> {
    e.attributes()
        .filter_map(|a| a.ok())
        .map(|a| {
            let key = a.key.as_ref().to_string();
            let value = a
                .normalized_value(quick_xml::XmlVersion::Implicit1_0)
                .map(|v| v.into_owned())
                .unwrap_or_default();
            (key, value)
        })
        .collect()
}

fn parse(path: &Path, xml: &str) -> Model {
    let mut reader = quick_xml::Reader::from_str(xml);
    let mut model = Model {
        identifier: String::new(),
        vars: Vec::new(),
        outputs: Vec::new(),
        initial_unknowns: Vec::new(),
    };
    let mut section = String::new();
    loop {
        let event = reader
            .read_event()
            .unwrap_or_else(|e| panic!("{}: XML error: {e}", path.display()));
        match event {
            Event::Start(e) | Event::Empty(e) => {
                let tag = e.name().as_ref().to_string();
                let a = attrs(&e);
                match tag.as_str() {
                    "CoSimulation" => model.identifier = a["modelIdentifier"].clone(),
                    "ScalarVariable" => model.vars.push(Var {
                        name: a["name"].clone(),
                        vr: a["valueReference"]
                            .parse()
                            .expect("valueReference is an unsigned integer"),
                        ty: String::new(),
                        causality: a.get("causality").cloned().unwrap_or_else(|| "local".into()),
                        variability: a.get("variability").cloned().unwrap_or_else(|| "continuous".into()),
                        initial: a.get("initial").cloned(),
                        start: None,
                        min: None,
                        max: None,
                        description: a.get("description").cloned(),
                        unit: None,
                    }),
                    "Real" | "Integer" | "Boolean" | "String" if !model.vars.is_empty() && section.is_empty() => {
                        let v = model.vars.last_mut().unwrap();
                        v.ty = tag.clone();
                        v.start = a.get("start").cloned();
                        v.min = a.get("min").cloned();
                        v.max = a.get("max").cloned();
                        v.unit = a.get("unit").cloned();
                    }
                    "Outputs" | "InitialUnknowns" | "Derivatives" => section = tag.clone(),
                    "Unknown" => {
                        let index: usize = a["index"].parse().expect("Unknown/@index is an integer");
                        match section.as_str() {
                            "Outputs" => model.outputs.push(index),
                            "InitialUnknowns" => model.initial_unknowns.push(index),
                            _ => {}
                        }
                    }
                    _ => {}
                }
            }
            Event::End(e) => {
                let tag = e.name().as_ref().to_string();
                if tag == section {
                    section.clear();
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    model
}

/// The checks fmpy's validator makes on ModelStructure, made at build time so a wrong XML never ships.
fn check(path: &Path, m: &Model) {
    let fail = |msg: String| panic!("{}: {msg}", path.display());
    let mut names = BTreeSet::new();
    let mut refs = BTreeSet::new();
    for v in &m.vars {
        if !names.insert(v.name.clone()) {
            fail(format!("duplicate variable name {}", v.name));
        }
        if !refs.insert((v.ty.clone(), v.vr)) {
            fail(format!("duplicate {} valueReference {}", v.ty, v.vr));
        }
        if v.ty.is_empty() {
            fail(format!("variable {} has no type element", v.name));
        }
        let needs_start = matches!(v.initial.as_deref(), Some("exact") | Some("approx")) || v.causality == "input";
        if needs_start != v.start.is_some() {
            fail(format!(
                "variable {}: start value {} (initial={:?}, causality={})",
                v.name,
                if needs_start { "required" } else { "forbidden" },
                v.initial,
                v.causality
            ));
        }
    }
    let expected_outputs: Vec<usize> = m
        .vars
        .iter()
        .enumerate()
        .filter(|(_, v)| v.causality == "output")
        .map(|(i, _)| i + 1)
        .collect();
    if m.outputs != expected_outputs {
        fail(format!(
            "<Outputs> must list exactly the outputs by 1-based position: expected {expected_outputs:?}"
        ));
    }
    let expected_initial: Vec<usize> = m
        .vars
        .iter()
        .enumerate()
        .filter(|(_, v)| {
            (v.causality == "output" && matches!(v.initial.as_deref(), Some("calculated") | Some("approx")))
                || v.causality == "calculatedParameter"
        })
        .map(|(i, _)| i + 1)
        .collect();
    if m.initial_unknowns != expected_initial {
        fail(format!("<InitialUnknowns> must list exactly {expected_initial:?}"));
    }
}

fn fnv1a(seed: u64, bytes: &[u8]) -> u64 {
    let mut h = seed;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

fn source_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let p = entry.path();
        if p.is_dir() {
            source_files(&p, out);
        } else {
            out.push(p);
        }
    }
}

/// A GUID per interface and build: a hash of the XML and every library source file, so two
/// different FMUs or two builds of changed code never share one (libcosim caches by GUID).
fn guid(xml: &str, root: &Path) -> String {
    let mut files = Vec::new();
    source_files(&root.join("src"), &mut files);
    files.sort();
    let (mut a, mut b) = (0xcbf2_9ce4_8422_2325u64, 0x6c62_272e_07bb_0142u64);
    for bytes in std::iter::once(xml.as_bytes().to_vec())
        .chain(std::iter::once(env!("CARGO_PKG_VERSION").as_bytes().to_vec()))
        .chain(files.iter().filter_map(|f| std::fs::read(f).ok()))
    {
        a = fnv1a(a, &bytes);
        b = fnv1a(b ^ a.rotate_left(17), &bytes);
    }
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        a >> 32,
        (a >> 16) & 0xffff,
        a & 0xffff,
        b >> 48,
        b & 0xffff_ffff_ffff
    )
}

fn const_name(name: &str) -> String {
    name.to_uppercase().replace(['.', '[', ']', ' '], "_")
}

fn real_literal(s: &str) -> String {
    let v: f64 = s.parse().unwrap_or_else(|_| panic!("not a real number: {s}"));
    format!("{v:?}")
}

fn generate(m: &Model, xml: &str, guid: &str) -> String {
    let mut s = String::new();
    writeln!(
        s,
        "// Generated by build.rs from modelDescription/{}.xml. Do not edit.",
        m.identifier
    )
    .unwrap();
    writeln!(
        s,
        "use crate::fmi2::fmu::variables::{{Causality, Start, VarType, Variability, Variable}};"
    )
    .unwrap();
    writeln!(s, "use crate::fmi2::fmu::slave as s;").unwrap();
    writeln!(s, "use crate::fmi2::fmu::error as e;").unwrap();
    writeln!(s, "pub const MODEL_IDENTIFIER: &str = {:?};", m.identifier).unwrap();
    writeln!(s, "pub const GUID: &str = {guid:?};").unwrap();
    writeln!(
        s,
        "pub const MODEL_DESCRIPTION_XML: &str = {:?};",
        xml.replace("@GUID@", guid)
    )
    .unwrap();
    writeln!(s, "/// Value references, one constant per variable (upper-case name).").unwrap();
    writeln!(s, "pub mod vr {{").unwrap();
    for v in &m.vars {
        writeln!(s, "    pub const {}: u32 = {};", const_name(&v.name), v.vr).unwrap();
    }
    writeln!(s, "}}").unwrap();
    writeln!(s, "pub static VARIABLES: &[Variable] = &[").unwrap();
    for v in &m.vars {
        let start = match (v.ty.as_str(), &v.start) {
            (_, None) => "Start::None".to_string(),
            ("Real", Some(x)) => format!("Start::Real({})", real_literal(x)),
            ("Integer", Some(x)) => format!("Start::Integer({x})"),
            ("Boolean", Some(x)) => format!("Start::Boolean({})", x == "true" || x == "1"),
            (_, Some(x)) => format!("Start::String({x:?})"),
        };
        let cap = |s: &str| {
            let mut c = s.chars();
            c.next()
                .map(|f| f.to_uppercase().collect::<String>() + c.as_str())
                .unwrap_or_default()
        };
        let bound = |b: &Option<String>| {
            b.as_deref()
                .map(|x| format!("Some({})", real_literal(x)))
                .unwrap_or("None".into())
        };
        writeln!(
            s,
            "    Variable {{ name: {:?}, vr: {}, ty: VarType::{}, causality: Causality::{}, variability: Variability::{}, start: {}, min: {}, max: {} }},",
            v.name, v.vr, v.ty, cap(&v.causality), cap(&v.variability), start, bound(&v.min), bound(&v.max)
        )
        .unwrap();
    }
    writeln!(s, "];").unwrap();
    // Dense value-reference → table-index maps per type: an FMI call resolves a reference in O(1).
    writeln!(
        s,
        "/// The variable with this type and value reference (inlined: every value a host sets or gets passes here)."
    )
    .unwrap();
    writeln!(s, "#[inline]").unwrap();
    writeln!(
        s,
        "pub fn variable(ty: VarType, vr: u32) -> Option<&'static Variable> {{"
    )
    .unwrap();
    writeln!(s, "    const NONE: u16 = u16::MAX;").unwrap();
    for ty in ["Real", "Integer", "Boolean", "String"] {
        let max = m
            .vars
            .iter()
            .filter(|v| v.ty == ty)
            .map(|v| v.vr)
            .max()
            .map_or(0, |x| x as usize + 1);
        let mut table = vec!["NONE".to_string(); max];
        for (i, v) in m.vars.iter().enumerate().filter(|(_, v)| v.ty == ty) {
            table[v.vr as usize] = i.to_string();
        }
        writeln!(
            s,
            "    static {}: [u16; {max}] = [{}];",
            ty.to_uppercase(),
            table.join(", ")
        )
        .unwrap();
    }
    writeln!(s, "    let table: &[u16] = match ty {{ VarType::Real => &REAL, VarType::Integer => &INTEGER, VarType::Boolean => &BOOLEAN, VarType::String => &STRING }};").unwrap();
    // no indexing that could panic: a panic location would embed this file's build-tree path in the FMU
    writeln!(
        s,
        "    table.get(vr as usize).filter(|i| **i != NONE).and_then(|i| VARIABLES.get(*i as usize))"
    )
    .unwrap();
    writeln!(s, "}}").unwrap();
    generate_faces(m, &mut s);
    s
}

/// How one FMI type appears in the generated Rust.
struct TypeMap {
    /// FMI type name and the suffix of the generated methods.
    fmi: &'static str,
    method: &'static str,
    /// Rust type of a parameter field, of a setter's argument, of a getter's result and of the
    /// combined getter's result.
    field: &'static str,
    arg: &'static str,
    get: &'static str,
    owned: &'static str,
}

const TYPES: [TypeMap; 4] = [
    TypeMap {
        fmi: "Real",
        method: "real",
        field: "f64",
        arg: "f64",
        get: "f64",
        owned: "f64",
    },
    TypeMap {
        fmi: "Integer",
        method: "integer",
        field: "i32",
        arg: "i32",
        get: "i32",
        owned: "i32",
    },
    TypeMap {
        fmi: "Boolean",
        method: "boolean",
        field: "bool",
        arg: "bool",
        get: "bool",
        owned: "bool",
    },
    TypeMap {
        fmi: "String",
        method: "string",
        field: "String",
        arg: "&str",
        get: "&str",
        owned: "String",
    },
];

const KEYWORDS: &[&str] = &[
    "as", "break", "const", "continue", "crate", "else", "enum", "extern", "false", "fn", "for", "if", "impl", "in",
    "let", "loop", "match", "mod", "move", "mut", "pub", "ref", "return", "self", "static", "struct", "super", "trait",
    "true", "type", "unsafe", "use", "where", "while", "async", "await", "dyn", "gen", "box", "try",
];

fn field_name(name: &str) -> String {
    let f = name.to_lowercase().replace(['.', '[', ']', ' '], "_");
    if KEYWORDS.contains(&f.as_str()) {
        format!("r#{f}")
    } else {
        f
    }
}

/// A field's doc comment: the XML description, unit and range.
fn doc(v: &Var) -> String {
    let mut extra = Vec::new();
    if let Some(u) = &v.unit {
        extra.push(format!("unit {u}"));
    }
    match (&v.min, &v.max) {
        (Some(a), Some(b)) => extra.push(format!("{a} ..= {b}")),
        (Some(a), None) => extra.push(format!(">= {a}")),
        (None, Some(b)) => extra.push(format!("<= {b}")),
        (None, None) => {}
    }
    let mut d = v.description.clone().unwrap_or_else(|| v.name.clone());
    if !extra.is_empty() {
        write!(d, " [{}]", extra.join("; ")).unwrap();
    }
    format!("    /// {}\n", d.replace('\n', " "))
}

fn option_literal(b: &Option<String>) -> String {
    b.as_deref()
        .map_or("None".into(), |x| format!("Some({})", real_literal(x)))
}

/// The start value of a parameter or input as a Rust expression of its field type.
fn start_expr(v: &Var, input: bool) -> String {
    let x = v
        .start
        .as_deref()
        .unwrap_or_else(|| panic!("{} has no start value", v.name));
    let value = match v.ty.as_str() {
        "Real" => real_literal(x),
        "Integer" => x
            .parse::<i32>()
            .unwrap_or_else(|_| panic!("{}: not an Integer: {x}", v.name))
            .to_string(),
        "Boolean" => (x == "true" || x == "1").to_string(),
        _ => format!("{x:?}.to_string()"),
    };
    if input && v.ty == "Real" {
        format!("s::InputPolynomial::new({value})")
    } else {
        value
    }
}

/// `pub struct <name>` with a field per variable (Real inputs as input polynomials) and its
/// `Default` of the XML's start values.
fn emit_struct(s: &mut String, name: &str, doc_text: &str, vars: &[&Var], input: bool) {
    let copy = if vars.iter().any(|v| v.ty == "String") {
        ""
    } else {
        "Copy, "
    };
    write!(
        s,
        "\n/// {doc_text}\n#[derive(Debug, Clone, {copy}PartialEq, serde::Serialize, serde::Deserialize)]\n"
    )
    .unwrap();
    writeln!(s, "pub struct {name} {{").unwrap();
    for v in vars {
        let t = TYPES.iter().find(|t| t.fmi == v.ty).unwrap();
        let ty = if input && v.ty == "Real" {
            "s::InputPolynomial"
        } else {
            t.field
        };
        writeln!(s, "{}    pub {}: {ty},", doc(v), field_name(&v.name)).unwrap();
    }
    writeln!(
        s,
        "}}\n\nimpl Default for {name} {{\n    fn default() -> Self {{\n        Self {{"
    )
    .unwrap();
    for v in vars {
        writeln!(s, "            {}: {},", field_name(&v.name), start_expr(v, input)).unwrap();
    }
    s.push_str("        }\n    }\n}\n\n");
}

/// `get_<type>(r)`: the value of the `what` (parameter or input) with value reference `r`.
fn emit_getter(s: &mut String, t: &TypeMap, these: &[&Var], what: &str, input: bool) {
    let r = if these.is_empty() { "_r" } else { "r" };
    writeln!(
        s,
        "    /// The {} {what} with value reference `r`, if it is one.",
        t.fmi
    )
    .unwrap();
    writeln!(
        s,
        "    pub fn get_{}(&self, {r}: u32) -> Option<{}> {{",
        t.method, t.get
    )
    .unwrap();
    if these.is_empty() {
        s.push_str("        None\n    }\n\n");
        return;
    }
    s.push_str("        match r {\n");
    for v in these {
        let f = field_name(&v.name);
        let get = match t.fmi {
            "Real" if input => format!("self.{f}.value()"),
            "String" => format!("self.{f}.as_str()"),
            _ => format!("self.{f}"),
        };
        writeln!(s, "            vr::{} => Some({get}),", const_name(&v.name)).unwrap();
    }
    s.push_str("            _ => None,\n        }\n    }\n\n");
}

/// `set_<type>`: one match arm per variable of `these` (`arm` gives the arm's expression or
/// block), `miss` for any other value reference, `hit` after a match.
fn emit_setter(
    s: &mut String,
    doc: &str,
    signature: &str,
    these: &[&Var],
    arm: impl Fn(&Var) -> String,
    miss: &str,
    hit: &str,
) {
    writeln!(s, "    /// {doc}\n    #[inline]\n    pub fn {signature} {{").unwrap();
    if these.is_empty() {
        writeln!(s, "        {miss}\n    }}\n").unwrap();
        return;
    }
    s.push_str("        match r {\n");
    for v in these {
        writeln!(s, "            vr::{} => {},", const_name(&v.name), arm(v)).unwrap();
    }
    writeln!(
        s,
        "            _ => return {miss},\n        }}\n        {hit}\n    }}\n"
    )
    .unwrap();
}

/// The range check of a Real or Integer parameter with a min or max, as a statement.
fn range_check(v: &Var) -> String {
    let x = match v.ty.as_str() {
        "Real" => "value",
        "Integer" => "f64::from(value)",
        _ => return String::new(),
    };
    if v.min.is_none() && v.max.is_none() {
        return String::new();
    }
    let (min, max) = (option_literal(&v.min), option_literal(&v.max));
    format!("e::ParameterError::check_range({:?}, {x}, {min}, {max})?; ", v.name)
}

/// The variables of `vars` with type `t`.
fn of_type<'a>(vars: &[&'a Var], t: &TypeMap) -> Vec<&'a Var> {
    vars.iter().copied().filter(|v| v.ty == t.fmi).collect()
}

/// `Parameters`, `Inputs` and the dispatching functions of one model.
fn generate_faces(m: &Model, s: &mut String) {
    let params: Vec<&Var> = m.vars.iter().filter(|v| v.causality == "parameter").collect();
    let inputs: Vec<&Var> = m.vars.iter().filter(|v| v.causality == "input").collect();
    let file = format!("{}.xml", m.identifier);
    let unused = |these: &[&Var], name: &'static str| {
        if these.is_empty() {
            format!("_{name}")
        } else {
            name.to_string()
        }
    };

    let doc = format!(
        "The parameters (causality=\"parameter\") of {file}, one field each; `Default` is the XML's\n/// start \
         values. Real and Integer setters refuse values outside the XML's min/max."
    );
    emit_struct(s, "Parameters", &doc, &params, false);
    s.push_str("impl Parameters {\n");
    for t in &TYPES {
        let these = of_type(&params, t);
        emit_getter(s, t, &these, "parameter", false);
        let range = if matches!(t.fmi, "Real" | "Integer") {
            " within the XML's min/max"
        } else {
            ""
        };
        let assign = if t.fmi == "String" {
            "value.to_string()"
        } else {
            "value"
        };
        emit_setter(
            s,
            &format!(
                "Sets the {0} parameter `r`{range}; `Ok(false)` when `r` is no {0} parameter.",
                t.fmi
            ),
            &format!(
                "set_{}(&mut self, {}: u32, {}: {}) -> Result<bool, e::ParameterError>",
                t.method,
                unused(&these, "r"),
                unused(&these, "value"),
                t.arg
            ),
            &these,
            |v| format!("{{ {}self.{} = {assign}; }}", range_check(v), field_name(&v.name)),
            "Ok(false)",
            "Ok(true)",
        );
    }
    s.truncate(s.trim_end().len());
    s.push_str("\n}\n");

    let doc = format!(
        "The inputs (causality=\"input\") of {file}: each Real one an [`s::InputPolynomial`] (value and\n/// \
         time derivatives of order 1 and 2 for canInterpolateInputs); `Default` is the XML's start values."
    );
    emit_struct(s, "Inputs", &doc, &inputs, true);
    s.push_str("impl Inputs {\n");
    for t in &TYPES {
        let these = of_type(&inputs, t);
        emit_getter(s, t, &these, "input", true);
        let bounded: Vec<&Var> = these
            .iter()
            .copied()
            .filter(|v| t.fmi == "Real" && (v.min.is_some() || v.max.is_some()))
            .collect();
        let note = if t.fmi == "Real" {
            " (its derivatives cleared, clamped to the XML's min/max with a warning)"
        } else {
            ""
        };
        emit_setter(
            s,
            &format!("Sets the {0} input `r`{note}; false when `r` is no {0} input.", t.fmi),
            &format!(
                "set_{}(&mut self, {}: u32, {}: {}, {}: &mut dyn s::Log) -> bool",
                t.method,
                unused(&these, "r"),
                unused(&these, "value"),
                t.arg,
                unused(&bounded, "log")
            ),
            &these,
            |v| {
                let f = field_name(&v.name);
                match t.fmi {
                    "Real" if v.min.is_some() || v.max.is_some() => format!(
                        "self.{f}.set(s::clamp_input({:?}, value, {}, {}, log))",
                        v.name,
                        option_literal(&v.min),
                        option_literal(&v.max)
                    ),
                    "Real" => format!("self.{f}.set(value)"),
                    "String" => format!("self.{f} = value.to_string()"),
                    _ => format!("self.{f} = value"),
                }
            },
            "false",
            "true",
        );
    }
    let reals: Vec<&Var> = inputs.iter().copied().filter(|v| v.ty == "Real").collect();
    writeln!(
        s,
        "    /// Sets the `order`-th time derivative (1 or 2) of the Real input `r`."
    )
    .unwrap();
    let (order, value) = (unused(&reals, "order"), unused(&reals, "value"));
    writeln!(s, "    pub fn set_derivative(&mut self, r: u32, {order}: i32, {value}: f64) -> e::SlaveResult<()> {{\n        match r {{").unwrap();
    for v in &reals {
        writeln!(
            s,
            "            vr::{} => self.{}.set_derivative(order, value),",
            const_name(&v.name),
            field_name(&v.name)
        )
        .unwrap();
    }
    writeln!(
        s,
        "            _ => Err(e::err(format!(\"Real value reference {{r}} is not an input\"))),\n        }}\n    }}\n"
    )
    .unwrap();
    writeln!(s, "    /// Moves every Real input's expansion point forward by `h` seconds (after a step), so the\n    /// polynomials continue if nobody sets new values.").unwrap();
    writeln!(s, "    pub fn advance(&mut self, {}: f64) {{", unused(&reals, "h")).unwrap();
    for v in &reals {
        writeln!(s, "        self.{}.advance(h);", field_name(&v.name)).unwrap();
    }
    s.push_str("    }\n}\n");

    // dispatch to either
    writeln!(
        s,
        "\n/// The refusal to read a variable the face has no getter for, naming it."
    )
    .unwrap();
    writeln!(
        s,
        "pub fn no_getter(ty: VarType, r: u32) -> e::SlaveError {{\n    s::no_getter(variable(ty, r), ty, r)\n}}"
    )
    .unwrap();
    for t in &TYPES {
        let (m, f) = (t.method, t.fmi);
        let a = if f == "Integer" { "An" } else { "A" };
        let to_owned = if f == "String" { ".map(str::to_string)" } else { "" };
        writeln!(
            s,
            "\n/// {a} {f} parameter or input by value reference (None for calculated parameters and outputs)."
        )
        .unwrap();
        writeln!(s, "#[inline]\npub fn get_{m}(p: &Parameters, i: &Inputs, r: u32) -> Option<{}> {{\n    p.get_{m}(r).or_else(|| i.get_{m}(r)){to_owned}\n}}", t.owned).unwrap();
        writeln!(s, "\n/// Sets {} {f} parameter or input by value reference (see [`Parameters::set_{m}`] and\n/// [`Inputs::set_{m}`]); anything else is refused by name. The parameters are shared with the\n/// FMU states taken since they last changed: only a parameter's value copies them (an input's\n/// never does).", a.to_lowercase()).unwrap();
        writeln!(s, "#[inline]\npub fn set_{m}(p: &mut std::sync::Arc<Parameters>, i: &mut Inputs, r: u32, value: {}, log: &mut dyn s::Log) -> e::SlaveResult<s::Changed> {{", t.arg).unwrap();
        writeln!(s, "    if i.set_{m}(r, value, log) {{\n        Ok(s::Changed::Input)\n    }} else if std::sync::Arc::make_mut(p).set_{m}(r, value)? {{\n        Ok(s::Changed::Parameter)\n    }} else {{\n        Err(s::cannot_set(variable(VarType::{f}, r), VarType::{f}, r))\n    }}\n}}").unwrap();
    }
}

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap());
    let out = PathBuf::from(std::env::var("OUT_DIR").unwrap());
    println!("cargo:rerun-if-changed=modelDescription");
    println!("cargo:rerun-if-changed=src");
    let mut xmls: Vec<PathBuf> = std::fs::read_dir(root.join("modelDescription"))
        .expect("modelDescription/ exists")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "xml"))
        .collect();
    xmls.sort();
    let mut index = String::from("// Generated by build.rs: one module per modelDescription/*.xml.\n");
    for path in xmls {
        let xml = std::fs::read_to_string(&path).expect("readable XML");
        let model = parse(&path, &xml);
        let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
        if model.identifier != stem {
            panic!(
                "{}: modelIdentifier {} must equal the file name",
                path.display(),
                model.identifier
            );
        }
        check(&path, &model);
        let code = generate(&model, &xml, &guid(&xml, &root));
        std::fs::write(out.join(format!("model_{stem}.rs")), code).unwrap();
        writeln!(
            index,
            "pub mod {stem} {{ include!(concat!(env!(\"OUT_DIR\"), \"/model_{stem}.rs\")); }}"
        )
        .unwrap();
    }
    std::fs::write(out.join("models.rs"), index).unwrap();

    #[cfg(feature = "cli")]
    {
        println!("cargo:rerun-if-changed=src/fmi2/host/logger.c");
        cc::Build::new()
            .file("src/fmi2/host/logger.c")
            .warnings(true)
            .compile("windrive_logger");
    }
}
