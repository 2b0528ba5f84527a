//! Everything a load-case campaign asks of one case's series, in one pass over the series in memory
//! (`windrive run SCENE --analyse SPEC`): per channel its mean, standard deviation, extremes,
//! damage-equivalent loads and load duration distribution, and with `gears` or `bearings` every tooth's
//! or bearing's rating. One flat table row, so the campaign driver stores it as it comes:
//!
//! - `analysed_s`: last − first time after the transient;
//! - `<channel>.mean`, `.std` (population), `.min`, `.max`;
//! - `<channel>.del_m<m>` per Wöhler slope: DEL_m = (Σ n_i S_i^m / N_eq)^(1/m), S_i the rainflow ranges
//!   (ASTM E1049-85, half cycles count ½), N_eq = f_eq × `analysed_s` — as `windrive del`;
//! - `<channel>.ldd_s` and `.ldd_rev`: seconds and revolutions n = Σ t_j·|ω_j|/2π per load bin over the
//!   spec's fixed [min, max] (fixed, so cases add up; loads outside count in the end bins), each sample
//!   holding until the next — as `windrive ldd`, whose bins span the series instead;
//! - `gear.<tooth>.{flank_day, root_day, max_contact, max_root, cycles}` as `windrive gears --json`;
//! - `bearing.<name>.{day, p_eq, p_max, revolutions, c, thesis_day, nm_day}` as `windrive bearings --json`
//!   (nm_day: the damage per day over ISO 281's modified life a_ISO·L10 with the default oil).
//!
//! A quantity that is not a number (a tooth windrive does not rate) is NaN, JSON's `null`.

use crate::analysis::fatigue::damage::DamageSums;
use crate::analysis::fatigue::ldd::sample_revolutions;
use crate::analysis::fatigue::matrix::Bins;
use crate::analysis::fatigue::rainflow::Counter;
use crate::analysis::rating::bearing_set::{BearingSetError, BearingTable};
use crate::analysis::rating::gear_set::{
    GearSetError, fmu_mesh_force, gear_table, rate_columns, with_dynamic_factor, with_model_face_load,
};
use crate::analysis::rating::life_modification::Lubrication;
use serde::Deserialize;
use serde::ser::{Serialize, SerializeMap, Serializer};

/// What to compute: read from the JSON a campaign driver (or a user) writes.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseSpec {
    /// Seconds at the start left out.
    #[serde(default)]
    pub transient: f64,
    /// Frequency of the equivalent cycles, Hz: N_eq = f_eq × analysed seconds.
    #[serde(default = "one_hertz")]
    pub feq: f64,
    #[serde(default)]
    pub channels: Vec<ChannelSpec>,
    pub gears: Option<GearsSpec>,
    pub bearings: Option<BearingsSpec>,
}

fn one_hertz() -> f64 {
    1.0
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChannelSpec {
    /// component.variable, as recorded.
    pub name: String,
    /// Wöhler slopes, one DEL each.
    #[serde(default)]
    pub m: Vec<f64>,
    pub ldd: Option<LddSpec>,
}

/// A load duration distribution over fixed bins.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LddSpec {
    /// The shaft speed channel (rad/s) whose revolutions count the load cycles.
    pub speed: String,
    pub min: f64,
    pub max: f64,
    pub bins: usize,
}

/// Every tooth of a gear table rated (`windrive gears`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GearsSpec {
    /// P (the paper's gear table) or a gearbox6dof preset or description file.
    pub table: String,
    /// Whose mesh forces the series holds: `torsional` or `gearbox6dof`.
    #[serde(default = "torsional")]
    pub fmu: String,
    /// That FMU's name in the scene [default: as the repository's scenes name it].
    pub component: Option<String>,
    /// The face load factor K_Hβ: `one` (nominal stresses) or `model` (each sample's from gearbox6dof,
    /// `windrive gears --face-load model`) [default: one].
    pub face_load: Option<String>,
    /// ISO 6336-1's dynamic factor K_v on every mesh, ≥ 1 (`windrive gears --dynamic-factor`) [default: 1].
    pub dynamic_factor: Option<f64>,
}

fn torsional() -> String {
    "torsional".into()
}

