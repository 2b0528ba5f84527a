//! Every number of the thesis this project computes, beside ours (`windrive reproduce` prints it as
//! docs/REPRODUCTION.md's table). The thesis's values are data, not code: data/thesis.toml lists each
//! with where it stands in the thesis, the tolerance within which we claim to reproduce it, the reason
//! where they differ, and which of our computations it is set beside ([`Ours`]). This file computes
//! ours: modes, gear ratios, mesh orders, operating hours and rated speeds directly; braking
//! frequencies, peaks, ratios and speeds from the scenes run through the master.

use crate::analysis::fatigue::operating_hours::WindDistribution;
use crate::analysis::fatigue::rainflow::cycles;
use crate::analysis::shutdown::F_MIN_HZ;
use crate::analysis::signal::metrics::peak;
use crate::analysis::signal::spectrum::dominant_in_window;
use crate::cosim::Scene;
use crate::cosim::master::run_columns;
use crate::physics::drivetrain::{Drivetrain, Stage};
use crate::studies::calibration::{self, fit::Scenes};
use crate::studies::chapter7;
use crate::studies::preset_modes::preset_modes;
use crate::studies::shutdown::{Reading, read_runs, run_scene};
use crate::studies::thesis_life;
use anyhow::{Context, anyhow, bail};
use serde::Deserialize;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The thesis's numbers, in the order of the table.
const THESIS: &str = include_str!("data/thesis.toml");

/// What the thesis states: a number, or a bound its text claims ("exceeds 1.35", "5 to 6.5 times").
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(untagged, deny_unknown_fields)]
pub enum Thesis {
    Value(f64),
    Bound(Bound),
}

#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Bound {
    Above(f64),
    Below(f64),
    Between([f64; 2]),
}

impl Thesis {
    /// The number, for a thesis value; None for a bound.
    pub fn value(&self) -> Option<f64> {
        match self {
            Thesis::Value(v) => Some(*v),
            Thesis::Bound(_) => None,
        }
    }

    /// Whether `ours` meets a bound (None for a value, which is judged by its tolerance).
    fn holds(&self, ours: f64) -> Option<bool> {
        match self {
            Thesis::Value(_) => None,
            Thesis::Bound(Bound::Above(x)) => Some(ours > *x),
            Thesis::Bound(Bound::Below(x)) => Some(ours < *x),
            Thesis::Bound(Bound::Between([lo, hi])) => Some((*lo..=*hi).contains(&ours)),
        }
    }
}

impl std::fmt::Display for Thesis {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match self {
            Thesis::Value(v) => write!(f, "{v}"),
            Thesis::Bound(Bound::Above(x)) => write!(f, "> {x}"),
            Thesis::Bound(Bound::Below(x)) => write!(f, "< {x}"),
            Thesis::Bound(Bound::Between([lo, hi])) => write!(f, "{lo}–{hi}"),
        }
    }
}

/// How ours stands against the thesis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Verdict {
    /// Within the claimed relative tolerance of the thesis's number.
    Reproduced(f64),
    /// Claimed, and outside the tolerance: a test fails on it.
    NotReproduced(f64),
    /// The thesis's bound holds for ours.
    Holds,
    /// The thesis's bound does not hold for ours: our models contradict the statement.
    Contradicts,
    /// A number not claimed: shown with the reason it differs.
    Differs,
}

impl Verdict {
    /// The verdict as one plain word or two (for JSON and the sensitivity campaign).
    pub fn label(&self) -> &'static str {
        match self {
            Verdict::Reproduced(_) => "reproduced",
            Verdict::NotReproduced(_) => "not reproduced",
            Verdict::Holds => "holds",
            Verdict::Contradicts => "contradicts",
            Verdict::Differs => "differs",
        }
    }
}

impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match self {
            Verdict::Reproduced(t) => write!(f, "reproduced (±{:.1} %)", t * 100.0),
            Verdict::NotReproduced(t) => write!(f, "**not reproduced** (±{:.1} %)", t * 100.0),
            Verdict::Holds => write!(f, "holds"),
            Verdict::Contradicts => write!(f, "**contradicts**"),
            Verdict::Differs => write!(f, "differs"),
        }
    }
}

/// One number of the thesis beside ours.
#[derive(Debug, Clone)]
pub struct Row {
    pub quantity: String,
    /// Where it stands in the thesis: a table, figure or chapter.
    pub source: String,
    pub thesis: Thesis,
    pub ours: f64,
    /// Relative tolerance within which we claim to reproduce a thesis value; None: shown, not claimed.
    pub claimed: Option<f64>,
    pub reason: String,
    /// Ours comes from a scene run (estimates may move it).
    pub ours_runs_a_scene: bool,
}

impl Row {
    /// Ours against the thesis's value, relative; against a bound, how far outside it (0 inside; NaN
    /// outside a bound of 0, which has no relative distance).
    pub fn difference(&self) -> f64 {
        let outside = |x: f64| if x == 0.0 { f64::NAN } else { self.ours / x - 1.0 };
        match self.thesis {
            Thesis::Value(v) => self.ours / v - 1.0,
            _ if self.thesis.holds(self.ours) == Some(true) => 0.0,
            Thesis::Bound(Bound::Above(x) | Bound::Below(x)) => outside(x),
            Thesis::Bound(Bound::Between([lo, hi])) => outside(if self.ours < lo { lo } else { hi }),
        }
    }

