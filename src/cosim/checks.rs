//! The checks a scene must pass before any FMU is instantiated: connectors against the FMUs,
//! parameter values against their variables, and algebraic loops through direct feedthrough.

use super::error::SystemError;
use super::ssp::{Component, Scene, Value};
use crate::fmi2::host::description::{ModelDescription, ScalarVariable};
use crate::fmi2::host::import::Fmu;
use std::collections::HashMap;
use std::sync::Arc;

/// A connection end: (unit, variable name).
pub(super) type Endpoint = (usize, String);

/// Checks that can fail before any FMU is instantiated.
pub(super) struct Checker<'a> {
    pub(super) scene: &'a Scene,
}

impl Checker<'_> {
    pub(super) fn invalid(&self, line: usize, message: impl Into<String>) -> SystemError {
        SystemError::Invalid {
            ssd: self.scene.ssd.clone(),
            line,
            message: message.into(),
        }
    }
}

pub(super) fn variable<'a>(md: &'a ModelDescription, name: &str) -> Option<&'a ScalarVariable> {
    md.variable(name)
}

pub(super) fn component_list(scene: &Scene) -> String {
    scene
        .components
        .iter()
        .map(|c| c.name.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}

pub(super) fn parameter_bound(scene: &Scene, overrides: &[(String, String, Value)], u: usize, name: &str) -> bool {
    let comp = &scene.components[u];
    comp.parameters.iter().any(|p| p.name == name) || overrides.iter().any(|(c, n, _)| *c == comp.name && n == name)
}

/// SSD connectors, when declared, must exist in the FMU with the same kind and type.
pub(super) fn check_connectors(check: &Checker, c: &Component, md: &ModelDescription) -> Result<(), SystemError> {
    for k in &c.connectors {
        let v = variable(md, &k.name).ok_or_else(|| {
            check.invalid(
                c.line,
                format!(
                    "component {}: connector {} is not a variable of {}",
                    c.name, k.name, md.model_name
                ),
            )
        })?;
        if !k.kind.is_empty()
            && k.kind != v.causality
            && !(k.kind == "parameter" && v.causality == "calculatedParameter")
        {
            return Err(check.invalid(
                c.line,
                format!(
                    "component {}: connector {} is declared {} but the FMU has it as {}",
                    c.name, k.name, k.kind, v.causality
                ),
            ));
        }
        if let Some(t) = &k.type_name {
            let same = t == v.type_name() || (t == "Integer" && v.type_name() == "Enumeration");
            if !same {
                return Err(check.invalid(
                    c.line,
                    format!(
                        "component {}: connector {} is declared {t} but the FMU has it as {}",
                        c.name,
                        k.name,
                        v.type_name()
                    ),
                ));
            }
        }
    }
    Ok(())
}

pub(super) fn typed_overrides(
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
                "Integer" | "Enumeration" => {
                    Value::Integer(text.trim().parse().map_err(|_| bad("not an integer".into()))?)
                }
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

pub(super) fn check_parameters(
    check: &Checker,
    scene: &Scene,
    fmus: &[Arc<Fmu>],
    overrides: &[(String, String, Value)],
) -> Result<(), SystemError> {
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
                check.invalid(
                    line,
                    format!(
                        "component {}: {origin}: {} has no variable {name}",
                        comp.name, md.model_name
                    ),
                )
            })?;
            if !matches!(v.causality.as_str(), "parameter" | "input") || v.variability == "constant" {
                return Err(check.invalid(
                    line,
                    format!(
                        "component {}: {origin}: {name} is a {} {} variable and cannot be set",
                        comp.name, v.variability, v.causality
                    ),
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
                    format!(
                        "component {}: {origin}: {name} is {} but the value is {}",
                        comp.name,
                        v.type_name(),
                        value.type_name()
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Outputs feeding inputs that the same FMU's outputs depend on directly form a graph; a cycle is
/// an algebraic loop. Declared dependencies make it an error; outputs without a declared list may
/// depend on every input (FMI 2.0 §2.2.8), which many exporters leave open, so such cycles warn.
pub(super) fn find_algebraic_loops(
    scene: &Scene,
    fmus: &[Arc<Fmu>],
    edges: &[(Endpoint, Endpoint)],
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
    let nodes: Vec<(usize, &str)> = deps
        .iter()
        .enumerate()
        .flat_map(|(u, d)| d.iter().map(move |(o, _)| (u, o.as_str())))
        .collect();
    let index: HashMap<(usize, &str), usize> = nodes.iter().enumerate().map(|(i, &n)| (n, i)).collect();
    let mut arcs: Vec<Vec<(usize, bool)>> = vec![Vec::new(); nodes.len()];
    for ((su, out), (du, input)) in edges {
        let Some(&from) = index.get(&(*su, out.as_str())) else {
            continue;
        };
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

fn dfs(
    n: usize,
    arcs: &[Vec<(usize, bool)>],
    declared_only: bool,
    colour: &mut [u8],
    path: &mut Vec<usize>,
) -> Option<Vec<usize>> {
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
