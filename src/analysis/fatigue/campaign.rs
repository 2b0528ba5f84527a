//! A load-case campaign's lifetime from its table of finished cases (`windrive life --cases`, which
//! the campaign report calls): the same convention as a single normal-operation and shutdown pair
//! ([`super::lifetime`]), over many weighted cases.
//!
//! - Each case stands for w_i repetitions in the design life: a DLC 1.2 case w_i = hours_i · 3600 / T_i
//!   (its climate hours over its analysed seconds T_i), an event w_i = its count over the design life.
//!   Grid cases have no weight and stay out; unfinished cases stay out and are listed.
//! - A case's Σ n S^m is recovered from its DEL: DEL_i^m · f_eq · T_i.
//! - The lifetime damage sum D = Σ w_i · DEL_i^m · f_eq · T_i and the lifetime DEL = (D / (f_eq T_life))^(1/m),
//!   T_life the whole design life (years × 8760 h), not its operating hours, as `windrive life` divides.
//! - A group's share of D: each DLC 1.2 wind bin (its seeds together) and each event.
//! - The lifetime LDD: Σ w_i · (seconds, revolutions) per load bin.
//! - Miner damage of rated parts (gear teeth, bearings) from their damage per day: the window's damage
//!   D_i = day_i · T_i / 86 400, summed with the same weights, the life years / D.
//! - Intervals (95 %) over the seeds of each DLC 1.2 bin, Student's t with Welch and Satterthwaite's degrees
//!   of freedom ([`Scatter::half_width`]): of every damage sum (and so of the lifetime DEL and life it
//!   gives), and of every share, taken to first order in the bins' sums. Events and bins of one seed
//!   carry none.
//! - The thesis's DEL ratios (§3.4.3, m = 6): a shutdown's DEL over normal operation's (DLC 1.2 pooled
//!   over its hours, and the bin at the shutdown's wind speed) and over start-ups' and normal stops'.
//!
//! D is a damage sum in load^m × cycles, not a Miner damage: no S-N curve is attached to a channel here.

use super::operating_hours::HOURS_PER_YEAR;
use serde::ser::{SerializeMap, Serializer};
use serde::{Deserialize, Serialize};
use statrs::distribution::{ContinuousCDF, StudentsT};

const SECONDS_PER_DAY: f64 = 86_400.0;
/// The thesis's ratios are DELs at m = 6, the same for HSS and LSS torque (§3.4.3).
pub const THESIS_M: f64 = 6.0;
const THESIS_NORMAL_OPERATION: f64 = 3.65;
const THESIS_START_UP: f64 = 1.43;
const THESIS_NORMAL_STOP: f64 = 1.1;

/// The campaign's table as its driver stores it: column names, then one row per case.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CampaignTable {
    #[serde(default)]
    pub campaign: String,
    /// Design life, years (20 when the campaign has no climate).
    pub years: Option<f64>,
    /// Frequency of the equivalent cycles, Hz (1 when not given).
    pub feq_hz: Option<f64>,
    /// The fixed load bins of each channel's LDD, as the cases counted them.
    #[serde(default)]
    pub ldd_bins: Vec<LddBins>,
    pub columns: Vec<String>,
    pub rows: Vec<Vec<Option<Cell>>>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LddBins {
    pub channel: String,
    pub speed: String,
    pub min: f64,
    pub max: f64,
    pub bins: usize,
}

/// One value of the table; `null` is missing (NaN, a case that did not run).
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum Cell {
    Number(f64),
    Flag(bool),
    Text(String),
    List(Vec<Option<f64>>),
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CampaignLifeError {
    #[error("campaign {campaign}: no finished DLC 1.2 or event case to weigh ({left_out})")]
    NothingToWeigh { campaign: String, left_out: String },
    #[error("not a campaign table (no column {0})")]
    NoColumn(String),
    #[error("row {row} has {found} values for {columns} columns")]
    RowLength { row: usize, found: usize, columns: usize },
    #[error(
        "campaign {campaign}: column {column} is NaN in {count} finished case(s) ({names}) but rated in the \
         others: run them again"
    )]
    PartlyRated {
        campaign: String,
        column: String,
        count: usize,
        names: String,
    },
    #[error(
        "campaign {campaign}: bearing {bearing} has C_r = {values} N in different finished cases: they were \
         rated with different gearbox descriptions"
    )]
    TwoRatings {
        campaign: String,
        bearing: String,
        values: String,
    },
    #[error("campaign {campaign}: case {case}: {column} has {found} bins, the campaign's LDD {bins}")]
    LddBins {
        campaign: String,
        case: String,
        column: String,
        found: usize,
        bins: usize,
    },
}

/// A value per group (a share of a damage, or its interval), in the campaign's group order
/// (serialised as a JSON object).
#[derive(Debug, Clone, PartialEq)]
pub struct Shares<T = f64>(pub Vec<(String, T)>);

impl Shares {
    pub fn get(&self, group: &str) -> f64 {
        self.0.iter().find(|(g, _)| g == group).map_or(f64::NAN, |s| s.1)
    }
}