/// Every bearing with a roller set rated (`windrive bearings`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BearingsSpec {
    /// The gearbox6dof preset or description file the scene runs.
    pub gearbox: String,
    /// The gearbox6dof FMU's name in the scene.
    #[serde(default = "gearbox")]
    pub component: String,
    /// The oil a_ISO is taken with (`windrive bearings --oil-viscosity`, `--oil-temperature`,
    /// `--contamination`); each left out is [`Lubrication::default`]'s.
    #[serde(default)]
    pub oil_viscosity: Option<[f64; 2]>,
    #[serde(default)]
    pub oil_temperature: Option<f64>,
    #[serde(default)]
    pub contamination: Option<f64>,
}

impl BearingsSpec {
    /// The oil these settings give, checked.
    fn lubrication(&self) -> Result<Lubrication, CaseError> {
        Lubrication::given(self.oil_viscosity, self.oil_temperature, self.contamination)
            .map_err(|e| CaseError::Spec(format!("bearings: {e}")))
    }
}

fn gearbox() -> String {
    "gearbox".into()
}

#[derive(Debug, thiserror::Error)]
pub enum CaseError {
    #[error("{0}")]
    Spec(String),
    #[error("{0} not in the series (its columns: {1})")]
    Missing(String, String),
    #[error("fewer than two samples after the transient of {0} s")]
    TooShort(f64),
    #[error("{channel} is {value} at t = {time} s")]
    NotFinite { channel: String, value: f64, time: f64 },
    #[error(transparent)]
    Gears(#[from] GearSetError),
    #[error(transparent)]
    Bearings(#[from] BearingSetError),
}

/// One value of the row: a number, or a list (an LDD's bins).
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Number(f64),
    List(Vec<f64>),
}

/// The case's row, in a stable order: `analysed_s`, then each channel's columns, the teeth, the bearings.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Statistics(pub Vec<(String, Value)>);

/// The line `windrive run --analyse` prints: a case's statistics, and the simulation's and the
/// analysis's wall times, s. A struct, not `json!`: the row keeps its order (channels as the spec
/// lists them, then teeth, bearings).
#[derive(serde::Serialize)]
pub struct Report<'a> {
    pub statistics: &'a Statistics,
    pub simulation_s: f64,
    pub analysis_s: f64,
}

impl Statistics {
    fn number(&mut self, key: String, x: f64) {
        self.0.push((key, Value::Number(x)));
    }

    pub fn get(&self, key: &str) -> Option<&Value> {
        self.0.iter().find(|(k, _)| k == key).map(|(_, v)| v)
    }
}

impl Serialize for Statistics {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(Some(self.0.len()))?;
        for (k, v) in &self.0 {
            match v {
                Value::Number(x) => map.serialize_entry(k, x)?,
                Value::List(xs) => map.serialize_entry(k, xs)?,
            }
        }
        map.end()
    }
}

impl CaseSpec {
    /// Every channel the analysis reads, each once: the analysed ones, their LDD speeds. The teeth's
    /// and bearings' channels come from their tables ([`CaseSpec::rating_channels`]).
    pub fn channels(&self) -> Vec<&str> {
        let mut names: Vec<&str> = Vec::new();
        for c in &self.channels {
            for n in std::iter::once(c.name.as_str()).chain(c.ldd.as_ref().map(|l| l.speed.as_str())) {
                if !names.contains(&n) {
                    names.push(n);
                }
            }
        }
        names
    }

