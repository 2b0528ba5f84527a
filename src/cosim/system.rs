//! A scene made runnable: every component's FMU opened and instantiated, connections resolved to
//! value references, the whole checked before anything runs, parameters applied, initial values
//! propagated. The master (`master.rs`) only sees the [`Unit`]s built here.

use super::ssp::{Component, Scene, Value};
use crate::fmi2::description::{ModelDescription, ScalarVariable};
use crate::fmi2::import::{Fmu, ImportError, Instance, SavedState};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

#[derive(Debug, thiserror::Error)]
pub enum SystemError {
    #[error("component {component}: {error}")]
    Load {
        component: String,
        error: ImportError,
    },
    #[error("{ssd}:{line}: {message}")]
    Invalid { ssd: PathBuf, line: usize, message: String },
    #[error("algebraic loop through direct-feedthrough outputs: {0}")]
    AlgebraicLoop(String),
    #[error("component {component}: {error}")]
    Call {
        component: String,
        error: ImportError,
    },
    #[error("{0}")]
    Record(String),
}

/// Kinds of values a master moves between FMUs. Enumerations travel as Integer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Kind {
    Real,
    Integer,
    Boolean,
}

fn kind_of(v: &ScalarVariable) -> Option<Kind> {
    match v.type_name() {
        "Real" => Some(Kind::Real),
        "Integer" | "Enumeration" => Some(Kind::Integer),
        "Boolean" => Some(Kind::Boolean),
        _ => None,
    }
}

/// One connected input: where its value comes from and the linear transformation on the way.
#[derive(Debug, Clone, Copy)]
pub struct Link {
    pub src_unit: usize,
    /// Index into the source unit's fetched values.
    pub src: usize,
    pub factor: f64,
    pub offset: f64,
}

/// Inputs of one kind a unit receives: value references, their sources and the values set.
#[derive(Debug, Default)]
pub struct Inputs {
    pub vr: Vec<u32>,
    pub links: Vec<Link>,
}

/// One instantiated component.
pub struct Unit {
    pub name: String,
    pub instance: Instance,
    pub fmu: Arc<Fmu>,
    pub can_interpolate_inputs: bool,
    pub can_get_set_state: bool,
    pub can_vary_step: bool,
    /// Variables read after every step, Real first, then Integer, then Boolean: `values` holds
    /// them in that order.
    pub fetch_real: Vec<u32>,
    pub fetch_integer: Vec<u32>,
    pub fetch_boolean: Vec<u32>,
    pub fetch_names: Vec<String>,
    pub values: Vec<f64>,
    pub real_in: Inputs,
    pub integer_in: Inputs,
    pub boolean_in: Inputs,
    /// Scratch for inputs and non-real fetches, reused every step.
    pub u_real: Vec<f64>,
    pub du1: Vec<f64>,
    pub du2: Vec<f64>,
    pub scratch_int: Vec<i32>,
    pub scratch_bool: Vec<bool>,
    pub saved: Option<SavedState>,
}

impl Drop for Unit {
    fn drop(&mut self) {
        if let Some(s) = self.saved.take() {
            let _ = self.instance.free_state(s);
        }
    }
}

impl Unit {
    /// Reads every fetched variable into `values`.
    pub fn fetch(&mut self) -> Result<(), ImportError> {
        let nr = self.fetch_real.len();
        let ni = self.fetch_integer.len();
        if nr > 0 {
            self.instance.get_real(&self.fetch_real, &mut self.values[..nr])?;
        }
        if ni > 0 {
            self.scratch_int.resize(ni, 0);
            self.instance.get_integer(&self.fetch_integer, &mut self.scratch_int)?;
            for (v, i) in self.values[nr..nr + ni].iter_mut().zip(&self.scratch_int) {
                *v = f64::from(*i);
            }
        }
        if !self.fetch_boolean.is_empty() {
            self.scratch_bool.resize(self.fetch_boolean.len(), false);
            self.instance.get_boolean(&self.fetch_boolean, &mut self.scratch_bool)?;
            for (v, b) in self.values[nr + ni..].iter_mut().zip(&self.scratch_bool) {
                *v = f64::from(u8::from(*b));
            }
        }
        Ok(())
    }