impl<T: Serialize> Serialize for Shares<T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(Some(self.0.len()))?;
        for (g, v) in &self.0 {
            map.serialize_entry(g, v)?;
        }
        map.end()
    }
}

/// A 95 % confidence interval over seeds (Student's t, [`Scatter::half_width`]).
pub type Interval = [f64; 2];

/// A channel's lifetime damage sum and DEL at one slope.
#[derive(Debug, Clone, Serialize)]
pub struct DelRow {
    pub channel: String,
    pub m: f64,
    pub lifetime_del: f64,
    pub damage_sum: f64,
    pub share: Shares,
    pub lifetime_del_ci: Interval,
    pub damage_sum_ci: Interval,
    pub share_ci: Shares<Interval>,
}

#[derive(Debug, Clone, Serialize)]
pub struct LifetimeLdd {
    pub channel: String,
    pub speed: String,
    pub edges: Vec<f64>,
    pub seconds: Vec<f64>,
    pub revolutions: Vec<f64>,
}

/// A part's Miner damage over the design life; `life_years` is infinite (JSON `null`) without damage.
#[derive(Debug, Clone, Serialize)]
pub struct MinerLife {
    pub damage: f64,
    pub life_years: f64,
    pub share: Shares,
    pub damage_ci: Interval,
    pub life_years_ci: Interval,
    pub share_ci: Shares<Interval>,
}

#[derive(Debug, Clone, Serialize)]
pub struct GearRow {
    pub tooth: String,
    pub kind: &'static str,
    #[serde(flatten)]
    pub life: MinerLife,
}

#[derive(Debug, Clone, Serialize)]
pub struct BearingRow {
    pub bearing: String,
    /// Basic dynamic load rating C_r, N.
    pub dynamic_load_rating: f64,
    #[serde(flatten)]
    pub life: MinerLife,
    /// The events' share of the ISO 281 damage.
    pub events_share: f64,
    /// The thesis's count (rainflow cycles of P as load cycles, its ch. 5.4), for comparison.
    pub thesis_damage: f64,
    pub thesis_events_share: f64,
    /// Miner over ISO 281's modified life a_ISO·L10 (the cases' `nm_day`, rated with the default oil;
    /// NaN for cases rated before it existed), and the events' share of it.
    pub modified_damage: f64,
    pub modified_events_share: f64,
}

/// Our DEL ratio of a shutdown to another group, beside the thesis's.
#[derive(Debug, Clone, Serialize)]
pub struct Ratio {
    pub channel: String,
    pub m: f64,
    pub shutdown: String,
    pub versus: &'static str,
    pub versus_cases: String,
    pub ours: f64,
    pub thesis: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct CampaignLife {
    pub campaign: String,
    pub years: f64,
    pub feq_hz: f64,
    /// T_life, the reference of the lifetime DELs, s.
    pub life_s: f64,
    pub groups: Vec<String>,
    pub rows: Vec<DelRow>,
    pub ldd: Vec<LifetimeLdd>,
    pub ratios: Vec<Ratio>,
    pub used: usize,
    pub operating_hours: f64,
    pub events: f64,
    /// Status → the cases not counted, statuses sorted, the grid (no weight) last.
    pub left_out: Vec<(String, Vec<String>)>,
    pub gears: Vec<GearRow>,
    pub bearings: Vec<BearingRow>,
    /// How the intervals are taken and the groups whose scatter they cannot see (one case).
    pub intervals: IntervalInfo,
}

#[derive(Debug, Clone, Serialize)]
pub struct IntervalInfo {
    pub method: &'static str,
    pub one_seed: Vec<String>,
}

/// The thesis's event kinds from an event's name: its shutdown is a stop with the mechanical brake
/// (emergency-like), its normal stop a slow-down without it.
pub fn event_kind(name: &str) -> Option<&'static str> {
    let n = name.to_lowercase();
    if n.contains("shutdown") || n.contains("emergency") {
        Some("shutdown")
    } else if n.contains("start") {
        Some("start-up")
    } else if n.contains("stop") {
        Some("normal stop")
    } else {
        None
    }
}

/// A finished, weighted case.
struct Case<'a> {
    name: &'a str,
    group: &'a str,
    /// Share group: a DLC 1.2 wind bin pools its seeds; an event is its own group.
    label: String,
    weight: f64,
    /// A DLC 1.2 case's hours in the design life.
    hours: f64,
    analysed_s: f64,
    wind_speed: f64,
    /// An event's wind speed, from its first `param.*.wind_speed`.
    event_wind_speed: Option<f64>,
    row: &'a [Option<Cell>],
}

impl Case<'_> {
    fn number(&self, column: usize) -> f64 {
        number(&self.row[column])
    }
}

fn number(c: &Option<Cell>) -> f64 {
    match c {
        Some(Cell::Number(x)) => *x,
        _ => f64::NAN,
    }
}

fn text(c: &Option<Cell>) -> &str {
    match c {
        Some(Cell::Text(s)) => s,
        _ => "",
    }
}