    pub fn verdict(&self) -> Verdict {
        match (self.thesis.holds(self.ours), self.claimed) {
            (Some(true), _) => Verdict::Holds,
            (Some(false), _) => Verdict::Contradicts,
            (None, Some(t)) if self.difference().abs() <= t => Verdict::Reproduced(t),
            (None, Some(t)) => Verdict::NotReproduced(t),
            (None, None) => Verdict::Differs,
        }
    }

    pub fn reproduced(&self) -> bool {
        matches!(self.verdict(), Verdict::Reproduced(_))
    }

    /// Whether the verdict is the same for every value between `low` and `high`: no edge of the
    /// thesis's bound or of the claimed tolerance lies inside. A value moving continuously with the
    /// estimates takes every value of its band, so a sample that never lands past such an edge does not
    /// make the verdict hold.
    pub fn verdict_constant_over(&self, low: f64, high: f64) -> bool {
        let edges: Vec<f64> = match (self.thesis, self.claimed) {
            (Thesis::Bound(Bound::Above(x) | Bound::Below(x)), _) => vec![x],
            (Thesis::Bound(Bound::Between([lo, hi])), _) => vec![lo, hi],
            (Thesis::Value(v), Some(t)) => vec![v * (1.0 - t), v * (1.0 + t)],
            (Thesis::Value(_), None) => vec![],
        };
        !edges.iter().any(|&e| low < e && e < high)
    }
}

/// A row of data/thesis.toml.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Entry {
    quantity: String,
    source: String,
    thesis: Thesis,
    claimed: Option<f64>,
    #[serde(default)]
    reason: String,
    ours: Ours,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Entries {
    row: Vec<Entry>,
}

/// Which of our numbers a thesis value is set beside.
#[derive(Debug, Clone, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Ours {
    /// The preset's overall ratio from its tooth counts.
    GearRatio { preset: String },
    /// Stage `stage` (from 1)'s mesh order in the thesis's convention (its Table 4.8).
    MeshOrder { preset: String, stage: usize },
    /// Natural frequency number `number` (1: the lowest, the rigid mode counted) of the preset's
    /// model at `fidelity` with the generator `generator` (as `windrive modes` names them), Hz.
    Mode {
        preset: String,
        fidelity: String,
        generator: String,
        number: usize,
    },
    /// Hours out of `hours` in the wind bin (bin − width, bin] of a Rayleigh climate.
    OperatingHours {
        rayleigh_mean_m_s: f64,
        bin_m_s: f64,
        bin_width_m_s: f64,
        hours: f64,
    },
    /// The generator's rated speed over the tooth-count ratio, rpm.
    RatedRotorSpeedRpm { preset: String },
    /// The dominant HSS-torque frequency of a shutdown scene while the brake slips, Hz.
    BrakingFrequency { scene: String },
    /// A shutdown scene's peak LSS torque over the preset's rated rotor torque.
    PeakLssTorqueRatio { scene: String, preset: String },
    /// A statistic of drivetrain C's scenes (the names of [`calibration::statistics`]).
    Calibration { statistic: String },
    /// One statistic of C's scenes over another.
    CalibrationRatio { statistic: String, over: String },
    /// A scene's mean generator speed, rpm.
    MeanGeneratorSpeedRpm { scene: String },
    /// A quantity of a drivetrain's normal operation and shutdown, run and summarised as
    /// `windrive shutdown --preset` does; `shaft` (lss, is1, is2, hss) where the quantity is a shaft's.
    Shutdown {
        preset: String,
        quantity: ShutdownQuantity,
        #[serde(default)]
        shaft: Option<String>,
    },
    /// A chapter-7 quantity of a 6-DOF gearbox shutdown scene ([`chapter7::Quantity`]).
    Gearbox {
        scene: String,
        quantity: chapter7::Quantity,
        #[serde(default)]
        part: Option<String>,
        #[serde(default)]
        over: Option<String>,
        #[serde(default)]
        window: Option<chapter7::Window>,
    },
    /// A 20-year conclusion of the thesis, from a 6-DOF normal-operation and shutdown scene the thesis's
    /// way ([`thesis_life`]); `count` is how bearings' damage is counted (not for the flanks).
    Life {
        normal: String,
        shutdown: String,
        quantity: thesis_life::Quantity,
        #[serde(default)]
        count: Option<thesis_life::Count>,
    },
}

/// What a [`Ours::Shutdown`] row reads from [`crate::analysis::shutdown::Summary`].
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShutdownQuantity {
    /// A shaft's largest |torque| in the shutdown over its rated torque.
    PeakRatio,
    /// The same in normal operation.
    NormalPeakRatio,
    /// A shaft's largest |torque| in the shutdown over that in normal operation.
    PeakRise,
    /// A shaft's torque range in the shutdown over that in normal operation.
    RangeRatio,
    /// The sun–planet mesh force's range in the shutdown over that in normal operation.
    SunPlanetRangeRatio,
    /// The smallest sun–planet mesh force in normal operation, N (negative: a reversal).
    NormalSunPlanetMinimum,
    /// The lowest mean of the sun–planet force's rainflow cycles in the shutdown, N.
    SunPlanetLowestCycleMean,
    /// The lowest mean of the HSS torque's rainflow cycles in the shutdown, N·m.
    HssLowestCycleMean,
    /// The dominant HSS-torque frequency while the brake slips over the lowest free–free mode.
    BrakingOverFreeMode,
    /// The dominant HSS-torque frequency in normal operation, Hz.
    NormalDominantFrequency,
}