    /// Saves the FMU state, reusing the previous snapshot's memory.
    pub fn save_state(&mut self) -> Result<(), ImportError> {
        match &mut self.saved {
            Some(s) => self.instance.update_state(s),
            None => {
                self.saved = Some(self.instance.get_state()?);
                Ok(())
            }
        }
    }

    pub fn restore_state(&mut self) -> Result<(), ImportError> {
        match &self.saved {
            Some(s) => self.instance.set_state(s),
            None => unreachable!("restore_state before save_state"),
        }
    }

    /// Index in `values` of a fetched variable.
    pub fn value_index(&self, name: &str) -> Option<usize> {
        self.fetch_names.iter().position(|n| n == name)
    }
}

/// The runnable system.
pub struct System {
    pub name: String,
    pub units: Vec<Unit>,
    pub start_time: f64,
    /// Names and (unit, index) of the recorded columns.
    pub recorded: Vec<(String, usize, usize)>,
    /// Warnings found while checking (for example outputs whose dependencies are not declared).
    pub warnings: Vec<String>,
}

/// What to record: every output of every component, or the listed `component.variable` names.
pub enum Record {
    Outputs,
    Only(Vec<String>),
}

/// Checks that can fail before any FMU is instantiated.
struct Checker<'a> {
    scene: &'a Scene,
}

impl Checker<'_> {
    fn invalid(&self, line: usize, message: impl Into<String>) -> SystemError {
        SystemError::Invalid {
            ssd: self.scene.ssd.clone(),
            line,
            message: message.into(),
        }
    }
}

fn variable<'a>(md: &'a ModelDescription, name: &str) -> Option<&'a ScalarVariable> {
    md.variable(name)
}