    /// Refuses what cannot be computed, naming the field.
    pub fn check(&self) -> Result<(), CaseError> {
        let bad = |what: String| Err(CaseError::Spec(what));
        if !(self.transient.is_finite() && self.transient >= 0.0) {
            return bad(format!("transient {}: must be a number ≥ 0", self.transient));
        }
        if !(self.feq.is_finite() && self.feq > 0.0) {
            return bad(format!("feq {}: must be a positive frequency", self.feq));
        }
        for c in &self.channels {
            if let Some(m) = c.m.iter().find(|m| !(m.is_finite() && **m > 0.0)) {
                return bad(format!("{}: slope m = {m} must be a positive number", c.name));
            }
            if let Some(l) = &c.ldd
                && (l.bins == 0 || !(l.min.is_finite() && l.max.is_finite() && l.min < l.max))
            {
                return bad(format!(
                    "{}: ldd needs bins ≥ 1 and finite min < max (got {} bins over [{}, {}])",
                    c.name, l.bins, l.min, l.max
                ));
            }
        }
        if let Some(g) = &self.gears {
            if fmu_mesh_force(&g.fmu).is_none() {
                return bad(format!("gears.fmu {:?}: use torsional or gearbox6dof", g.fmu));
            }
            match g.face_load.as_deref() {
                None | Some("one") => {}
                Some("model") if g.fmu == "gearbox6dof" => {}
                Some("model") => return bad("gears.face_load \"model\" needs gears.fmu \"gearbox6dof\"".into()),
                Some(other) => return bad(format!("gears.face_load {other:?}: use one or model")),
            }
            if let Some(k_v) = g.dynamic_factor
                && !(k_v.is_finite() && k_v >= 1.0)
            {
                return bad(format!("gears.dynamic_factor {k_v}: a number ≥ 1 (ISO 6336-1's K_v)"));
            }
        }
        Ok(())
    }
}

/// The row of a series held in memory: `time`, and `columns[i]` named `names[i]`, one value per time.
pub fn analyse(time: &[f64], names: &[String], columns: &[Vec<f64>], spec: &CaseSpec) -> Result<Statistics, CaseError> {
    spec.check()?;
    let gears = spec
        .gears
        .as_ref()
        .map(|g| {
            let (kind, default_component) = fmu_mesh_force(&g.fmu).expect("checked");
            let component = g.component.as_deref().unwrap_or(default_component);
            let teeth = gear_table(&g.table, component, kind)
                .map_err(|e| CaseError::Spec(format!("gears.table {:?}: {e}", g.table)))?;
            let teeth = if g.face_load.as_deref() == Some("model") {
                with_model_face_load(teeth)
                    .ok_or_else(|| CaseError::Spec(format!("gears.table {:?}: no gearbox6dof mesh forces", g.table)))?
            } else {
                teeth
            };
            Ok::<_, CaseError>(with_dynamic_factor(teeth, g.dynamic_factor.unwrap_or(1.0)).expect("checked"))
        })
        .transpose()?;
    let bearings = spec
        .bearings
        .as_ref()
        .map(|b| -> Result<BearingTable, CaseError> {
            let mut table = BearingTable::load(&b.gearbox, &b.component)?;
            table.lubrication = b.lubrication()?;
            Ok(table)
        })
        .transpose()?;

    let first = time.partition_point(|&t| t < spec.transient);
    if time.len() < first + 2 {
        return Err(CaseError::TooShort(spec.transient));
    }
    let t = &time[first..];
    let column = |name: &str| -> Result<&[f64], CaseError> {
        let i = names
            .iter()
            .position(|n| n == name)
            .ok_or_else(|| CaseError::Missing(name.to_string(), names.join(", ")))?;
        let x = &columns[i][first..];
        match x.iter().position(|v| !v.is_finite()) {
            Some(j) => Err(CaseError::NotFinite {
                channel: name.to_string(),
                value: x[j],
                time: t[j],
            }),
            None => Ok(x),
        }
    };
    // every channel the row reads, found (and checked finite) before anything is computed
    let mut wanted = spec.channels();
    let gear_channels = gears
        .as_deref()
        .map(crate::analysis::rating::gear_set::channels)
        .unwrap_or_default();
    let bearing_channels = bearings.as_ref().map(BearingTable::channels).unwrap_or_default();
    wanted.extend(gear_channels.iter().chain(&bearing_channels));
    let found: Vec<(&str, &[f64])> = wanted
        .iter()
        .map(|n| Ok((*n, column(n)?)))
        .collect::<Result<_, CaseError>>()?;
    let get = |name: &str| {
        found
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, x)| *x)
            .expect("found above")
    };

    let duration = t[t.len() - 1] - t[0];
    let mut row = Statistics::default();
    row.number("analysed_s".into(), duration);
    for c in &spec.channels {
        let x = get(&c.name);
        channel_statistics(&mut row, &c.name, x);
        if !c.m.is_empty() {
            let mut sums = DamageSums::new(&c.m);
            let mut counter = Counter::new();
            counter.extend(x, &mut |cycle| sums.add(&cycle));
            counter.finish(&mut |cycle| sums.add(&cycle));
            for (m, del) in c.m.iter().zip(sums.dels(spec.feq * duration)) {
                row.number(format!("{}.del_m{}", c.name, short(*m)), del);
            }
        }
        if let Some(l) = &c.ldd {
            let (seconds, revolutions) = load_duration(t, x, get(&l.speed), l);
            row.0.push((format!("{}.ldd_s", c.name), Value::List(seconds)));
            row.0.push((format!("{}.ldd_rev", c.name), Value::List(revolutions)));
        }
    }
    if let Some(teeth) = &gears {
        for r in rate_columns(teeth, t, get)? {
            for (column, x) in [
                ("flank_day", r.flank_damage_per_day),
                ("root_day", r.root_damage_per_day),
                ("max_contact", r.max_contact_stress),
                ("max_root", r.max_root_stress),
                ("cycles", r.load_cycles),
            ] {
                row.number(format!("gear.{}.{column}", r.name), x);
            }
        }
    }
    if let Some(table) = &bearings {
        for r in table.rate_columns("the series", t, get)? {
            for (column, x) in [
                ("day", r.damage_per_day),
                ("p_eq", r.equivalent_load),
                ("p_max", r.max_equivalent_load),
                ("revolutions", r.revolutions),
                ("c", r.dynamic_load_rating),
                ("thesis_day", r.thesis_damage_per_day),
                ("nm_day", r.modified_damage_per_day),
            ] {
                row.number(format!("bearing.{}.{column}", r.name), x);
            }
        }
    }
    Ok(row)
}