impl Ours {
    /// Whether this number needs a scene run through the master.
    pub fn runs_a_scene(&self) -> bool {
        !self.scenes().is_empty()
    }

    /// The scenes (folder names under scenes/) this number runs.
    pub fn scenes(&self) -> Vec<String> {
        match self {
            Ours::BrakingFrequency { scene }
            | Ours::PeakLssTorqueRatio { scene, .. }
            | Ours::MeanGeneratorSpeedRpm { scene }
            | Ours::Gearbox { scene, .. } => vec![scene.clone()],
            Ours::Life { normal, shutdown, .. } => vec![normal.clone(), shutdown.clone()],
            Ours::Calibration { .. } | Ours::CalibrationRatio { .. } => {
                vec!["c-normal".to_string(), "c-shutdown".to_string()]
            }
            Ours::Shutdown { preset, .. } => {
                let lower = preset.to_ascii_lowercase();
                vec![format!("{lower}-normal"), format!("{lower}-shutdown")]
            }
            Ours::GearRatio { .. }
            | Ours::MeshOrder { .. }
            | Ours::Mode { .. }
            | Ours::OperatingHours { .. }
            | Ours::RatedRotorSpeedRpm { .. } => vec![],
        }
    }
}

fn entries() -> anyhow::Result<Vec<Entry>> {
    let e: Entries = toml::from_str(THESIS).map_err(|e| anyhow!("src/studies/data/thesis.toml: {e}"))?;
    Ok(e.row)
}

/// Opens a repository scene by name (e.g. "c-shutdown"), its FMUs in place.
pub type OpenScene<'a> = &'a dyn Fn(&str) -> anyhow::Result<Scene>;

/// Every row: the thesis's value beside ours, in the table's order. `open` opens the scenes the
/// rows run; each runs once.
pub fn rows(open: OpenScene) -> anyhow::Result<Vec<Row>> {
    rows_where(open, &|_| true)
}

/// The rows whose computation `keep` accepts (e.g. those running the scenes a sensitivity sample
/// changes), in the table's order.
pub fn rows_where(open: OpenScene, keep: &dyn Fn(&Ours) -> bool) -> anyhow::Result<Vec<Row>> {
    Ok(report_where(open, keep)?.rows)
}

/// Every row, and the 20-year damage per bearing and flank behind the conclusion rows.
pub struct Report {
    pub rows: Vec<Row>,
    /// Per pair of scenes (normal operation, shutdown), in the order the rows first use them.
    pub lives: Vec<((String, String), thesis_life::Life)>,
    /// The bands of the rows counted with ISO 281's modified life over the oil's estimated range
    /// ([`thesis_life::oils`]), computed here: the oil is a rating input, not a scene's, so the
    /// sensitivity campaign does not vary it.
    pub oil_bands: HashMap<String, Band>,
}

impl Report {
    /// docs/REPRODUCTION.md: the table ([`markdown`]), then the damage behind the 20-year rows. A row
    /// with an oil band takes the union of it and the sensitivity campaign's band (its verdict rests on
    /// both the scenes' estimates and the oil), or the oil band alone before the campaign has varied it.
    pub fn markdown(&self, bands: &HashMap<String, Band>) -> anyhow::Result<String> {
        let mut all = bands.clone();
        for (quantity, oil) in &self.oil_bands {
            let band = match all.remove(quantity) {
                Some(campaign) => campaign.union(oil.clone())?,
                None => oil.clone(),
            };
            all.insert(quantity.clone(), band);
        }
        let mut s = markdown(&self.rows, &all);
        for ((normal, shutdown), life) in &self.lives {
            s.push('\n');
            s.push_str(&life.markdown(normal, shutdown));
        }
        Ok(s)
    }
}

/// Every row and what stands behind them (the page `windrive reproduce` writes).
pub fn report(open: OpenScene) -> anyhow::Result<Report> {
    report_where(open, &|_| true)
}

fn report_where(open: OpenScene, keep: &dyn Fn(&Ours) -> bool) -> anyhow::Result<Report> {
    let mut ours = Computed::new(open);
    let kept: Vec<Entry> = entries()?.into_iter().filter(|e| keep(&e.ours)).collect();
    ours.plan(&kept.iter().map(|e| &e.ours).collect::<Vec<_>>())?;
    let modified: Vec<(String, (String, String), thesis_life::Quantity)> = kept
        .iter()
        .filter_map(|e| match &e.ours {
            Ours::Life {
                normal,
                shutdown,
                quantity,
                count: Some(thesis_life::Count::Iso281Modified),
            } => Some((e.quantity.clone(), (normal.clone(), shutdown.clone()), *quantity)),
            _ => None,
        })
        .collect();
    let rows = kept
        .into_iter()
        .map(|e| {
            Ok(Row {
                ours: ours.of(&e.ours)?,
                ours_runs_a_scene: e.ours.runs_a_scene(),
                quantity: e.quantity,
                source: e.source,
                thesis: e.thesis,
                claimed: e.claimed,
                reason: e.reason,
            })
        })
        .collect::<anyhow::Result<Vec<Row>>>()?;
    let mut oil_bands = HashMap::new();
    for (name, scenes, quantity) in modified {
        let row = rows.iter().find(|r| r.quantity == name).expect("a row per kept entry");
        let life = &ours
            .lives
            .iter()
            .find(|(k, _)| *k == scenes)
            .expect("computed with the row")
            .1;
        oil_bands.insert(name, oil_band(row, &life.over_oils(quantity)?));
    }
    Ok(Report {
        rows,
        lives: ours.lives,
        oil_bands,
    })
}

