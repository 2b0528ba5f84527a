//! Reads every `modelDescription/<name>.xml`, checks its ModelStructure against its variables and
//! generates `$OUT_DIR/model_<name>.rs`: value-reference constants, the variable table with start
//! values, the GUID and the final XML. The binary and the XML therefore cannot drift apart.
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
                    }),
                    "Real" | "Integer" | "Boolean" | "String" if !model.vars.is_empty() && section.is_empty() => {
                        let v = model.vars.last_mut().unwrap();
                        v.ty = tag.clone();
                        v.start = a.get("start").cloned();
                        v.min = a.get("min").cloned();
                        v.max = a.get("max").cloned();
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
        "use crate::fmi2::variables::{{Causality, Start, VarType, Variability, Variable}};"
    )
    .unwrap();
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
    writeln!(s, "/// The variable with this type and value reference.").unwrap();
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
    s
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
        println!("cargo:rerun-if-changed=src/fmi2/logger.c");
        cc::Build::new()
            .file("src/fmi2/logger.c")
            .warnings(true)
            .compile("windrive_logger");
    }
}
