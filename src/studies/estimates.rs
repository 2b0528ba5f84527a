//! The inputs of the reproduction's scenes that no source gives (src/studies/data/estimates.toml): each
//! with the value the scenes use, the range it may plausibly take and why, and where it goes (a scene's
//! parameter binding or a key of a shipped gearbox description). [`Setting`] puts chosen values into the
//! scenes a study opens, so the sensitivity campaign (`scripts/campaign sensitivity`) can run the
//! reproduction's rows anywhere in the band.

use crate::cosim::Scene;
use crate::cosim::ssp::{Parameter, Value};
use crate::physics::drivetrain::Drivetrain;
use crate::physics::gearbox::description::PRESETS;
use anyhow::{Context, anyhow, bail};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

const ESTIMATES: &str = include_str!("data/estimates.toml");

/// One input no source gives.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Estimate {
    pub name: String,
    /// Estimates varied together (they share the scenes they act on).
    pub group: String,
    pub description: String,
    pub unit: String,
    /// The value the scenes run at (in `unit`).
    pub nominal: f64,
    pub low: f64,
    pub high: f64,
    /// Why this range.
    pub reason: String,
    /// The value is a multiple of this preset's rated generator torque.
    #[serde(default)]
    pub per_rated_generator_torque: Option<String>,
    /// The scenes leave the parameter at the FMU's default, which `nominal` states.
    #[serde(default)]
    pub unbound: bool,
    pub targets: Vec<Target>,
}

/// Where an estimate's value goes.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(untagged, deny_unknown_fields)]
pub enum Target {
    /// A parameter binding of `component.variable` in each of `scenes` (scene folder names).
    Parameter {
        scenes: Vec<String>,
        component: String,
        variable: String,
    },
    /// A key of a shipped gearbox description, dotted, `*` for every element of an array; in every
    /// scene whose gearbox6dof binds `gearbox`.
    Gearbox { gearbox: String, key: String },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    estimate: Vec<Estimate>,
}

/// Every estimate, in the file's order.
pub fn all() -> anyhow::Result<Vec<Estimate>> {
    let file: File = toml::from_str(ESTIMATES).map_err(|e| anyhow!("src/studies/data/estimates.toml: {e}"))?;
    for e in &file.estimate {
        if !(e.low <= e.nominal && e.nominal <= e.high) {
            bail!(
                "src/studies/data/estimates.toml: {}: nominal {} outside its range {}–{}",
                e.name,
                e.nominal,
                e.low,
                e.high
            );
        }
    }
    Ok(file.estimate)
}

impl Estimate {
    /// The value as the scene or description takes it (N·m where the estimate is per unit of rated
    /// generator torque).
    pub fn in_scene(&self, value: f64) -> anyhow::Result<f64> {
        Ok(match &self.per_rated_generator_torque {
            Some(preset) => {
                let d =
                    Drivetrain::preset(preset).ok_or_else(|| anyhow!("{}: unknown preset {preset:?}", self.name))?;
                value * d.rated_generator_torque()
            }
            None => value,
        })
    }

    /// Whether this estimate acts on the scene `name` (opened as `scene`).
    pub fn acts_on(&self, name: &str, scene: &Scene) -> bool {
        self.targets.iter().any(|t| match t {
            Target::Parameter { scenes, .. } => scenes.iter().any(|s| s == name),
            Target::Gearbox { gearbox, .. } => binds_gearbox(scene, gearbox),
        })
    }
}

fn binds_gearbox(scene: &Scene, gearbox: &str) -> bool {
    gearbox_component(scene, gearbox).is_some()
}

/// The component (a gearbox6dof FMU, whatever the scene calls it) that loads the shipped `gearbox`.
pub fn gearbox_component(scene: &Scene, gearbox: &str) -> Option<String> {
    scene
        .components
        .iter()
        .find(|c| {
            scene
                .string_parameter(&c.name, "gearbox")
                .is_some_and(|g| g.eq_ignore_ascii_case(gearbox))
        })
        .map(|c| c.name.clone())
}

/// Chosen values of some estimates, put into the scenes a study opens.
pub struct Setting {
    values: Vec<(Estimate, f64)>,
    /// Where edited gearbox descriptions are written (they must outlive the runs).
    folder: PathBuf,
}