fn channel_statistics(row: &mut Statistics, name: &str, x: &[f64]) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let variance = x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n;
    row.number(format!("{name}.mean"), mean);
    row.number(format!("{name}.std"), variance.sqrt());
    row.number(format!("{name}.min"), x.iter().copied().fold(f64::INFINITY, f64::min));
    row.number(
        format!("{name}.max"),
        x.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
}

/// Seconds and revolutions per bin of [min, max]; loads outside count in the end bins.
fn load_duration(t: &[f64], load: &[f64], speed: &[f64], l: &LddSpec) -> (Vec<f64>, Vec<f64>) {
    let bins = Bins {
        lo: l.min,
        hi: l.max,
        n: l.bins,
    };
    let (mut seconds, mut revolutions) = (vec![0.0; l.bins], vec![0.0; l.bins]);
    for (j, (dt, revs)) in sample_revolutions(t, speed).enumerate() {
        let i = bins.index(load[j]);
        seconds[i] += dt;
        revolutions[i] += revs;
    }
    (seconds, revolutions)
}

/// A slope as the column names write it: 3 for 3.0, 3.5 for 3.5 (Python's `{m:g}`).
fn short(m: f64) -> String {
    if m.fract() == 0.0 && m.abs() < 1e15 {
        format!("{}", m as i64)
    } else {
        format!("{m}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::rating::gear::MeshForce;
    use crate::analysis::rating::gear_set::{RatedTooth, channels};

    fn spec(json_channels: Vec<ChannelSpec>, transient: f64, feq: f64) -> CaseSpec {
        CaseSpec {
            transient,
            feq,
            channels: json_channels,
            gears: None,
            bearings: None,
        }
    }

    fn number(row: &Statistics, key: &str) -> f64 {
        match row.get(key) {
            Some(Value::Number(x)) => *x,
            other => panic!("{key}: {other:?}"),
        }
    }

    /// A cosine of amplitude 3, 25 periods in 10 s: 50 half cycles of range 6, so
    /// DEL_m = 6·(25/N_eq)^(1/m) with N_eq = 2 Hz × 10 s; population std of a sampled cosine → 3/√2.
    #[test]
    fn del_of_a_cosine_is_its_range_scaled_by_the_cycle_ratio() {
        let t: Vec<f64> = (0..=10000).map(|i| i as f64 * 1e-3).collect();
        let x: Vec<f64> = t
            .iter()
            .map(|t| 3.0 * (std::f64::consts::TAU * 2.5 * t).cos())
            .collect();
        let ch = ChannelSpec {
            name: "a.x".into(),
            m: vec![3.0, 6.0],
            ldd: None,
        };
        let row = analyse(&t, &["a.x".into()], &[x], &spec(vec![ch], 0.0, 2.0)).unwrap();
        for m in [3.0, 6.0f64] {
            let del = number(&row, &format!("a.x.del_m{m}"));
            approx::assert_relative_eq!(del, 6.0 * (25.0f64 / 20.0).powf(1.0 / m), max_relative = 1e-12);
        }
        approx::assert_relative_eq!(number(&row, "a.x.mean"), 3.0 / 10001.0, max_relative = 1e-6);
        approx::assert_relative_eq!(number(&row, "a.x.std"), 3.0 / 2f64.sqrt(), max_relative = 1e-3);
        assert_eq!((number(&row, "a.x.min"), number(&row, "a.x.max")), (-3.0, 3.0));
        assert_eq!(number(&row, "analysed_s"), 10.0);
    }

    /// Fixed bins: a load at 1 for 1 s and at 5 for 1 s over bins of [0, 4): the 5 is clipped into the
    /// last bin; at 2π rad/s each second is one revolution; the last sample holds no time.
    #[test]
    fn ldd_bins_are_fixed_and_clip_into_the_end_bins() {
        let t = vec![0.0, 1.0, 2.0];
        let load = vec![1.0, 5.0, -3.0];
        let speed = vec![std::f64::consts::TAU; 3];
        let ch = ChannelSpec {
            name: "a.x".into(),
            m: vec![],
            ldd: Some(LddSpec {
                speed: "a.w".into(),
                min: 0.0,
                max: 4.0,
                bins: 4,
            }),
        };
        let row = analyse(
            &t,
            &["a.x".into(), "a.w".into()],
            &[load, speed],
            &spec(vec![ch], 0.0, 1.0),
        )
        .unwrap();
        assert_eq!(row.get("a.x.ldd_s"), Some(&Value::List(vec![0.0, 1.0, 0.0, 1.0])));
        assert_eq!(row.get("a.x.ldd_rev"), Some(&Value::List(vec![0.0, 1.0, 0.0, 1.0])));
    }

    #[test]
    fn the_transient_missing_channels_and_bad_values_are_named() {
        let t = vec![0.0, 1.0, 2.0];
        let ch = |name: &str| ChannelSpec {
            name: name.into(),
            m: vec![3.0],
            ldd: None,
        };
        let names = vec!["a.x".to_string()];
        let err = analyse(&t, &names, &[vec![1.0, 2.0, 3.0]], &spec(vec![ch("a.y")], 0.0, 1.0)).unwrap_err();
        assert_eq!(err.to_string(), "a.y not in the series (its columns: a.x)");
        let err = analyse(&t, &names, &[vec![1.0, 2.0, 3.0]], &spec(vec![ch("a.x")], 1.5, 1.0)).unwrap_err();
        assert_eq!(err.to_string(), "fewer than two samples after the transient of 1.5 s");
        let err = analyse(
            &t,
            &names,
            &[vec![1.0, f64::NAN, 3.0]],
            &spec(vec![ch("a.x")], 0.0, 1.0),
        )
        .unwrap_err();
        assert_eq!(err.to_string(), "a.x is NaN at t = 1 s");
        let err = analyse(&t, &names, &[vec![1.0, 2.0, 3.0]], &spec(vec![ch("a.x")], 0.0, 0.0)).unwrap_err();
        assert!(err.to_string().starts_with("feq 0"), "{err}");
        // only what follows the transient is read: a NaN before it is no error
        let row = analyse(
            &t,
            &names,
            &[vec![f64::NAN, 2.0, 3.0]],
            &spec(vec![ch("a.x")], 1.0, 1.0),
        )
        .unwrap();
        assert_eq!(number(&row, "analysed_s"), 1.0);
    }

    /// [gears]' face load: `model` rates every tooth with its mesh's face_load_factor channel, as
    /// `windrive gears --face-load model` (the same rate_columns on the same columns); `one` or unset
    /// rates the nominal stresses; `model` on the torsional FMU's forces, or another word, is named.
    #[test]
    fn the_gears_face_load_is_the_models_when_asked() {
        let parse = |json: &str| serde_json::from_str::<GearsSpec>(json).unwrap();
        let t: Vec<f64> = (0..=2000).map(|i| i as f64 * 5e-3).collect();
        let teeth = with_model_face_load(gear_table("grc750", "gearbox", MeshForce::Normal).unwrap()).unwrap();
        let names: Vec<String> = channels(&teeth).iter().map(|c| c.to_string()).collect();
        let columns: Vec<Vec<f64>> = names
            .iter()
            .map(|n| {
                t.iter()
                    .map(|&x| {
                        if n.contains("face_load_factor_") {
                            1.3 + 0.2 * (3.0 * x).sin()
                        } else if n.contains("mesh_force_") {
                            2e5 * (1.0 + 0.3 * (2.0 * x).cos())
                        } else {
                            2.3
                        }
                    })
                    .collect()
            })
            .collect();
        let run = |gears: &str| {
            let mut s = spec(vec![], 1.0, 1.0);
            s.gears = Some(parse(gears));
            analyse(&t, &names, &columns, &s)
        };
        let model = run(r#"{"table": "grc750", "fmu": "gearbox6dof", "face_load": "model"}"#).unwrap();
        let nominal = run(r#"{"table": "grc750", "fmu": "gearbox6dof"}"#).unwrap();
        assert_eq!(
            format!(
                "{:?}",
                run(r#"{"table": "grc750", "fmu": "gearbox6dof", "face_load": "one"}"#).unwrap()
            ),
            format!("{nominal:?}")
        );
        let from = t.iter().position(|&x| x >= 1.0).unwrap();
        let column = |n: &str| &columns[names.iter().position(|c| c == n).unwrap()][from..];
        // every rated flank of `row` is rate_columns' on `teeth`, and above `below`'s
        let rates_as = |row: &Statistics, teeth: &[RatedTooth], below: &Statistics| {
            for r in rate_columns(teeth, &t[from..], column).unwrap() {
                let key = format!("gear.{}.flank_day", r.name);
                if r.flank_damage_per_day.is_nan() {
                    continue;
                }
                assert_eq!(number(row, &key), r.flank_damage_per_day, "{key}");
                assert!(number(row, &key) > number(below, &key), "{key}");
            }
        };
        rates_as(&model, &teeth, &nominal);
        let torsional = run(r#"{"table": "P", "face_load": "model"}"#);
        assert!(matches!(torsional, Err(CaseError::Spec(m)) if m.contains("gearbox6dof")));
        let other = run(r#"{"table": "grc750", "fmu": "gearbox6dof", "face_load": "iso"}"#);
        assert!(matches!(other, Err(CaseError::Spec(m)) if m.contains("\"iso\"")));
        // the dynamic factor on top of the model's face load: the same rate_columns on teeth with K_v set
        let with_k_v =
            run(r#"{"table": "grc750", "fmu": "gearbox6dof", "face_load": "model", "dynamic_factor": 1.05}"#).unwrap();
        rates_as(&with_k_v, &with_dynamic_factor(teeth.clone(), 1.05).unwrap(), &model);
        for bad in ["0.9", "-1"] {
            let r = run(&format!(
                r#"{{"table": "grc750", "fmu": "gearbox6dof", "dynamic_factor": {bad}}}"#
            ));
            assert!(
                matches!(r, Err(CaseError::Spec(m)) if m.contains("gears.dynamic_factor")),
                "{bad}"
            );
        }
    }

    /// [bearings]' oil: unset keys take windrive's estimate, set ones replace it, and a value the
    /// formulas do not hold for is a spec error naming it.
    #[test]
    fn the_bearings_oil_is_the_estimate_unless_set() {
        let parse = |json: &str| serde_json::from_str::<BearingsSpec>(json).unwrap();
        let plain = parse(r#"{"gearbox": "grc750"}"#).lubrication().unwrap();
        assert_eq!(plain, Lubrication::default());
        let warm = parse(r#"{"gearbox": "grc750", "oil_temperature": 80, "oil_viscosity": [220, 19]}"#)
            .lubrication()
            .unwrap();
        assert_eq!(
            (warm.temperature_c, warm.viscosity_40, warm.viscosity_100),
            (80.0, 220.0, 19.0)
        );
        assert_eq!(warm.contamination, Lubrication::default().contamination);
        let dirty = parse(r#"{"gearbox": "grc750", "contamination": 2}"#).lubrication();
        assert!(matches!(dirty, Err(CaseError::Spec(m)) if m.contains("contamination factor e_C 2")));
    }
}