/// Python's `%g` for a name: 12 → "12", 11.5 → "11.5".
fn short(x: f64) -> String {
    format!("{x}")
}

/// A damage summed over the cases and by group, with its intervals over the seeds.
struct Summed {
    total: f64,
    share: Shares,
    total_ci: Interval,
    share_ci: Shares<Interval>,
}

fn sum_by_group(cases: &[Case], groups: &[String], bins: &SeedBins, per_case: impl Fn(&Case) -> f64) -> Summed {
    // a NaN (a DEL not computed) adds nothing, as pandas sums
    let values: Vec<f64> = cases
        .iter()
        .map(per_case)
        .map(|v| if v.is_nan() { 0.0 } else { v })
        .collect();
    let total: f64 = values.iter().sum();
    let scatter = bins.scatter(&values);
    // the total: every bin's sum counts once
    let total_ci = match scatter.half_width(|_| 1.0) {
        Some(half) if total.is_finite() => [(total - half).max(0.0), total + half],
        _ => [total, total],
    };
    let mut share = Vec::with_capacity(groups.len());
    let mut share_ci = Vec::with_capacity(groups.len());
    for g in groups {
        let part: f64 = cases
            .iter()
            .zip(&values)
            .filter(|(c, _)| &c.label == g)
            .map(|(_, v)| v)
            .sum();
        let s = if total > 0.0 { part / total } else { f64::NAN };
        // s = S_g / T to first order in each bin's sum: ∂s/∂S_b = (1 − s)/T for the group's own bin, −s/T
        // for every other
        let ci = match scatter.half_width(|label| (f64::from(u8::from(label == g)) - s) / total) {
            Some(half) if s.is_finite() => [(s - half).max(0.0), (s + half).min(1.0)],
            _ => [s, s],
        };
        share.push((g.clone(), s));
        share_ci.push((g.clone(), ci));
    }
    Summed {
        total,
        share: Shares(share),
        total_ci,
        share_ci: Shares(share_ci),
    }
}

/// The DLC 1.2 bins with more than one seed, whose seeds' scatter the intervals carry; the groups of one
/// case (events, bins of one seed) add none and are named.
struct SeedBins {
    /// each such bin's label and its cases
    bins: Vec<(String, Vec<usize>)>,
    one_seed: Vec<String>,
}

impl SeedBins {
    fn new(cases: &[Case], groups: &[String]) -> Self {
        let members: Vec<(String, Vec<usize>)> = groups
            .iter()
            .map(|g| (g.clone(), (0..cases.len()).filter(|&i| &cases[i].label == g).collect()))
            .collect();
        let one_seed = members
            .iter()
            .filter(|(_, m)| m.len() == 1)
            .map(|(g, _)| g.clone())
            .collect();
        let bins = members
            .into_iter()
            .filter(|(_, m)| m.len() > 1 && cases[m[0]].group == "dlc12")
            .collect();
        Self { bins, one_seed }
    }

    /// Each bin's variance of its sum of `values` over its seeds: the sum n·ȳ varies as n·s².
    fn scatter(&self, values: &[f64]) -> Scatter<'_> {
        let bins = self
            .bins
            .iter()
            .map(|(label, bin)| {
                let n = bin.len() as f64;
                let mean = bin.iter().map(|&i| values[i]).sum::<f64>() / n;
                let s2 = bin.iter().map(|&i| (values[i] - mean).powi(2)).sum::<f64>() / (n - 1.0);
                (label.as_str(), n * s2, n - 1.0)
            })
            .collect();
        Scatter { bins }
    }
}

/// The seed bins' variances of a sum: (label, variance, degrees of freedom n − 1).
struct Scatter<'a> {
    bins: Vec<(&'a str, f64, f64)>,
}

impl Scatter<'_> {
    /// The 95 % half-width of Σ_b c_b S_b, S_b the bins' independent sums: Student's t with Welch and
    /// Satterthwaite's degrees of freedom; None without scatter. Over few seeds a percentile bootstrap is
    /// far too narrow (two seeds give a bin three distinct means): tests/python/test_campaign_lifetime.py
    /// measures the coverage of both.
    fn half_width(&self, coefficient: impl Fn(&str) -> f64) -> Option<f64> {
        let (mut variance, mut dof_terms) = (0.0, 0.0);
        for &(label, v, dof) in &self.bins {
            let term = coefficient(label).powi(2) * v;
            variance += term;
            dof_terms += term * term / dof;
        }
        if !(variance > 0.0 && dof_terms > 0.0 && variance.is_finite()) {
            return None;
        }
        let dof = variance * variance / dof_terms;
        let t = StudentsT::new(0.0, 1.0, dof).ok()?.inverse_cdf(0.975);
        Some(t * variance.sqrt())
    }
}