/// A row's band over the oils of [`thesis_life::oils`] (`values`, the estimate's first), as the
/// sensitivity campaign writes a band: the verdict at each oil counted.
fn oil_band(row: &Row, values: &[f64]) -> Band {
    let verdict = |ours: f64| {
        Row {
            ours,
            quantity: String::new(),
            source: String::new(),
            reason: String::new(),
            ..*row
        }
        .verdict()
        .label()
    };
    let mut counts: Vec<(&str, usize)> = Vec::new();
    for v in values {
        let label = verdict(*v);
        match counts.iter_mut().find(|(l, _)| *l == label) {
            Some((_, n)) => *n += 1,
            None => counts.push((label, 1)),
        }
    }
    Band {
        quantity: row.quantity.clone(),
        group: "oil".into(),
        evaluations: values.len(),
        nominal: values[0],
        low: values.iter().copied().fold(f64::INFINITY, f64::min),
        high: values.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        nominal_verdict: verdict(values[0]).into(),
        verdicts: counts
            .iter()
            .map(|(l, n)| format!("{l} {n}"))
            .collect::<Vec<_>>()
            .join("; "),
        holds: counts.len() == 1,
        drivers: "the bearings' temperature (50–80 °C) and the oil's cleanliness (e_C 0.2–0.8)".into(),
    }
}

/// Every scene some row runs (folder names under scenes/), each once.
pub fn scenes_run() -> anyhow::Result<Vec<String>> {
    let mut all: Vec<String> = entries()?.iter().flat_map(|e| e.ours.scenes()).collect();
    all.sort();
    all.dedup();
    Ok(all)
}

/// The thesis's values of the rows whose quantity starts with `prefix`, in the table's order (for
/// the commands that quote them).
pub fn thesis_values(prefix: &str) -> anyhow::Result<Vec<f64>> {
    Ok(entries()?
        .into_iter()
        .filter(|e| e.quantity.starts_with(prefix))
        .filter_map(|e| e.thesis.value())
        .collect())
}

fn preset(name: &str) -> anyhow::Result<Drivetrain> {
    Drivetrain::preset(name).ok_or_else(|| anyhow!("unknown preset {name:?}"))
}

/// Our numbers, with each scene's runs kept for the rows that share them.
struct Computed<'a> {
    open: OpenScene<'a>,
    /// Per shutdown scene: the braking frequency, Hz, and the peak |LSS torque|, N·m.
    shutdowns: HashMap<String, (f64, f64)>,
    /// C's statistics (achieved, misfit), in the order of [`calibration::statistics`].
    calibration: Option<Vec<(f64, f64)>>,
    /// Per preset: its normal operation and shutdown, summarised.
    readings: HashMap<String, Reading>,
    /// Per 6-DOF scene: its run.
    gearbox_runs: HashMap<String, chapter7::Run>,
    /// The 6-DOF scenes' series, each scene run once for every row that reads it.
    series: SharedRuns,
    /// Per pair of 6-DOF scenes (normal operation, shutdown): their 20-year damage, in the order computed.
    lives: Vec<((String, String), thesis_life::Life)>,
}

impl<'a> Computed<'a> {
    fn new(open: OpenScene<'a>) -> Self {
        Self {
            open,
            shutdowns: HashMap::new(),
            calibration: None,
            readings: HashMap::new(),
            gearbox_runs: HashMap::new(),
            series: SharedRuns::default(),
            lives: Vec::new(),
        }
    }

    /// Registers what the rows will read of each 6-DOF scene, so that each runs once: c-shutdown-6dof
    /// serves both chapter 7's rows and the 20-year conclusions (a run of 6-DOF seconds each).
    fn plan(&mut self, rows: &[&Ours]) -> anyhow::Result<()> {
        // each scene or pair once: many rows read the same run, and opening a scene provides its FMUs
        let mut planned = std::collections::HashSet::new();
        for ours in rows {
            match ours {
                Ours::Gearbox { scene, .. } if planned.insert((scene, scene)) => {
                    self.series.want(scene, chapter7::channels())
                }
                Ours::Life { normal, shutdown, .. } if planned.insert((normal, shutdown)) => {
                    let channels = thesis_life::Life::channels(&(self.open)(normal)?, &(self.open)(shutdown)?)?;
                    self.series.want(normal, channels.clone());
                    self.series.want(shutdown, channels);
                }
                _ => {}
            }
        }
        Ok(())
    }