impl System {
    /// Opens every FMU of the scene and checks the system; instantiates nothing yet.
    /// `overrides` are (component, variable, value as text) from the command line; they are read
    /// as the variable's type and applied after the scene's own parameter bindings.
    pub fn build(scene: &Scene, overrides: &[(String, String, String)], record: &Record) -> Result<Self, SystemError> {
        let check = Checker { scene };
        let mut names: HashMap<&str, usize> = HashMap::new();
        for (i, c) in scene.components.iter().enumerate() {
            if names.insert(&c.name, i).is_some() {
                return Err(check.invalid(c.line, format!("two components are called {}", c.name)));
            }
        }
        if scene.components.is_empty() {
            return Err(check.invalid(1, "the system has no components"));
        }
        // one Fmu per distinct file, shared by its instances
        let mut opened: HashMap<PathBuf, Arc<Fmu>> = HashMap::new();
        let mut fmus = Vec::new();
        for c in &scene.components {
            let key = c.path.canonicalize().unwrap_or_else(|_| c.path.clone());
            let fmu = match opened.get(&key) {
                Some(f) => Arc::clone(f),
                None => {
                    if !c.path.exists() {
                        return Err(check.invalid(
                            c.line,
                            format!("component {}: FMU {} not found (source=\"{}\")", c.name, c.path.display(), c.source),
                        ));
                    }
                    let f = Arc::new(Fmu::open(&c.path).map_err(|error| SystemError::Load {
                        component: c.name.clone(),
                        error,
                    })?);
                    opened.insert(key, Arc::clone(&f));
                    f
                }
            };
            check_connectors(&check, c, &fmu.description)?;
            fmus.push(fmu);
        }

        // resolve connections
        let mut fetch: Vec<Vec<(Kind, u32, String)>> = vec![Vec::new(); fmus.len()];
        let fetch_slot = |fetch: &mut Vec<Vec<(Kind, u32, String)>>, unit: usize, v: &ScalarVariable| {
            let kind = kind_of(v).expect("checked");
            let list = &mut fetch[unit];
            match list.iter().position(|(_, vr, _)| *vr == v.value_reference) {
                Some(i) => i,
                None => {
                    list.push((kind, v.value_reference, v.name.clone()));
                    list.len() - 1
                }
            }
        };
        // (dst unit, kind, vr) -> (src unit, src fetch position, factor, offset, line)
        let mut inputs: Vec<Vec<(Kind, u32, usize, usize, f64, f64)>> = vec![Vec::new(); fmus.len()];
        let mut connected: HashMap<(usize, u32), usize> = HashMap::new();
        let mut edges: Vec<((usize, String), (usize, String))> = Vec::new();
        for k in &scene.connections {
            let end_of = |element: &str, connector: &str, want: &str| -> Result<(usize, &ScalarVariable), SystemError> {
                let &u = names.get(element).ok_or_else(|| {
                    check.invalid(
                        k.line,
                        format!("connection {}: unknown component {element} (components: {})", k.describe(), component_list(scene)),
                    )
                })?;
                let v = variable(&fmus[u].description, connector).ok_or_else(|| {
                    check.invalid(
                        k.line,
                        format!("connection {}: component {element} ({}) has no variable {connector}", k.describe(), fmus[u].description.model_name),
                    )
                })?;
                let ok = match want {
                    "output" => v.causality == "output",
                    _ => v.causality == "input",
                };
                if !ok {
                    return Err(check.invalid(
                        k.line,
                        format!("connection {}: {element}.{connector} is {}, not an {want}", k.describe(), v.causality),
                    ));
                }
                Ok((u, v))
            };
            let (su, sv) = end_of(&k.start_element, &k.start_connector, "output")?;
            let (du, dv) = end_of(&k.end_element, &k.end_connector, "input")?;
            let (sk, dk) = (kind_of(sv), kind_of(dv));
            if sk.is_none() || dk.is_none() {
                return Err(check.invalid(k.line, format!("connection {}: String variables cannot be connected", k.describe())));
            }
            if sk != dk {
                return Err(check.invalid(
                    k.line,
                    format!("connection {}: type mismatch, {} output to {} input", k.describe(), sv.type_name(), dv.type_name()),
                ));
            }
            if sk != Some(Kind::Real) && (k.factor != 1.0 || k.offset != 0.0) {
                return Err(check.invalid(
                    k.line,
                    format!("connection {}: a linear transformation needs Real connectors, these are {}", k.describe(), sv.type_name()),
                ));
            }
            if let Some(prev) = connected.insert((du, dv.value_reference), k.line) {
                return Err(check.invalid(
                    k.line,
                    format!("input {}.{} is connected twice (also at line {prev})", k.end_element, k.end_connector),
                ));
            }
            let slot = fetch_slot(&mut fetch, su, sv);
            inputs[du].push((dk.expect("checked"), dv.value_reference, su, slot, k.factor, k.offset));
            edges.push(((su, sv.name.clone()), (du, dv.name.clone())));
        }

        let overrides = &typed_overrides(scene, &fmus, overrides)?;
        // unconnected inputs need a start value
        for (u, fmu) in fmus.iter().enumerate() {
            for v in &fmu.description.model_variables.variables {
                if v.causality == "input"
                    && !connected.contains_key(&(u, v.value_reference))
                    && v.attributes().and_then(|a| a.start.as_ref()).is_none()
                    && !parameter_bound(scene, overrides, u, &v.name)
                {
                    return Err(check.invalid(
                        scene.components[u].line,
                        format!("input {}.{} is not connected and has no start value", scene.components[u].name, v.name),
                    ));
                }
            }
        }

        let mut warnings = Vec::new();
        find_algebraic_loops(scene, &fmus, &edges, &mut warnings)?;
        check_parameters(&check, scene, &fmus, overrides)?;

        // recorded columns
        let mut recorded_vars: Vec<(usize, usize)> = Vec::new();
        let mut recorded_names = Vec::new();
        match record {
            Record::Outputs => {
                for (u, fmu) in fmus.iter().enumerate() {
                    for v in &fmu.description.model_variables.variables {
                        if v.causality == "output" && kind_of(v).is_some() {
                            let slot = fetch_slot(&mut fetch, u, v);
                            recorded_vars.push((u, slot));
                            recorded_names.push(format!("{}.{}", scene.components[u].name, v.name));
                        }
                    }
                }
            }
            Record::Only(list) => {
                for full in list {
                    let (comp, var) = full.split_once('.').ok_or_else(|| {
                        SystemError::Record(format!("--record {full}: expected component.variable"))
                    })?;
                    let &u = names.get(comp).ok_or_else(|| {
                        SystemError::Record(format!("--record {full}: unknown component {comp} (components: {})", component_list(scene)))
                    })?;
                    let v = variable(&fmus[u].description, var)
                        .ok_or_else(|| SystemError::Record(format!("--record {full}: {comp} has no variable {var}")))?;
                    if kind_of(v).is_none() {
                        return Err(SystemError::Record(format!("--record {full}: String variables cannot be recorded")));
                    }
                    let slot = fetch_slot(&mut fetch, u, v);
                    recorded_vars.push((u, slot));
                    recorded_names.push(full.clone());
                }
            }
        }

        // instantiate, ordering fetched values by kind
        let start_time = scene.experiment.start_time.unwrap_or(0.0);
        let mut units = Vec::with_capacity(fmus.len());
        let mut remaps = Vec::with_capacity(fmus.len());
        for (u, fmu) in fmus.iter().enumerate() {
            let name = scene.components[u].name.clone();
            let instance = fmu.instantiate(&name, false).map_err(|error| SystemError::Load {
                component: name.clone(),
                error,
            })?;
            let mut order: Vec<usize> = (0..fetch[u].len()).collect();
            order.sort_by_key(|&i| match fetch[u][i].0 {
                Kind::Real => 0,
                Kind::Integer => 1,
                Kind::Boolean => 2,
            });
            let mut remap = vec![0; order.len()];
            for (new, &old) in order.iter().enumerate() {
                remap[old] = new;
            }
            let pick = |kind: Kind| -> Vec<u32> { order.iter().filter(|&&i| fetch[u][i].0 == kind).map(|&i| fetch[u][i].1).collect() };
            let cs = fmu.description.co_simulation.as_ref().expect("checked on open");
            units.push(Unit {
                name,
                instance,
                fmu: Arc::clone(fmu),
                can_interpolate_inputs: cs.can_interpolate_inputs,
                can_get_set_state: cs.can_get_and_set_fmu_state,
                can_vary_step: cs.can_handle_variable_step,
                fetch_real: pick(Kind::Real),
                fetch_integer: pick(Kind::Integer),
                fetch_boolean: pick(Kind::Boolean),
                fetch_names: order.iter().map(|&i| fetch[u][i].2.clone()).collect(),
                values: vec![0.0; order.len()],
                real_in: Inputs::default(),
                integer_in: Inputs::default(),
                boolean_in: Inputs::default(),
                u_real: Vec::new(),
                du1: Vec::new(),
                du2: Vec::new(),
                scratch_int: Vec::new(),
                scratch_bool: Vec::new(),
                saved: None,
            });
            remaps.push(remap);
        }
        for (du, list) in inputs.into_iter().enumerate() {
            for (kind, vr, su, slot, factor, offset) in list {
                let link = Link {
                    src_unit: su,
                    src: remaps[su][slot],
                    factor,
                    offset,
                };
                let target = match kind {
                    Kind::Real => &mut units[du].real_in,
                    Kind::Integer => &mut units[du].integer_in,
                    Kind::Boolean => &mut units[du].boolean_in,
                };
                target.vr.push(vr);
                target.links.push(link);
            }
            let n = units[du].real_in.vr.len();
            units[du].u_real = vec![0.0; n];
            units[du].du1 = vec![0.0; n];
            units[du].du2 = vec![0.0; n];
        }
        let recorded = recorded_names
            .into_iter()
            .zip(recorded_vars)
            .map(|(n, (u, slot))| (n, u, remaps[u][slot]))
            .collect();
        let mut system = Self {
            name: scene.name.clone(),
            units,
            start_time,
            recorded,
            warnings,
        };
        system.apply_parameters(scene, overrides)?;
        Ok(system)
    }

