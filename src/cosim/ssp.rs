//! SSP 1.0 system structures: a `.ssp` archive, an unpacked folder, or a `.ssd` file, read into a
//! [`Scene`]: components with their FMU and parameter bindings (inline or `.ssv`), connections with
//! optional linear transformations, and the default experiment.
//!
//! Prefixes are not interpreted (see `xml.rs`), so `ssd:Component` and `Component` read the same.

use super::xml::{self, Element};
use crate::fmi2::host::archive::{TempDir, unzip};
use crate::fmi2::host::error::ImportError;
use std::path::{Path, PathBuf};

#[derive(Debug, thiserror::Error)]
pub enum SspError {
    #[error("{path}: {message}")]
    File { path: PathBuf, message: String },
    #[error("{path}:{line}: {message}")]
    Content {
        path: PathBuf,
        line: usize,
        message: String,
    },
}

impl SspError {
    /// The same error with a path under `from` (an archive's temporary folder) named under `to`
    /// (the archive), so that messages name the file the user gave.
    fn relocated(self, from: &Path, to: &Path) -> Self {
        let moved = |p: PathBuf| p.strip_prefix(from).map_or_else(|_| p.clone(), |rel| to.join(rel));
        match self {
            Self::File { path, message } => Self::File {
                path: moved(path),
                message: message.replace(&from.display().to_string(), &to.display().to_string()),
            },
            Self::Content { path, line, message } => Self::Content {
                path: moved(path),
                line,
                message: message.replace(&from.display().to_string(), &to.display().to_string()),
            },
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Real(f64),
    Integer(i64),
    Boolean(bool),
    String(String),
}

impl Value {
    pub fn type_name(&self) -> &'static str {
        match self {
            Value::Real(_) => "Real",
            Value::Integer(_) => "Integer",
            Value::Boolean(_) => "Boolean",
            Value::String(_) => "String",
        }
    }
}

/// A parameter value bound to a component, with where it came from for error messages.
#[derive(Debug, Clone)]
pub struct Parameter {
    pub name: String,
    pub value: Value,
    pub origin: String,
}

#[derive(Debug, Clone)]
pub struct Connector {
    pub name: String,
    pub kind: String,
    /// Real, Integer, Boolean, String or Enumeration when the SSD declares it.
    pub type_name: Option<String>,
}

#[derive(Debug, Clone)]
pub struct Component {
    pub name: String,
    /// The source attribute as written.
    pub source: String,
    /// The FMU it resolves to.
    pub path: PathBuf,
    pub connectors: Vec<Connector>,
    pub parameters: Vec<Parameter>,
    pub line: usize,
}

/// `end = factor · start + offset` (ssc:LinearTransformation); identity when absent.
#[derive(Debug, Clone)]
pub struct Connection {
    pub start_element: String,
    pub start_connector: String,
    pub end_element: String,
    pub end_connector: String,
    pub factor: f64,
    pub offset: f64,
    pub line: usize,
}

impl Connection {
    pub fn describe(&self) -> String {
        format!(
            "{}.{} -> {}.{}",
            self.start_element, self.start_connector, self.end_element, self.end_connector
        )
    }
}

#[derive(Debug, Clone, Default)]
pub struct Experiment {
    pub start_time: Option<f64>,
    pub stop_time: Option<f64>,
    /// From an `osp:FixedStepAlgorithm baseStepSize` annotation (libcosim's), if present.
    pub step_size: Option<f64>,
}

#[derive(Debug)]
pub struct Scene {
    pub name: String,
    /// The folder component sources are relative to.
    pub root: PathBuf,
    /// The .ssd file, for messages.
    pub ssd: PathBuf,
    pub components: Vec<Component>,
    pub connections: Vec<Connection>,
    pub experiment: Experiment,
    _unpacked: Option<TempDir>,
}

fn file_error(path: &Path, message: impl std::fmt::Display) -> SspError {
    SspError::File {
        path: path.to_path_buf(),
        message: message.to_string(),
    }
}

fn content_error(path: &Path, line: usize, message: impl Into<String>) -> SspError {
    SspError::Content {
        path: path.to_path_buf(),
        line,
        message: message.into(),
    }
}

fn parse_f64(path: &Path, e: &Element, attr: &str) -> Result<Option<f64>, SspError> {
    match e.attr(attr) {
        None => Ok(None),
        Some(v) => v
            .trim()
            .parse::<f64>()
            .map(Some)
            .map_err(|_| content_error(path, e.line, format!("<{}> {attr}=\"{v}\" is not a number", e.name))),
    }
}

fn required<'a>(path: &Path, e: &'a Element, attr: &str) -> Result<&'a str, SspError> {
    e.attr(attr)
        .ok_or_else(|| content_error(path, e.line, format!("<{}> has no {attr} attribute", e.name)))
}