    fn of(&mut self, ours: &Ours) -> anyhow::Result<f64> {
        Ok(match ours {
            Ours::GearRatio { preset: p } => preset(p)?.gear_ratio(),
            Ours::MeshOrder { preset: p, stage } => *thesis_mesh_orders(&preset(p)?)
                .get(stage.wrapping_sub(1))
                .ok_or_else(|| anyhow!("preset {p} has no stage {stage}"))?,
            Ours::Mode {
                preset,
                fidelity,
                generator,
                number,
            } => {
                let (_, m) = preset_modes(preset, fidelity, generator, "physical")?;
                *m.frequencies_hz
                    .get(number.wrapping_sub(1))
                    .ok_or_else(|| anyhow!("drivetrain {preset} has no mode {number}"))?
            }
            Ours::OperatingHours {
                rayleigh_mean_m_s,
                bin_m_s,
                bin_width_m_s,
                hours,
            } => WindDistribution::Rayleigh {
                mean: *rayleigh_mean_m_s,
            }
            .hours_per_bin(&[*bin_m_s], *bin_width_m_s, *hours)[0],
            Ours::RatedRotorSpeedRpm { preset: p } => preset(p)?.rated_rotor_speed * 30.0 / std::f64::consts::PI,
            Ours::BrakingFrequency { scene } => self.shutdown(scene)?.0,
            Ours::PeakLssTorqueRatio { scene, preset: p } => {
                let rated = preset(p)?.rated_rotor_torque();
                self.shutdown(scene)?.1 / rated
            }
            Ours::Calibration { statistic } => self.statistic(statistic)?,
            Ours::CalibrationRatio { statistic, over } => self.statistic(statistic)? / self.statistic(over)?,
            Ours::MeanGeneratorSpeedRpm { scene } => {
                let scene = (self.open)(scene)?;
                let speed = run_columns(&scene, &[], &["torsional.generator_speed"], None).map_err(|e| anyhow!(e))?;
                speed[1].iter().sum::<f64>() / speed[1].len() as f64 * 30.0 / std::f64::consts::PI
            }
            Ours::Shutdown {
                preset,
                quantity,
                shaft,
            } => {
                let reading = self.reading(preset)?;
                let summary = &reading.summary;
                let shaft = || {
                    let name = shaft.as_deref().ok_or_else(|| anyhow!("{quantity:?} needs a shaft"))?;
                    summary
                        .shafts
                        .iter()
                        .find(|s| s.name == name)
                        .ok_or_else(|| anyhow!("drivetrain {preset} has no shaft {name:?}"))
                };
                let lowest_mean = |x: &[f64]| cycles(x).iter().map(|c| c.mean).fold(f64::MAX, f64::min);
                match quantity {
                    ShutdownQuantity::PeakRatio => shaft()?.peak_ratio,
                    ShutdownQuantity::NormalPeakRatio => shaft()?.normal_peak_ratio,
                    ShutdownQuantity::PeakRise => shaft()?.peak_ratio / shaft()?.normal_peak_ratio,
                    ShutdownQuantity::RangeRatio => shaft()?.range_ratio,
                    ShutdownQuantity::SunPlanetRangeRatio => summary.mesh_range_ratio.0,
                    ShutdownQuantity::NormalSunPlanetMinimum => summary.normal_min_mesh.0,
                    ShutdownQuantity::SunPlanetLowestCycleMean => lowest_mean(&summary.series.sun_planet),
                    ShutdownQuantity::HssLowestCycleMean => lowest_mean(&summary.series.hss_torque),
                    // NaN where the brake locks before it slips (as in `shutdown` below)
                    ShutdownQuantity::BrakingOverFreeMode => summary
                        .slipping
                        .as_ref()
                        .map_or(f64::NAN, |s| s.frequency_hz / reading.free_hz),
                    ShutdownQuantity::NormalDominantFrequency => summary
                        .normal_dominant_hz
                        .ok_or_else(|| anyhow!("drivetrain {preset}: normal operation too short for a spectrum"))?,
                }
            }
            Ours::Gearbox {
                scene,
                quantity,
                part,
                over,
                window,
            } => self
                .gearbox_run(scene)?
                .quantity(*quantity, part.as_deref(), over.as_deref(), *window)
                .with_context(|| format!("scene {scene}"))?,
            Ours::Life {
                normal,
                shutdown,
                quantity,
                count,
            } => {
                let key = (normal.clone(), shutdown.clone());
                let index = match self.lives.iter().position(|(k, _)| *k == key) {
                    Some(i) => i,
                    None => {
                        let (n, s) = ((self.open)(normal)?, (self.open)(shutdown)?);
                        let series = &mut self.series;
                        let life =
                            thesis_life::Life::of(&n, &s, &mut |scene, channels| series.columns(scene, channels))?;
                        self.lives.push((key, life));
                        self.lives.len() - 1
                    }
                };
                let bearings = !matches!(
                    quantity,
                    thesis_life::Quantity::FlankShutdownShare | thesis_life::Quantity::HssFlankShutdownDamageOverOthers
                );
                let count = match count {
                    Some(c) => *c,
                    None if !bearings => thesis_life::Count::Iso281,
                    None => {
                        return Err(anyhow!(
                            "{quantity:?} needs a count (iso281, iso281_modified or thesis)"
                        ));
                    }
                };
                self.lives[index].1.quantity(*quantity, count)?
            }
        })
    }

    /// A 6-DOF gearbox scene's run, once per scene.
    fn gearbox_run(&mut self, scene: &str) -> anyhow::Result<&chapter7::Run> {
        if !self.gearbox_runs.contains_key(scene) {
            let opened = (self.open)(scene)?;
            let series = &mut self.series;
            let run = chapter7::Run::of(&opened, &mut |scene, channels| series.columns(scene, channels))?;
            self.gearbox_runs.insert(scene.to_string(), run);
        }
        Ok(&self.gearbox_runs[scene])
    }