    fn call<T>(&self, u: usize, r: Result<T, ImportError>) -> Result<T, SystemError> {
        r.map_err(|error| SystemError::Call {
            component: self.units[u].name.clone(),
            error,
        })
    }

    fn apply_parameters(&mut self, scene: &Scene, overrides: &[(String, String, Value)]) -> Result<(), SystemError> {
        for u in 0..self.units.len() {
            let comp = &scene.components[u];
            let own = overrides.iter().filter(|(c, _, _)| *c == comp.name).map(|(_, n, v)| (n.as_str(), v));
            let bound: Vec<(&str, &Value)> = comp.parameters.iter().map(|p| (p.name.as_str(), &p.value)).chain(own).collect();
            for (name, value) in bound {
                let v = variable(&self.units[u].fmu.description, name).expect("checked").clone();
                let vr = [v.value_reference];
                let unit = &mut self.units[u];
                let r = match (kind_of(&v), value) {
                    (Some(Kind::Real), Value::Real(x)) => unit.instance.set_real(&vr, &[*x]),
                    (Some(Kind::Real), Value::Integer(x)) => unit.instance.set_real(&vr, &[*x as f64]),
                    (Some(Kind::Integer), Value::Integer(x)) => unit.instance.set_integer(&vr, &[*x as i32]),
                    (Some(Kind::Boolean), Value::Boolean(x)) => unit.instance.set_boolean(&vr, &[*x]),
                    (None, Value::String(x)) => unit.instance.set_string(&vr, &[x.as_str()]),
                    _ => unreachable!("types checked in check_parameters"),
                };
                self.call(u, r)?;
            }
        }
        Ok(())
    }