impl Scene {
    /// Opens a `.ssp` archive (unpacked into a private temporary folder), a folder holding
    /// `SystemStructure.ssd`, or a `.ssd` file.
    pub fn open(path: &Path) -> Result<Self, SspError> {
        if path.is_dir() {
            return Self::read(path.join("SystemStructure.ssd"), path.to_path_buf(), None);
        }
        if !path.exists() {
            return Err(file_error(path, "no such file or folder"));
        }
        if path.extension().is_some_and(|e| e == "ssd") {
            let root = path.parent().map(Path::to_path_buf).unwrap_or_default();
            return Self::read(path.to_path_buf(), root, None);
        }
        let tmp = TempDir::new("windrive-ssp").map_err(|e| file_error(path, e))?;
        unzip(path, tmp.path()).map_err(|e| match e {
            ImportError::Archive { message, .. } => file_error(path, message),
            other => file_error(path, other),
        })?;
        let root = tmp.path().to_path_buf();
        let mut scene = Self::read(root.join("SystemStructure.ssd"), root.clone(), Some(tmp))
            .map_err(|e| e.relocated(&root, path))?;
        scene.ssd = path.join("SystemStructure.ssd");
        Ok(scene)
    }

    fn read(ssd: PathBuf, root: PathBuf, unpacked: Option<TempDir>) -> Result<Self, SspError> {
        let text = std::fs::read_to_string(&ssd).map_err(|e| file_error(&ssd, e))?;
        let doc = xml::parse(&text).map_err(|e| file_error(&ssd, e))?;
        if doc.name != "SystemStructureDescription" {
            return Err(content_error(
                &ssd,
                doc.line,
                format!("root element is <{}>, not <ssd:SystemStructureDescription>", doc.name),
            ));
        }
        let system = doc
            .child("System")
            .ok_or_else(|| content_error(&ssd, doc.line, "no <ssd:System> element"))?;
        let mut components = Vec::new();
        for c in system.list("Elements", "Component") {
            components.push(read_component(&ssd, &root, unpacked.is_some(), c)?);
        }
        for other in system.child("Elements").into_iter().flat_map(|e| &e.children) {
            if other.name != "Component" {
                return Err(content_error(
                    &ssd,
                    other.line,
                    format!(
                        "<{}> is not supported: systems must be flat lists of FMU components",
                        other.name
                    ),
                ));
            }
        }
        let mut connections = Vec::new();
        for c in system.list("Connections", "Connection") {
            let transform = c.child("LinearTransformation");
            let (factor, offset) = match transform {
                Some(t) => (
                    parse_f64(&ssd, t, "factor")?.unwrap_or(1.0),
                    parse_f64(&ssd, t, "offset")?.unwrap_or(0.0),
                ),
                None => (1.0, 0.0),
            };
            if let Some(other) = c
                .children
                .iter()
                .find(|x| x.name.ends_with("Transformation") && x.name != "LinearTransformation")
            {
                return Err(content_error(
                    &ssd,
                    other.line,
                    format!("<{}> is not supported", other.name),
                ));
            }
            // libcosim needs both elements; a system-level connector has no element
            connections.push(Connection {
                start_element: required(&ssd, c, "startElement")?.into(),
                start_connector: required(&ssd, c, "startConnector")?.into(),
                end_element: required(&ssd, c, "endElement")?.into(),
                end_connector: required(&ssd, c, "endConnector")?.into(),
                factor,
                offset,
                line: c.line,
            });
        }
        let mut experiment = Experiment::default();
        if let Some(x) = doc.child("DefaultExperiment") {
            experiment.start_time = parse_f64(&ssd, x, "startTime")?;
            experiment.stop_time = parse_f64(&ssd, x, "stopTime")?;
            if let Some(fixed) = find_descendant(x, "FixedStepAlgorithm") {
                experiment.step_size = parse_f64(&ssd, fixed, "baseStepSize")?;
            }
        }
        Ok(Self {
            name: doc.attr("name").unwrap_or("system").into(),
            root,
            ssd,
            components,
            connections,
            experiment,
            _unpacked: unpacked,
        })
    }

    pub fn component(&self, name: &str) -> Option<&Component> {
        self.components.iter().find(|c| c.name == name)
    }

    /// The Real value the scene binds to `component.variable`, if any.
    pub fn real_parameter(&self, component: &str, variable: &str) -> Option<f64> {
        match self.parameter(component, variable)? {
            Value::Real(x) => Some(*x),
            _ => None,
        }
    }

    /// The String value the scene binds to `component.variable`, if any.
    pub fn string_parameter(&self, component: &str, variable: &str) -> Option<&str> {
        match self.parameter(component, variable)? {
            Value::String(s) => Some(s),
            _ => None,
        }
    }

    /// The value bound last to `component.variable`.
    fn parameter(&self, component: &str, variable: &str) -> Option<&Value> {
        self.component(component)?
            .parameters
            .iter()
            .rev()
            .find(|p| p.name == variable)
            .map(|p| &p.value)
    }
}