    /// A preset's normal operation and shutdown (scenes `<preset>-normal` and `<preset>-shutdown`), run
    /// at their own steps as `windrive shutdown` runs them and summarised; each preset runs once.
    fn reading(&mut self, preset: &str) -> anyhow::Result<&Reading> {
        if !self.readings.contains_key(preset) {
            // a folder of this call's own: tests run rows() on several threads at once
            static CALLS: AtomicUsize = AtomicUsize::new(0);
            let call = CALLS.fetch_add(1, Ordering::Relaxed);
            let dir = std::env::temp_dir().join(format!("windrive-reproduce-{}-{call}", std::process::id()));
            std::fs::create_dir_all(&dir).with_context(|| dir.display().to_string())?;
            let lower = preset.to_ascii_lowercase();
            let (normal, shutdown) = (dir.join("normal.csv"), dir.join("shutdown.csv"));
            for (scene, csv) in [("normal", &normal), ("shutdown", &shutdown)] {
                run_scene(&(self.open)(&format!("{lower}-{scene}"))?, csv, &[])?;
            }
            let reading = read_runs(preset, &self::preset(preset)?, &normal, &shutdown);
            let _ = std::fs::remove_dir_all(&dir);
            self.readings.insert(preset.to_string(), reading?);
        }
        Ok(&self.readings[preset])
    }

    /// Dominant HSS-torque frequency while the brake slips, Hz, and the peak |LSS torque|, N·m, of a
    /// shutdown scene. A brake that locks before it is fully applied (a strong brake on a long ramp, as
    /// the sensitivity study's corners set it) leaves no slipping phase: the frequency is NaN, its rows
    /// then "not reproduced" and left out of the study's bands, and the rest of the scene's rows stand.
    fn shutdown(&mut self, name: &str) -> anyhow::Result<(f64, f64)> {
        if let Some(known) = self.shutdowns.get(name) {
            return Ok(*known);
        }
        let scene = (self.open)(name)?;
        let channels = ["torsional.hss_torque", "torsional.brake_locked", "torsional.lss_torque"];
        let c = run_columns(&scene, &[], &channels, None).map_err(|e| anyhow!(e))?;
        let (t, hss, locked, lss) = (&c[0], &c[1], &c[2], &c[3]);
        // the FMUs' defaults where the scene sets nothing
        let param = |n: &str, d: f64| scene.real_parameter("rotor", n).unwrap_or(d);
        let applied = param("shutdown_time", 5.0) + param("brake_delay", 0.5) + param("brake_ramp_time", 0.6);
        let end = t.last().copied().unwrap_or(0.0);
        let lock = locked.iter().position(|&l| l > 0.5).map_or(end, |i| t[i]);
        let f = dominant_in_window(t, hss, applied + 0.1, lock - 0.1, F_MIN_HZ).map_or(f64::NAN, |(f, _, _)| f);
        let peak = peak(lss);
        self.shutdowns.insert(name.to_string(), (f, peak));
        Ok((f, peak))
    }

    /// The achieved value of one of C's statistics, its scenes as they are.
    fn statistic(&mut self, name: &str) -> anyhow::Result<f64> {
        let index = calibration::statistics()
            .iter()
            .position(|s| s.name == name)
            .ok_or_else(|| anyhow!("no statistic {name:?} in studies::calibration"))?;
        if self.calibration.is_none() {
            let scenes = Scenes::new((self.open)("c-normal")?, (self.open)("c-shutdown")?);
            self.calibration = Some(scenes.evaluate(&scenes.current_values())?.statistics);
        }
        Ok(self.calibration.as_ref().expect("just evaluated")[index].0)
    }
}

/// What the sensitivity campaign found for one row (`scripts/campaign sensitivity GROUP` writes
/// docs/sensitivity/bands.json): its value at the nominal estimates, the band over the group's Morris
/// sample, the verdicts counted there, and the inputs that move it most.
#[derive(Debug, Clone, Deserialize)]
pub struct Band {
    pub quantity: String,
    pub group: String,
    pub evaluations: usize,
    pub nominal: f64,
    pub low: f64,
    pub high: f64,
    pub nominal_verdict: String,
    /// e.g. "contradicts 20; holds 9"
    pub verdicts: String,
    /// The verdict is the same in every evaluation.
    pub holds: bool,
    /// The inputs by Morris μ* (relative to |nominal|), largest first.
    pub drivers: String,
}

/// The bands by quantity, from bands.json's text; a row two groups vary (C's stop sequence and the 2 MW
/// gearbox's estimates both act on c-shutdown-6dof) gets the union of their bands.
pub fn read_bands(json: &str) -> anyhow::Result<HashMap<String, Band>> {
    let bands: Vec<Band> = serde_json::from_str(json).map_err(|e| anyhow!("bands.json: {e}"))?;
    let mut by_quantity: HashMap<String, Band> = HashMap::new();
    for b in bands {
        match by_quantity.remove(&b.quantity) {
            Some(a) => {
                let merged = a.union(b)?;
                by_quantity.insert(merged.quantity.clone(), merged)
            }
            None => by_quantity.insert(b.quantity.clone(), b),
        };
    }
    Ok(by_quantity)
}

/// Two verdict counts ("contradicts 20; holds 9") added, in the order the verdicts first appear.
fn add_counts(a: &str, b: &str) -> String {
    let mut counts: Vec<(String, usize)> = Vec::new();
    for part in a.split("; ").chain(b.split("; ")).filter(|p| !p.is_empty()) {
        let (verdict, n) = match part.rsplit_once(' ') {
            Some((v, n)) => (v, n.parse().unwrap_or(0)),
            None => (part, 0),
        };
        match counts.iter_mut().find(|(v, _)| v == verdict) {
            Some((_, total)) => *total += n,
            None => counts.push((verdict.to_string(), n)),
        }
    }
    counts
        .iter()
        .map(|(v, n)| format!("{v} {n}"))
        .collect::<Vec<_>>()
        .join("; ")
}