    /// FMI initialization of every unit: setup, initialization mode, `rounds` passes of
    /// outputs → inputs so initial values propagate along chains (as libcosim does), then
    /// the values at the start time.
    pub fn initialize(&mut self, stop_time: Option<f64>) -> Result<(), SystemError> {
        let t0 = self.start_time;
        for u in 0..self.units.len() {
            let r = self.units[u].instance.setup_experiment(t0, stop_time);
            self.call(u, r)?;
            let r = self.units[u].instance.enter_initialization_mode();
            self.call(u, r)?;
        }
        for _ in 0..self.units.len() {
            for u in 0..self.units.len() {
                let r = self.units[u].fetch();
                self.call(u, r)?;
            }
            for u in 0..self.units.len() {
                let r = self.set_held_inputs(u);
                self.call(u, r)?;
            }
        }
        for u in 0..self.units.len() {
            let r = self.units[u].instance.exit_initialization_mode();
            self.call(u, r)?;
            let r = self.units[u].fetch();
            self.call(u, r)?;
        }
        Ok(())
    }

    /// Sets every connected input of unit `u` to its source's current value (zero-order hold).
    pub fn set_held_inputs(&mut self, u: usize) -> Result<(), ImportError> {
        let values = |l: &Link| self.units[l.src_unit].values[l.src];
        let real: Vec<f64> = self.units[u].real_in.links.iter().map(|l| l.factor * values(l) + l.offset).collect();
        let discrete = DiscreteInputs::of(&self.units, u);
        let unit = &mut self.units[u];
        if !unit.real_in.vr.is_empty() {
            unit.instance.set_real(&unit.real_in.vr, &real)?;
        }
        discrete.set(unit)
    }

    pub fn terminate(&mut self) {
        for u in &mut self.units {
            let _ = u.instance.terminate();
        }
    }
}

/// Integer and Boolean inputs of one unit: always the source's current value.
pub struct DiscreteInputs {
    integers: Vec<i32>,
    booleans: Vec<bool>,
}

impl DiscreteInputs {
    pub fn of(units: &[Unit], u: usize) -> Self {
        let value = |l: &Link| units[l.src_unit].values[l.src];
        Self {
            integers: units[u].integer_in.links.iter().map(|l| value(l) as i32).collect(),
            booleans: units[u].boolean_in.links.iter().map(|l| value(l) != 0.0).collect(),
        }
    }

    pub fn set(&self, unit: &mut Unit) -> Result<(), ImportError> {
        if !self.integers.is_empty() {
            unit.instance.set_integer(&unit.integer_in.vr, &self.integers)?;
        }
        if !self.booleans.is_empty() {
            unit.instance.set_boolean(&unit.boolean_in.vr, &self.booleans)?;
        }
        Ok(())
    }
}