pub fn compute(table: &CampaignTable) -> Result<CampaignLife, CampaignLifeError> {
    let campaign = table.campaign.clone();
    let years = table.years.filter(|&y| y != 0.0).unwrap_or(20.0);
    let feq = table.feq_hz.filter(|&f| f != 0.0).unwrap_or(1.0);
    let columns = &table.columns;
    let find = |name: &str| columns.iter().position(|c| c == name);
    let require = |name: &str| find(name).ok_or_else(|| CampaignLifeError::NoColumn(name.into()));
    for (i, r) in table.rows.iter().enumerate() {
        if r.len() != columns.len() {
            return Err(CampaignLifeError::RowLength {
                row: i,
                found: r.len(),
                columns: columns.len(),
            });
        }
    }
    let (name, group, status) = (require("name")?, require("group")?, require("status")?);
    let left_out = left_out(table, name, group, status);
    let finished: Vec<&Vec<Option<Cell>>> = table
        .rows
        .iter()
        .filter(|r| text(&r[status]) == "ok" && matches!(text(&r[group]), "dlc12" | "event"))
        .collect();
    if finished.is_empty() {
        let described: Vec<String> = left_out.iter().map(|(k, v)| format!("{} {k}", v.len())).collect();
        return Err(CampaignLifeError::NothingToWeigh {
            campaign,
            left_out: if described.is_empty() {
                "the table is empty".into()
            } else {
                described.join(", ")
            },
        });
    }
    let (wind_speed, hours, events, analysed) = (
        require("wind_speed")?,
        require("hours")?,
        require("events")?,
        require("analysed_s")?,
    );
    let event_speed_columns: Vec<usize> = (0..columns.len())
        .filter(|&i| columns[i].starts_with("param.") && columns[i].ends_with(".wind_speed"))
        .collect();
    let cases: Vec<Case> = finished
        .iter()
        .map(|r| {
            let (n, g) = (text(&r[name]), text(&r[group]));
            let analysed_s = number(&r[analysed]);
            let dlc = g == "dlc12";
            Case {
                name: n,
                group: g,
                label: if dlc {
                    format!("DLC 1.2 {} m/s", short(number(&r[wind_speed])))
                } else {
                    n.strip_prefix("event-").unwrap_or(n).to_string()
                },
                weight: if dlc {
                    number(&r[hours]) * 3600.0 / analysed_s
                } else {
                    number(&r[events])
                },
                hours: number(&r[hours]),
                analysed_s,
                wind_speed: number(&r[wind_speed]),
                event_wind_speed: event_speed_columns.iter().map(|&i| number(&r[i])).find(|v| !v.is_nan()),
                row: r,
            }
        })
        .collect();
    let mut groups: Vec<String> = Vec::new();
    for c in &cases {
        if !groups.contains(&c.label) {
            groups.push(c.label.clone());
        }
    }
    let life_s = years * HOURS_PER_YEAR * 3600.0;
    let bins = SeedBins::new(&cases, &groups);
    let slopes = del_columns(columns);
    let rows = slopes
        .iter()
        .map(|&(ref channel, m, column)| {
            let sum = sum_by_group(&cases, &groups, &bins, |c| {
                c.weight * c.number(column).powf(m) * feq * c.analysed_s
            });
            let del = |total: f64| (total / (feq * life_s)).powf(1.0 / m);
            DelRow {
                channel: channel.clone(),
                m,
                lifetime_del: del(sum.total),
                damage_sum: sum.total,
                share: sum.share,
                lifetime_del_ci: sum.total_ci.map(del),
                damage_sum_ci: sum.total_ci,
                share_ci: sum.share_ci,
            }
        })
        .collect();
    let mut ldd = Vec::new();
    for bins in &table.ldd_bins {
        let (Some(s), Some(n)) = (
            find(&format!("{}.ldd_s", bins.channel)),
            find(&format!("{}.ldd_rev", bins.channel)),
        ) else {
            continue;
        };
        ldd.push(lifetime_ldd(&campaign, &cases, bins, s, n)?);
    }
    let ratios = thesis_ratios(&cases, &slopes, feq);
    let weighed = Weighed {
        campaign: &campaign,
        cases: &cases,
        groups: &groups,
        years,
        bins: &bins,
    };
    let gears = gear_rows(&weighed, columns)?;
    let bearings = bearing_rows(&weighed, columns)?;
    let one_seed = bins.one_seed.clone();
    Ok(CampaignLife {
        campaign,
        years,
        feq_hz: feq,
        life_s,
        groups,
        rows,
        ldd,
        ratios,
        used: cases.len(),
        operating_hours: cases
            .iter()
            .filter(|c| c.group == "dlc12")
            .fold(0.0, |sum, c| sum + c.hours),
        events: cases
            .iter()
            .filter(|c| c.group == "event")
            .fold(0.0, |sum, c| sum + c.weight),
        left_out,
        gears,
        bearings,
        intervals: IntervalInfo {
            method: "Student's t over each DLC 1.2 bin's seeds (Welch-Satterthwaite degrees of freedom; a share to \
                     first order in the bins' sums)",
            one_seed,
        },
    })
}

