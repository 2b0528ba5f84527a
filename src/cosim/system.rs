//! A scene made runnable: every component's FMU opened and instantiated, connections resolved to
//! value references, the whole checked before anything runs, parameters applied, initial values
//! propagated. The master (`master.rs`) only sees the [`Unit`]s built here.

use super::checks::{
    Checker, Endpoint, check_connectors, check_parameters, component_list, find_algebraic_loops, parameter_bound,
    typed_overrides, variable,
};
use super::error::SystemError;
use super::ssp::{Scene, Value};
use super::unit::{DiscreteInputs, Inputs, Kind, Link, Unit, VarGroup, kind_of};
use crate::fmi2::host::description::ScalarVariable;
use crate::fmi2::host::error::ImportError;
use crate::fmi2::host::import::Fmu;
use crate::fmi2::host::isolate::Isolation;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

/// A connection resolved to value references, before the units exist.
#[derive(Debug, Clone, Copy)]
struct PendingInput {
    kind: Kind,
    vr: u32,
    src_unit: usize,
    /// Position in the source unit's fetch list as first collected.
    slot: usize,
    factor: f64,
    offset: f64,
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
    /// Whether the observer keeps the next communication point's row ([`super::recorder::Recorder`]
    /// says so after each row it offers): a Jacobi or Gauss–Seidel step, never retaken, then reads
    /// the recorder's variables with the coupled outputs ([`Unit::fetch_with_recorded`]). False, the
    /// start: the recorder reads them itself when it keeps a row.
    pub record_next: bool,
}

/// What to record: every output of every component, or the listed `component.variable` names.
pub enum Record {
    Outputs,
    Only(Vec<String>),
}

impl System {
    /// Opens every FMU of the scene and checks the system; instantiates nothing yet.
    /// `overrides` are (component, variable, value as text) from the command line; they are read
    /// as the variable's type and applied after the scene's own parameter bindings.
    pub fn build(scene: &Scene, overrides: &[(String, String, String)], record: &Record) -> Result<Self, SystemError> {
        Self::build_with(scene, overrides, record, None)
    }

    /// Like [`System::build`], with every FMU instance in a process of its own (see [`Isolation`]):
    /// an FMU that crashes ends the run with an error naming it instead of taking the master down.
    pub fn build_isolated(
        scene: &Scene,
        overrides: &[(String, String, String)],
        record: &Record,
        how: &Isolation,
    ) -> Result<Self, SystemError> {
        Self::build_with(scene, overrides, record, Some(how))
    }