fn component_list(scene: &Scene) -> String {
    scene.components.iter().map(|c| c.name.as_str()).collect::<Vec<_>>().join(", ")
}

fn parameter_bound(scene: &Scene, overrides: &[(String, String, Value)], u: usize, name: &str) -> bool {
    let comp = &scene.components[u];
    comp.parameters.iter().any(|p| p.name == name) || overrides.iter().any(|(c, n, _)| *c == comp.name && n == name)
}

/// SSD connectors, when declared, must exist in the FMU with the same kind and type.
fn check_connectors(check: &Checker, c: &Component, md: &ModelDescription) -> Result<(), SystemError> {
    for k in &c.connectors {
        let v = variable(md, &k.name).ok_or_else(|| {
            check.invalid(c.line, format!("component {}: connector {} is not a variable of {}", c.name, k.name, md.model_name))
        })?;
        if !k.kind.is_empty() && k.kind != v.causality && !(k.kind == "parameter" && v.causality == "calculatedParameter") {
            return Err(check.invalid(
                c.line,
                format!("component {}: connector {} is declared {} but the FMU has it as {}", c.name, k.name, k.kind, v.causality),
            ));
        }
        if let Some(t) = &k.type_name {
            let same = t == v.type_name() || (t == "Integer" && v.type_name() == "Enumeration");
            if !same {
                return Err(check.invalid(
                    c.line,
                    format!("component {}: connector {} is declared {t} but the FMU has it as {}", c.name, k.name, v.type_name()),
                ));
            }
        }
    }
    Ok(())
}

fn typed_overrides(
    scene: &Scene,
    fmus: &[Arc<Fmu>],
    raw: &[(String, String, String)],
) -> Result<Vec<(String, String, Value)>, SystemError> {
    raw.iter()
        .map(|(c, n, text)| {
            let bad = |m: String| SystemError::Record(format!("--param {c}.{n}={text}: {m}"));
            let u = scene
                .components
                .iter()
                .position(|x| x.name == *c)
                .ok_or_else(|| bad(format!("unknown component (components: {})", component_list(scene))))?;
            let v = variable(&fmus[u].description, n).ok_or_else(|| bad(format!("{c} has no variable {n}")))?;
            let value = match v.type_name() {
                "Real" => Value::Real(text.trim().parse().map_err(|_| bad("not a number".into()))?),
                "Integer" | "Enumeration" => Value::Integer(text.trim().parse().map_err(|_| bad("not an integer".into()))?),
                "Boolean" => Value::Boolean(match text.trim() {
                    "true" | "1" => true,
                    "false" | "0" => false,
                    _ => return Err(bad("not true or false".into())),
                }),
                _ => Value::String(text.clone()),
            };
            Ok((c.clone(), n.clone(), value))
        })
        .collect()
}

fn check_parameters(check: &Checker, scene: &Scene, fmus: &[Arc<Fmu>], overrides: &[(String, String, Value)]) -> Result<(), SystemError> {
    for (c, _, _) in overrides {
        if scene.component(c).is_none() {
            return Err(SystemError::Record(format!(
                "parameter override for unknown component {c} (components: {})",
                component_list(scene)
            )));
        }
    }
    for (u, comp) in scene.components.iter().enumerate() {
        let md = &fmus[u].description;
        let own = overrides
            .iter()
            .filter(|(c, _, _)| *c == comp.name)
            .map(|(_, n, v)| (n.clone(), v.clone(), "command line".to_string(), comp.line));
        let all = comp
            .parameters
            .iter()
            .map(|p| (p.name.clone(), p.value.clone(), p.origin.clone(), comp.line))
            .chain(own);
        for (name, value, origin, line) in all {
            let v = variable(md, &name).ok_or_else(|| {
                check.invalid(line, format!("component {}: {origin}: {} has no variable {name}", comp.name, md.model_name))
            })?;
            if !matches!(v.causality.as_str(), "parameter" | "input") || v.variability == "constant" {
                return Err(check.invalid(
                    line,
                    format!("component {}: {origin}: {name} is a {} {} variable and cannot be set", comp.name, v.variability, v.causality),
                ));
            }
            let fits = matches!(
                (v.type_name(), &value),
                ("Real", Value::Real(_) | Value::Integer(_))
                    | ("Integer" | "Enumeration", Value::Integer(_))
                    | ("Boolean", Value::Boolean(_))
                    | ("String", Value::String(_))
            );
            if !fits {
                return Err(check.invalid(
                    line,
                    format!("component {}: {origin}: {name} is {} but the value is {}", comp.name, v.type_name(), value.type_name()),
                ));
            }
        }
    }
    Ok(())
}