/// The cases not counted, by status (sorted), and the finished grid cases (no weight) last.
fn left_out(table: &CampaignTable, name: usize, group: usize, status: usize) -> Vec<(String, Vec<String>)> {
    let mut by_status: std::collections::BTreeMap<String, Vec<String>> = Default::default();
    let mut grid = Vec::new();
    for r in &table.rows {
        let (s, n) = (text(&r[status]), text(&r[name]).to_string());
        if s != "ok" {
            by_status.entry(s.to_string()).or_default().push(n);
        } else if text(&r[group]) == "grid" {
            grid.push(n);
        }
    }
    let mut out: Vec<(String, Vec<String>)> = by_status.into_iter().collect();
    if !grid.is_empty() {
        out.push(("grid (no weight)".into(), grid));
    }
    out
}

/// Every `<channel>.del_m<m>` column: (channel, m, its index), in table order.
fn del_columns(columns: &[String]) -> Vec<(String, f64, usize)> {
    columns
        .iter()
        .enumerate()
        .filter_map(|(i, c)| {
            let (channel, m) = c.rsplit_once(".del_m")?;
            let m: f64 = m.parse().ok()?;
            (!channel.is_empty()).then(|| (channel.to_string(), m, i))
        })
        .collect()
}

fn lifetime_ldd(
    campaign: &str,
    cases: &[Case],
    bins: &LddBins,
    s: usize,
    n: usize,
) -> Result<LifetimeLdd, CampaignLifeError> {
    let mut seconds = vec![0.0; bins.bins];
    let mut revolutions = vec![0.0; bins.bins];
    for c in cases {
        for (column, sums) in [(s, &mut seconds), (n, &mut revolutions)] {
            let values = match &c.row[column] {
                Some(Cell::List(v)) => v.as_slice(),
                _ => &[],
            };
            if values.len() != bins.bins {
                return Err(CampaignLifeError::LddBins {
                    campaign: campaign.into(),
                    case: c.name.into(),
                    column: format!("{}.{}", bins.channel, if column == s { "ldd_s" } else { "ldd_rev" }),
                    found: values.len(),
                    bins: bins.bins,
                });
            }
            for (sum, v) in sums.iter_mut().zip(values) {
                *sum += c.weight * v.unwrap_or(f64::NAN);
            }
        }
    }
    // as numpy.linspace: lo + i·step, the last edge exactly hi
    let step = (bins.max - bins.min) / bins.bins as f64;
    let mut edges: Vec<f64> = (0..=bins.bins).map(|i| bins.min + i as f64 * step).collect();
    if let Some(last) = edges.last_mut() {
        *last = bins.max;
    }
    Ok(LifetimeLdd {
        channel: bins.channel.clone(),
        speed: bins.speed.clone(),
        edges,
        seconds,
        revolutions,
    })
}

/// The DEL of several cases as one series of their summed time: (Σ w Σ n S^m / (f_eq Σ w T))^(1/m).
fn pooled_del(cases: &[&Case], column: usize, m: f64, feq: f64) -> f64 {
    let time: f64 = cases.iter().map(|c| c.weight * c.analysed_s).sum();
    let sums: f64 = cases
        .iter()
        .map(|c| c.weight * c.number(column).powf(m) * feq * c.analysed_s)
        .sum();
    (sums / (feq * time)).powf(1.0 / m)
}

/// numpy.isclose's default tolerances: a wind speed written in two places is one speed.
fn same_speed(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-8 + 1e-5 * b.abs()
}

fn thesis_ratios(cases: &[Case], slopes: &[(String, f64, usize)], feq: f64) -> Vec<Ratio> {
    let events: Vec<&Case> = cases.iter().filter(|c| c.group == "event").collect();
    let dlc: Vec<&Case> = cases.iter().filter(|c| c.group == "dlc12").collect();
    let mut out = Vec::new();
    for (channel, m, column) in slopes.iter().filter(|s| s.1 == THESIS_M) {
        let shutdowns = events.iter().filter(|e| event_kind(&e.label) == Some("shutdown"));
        for s in shutdowns {
            let mut against: Vec<(&'static str, String, f64, f64)> = Vec::new();
            if !dlc.is_empty() {
                let pooled = pooled_del(&dlc, *column, *m, feq);
                let weighted = "DLC 1.2, climate-weighted".to_string();
                against.push(("normal operation", weighted, THESIS_NORMAL_OPERATION, pooled));
                if let Some(v) = s.event_wind_speed {
                    let same: Vec<&Case> = dlc.iter().copied().filter(|c| same_speed(c.wind_speed, v)).collect();
                    if !same.is_empty() {
                        let label = format!("DLC 1.2 {} m/s", short(v));
                        let pooled = pooled_del(&same, *column, *m, feq);
                        against.push(("normal operation", label, THESIS_NORMAL_OPERATION, pooled));
                    }
                }
            }
            for e in &events {
                match event_kind(&e.label) {
                    Some("start-up") => against.push(("start-up", e.label.clone(), THESIS_START_UP, e.number(*column))),
                    Some("normal stop") => {
                        against.push(("normal stop", e.label.clone(), THESIS_NORMAL_STOP, e.number(*column)))
                    }
                    _ => {}
                }
            }
            for (versus, versus_cases, thesis, other) in against {
                out.push(Ratio {
                    channel: channel.clone(),
                    m: *m,
                    shutdown: s.label.clone(),
                    versus,
                    versus_cases,
                    ours: s.number(*column) / other,
                    thesis,
                });
            }
        }
    }
    out
}

/// The finished cases weighed, their share groups and their seed bins: what every lifetime sum reads.
#[derive(Clone, Copy)]
struct Weighed<'a> {
    campaign: &'a str,
    cases: &'a [Case<'a>],
    groups: &'a [String],
    years: f64,
    bins: &'a SeedBins,
}