impl Setting {
    /// `NAME=VALUE` pairs (values in each estimate's unit); edited descriptions go under `folder`.
    pub fn parse(pairs: &[String], folder: &Path) -> anyhow::Result<Self> {
        let known = all()?;
        let mut values = Vec::new();
        for pair in pairs {
            let (name, value) = pair
                .split_once('=')
                .ok_or_else(|| anyhow!("--set {pair:?}: write NAME=VALUE"))?;
            let estimate = known
                .iter()
                .find(|e| e.name == name.trim())
                .ok_or_else(|| {
                    anyhow!(
                        "--set {pair:?}: no estimate {name:?} (windrive reproduce --estimates lists them: {})",
                        known.iter().map(|e| e.name.as_str()).collect::<Vec<_>>().join(", ")
                    )
                })?
                .clone();
            let value: f64 = value
                .trim()
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite())
                .ok_or_else(|| anyhow!("--set {pair:?}: {value:?} is not a finite number"))?;
            values.push((estimate, value));
        }
        Ok(Self {
            values,
            folder: folder.to_path_buf(),
        })
    }

    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Whether any set estimate acts on the scene `name`.
    pub fn acts_on(&self, name: &str, scene: &Scene) -> bool {
        self.values.iter().any(|(e, _)| e.acts_on(name, scene))
    }

    /// Binds the set values in the scene `name`; gearbox keys go into an edited copy of the
    /// description, which the scene's gearbox6dof then loads by path.
    pub fn apply(&self, name: &str, scene: &mut Scene) -> anyhow::Result<()> {
        let mut edited: Option<(String, toml::Table)> = None;
        for (estimate, value) in &self.values {
            // at its nominal value an estimate leaves the scene as it is, so the nominal point of a
            // study reproduces the scene's own numbers to the bit
            if *value == estimate.nominal {
                continue;
            }
            let value = estimate.in_scene(*value)?;
            for target in &estimate.targets {
                match target {
                    Target::Parameter {
                        scenes,
                        component,
                        variable,
                    } if scenes.iter().any(|s| s == name) => {
                        bind(scene, component, variable, value, &estimate.name)?;
                    }
                    Target::Gearbox { gearbox, key } if binds_gearbox(scene, gearbox) => {
                        let (_, table) = match &mut edited {
                            Some(e) => e,
                            None => edited.insert((gearbox.clone(), preset_table(gearbox)?)),
                        };
                        let n = set_key(table, key, value)?;
                        if n == 0 {
                            bail!("{}: key {key} matches nothing in gearbox {gearbox}", estimate.name);
                        }
                    }
                    _ => {}
                }
            }
        }
        if let Some((gearbox, table)) = edited {
            let component = gearbox_component(scene, &gearbox).expect("the scene binds this gearbox");
            std::fs::create_dir_all(&self.folder).with_context(|| self.folder.display().to_string())?;
            let path = self.folder.join(format!("{gearbox}-{name}.toml"));
            let text = toml::to_string(&table).map_err(|e| anyhow!("gearbox {gearbox}: {e}"))?;
            std::fs::write(&path, text).with_context(|| path.display().to_string())?;
            let path = path.to_str().ok_or_else(|| anyhow!("{}: not UTF-8", path.display()))?;
            bind_value(
                scene,
                &component,
                "gearbox",
                Value::String(path.to_string()),
                "the set estimates",
            )?;
        }
        Ok(())
    }
}

fn bind(scene: &mut Scene, component: &str, variable: &str, value: f64, estimate: &str) -> anyhow::Result<()> {
    bind_value(
        scene,
        component,
        variable,
        Value::Real(value),
        &format!("estimate {estimate}"),
    )
}

/// A binding after the scene's own (the last binding wins).
fn bind_value(scene: &mut Scene, component: &str, variable: &str, value: Value, origin: &str) -> anyhow::Result<()> {
    let name = scene.name.clone();
    let c = scene
        .components
        .iter_mut()
        .find(|c| c.name == component)
        .ok_or_else(|| anyhow!("scene {name} has no component {component:?} for {origin}"))?;
    c.parameters.push(Parameter {
        name: variable.to_string(),
        value,
        origin: origin.to_string(),
    });
    Ok(())
}

/// A shipped gearbox description as a TOML table.
pub fn preset_table(gearbox: &str) -> anyhow::Result<toml::Table> {
    let key = gearbox.to_ascii_lowercase();
    let (_, text) = PRESETS
        .iter()
        .find(|(n, _)| *n == key)
        .ok_or_else(|| anyhow!("no shipped gearbox {gearbox:?}"))?;
    text.parse::<toml::Table>()
        .map_err(|e| anyhow!("gearbox {gearbox}: {e}"))
}

/// The values at a dotted key (`*`: every element of an array).
pub fn key_values(table: &toml::Table, key: &str) -> Vec<f64> {
    let mut found = Vec::new();
    let mut visit = |v: &mut toml::Value| {
        if let Some(x) = v.as_float().or_else(|| v.as_integer().map(|i| i as f64)) {
            found.push(x);
        }
    };
    let mut copy = toml::Value::Table(table.clone());
    walk(&mut copy, &key.split('.').collect::<Vec<_>>(), &mut visit);
    found
}

/// Sets every number at a dotted key to `value` (rounded where the description holds an integer);
/// how many it set.
fn set_key(table: &mut toml::Table, key: &str, value: f64) -> anyhow::Result<usize> {
    let mut n = 0;
    let mut set = |v: &mut toml::Value| {
        if v.is_integer() {
            *v = toml::Value::Integer(value.round() as i64);
            n += 1;
        } else if v.is_float() {
            *v = toml::Value::Float(value);
            n += 1;
        }
    };
    let mut root = toml::Value::Table(std::mem::take(table));
    walk(&mut root, &key.split('.').collect::<Vec<_>>(), &mut set);
    if let toml::Value::Table(t) = root {
        *table = t;
    }
    Ok(n)
}

fn walk(v: &mut toml::Value, path: &[&str], f: &mut dyn FnMut(&mut toml::Value)) {
    let Some((head, rest)) = path.split_first() else {
        f(v);
        return;
    };
    match v {
        toml::Value::Table(t) => {
            if let Some(child) = t.get_mut(*head) {
                walk(child, rest, f);
            }
        }
        toml::Value::Array(a) if *head == "*" => a.iter_mut().for_each(|child| walk(child, rest, f)),
        toml::Value::Array(a) => {
            if let Some(child) = head.parse::<usize>().ok().and_then(|i| a.get_mut(i)) {
                walk(child, rest, f);
            }
        }
        _ => {}
    }
}