    fn build_with(
        scene: &Scene,
        overrides: &[(String, String, String)],
        record: &Record,
        isolation: Option<&Isolation>,
    ) -> Result<Self, SystemError> {
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
                            format!(
                                "component {}: FMU {} not found (source=\"{}\")",
                                c.name,
                                c.path.display(),
                                c.source
                            ),
                        ));
                    }
                    let fmu = match isolation {
                        Some(_) => Fmu::open_for_host(&c.path),
                        None => Fmu::open(&c.path),
                    };
                    let f = Arc::new(fmu.map_err(|error| SystemError::Load {
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
        let mut inputs: Vec<Vec<PendingInput>> = vec![Vec::new(); fmus.len()];
        let mut connected: HashMap<(usize, u32), usize> = HashMap::new();
        let mut edges: Vec<(Endpoint, Endpoint)> = Vec::new();
        for k in &scene.connections {
            let end_of =
                |element: &str, connector: &str, want: &str| -> Result<(usize, &ScalarVariable), SystemError> {
                    let &u = names.get(element).ok_or_else(|| {
                        check.invalid(
                            k.line,
                            format!(
                                "connection {}: unknown component {element} (components: {})",
                                k.describe(),
                                component_list(scene)
                            ),
                        )
                    })?;
                    let v = variable(&fmus[u].description, connector).ok_or_else(|| {
                        check.invalid(
                            k.line,
                            format!(
                                "connection {}: component {element} ({}) has no variable {connector}",
                                k.describe(),
                                fmus[u].description.model_name
                            ),
                        )
                    })?;
                    let ok = match want {
                        "output" => v.causality == "output",
                        _ => v.causality == "input",
                    };
                    if !ok {
                        return Err(check.invalid(
                            k.line,
                            format!(
                                "connection {}: {element}.{connector} is {}, not an {want}",
                                k.describe(),
                                v.causality
                            ),
                        ));
                    }
                    Ok((u, v))
                };
            let (su, sv) = end_of(&k.start_element, &k.start_connector, "output")?;
            let (du, dv) = end_of(&k.end_element, &k.end_connector, "input")?;
            let (sk, dk) = (kind_of(sv), kind_of(dv));
            if sk.is_none() || dk.is_none() {
                return Err(check.invalid(
                    k.line,
                    format!("connection {}: String variables cannot be connected", k.describe()),
                ));
            }
            if sk != dk {
                return Err(check.invalid(
                    k.line,
                    format!(
                        "connection {}: type mismatch, {} output to {} input",
                        k.describe(),
                        sv.type_name(),
                        dv.type_name()
                    ),
                ));
            }
            if sk != Some(Kind::Real) && (k.factor != 1.0 || k.offset != 0.0) {
                return Err(check.invalid(
                    k.line,
                    format!(
                        "connection {}: a linear transformation needs Real connectors, these are {}",
                        k.describe(),
                        sv.type_name()
                    ),
                ));
            }
            if let Some(prev) = connected.insert((du, dv.value_reference), k.line) {
                return Err(check.invalid(
                    k.line,
                    format!(
                        "input {}.{} is connected twice (also at line {prev})",
                        k.end_element, k.end_connector
                    ),
                ));
            }
            let slot = fetch_slot(&mut fetch, su, sv);
            inputs[du].push(PendingInput {
                kind: dk.expect("checked"),
                vr: dv.value_reference,
                src_unit: su,
                slot,
                factor: k.factor,
                offset: k.offset,
            });
            edges.push(((su, sv.name.clone()), (du, dv.name.clone())));
        }

        // slots so far are read by other units; the recorder's own come after
        let coupled_count: Vec<usize> = fetch.iter().map(Vec::len).collect();
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
                        format!(
                            "input {}.{} is not connected and has no start value",
                            scene.components[u].name, v.name
                        ),
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
                    let (comp, var) = full
                        .split_once('.')
                        .ok_or_else(|| SystemError::Record(format!("--record {full}: expected component.variable")))?;
                    let &u = names.get(comp).ok_or_else(|| {
                        SystemError::Record(format!(
                            "--record {full}: unknown component {comp} (components: {})",
                            component_list(scene)
                        ))
                    })?;
                    let v = variable(&fmus[u].description, var)
                        .ok_or_else(|| SystemError::Record(format!("--record {full}: {comp} has no variable {var}")))?;
                    if kind_of(v).is_none() {
                        return Err(SystemError::Record(format!(
                            "--record {full}: String variables cannot be recorded"
                        )));
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
            let instance = match isolation {
                Some(how) => fmu.instantiate_isolated(&name, false, how),
                None => fmu.instantiate(&name, false),
            };
            let instance = instance.map_err(|error| SystemError::Load {
                component: name.clone(),
                error,
            })?;
            // coupled before recorder-only, and by kind inside each: two groups of `values`
            let rank = |i: usize| {
                let kind = match fetch[u][i].0 {
                    Kind::Real => 0,
                    Kind::Integer => 1,
                    Kind::Boolean => 2,
                };
                (usize::from(i >= coupled_count[u]), kind)
            };
            let mut order: Vec<usize> = (0..fetch[u].len()).collect();
            order.sort_by_key(|&i| rank(i));
            let mut remap = vec![0; order.len()];
            for (new, &old) in order.iter().enumerate() {
                remap[old] = new;
            }
            let group = |extra: bool, offset: usize| {
                let pick = |kind: Kind| -> Vec<u32> {
                    order
                        .iter()
                        .filter(|&&i| (i >= coupled_count[u]) == extra && fetch[u][i].0 == kind)
                        .map(|&i| fetch[u][i].1)
                        .collect()
                };
                VarGroup {
                    real: pick(Kind::Real),
                    integer: pick(Kind::Integer),
                    boolean: pick(Kind::Boolean),
                    offset,
                }
            };
            let coupled = group(false, 0);
            let recorded_only = group(true, coupled.len());
            let cs = fmu.description.co_simulation.as_ref().expect("checked on open");
            units.push(Unit {
                name,
                instance,
                fmu: Arc::clone(fmu),
                can_interpolate_inputs: cs.can_interpolate_inputs,
                can_get_set_state: cs.can_get_and_set_fmu_state,
                can_vary_step: cs.can_handle_variable_step,
                joined_real: [&coupled.real[..], &recorded_only.real[..]].concat(),
                joined_values: Vec::new(),
                recorded_fresh: false,
                coupled,
                recorded_only,
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
                discrete_held: DiscreteInputs::default(),
                discrete_scratch: DiscreteInputs::default(),
                clock: None,
            });
            remaps.push(remap);
        }
        for (du, list) in inputs.into_iter().enumerate() {
            for PendingInput {
                kind,
                vr,
                src_unit,
                slot,
                factor,
                offset,
            } in list
            {
                let link = Link {
                    src_unit,
                    src: remaps[src_unit][slot],
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
            record_next: false,
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
            let own = overrides
                .iter()
                .filter(|(c, _, _)| *c == comp.name)
                .map(|(_, n, v)| (n.as_str(), v));
            let bound: Vec<(&str, &Value)> = comp
                .parameters
                .iter()
                .map(|p| (p.name.as_str(), &p.value))
                .chain(own)
                .collect();
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
            let r = self.units[u].fetch_recorded();
            self.call(u, r)?;
        }
        Ok(())
    }

    /// Sets every connected input of unit `u` to its source's current value (zero-order hold).
    pub fn set_held_inputs(&mut self, u: usize) -> Result<(), ImportError> {
        let values = |l: &Link| self.units[l.src_unit].values[l.src];
        let real: Vec<f64> = self.units[u]
            .real_in
            .links
            .iter()
            .map(|l| l.factor * values(l) + l.offset)
            .collect();
        let unit = &mut self.units[u];
        if !unit.real_in.vr.is_empty() {
            unit.instance.set_real(&unit.real_in.vr, &real)?;
        }
        DiscreteInputs::send(&mut self.units, u)
    }

    pub fn terminate(&mut self) {
        for u in &mut self.units {
            let _ = u.instance.terminate();
        }
    }
}