fn find_descendant<'a>(e: &'a Element, name: &str) -> Option<&'a Element> {
    e.children.iter().find_map(|c| {
        if c.name == name {
            Some(c)
        } else {
            find_descendant(c, name)
        }
    })
}

/// `rel` joined to `root`, or None when it is absolute or climbs out of `root` (judged on the
/// words, before any file is touched).
fn inside(root: &Path, rel: &str) -> Option<PathBuf> {
    use std::path::Component as Part;
    let mut depth = 0usize;
    for part in Path::new(rel).components() {
        match part {
            Part::Normal(_) => depth += 1,
            Part::CurDir => {}
            Part::ParentDir => depth = depth.checked_sub(1)?,
            Part::RootDir | Part::Prefix(_) => return None,
        }
    }
    Some(root.join(rel))
}

/// Where a file a scene names lies. An `.ssp` archive (`confined`) may only name its own files: an
/// absolute or climbing path there would load whatever the machine has at that place.
fn scene_file(
    ssd: &Path,
    root: &Path,
    confined: bool,
    line: usize,
    what: &str,
    src: &str,
) -> Result<PathBuf, SspError> {
    let rel = src.strip_prefix("file:").unwrap_or(src).trim_start_matches("./");
    if confined {
        return inside(root, rel).ok_or_else(|| {
            content_error(
                ssd,
                line,
                format!("{what} \"{src}\" lies outside the .ssp archive; an archive may only name files it holds"),
            )
        });
    }
    Ok(if Path::new(rel).is_absolute() {
        PathBuf::from(rel)
    } else {
        root.join(rel)
    })
}

fn read_component(ssd: &Path, root: &Path, confined: bool, c: &Element) -> Result<Component, SspError> {
    let name = required(ssd, c, "name")?.to_string();
    let source = required(ssd, c, "source")?.to_string();
    if let Some(t) = c.attr("type")
        && t != "application/x-fmu-sharedlibrary"
    {
        return Err(content_error(
            ssd,
            c.line,
            format!("component {name}: type {t} is not supported (only application/x-fmu-sharedlibrary)"),
        ));
    }
    let path = scene_file(
        ssd,
        root,
        confined,
        c.line,
        &format!("component {name}: source"),
        &source,
    )?;
    let connectors = c
        .list("Connectors", "Connector")
        .map(|k| {
            Ok(Connector {
                name: required(ssd, k, "name")?.into(),
                kind: k.attr("kind").unwrap_or("").into(),
                type_name: k.children.first().map(|t| t.name.clone()),
            })
        })
        .collect::<Result<Vec<_>, SspError>>()?;
    let mut parameters = Vec::new();
    for binding in c.list("ParameterBindings", "ParameterBinding") {
        let prefix = binding.attr("prefix").unwrap_or("");
        let (file, set) = match binding.attr("source") {
            Some(src) => {
                let file = scene_file(
                    ssd,
                    root,
                    confined,
                    binding.line,
                    &format!("component {name}: parameter binding"),
                    src,
                )?;
                let text = std::fs::read_to_string(&file).map_err(|e| file_error(&file, e))?;
                let doc = xml::parse(&text).map_err(|e| file_error(&file, e))?;
                (file, doc)
            }
            None => {
                let set = binding
                    .child("ParameterValues")
                    .and_then(|v| v.child("ParameterSet"))
                    .ok_or_else(|| {
                        content_error(
                            ssd,
                            binding.line,
                            "ParameterBinding has neither source nor ParameterValues",
                        )
                    })?;
                (ssd.to_path_buf(), set.clone())
            }
        };
        for p in set.list("Parameters", "Parameter") {
            let pname = required(&file, p, "name")?;
            let pname = pname.strip_prefix(prefix).unwrap_or(pname).to_string();
            let typed = p
                .children
                .first()
                .ok_or_else(|| content_error(&file, p.line, format!("parameter {pname} has no value element")))?;
            let raw = required(&file, typed, "value")?;
            let bad = || {
                content_error(
                    &file,
                    typed.line,
                    format!("parameter {pname}: cannot read {raw:?} as {}", typed.name),
                )
            };
            let value = match typed.name.as_str() {
                "Real" => Value::Real(raw.trim().parse().map_err(|_| bad())?),
                "Integer" | "Enumeration" => Value::Integer(raw.trim().parse().map_err(|_| bad())?),
                "Boolean" => Value::Boolean(match raw.trim() {
                    "true" | "1" => true,
                    "false" | "0" => false,
                    _ => return Err(bad()),
                }),
                "String" => Value::String(raw.to_string()),
                other => {
                    return Err(content_error(
                        &file,
                        typed.line,
                        format!("parameter {pname}: unknown type {other}"),
                    ));
                }
            };
            parameters.push(Parameter {
                name: pname,
                value,
                origin: format!("{}:{}", file.display(), p.line),
            });
        }
    }
    Ok(Component {
        name,
        source,
        path,
        connectors,
        parameters,
        line: c.line,
    })
}