/// Outputs feeding inputs that the same FMU's outputs depend on directly form a graph; a cycle is
/// an algebraic loop. Declared dependencies make it an error; outputs without a declared list may
/// depend on every input (FMI 2.0 §2.2.8), which many exporters leave open, so such cycles warn.
fn find_algebraic_loops(
    scene: &Scene,
    fmus: &[Arc<Fmu>],
    edges: &[((usize, String), (usize, String))],
    warnings: &mut Vec<String>,
) -> Result<(), SystemError> {
    // node = (unit, output name); arc output -> output through one connection and one feedthrough
    let deps: Vec<Vec<(String, Option<Vec<String>>)>> = fmus
        .iter()
        .map(|f| {
            f.description
                .output_dependencies()
                .into_iter()
                .map(|(o, d)| (o.to_string(), d.map(|d| d.into_iter().map(String::from).collect())))
                .collect()
        })
        .collect();
    let nodes: Vec<(usize, &str)> = deps.iter().enumerate().flat_map(|(u, d)| d.iter().map(move |(o, _)| (u, o.as_str()))).collect();
    let index: HashMap<(usize, &str), usize> = nodes.iter().enumerate().map(|(i, &n)| (n, i)).collect();
    let mut arcs: Vec<Vec<(usize, bool)>> = vec![Vec::new(); nodes.len()];
    for ((su, out), (du, input)) in edges {
        let Some(&from) = index.get(&(*su, out.as_str())) else { continue };
        for (o, d) in &deps[*du] {
            let (feeds, declared) = match d {
                Some(list) => (list.iter().any(|i| i == input), true),
                None => (true, false),
            };
            if feeds {
                arcs[from].push((index[&(*du, o.as_str())], declared));
            }
        }
    }
    // depth-first search for a cycle; report the first, preferring declared ones
    for declared_only in [true, false] {
        let mut colour = vec![0u8; nodes.len()];
        let mut path = Vec::new();
        for start in 0..nodes.len() {
            if let Some(cycle) = dfs(start, &arcs, declared_only, &mut colour, &mut path) {
                let text = cycle
                    .iter()
                    .map(|&i| format!("{}.{}", scene.components[nodes[i].0].name, nodes[i].1))
                    .collect::<Vec<_>>()
                    .join(" -> ");
                if declared_only {
                    return Err(SystemError::AlgebraicLoop(text));
                }
                warnings.push(format!(
                    "possible algebraic loop {text}: an FMU on it does not declare its output dependencies, so the \
                     standard assumes direct feedthrough; the master breaks it with the previous step's values"
                ));
                return Ok(());
            }
        }
    }
    Ok(())
}

fn dfs(n: usize, arcs: &[Vec<(usize, bool)>], declared_only: bool, colour: &mut [u8], path: &mut Vec<usize>) -> Option<Vec<usize>> {
    if colour[n] == 2 {
        return None;
    }
    if colour[n] == 1 {
        let at = path.iter().position(|&p| p == n).unwrap_or(0);
        let mut cycle = path[at..].to_vec();
        cycle.push(n);
        return Some(cycle);
    }
    colour[n] = 1;
    path.push(n);
    for &(m, declared) in &arcs[n] {
        if declared_only && !declared {
            continue;
        }
        if let Some(c) = dfs(m, arcs, declared_only, colour, path) {
            return Some(c);
        }
    }
    path.pop();
    colour[n] = 2;
    None
}