impl Band {
    /// The row's verdict is the same over the whole band: in every evaluation, and with no edge of the
    /// thesis's bound or tolerance inside it.
    pub fn verdict_holds(&self, row: &Row) -> bool {
        self.holds && row.verdict_constant_over(self.low, self.high)
    }

    /// One row's bands from two groups, varied one group at a time: the union of their ranges (a lower
    /// bound on the band of varying both together), the verdicts counted over both samples.
    fn union(self, other: Band) -> anyhow::Result<Band> {
        if (self.nominal - other.nominal).abs() > 1e-9 * self.nominal.abs() {
            bail!(
                "bands.json: {:?} has nominal {} in group {} but {} in group {}: rerun the older group's campaign",
                self.quantity,
                self.nominal,
                self.group,
                other.nominal,
                other.group
            );
        }
        Ok(Band {
            group: format!("{} + {}", self.group, other.group),
            evaluations: self.evaluations + other.evaluations,
            low: self.low.min(other.low),
            high: self.high.max(other.high),
            verdicts: add_counts(&self.verdicts, &other.verdicts),
            holds: self.holds && other.holds && self.nominal_verdict == other.nominal_verdict,
            drivers: format!("{}: {}; {}: {}", self.group, self.drivers, other.group, other.drivers),
            ..self
        })
    }
}

/// A row against the estimates' band: how the verdict fares across it.
fn across(row: &Row, bands: &HashMap<String, Band>) -> String {
    let band = |b: &Band| format!("{}–{}", format_ours(b.low), format_ours(b.high));
    match bands.get(&row.quantity) {
        Some(b) if b.verdict_holds(row) => format!("same in all {} ({})", b.evaluations, band(b)),
        Some(b) if b.holds => format!("**flips**: the band ({}) crosses the thesis's edge", band(b)),
        Some(b) => format!("**flips**: {} ({})", b.verdicts, band(b)),
        None if row.ours_runs_a_scene => "not yet varied".to_string(),
        None => "—".to_string(),
    }
}

/// The rows as docs/REPRODUCTION.md's Markdown table, with its heading and the verdicts' count; each
/// row's verdict across the estimates' band where the sensitivity campaign has varied them.
pub fn markdown(rows: &[Row], bands: &HashMap<String, Band>) -> String {
    let count = |f: fn(&Verdict) -> bool| rows.iter().filter(|r| f(&r.verdict())).count();
    let studied: Vec<(&Row, &Band)> = rows
        .iter()
        .filter_map(|r| bands.get(&r.quantity).map(|b| (r, b)))
        .collect();
    let flips = studied.iter().filter(|(r, b)| !b.verdict_holds(r)).count();
    let mut s = format!(
        "# The thesis's numbers beside ours\n\n\
         Written by `windrive reproduce`; tests/it/reproduction.rs fails when this page differs from what the \
         code gives. A verdict is computed, not typed: **reproduced** where ours lies within the tolerance we \
         claim for a thesis number; **holds** or **contradicts** where the thesis states a bound (\"exceeds \
         1.35\", \"5 to 6.5 times\") and ours meets it or not; **differs** where a number is shown, not \
         claimed, with the reason. The difference column is ours against the thesis's number, or how far \
         outside its bound.\n\n\
         {} rows: {} reproduced, {} hold, {} contradict the thesis, {} differ.\n\n\
         Across the estimates: the inputs no source gives (brakes, trip and pitch sequence, damping, bearing \
         clearances and roller sets, carrier stiffness, backlash, face widths; each with its range and reason in \
         src/studies/data/estimates.toml, `windrive reproduce --estimates`) were varied over their ranges by \
         `scripts/campaign sensitivity` (docs/SENSITIVITY.md). Of the {} rows varied so far, {} keep their \
         verdict across the whole band and {} flip: a verdict that flips rests on an estimate, not on the \
         model.\n\n\
         | quantity | thesis | where | ours | difference | verdict | across the estimates | reason |\n\
         |---|---|---|---|---|---|---|---|\n",
        rows.len(),
        count(|v| matches!(v, Verdict::Reproduced(_))),
        count(|v| *v == Verdict::Holds),
        count(|v| *v == Verdict::Contradicts),
        count(|v| *v == Verdict::Differs),
        studied.len(),
        studied.len() - flips,
        flips,
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} |",
            r.quantity,
            r.thesis,
            r.source,
            format_ours(r.ours),
            match r.difference() {
                _ if r.verdict() == Verdict::Holds => "inside".to_string(),
                d if d.is_nan() => "—".to_string(),
                d => format!("{:+.2} %", d * 100.0),
            },
            r.verdict(),
            across(r, bands),
            r.reason
        );
    }
    s
}

fn format_ours(x: f64) -> String {
    if x.abs() >= 100.0 {
        format!("{x:.1}")
    } else {
        format!("{x:.4}")
    }
}