/// A part's Miner damage over the design life from its damage-per-day column; None when no case rates
/// it (p1's flank), an error when only some do (their sum would be silently short).
fn miner(w: &Weighed, column: usize, name: &str) -> Result<Option<MinerLife>, CampaignLifeError> {
    let Weighed {
        campaign,
        cases,
        groups,
        years,
        bins,
    } = *w;
    let missing: Vec<&Case> = cases.iter().filter(|c| c.number(column).is_nan()).collect();
    if missing.len() == cases.len() {
        return Ok(None);
    }
    if !missing.is_empty() {
        let names: Vec<&str> = missing.iter().take(5).map(|c| c.name).collect();
        return Err(CampaignLifeError::PartlyRated {
            campaign: campaign.into(),
            column: name.into(),
            count: missing.len(),
            names: names.join(", "),
        });
    }
    let sum = sum_by_group(cases, groups, bins, |c| {
        c.weight * c.number(column) * c.analysed_s / SECONDS_PER_DAY
    });
    let life = |damage: f64| if damage > 0.0 { years / damage } else { f64::INFINITY };
    Ok(Some(MinerLife {
        damage: sum.total,
        life_years: life(sum.total),
        share: sum.share,
        damage_ci: sum.total_ci,
        life_years_ci: [life(sum.total_ci[1]), life(sum.total_ci[0])],
        share_ci: sum.share_ci,
    }))
}

/// Every `gear.<tooth>.flank_day` / `.root_day`: teeth in table order, flank before root.
fn gear_rows(w: &Weighed, columns: &[String]) -> Result<Vec<GearRow>, CampaignLifeError> {
    let found: Vec<(&str, &'static str, usize)> = columns
        .iter()
        .enumerate()
        .filter_map(|(i, c)| {
            let rest = c.strip_prefix("gear.")?;
            let (tooth, kind) = rest.rsplit_once('.')?;
            let kind = match kind {
                "flank_day" => "flank",
                "root_day" => "root",
                _ => return None,
            };
            (!tooth.is_empty() && !tooth.contains('.')).then_some((tooth, kind, i))
        })
        .collect();
    let mut teeth: Vec<&str> = Vec::new();
    for (tooth, _, _) in &found {
        if !teeth.contains(tooth) {
            teeth.push(tooth);
        }
    }
    let mut rows = Vec::new();
    for tooth in teeth {
        for kind in ["flank", "root"] {
            let Some(&(_, _, column)) = found.iter().find(|f| f.0 == tooth && f.1 == kind) else {
                continue;
            };
            if let Some(life) = miner(w, column, &columns[column])? {
                rows.push(GearRow {
                    tooth: tooth.into(),
                    kind,
                    life,
                });
            }
        }
    }
    Ok(rows)
}

/// Every `bearing.<name>.day`, in table order, with its C_r and the thesis's count beside it.
fn bearing_rows(w: &Weighed, columns: &[String]) -> Result<Vec<BearingRow>, CampaignLifeError> {
    let (campaign, cases) = (w.campaign, w.cases);
    let column_of = |bearing: &str, what: &str| columns.iter().position(|c| *c == format!("bearing.{bearing}.{what}"));
    let events_share = |life: &MinerLife| -> f64 {
        let events: Vec<&str> = cases
            .iter()
            .filter(|c| c.group == "event")
            .map(|c| c.label.as_str())
            .collect();
        life.share
            .0
            .iter()
            .filter(|(g, _)| events.contains(&g.as_str()))
            .map(|s| s.1)
            .sum()
    };
    let mut rows = Vec::new();
    for (i, c) in columns.iter().enumerate() {
        let Some(bearing) = c.strip_prefix("bearing.").and_then(|r| r.strip_suffix(".day")) else {
            continue;
        };
        if bearing.is_empty() || bearing.contains('.') {
            continue;
        }
        let rating = match column_of(bearing, "c") {
            Some(k) => rating(campaign, cases, bearing, k)?,
            None => f64::NAN,
        };
        let Some(life) = miner(w, i, c)? else {
            continue;
        };
        let other_count = |what: &str| match column_of(bearing, what) {
            Some(k) => miner(w, k, &columns[k]),
            None => Ok(None),
        };
        let (thesis, modified) = (other_count("thesis_day")?, other_count("nm_day")?);
        rows.push(BearingRow {
            bearing: bearing.into(),
            dynamic_load_rating: rating,
            events_share: events_share(&life),
            thesis_damage: thesis.as_ref().map_or(f64::NAN, |t| t.damage),
            thesis_events_share: thesis.as_ref().map_or(f64::NAN, &events_share),
            modified_damage: modified.as_ref().map_or(f64::NAN, |m| m.damage),
            modified_events_share: modified.as_ref().map_or(f64::NAN, &events_share),
            life,
        });
    }
    Ok(rows)
}

/// A bearing's C_r, the same in every case of one gearbox: two values mean cases rated with different
/// descriptions (a description edited during the campaign), whose damage does not add.
fn rating(campaign: &str, cases: &[Case], bearing: &str, column: usize) -> Result<f64, CampaignLifeError> {
    let mut values: Vec<f64> = Vec::new();
    for v in cases.iter().map(|c| c.number(column)).filter(|v| !v.is_nan()) {
        if !values.contains(&v) {
            values.push(v);
        }
    }
    if values.len() > 1 {
        let shown: Vec<String> = values.iter().take(5).map(|v| format!("{v}")).collect();
        return Err(CampaignLifeError::TwoRatings {
            campaign: campaign.into(),
            bearing: bearing.into(),
            values: shown.join(", "),
        });
    }
    Ok(values.first().copied().unwrap_or(f64::NAN))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn n(x: f64) -> Option<Cell> {
        (!x.is_nan()).then_some(Cell::Number(x))
    }

    fn t(s: &str) -> Option<Cell> {
        Some(Cell::Text(s.into()))
    }

    const COLUMNS: [&str; 10] = [
        "name",
        "group",
        "status",
        "wind_speed",
        "hours",
        "events",
        "analysed_s",
        "param.rotor.wind_speed",
        "lss.del_m6",
        "bearing.x.day",
    ];

    /// Two seeds of the 10 m/s bin, a 12 m/s case, a rated shutdown, a start-up, a grid case and a
    /// failed one: small numbers added up by hand below.
    fn table() -> CampaignTable {
        let nan = f64::NAN;
        let row = |name, group, status, v, hours, events, analysed, event_v, del, day| {
            vec![
                t(name),
                t(group),
                t(status),
                n(v),
                n(hours),
                n(events),
                n(analysed),
                n(event_v),
                n(del),
                n(day),
            ]
        };
        CampaignTable {
            campaign: "hand".into(),
            years: Some(2.0),
            feq_hz: Some(0.5),
            ldd_bins: vec![],
            columns: COLUMNS.iter().map(|c| c.to_string()).collect(),
            rows: vec![
                row("dlc12-v10-s1", "dlc12", "ok", 10.0, 100.0, nan, 10.0, nan, 2.0, 1e-3),
                row("dlc12-v10-s2", "dlc12", "ok", 10.0, 100.0, nan, 10.0, nan, 1.0, 2e-3),
                row("dlc12-v12-s1", "dlc12", "ok", 12.0, 50.0, nan, 20.0, nan, 3.0, 4e-3),
                row(
                    "event-shutdown-rated",
                    "event",
                    "ok",
                    nan,
                    nan,
                    1000.0,
                    30.0,
                    12.0,
                    10.0,
                    0.5,
                ),
                row(
                    "event-startup-cut-in",
                    "event",
                    "ok",
                    nan,
                    nan,
                    100.0,
                    30.0,
                    4.0,
                    4.0,
                    0.0,
                ),
                row("grid-a", "grid", "ok", nan, nan, nan, 10.0, nan, 99.0, 9.0),
                row("dlc12-v14-s1", "dlc12", "failed", 14.0, 70.0, nan, nan, nan, nan, nan),
            ],
        }
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * b.abs()
    }

    #[test]
    fn the_damage_sum_and_lifetime_del_are_the_hand_computation() {
        let life = compute(&table()).unwrap();
        // Σ n S^m weighted: a DLC case hours·3600 · f_eq · DEL^m, an event count · f_eq · T · DEL^m
        let v10 = 100.0 * 3600.0 * 0.5 * (2f64.powi(6) + 1.0);
        let v12 = 50.0 * 3600.0 * 0.5 * 3f64.powi(6);
        let (shutdown, startup) = (1000.0 * 0.5 * 30.0 * 1e6, 100.0 * 0.5 * 30.0 * 4f64.powi(6));
        let total = v10 + v12 + shutdown + startup;
        let row = &life.rows[0];
        assert!(close(row.damage_sum, total));
        assert!(close(
            row.lifetime_del,
            (total / (0.5 * 2.0 * 8760.0 * 3600.0)).powf(1.0 / 6.0)
        ));
        assert_eq!(
            life.groups,
            ["DLC 1.2 10 m/s", "DLC 1.2 12 m/s", "shutdown-rated", "startup-cut-in"]
        );
        assert!(close(row.share.get("DLC 1.2 10 m/s"), v10 / total));
        assert!(close(row.share.get("shutdown-rated"), shutdown / total));
        assert_eq!((life.used, life.operating_hours, life.events), (5, 250.0, 1100.0));
        let left: Vec<(&str, usize)> = life.left_out.iter().map(|(k, v)| (k.as_str(), v.len())).collect();
        assert_eq!(left, [("failed", 1), ("grid (no weight)", 1)]);
    }

    #[test]
    fn a_bearings_miner_damage_adds_hours_over_a_day_and_events_windows() {
        let life = compute(&table()).unwrap();
        let b = &life.bearings[0];
        let hand = 100.0 / 24.0 * (1e-3 + 2e-3) + 50.0 / 24.0 * 4e-3 + 1000.0 * 0.5 * 30.0 / 86_400.0;
        assert!(close(b.life.damage, hand));
        assert!(close(b.life.life_years, 2.0 / hand));
        assert!(close(b.events_share, 1000.0 * 0.5 * 30.0 / 86_400.0 / hand));
        assert!(b.dynamic_load_rating.is_nan() && b.thesis_damage.is_nan());
    }

    #[test]
    fn the_thesis_ratios_set_a_shutdown_against_normal_operation_and_a_start_up() {
        let life = compute(&table()).unwrap();
        let by = |cases: &str| life.ratios.iter().find(|r| r.versus_cases == cases).unwrap();
        let pooled = ((100.0 * 64.0 + 100.0 + 50.0 * 729.0) / 250.0f64).powf(1.0 / 6.0);
        assert!(close(by("DLC 1.2, climate-weighted").ours, 10.0 / pooled));
        assert!(close(by("DLC 1.2 12 m/s").ours, 10.0 / 3.0));
        let startup = by("startup-cut-in");
        assert_eq!((startup.versus, startup.ours, startup.thesis), ("start-up", 2.5, 1.43));
        assert_eq!(life.ratios.len(), 3);
    }

    /// The 10 m/s bin's two seeds x1, x2 are the only scatter: the sum's variance n·s² = (x1 − x2)² with
    /// one degree of freedom, t(0.975, 1) = 12.7062, the lower end held at 0; the bin's share s moves as
    /// (1 − s)/T times its sum, another group's share s' as s'/T. Bins of one seed and events are fixed
    /// and named.
    #[test]
    fn the_intervals_carry_each_bins_seeds() {
        let life = compute(&table()).unwrap();
        let (x1, x2) = (100.0 * 3600.0 * 0.5 * 64.0, 100.0 * 3600.0 * 0.5);
        let t1 = 12.706_204_736_174_7;
        let row = &life.rows[0];
        let half = t1 * (x1 - x2);
        assert!(close(row.damage_sum_ci[1], row.damage_sum + half));
        assert_eq!(row.damage_sum_ci[0], (row.damage_sum - half).max(0.0));
        let del = |d: f64| (d / (0.5 * 2.0 * 8760.0 * 3600.0)).powf(1.0 / 6.0);
        assert!(close(row.lifetime_del_ci[1], del(row.damage_sum + half)));
        assert_eq!(
            life.intervals.one_seed,
            ["DLC 1.2 12 m/s", "shutdown-rated", "startup-cut-in"]
        );
        let b = &life.bearings[0].life;
        assert!(b.damage_ci[0] < b.damage && b.damage < b.damage_ci[1]);
        assert!(close(b.life_years_ci[0], 2.0 / b.damage_ci[1]));
        let share = |g: &str| (row.share.get(g), row.share_ci.0.iter().find(|x| x.0 == g).unwrap().1);
        let (s, [lo, hi]) = share("DLC 1.2 10 m/s");
        let h = t1 * (1.0 - s) * (x1 - x2) / row.damage_sum;
        assert!(close(hi, (s + h).min(1.0)) && close(lo, (s - h).max(0.0)));
        let (s, [lo, hi]) = share("shutdown-rated");
        let h = t1 * s * (x1 - x2) / row.damage_sum;
        assert!(close(hi, (s + h).min(1.0)) && close(lo, (s - h).max(0.0)));
    }

    #[test]
    fn event_kinds_follow_the_thesis_names() {
        let kinds: Vec<_> = [
            "shutdown-rated",
            "Emergency-stop",
            "startup-cut-in",
            "stop-rated",
            "gust",
        ]
        .iter()
        .map(|n| event_kind(n))
        .collect();
        assert_eq!(
            kinds,
            [
                Some("shutdown"),
                Some("shutdown"),
                Some("start-up"),
                Some("normal stop"),
                None
            ]
        );
    }

    #[test]
    fn errors_name_the_campaign_and_what_is_wrong() {
        let mut partly = table();
        partly.rows[1][9] = None;
        let e = compute(&partly).unwrap_err().to_string();
        assert!(
            e.contains("column bearing.x.day is NaN in 1 finished case(s) (dlc12-v10-s2)"),
            "{e}"
        );
        let mut empty = table();
        empty.rows.retain(|r| text(&r[1]) == "grid");
        let e = compute(&empty).unwrap_err().to_string();
        assert_eq!(
            e,
            "campaign hand: no finished DLC 1.2 or event case to weigh (1 grid (no weight))"
        );
        let mut short = table();
        short.rows[0].pop();
        assert!(matches!(
            compute(&short),
            Err(CampaignLifeError::RowLength { row: 0, .. })
        ));
    }
}