/// Mesh orders in the thesis's convention (Table 4.8): teeth of the sun or pinion times its speed
/// over the rotor's.
fn thesis_mesh_orders(dt: &Drivetrain) -> Vec<f64> {
    let mut speed = 1.0;
    dt.stages
        .iter()
        .map(|s| {
            speed *= s.ratio();
            speed
                * match s {
                    Stage::Planetary(p) => p.z_sun as f64,
                    Stage::Parallel(p) => p.z_pinion as f64,
                }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A band that straddles an edge of the thesis's bound or of the claimed tolerance flips the
    /// verdict, whatever the sampled points' verdicts were.
    #[test]
    fn a_band_across_an_edge_flips_the_verdict() {
        let row = |thesis, claimed| Row {
            quantity: String::new(),
            source: String::new(),
            thesis,
            ours: 1.0,
            claimed,
            reason: String::new(),
            ours_runs_a_scene: true,
        };
        let between = row(Thesis::Bound(Bound::Between([1.32, 1.38])), None);
        assert!(!between.verdict_constant_over(1.21, 2.45));
        assert!(between.verdict_constant_over(1.4, 2.45));
        assert!(!row(Thesis::Bound(Bound::Above(1.35)), None).verdict_constant_over(1.2, 1.5));
        assert!(row(Thesis::Bound(Bound::Below(0.0)), None).verdict_constant_over(0.1, 0.5));
        let claimed = row(Thesis::Value(10.0), Some(0.05));
        assert!(claimed.verdict_constant_over(9.6, 10.4));
        assert!(!claimed.verdict_constant_over(9.6, 10.6));
        assert!(row(Thesis::Value(10.0), None).verdict_constant_over(1.0, 100.0));
    }

    /// Two groups' bands of one row: their union, the verdicts added, and a verdict that holds in each
    /// group but differs between them does not hold; bands of different nominal values are refused.
    #[test]
    fn two_groups_bands_of_a_row_unite() {
        let band = |group: &str, low: f64, high: f64, verdicts: &str, holds: bool| {
            format!(
                r#"{{"quantity": "q", "group": "{group}", "evaluations": 29, "nominal": 1.5, "low": {low},
                "high": {high}, "nominal_verdict": "holds", "verdicts": "{verdicts}", "holds": {holds},
                "drivers": "x"}}"#
            )
        };
        let json = format!(
            "[{}, {}]",
            band("2MW", 1.4, 1.6, "holds 20; contradicts 9", false),
            band("C", 1.3, 1.55, "contradicts 1; holds 28", false)
        );
        let b = &read_bands(&json).unwrap()["q"];
        assert_eq!((b.low, b.high, b.evaluations), (1.3, 1.6, 58));
        assert_eq!(b.verdicts, "holds 48; contradicts 10");
        assert_eq!(b.group, "2MW + C");
        assert!(!b.holds);
        let json = format!(
            "[{}, {}]",
            band("2MW", 1.4, 1.6, "holds 29", true),
            band("C", 1.45, 1.5, "holds 29", true)
        );
        assert!(read_bands(&json).unwrap()["q"].holds);
        let stale = json.replacen("\"nominal\": 1.5", "\"nominal\": 1.7", 1);
        let err = read_bands(&stale).unwrap_err().to_string();
        assert!(err.contains("rerun the older group's campaign"), "{err}");
    }

    /// The data file parses, and every row that runs no scene computes.
    #[test]
    fn the_thesis_values_parse_and_the_static_rows_compute() {
        let entries = entries().unwrap();
        assert_eq!(entries.len(), 141);
        let no_scene: OpenScene = &|name| Err(anyhow!("{name}: no scene in this test"));
        let mut ours = Computed::new(no_scene);
        for e in entries.iter().filter(|e| !e.ours.runs_a_scene()) {
            let x = ours.of(&e.ours).unwrap();
            assert!(x.is_finite() && x > 0.0, "{}: {x}", e.quantity);
        }
        let names: Vec<&str> = calibration::statistics().iter().map(|s| s.name).collect();
        for e in &entries {
            if let Ours::Calibration { statistic } | Ours::CalibrationRatio { statistic, .. } = &e.ours {
                assert!(names.contains(&statistic.as_str()), "{statistic}");
            }
        }
    }
}

/// Scene runs shared by the rows: each scene runs once, recording every channel any row registered for
/// it, and hands each row its own channels (a row asking for one not registered runs the scene again).
#[derive(Default)]
struct SharedRuns {
    wanted: HashMap<String, Vec<String>>,
    /// Per scene: the channels recorded, and the run's time then those channels.
    done: HashMap<String, (Vec<String>, Vec<Vec<f64>>)>,
}

impl SharedRuns {
    fn want(&mut self, scene: &str, channels: Vec<String>) {
        let list = self.wanted.entry(scene.to_string()).or_default();
        for c in channels {
            if !list.contains(&c) {
                list.push(c);
            }
        }
    }

    /// The run's time, then `channels` in that order.
    fn columns(&mut self, scene: &Scene, channels: &[&str]) -> anyhow::Result<Vec<Vec<f64>>> {
        let held = self
            .done
            .get(&scene.name)
            .is_some_and(|(names, _)| channels.iter().all(|c| names.iter().any(|n| n == c)));
        if !held {
            self.want(&scene.name, channels.iter().map(|c| c.to_string()).collect());
            let names = self.wanted[&scene.name].clone();
            let requested: Vec<&str> = names.iter().map(String::as_str).collect();
            let columns = run_columns(scene, &[], &requested, None).map_err(|e| anyhow!("{}: {e}", scene.name))?;
            self.done.insert(scene.name.clone(), (names, columns));
        }
        let (names, columns) = &self.done[&scene.name];
        let mut out = vec![columns[0].clone()];
        for c in channels {
            let k = names.iter().position(|n| n == c).expect("recorded above");
            out.push(columns[k + 1].clone());
        }
        Ok(out)
    }
}
