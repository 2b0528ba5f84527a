//! The thesis's chapter-7 quantities of a 6-DOF gearbox scene (`windrive reproduce`'s chapter-7 rows):
//! one run of a shutdown scene with `gearbox6dof`, read in two windows, normal operation (the
//! [`NORMAL_S`] seconds before the trip, after the start transient) and the shutdown (from the trip), for the
//! planet and HSS bearings' Hertz pressures, loads and rollers, the meshes' contact pressures and
//! slice loads, and the depths of the largest subsurface shear (thesis §7.2, §8.1.3).

use crate::cosim::Scene;
use anyhow::{anyhow, bail};
use serde::Deserialize;

/// The normal-operation window: at most this long before the trip, s.
pub const NORMAL_S: f64 = 10.0;

/// A scene starts at rated speed in turbulent wind: its first second is a start transient in any case
/// (the pitch controller and the generator settle over several seconds more: a scene that trips early,
/// as d-shutdown-6dof at 5 s, has that settling in its normal window).
pub const SETTLE_S: f64 = 1.0;

/// When `scene`'s shutdown starts: its rotor's `shutdown_time`, s.
pub fn trip_time(scene: &Scene) -> anyhow::Result<f64> {
    scene
        .real_parameter("rotor", "shutdown_time")
        .filter(|t| t.is_finite() && *t > SETTLE_S)
        .ok_or_else(|| {
            anyhow!(
                "{}: its rotor binds no shutdown_time after the first {SETTLE_S} s (a chapter-7 scene trips its \
                 generator in the run)",
                scene.name
            )
        })
}

/// Every bearing of the 2 MW gearbox (the `c2mw` description) that the FMU reports (the sun's
/// support has no outputs); the linear ones report no pressure and are left out of the depth orderings.
const BEARINGS: [&str; 20] = [
    "carrier_a",
    "carrier_b",
    "planet_1_uw",
    "planet_1_dw",
    "planet_2_uw",
    "planet_2_dw",
    "planet_3_uw",
    "planet_3_dw",
    "lss_a",
    "lss_b",
    "ims_a",
    "ims_b",
    "ims_c",
    "hss_a",
    "hss_b",
    "hss_c",
    "main",
    "main_b",
    "generator_de",
    "generator_nde",
];

/// The meshes read, in the order of the thesis's gear-stress comparison (low to high speed).
const MESHES: [&str; 4] = ["ring_planet_1", "sun_planet_1", "gear_pinion_1", "gear_pinion_2"];

/// The part of the run a quantity is read in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Window {
    Normal,
    Shutdown,
}

/// What a chapter-7 row reads; `part` names a bearing (e.g. planet_1_uw, hss_a) or a mesh (e.g.
/// sun_planet_1, gear_pinion_2), `over` a second one.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// A bearing's largest inner-race Hertz pressure in the window, GPa.
    BearingPressure,
    /// A bearing's largest radial load in the shutdown over that in normal operation.
    BearingLoadRise,
    /// A bearing's fewest rollers in contact in the window.
    FewestRollers,
    /// A bearing's most rollers in contact in the window.
    MostRollers,
    /// Planet `part`'s (1–3) upwind over downwind bearing: largest radial load in the window.
    UpwindOverDownwindPeak,
    /// The same, mean radial loads.
    UpwindOverDownwindMean,
    /// A mesh's largest contact pressure in normal operation over mesh `over`'s.
    MeshPressureRatio,
    /// A mesh's largest contact pressure in the window, MPa.
    MeshPressure,
    /// A mesh's largest slice load in the shutdown over that in normal operation.
    SliceLoadRise,
    /// The smallest of every mesh's and planet and HSS bearing's shutdown-over-normal load rise.
    SmallestLoadRise,
    /// A mesh's deepest largest-shear depth over the whole run, mm.
    MeshShearDepth,
    /// The HSS gears' shear depth over the shallowest of the other meshes' (< 1: the HSS shallowest).
    HssGearDepthOverOthers,
    /// The planet bearings' shallowest shear depth over the other rolling bearings' shallowest.
    PlanetBearingDepthOverOthers,
}

/// Runs a scene recording the given channels: the time, then each channel, in that order (the master's
/// `run_columns`, or a cache of runs the rows share).
pub type RunColumns<'a> = dyn FnMut(&Scene, &[&str]) -> anyhow::Result<Vec<Vec<f64>>> + 'a;

/// One run of a 6-DOF shutdown scene, its channels by name, and the two windows' sample ranges.
pub struct Run {
    names: Vec<String>,
    columns: Vec<Vec<f64>>,
    normal: std::ops::Range<usize>,
    shutdown: std::ops::Range<usize>,
}

/// The gearbox outputs the quantities read.
pub fn channels() -> Vec<String> {
    let mut names = vec![];
    for b in BEARINGS {
        for n in [
            "inner_race_pressure",
            "radial_load",
            "rollers_in_contact",
            "max_shear_depth",
        ] {
            names.push(format!("gearbox.{b}_{n}"));
        }
    }
    for m in MESHES {
        for n in ["max_contact_pressure", "max_slice_load", "max_shear_depth"] {
            names.push(format!("gearbox.{n}_{m}"));
        }
    }
    names
}

impl Run {
    /// `scene`'s run through `run` (its time, then the [`channels`] asked for, in that order).
    pub fn of(scene: &Scene, run: &mut RunColumns) -> anyhow::Result<Self> {
        let names = channels();
        let requested: Vec<&str> = names.iter().map(String::as_str).collect();
        let mut columns = run(scene, &requested)?;
        let time = columns.remove(0);
        let trip = trip_time(scene)?;
        let at = |t: f64| time.partition_point(|&x| x < t);
        let (normal, shutdown) = (at((trip - NORMAL_S).max(SETTLE_S))..at(trip), at(trip)..time.len());
        if normal.is_empty() || shutdown.is_empty() {
            bail!("{}: the run ends before its shutdown at {trip} s", scene.name);
        }
        Ok(Self {
            names,
            columns,
            normal,
            shutdown,
        })
    }

    fn channel(&self, name: &str) -> anyhow::Result<&[f64]> {
        let key = format!("gearbox.{name}");
        let k = self.names.iter().position(|n| *n == key);
        Ok(&self.columns[k.ok_or_else(|| anyhow!("no gearbox output {name}"))?])
    }

    fn window(&self, w: Window) -> std::ops::Range<usize> {
        match w {
            Window::Normal => self.normal.clone(),
            Window::Shutdown => self.shutdown.clone(),
        }
    }

    fn most(&self, name: &str, w: Window) -> anyhow::Result<f64> {
        Ok(self.channel(name)?[self.window(w)]
            .iter()
            .fold(f64::MIN, |m, &v| m.max(v)))
    }

    fn fewest(&self, name: &str, w: Window) -> anyhow::Result<f64> {
        Ok(self.channel(name)?[self.window(w)]
            .iter()
            .fold(f64::MAX, |m, &v| m.min(v)))
    }

    fn mean(&self, name: &str, w: Window) -> anyhow::Result<f64> {
        let x = &self.channel(name)?[self.window(w)];
        Ok(x.iter().sum::<f64>() / x.len() as f64)
    }

    fn rise(&self, name: &str) -> anyhow::Result<f64> {
        Ok(self.most(name, Window::Shutdown)? / self.most(name, Window::Normal)?)
    }

    /// The largest value over both windows.
    fn peak(&self, name: &str) -> anyhow::Result<f64> {
        Ok(self.most(name, Window::Normal)?.max(self.most(name, Window::Shutdown)?))
    }

    /// The bearings with roller sets (the linear ones report no pressure).
    fn rolling(&self) -> anyhow::Result<Vec<&'static str>> {
        let mut rolling = vec![];
        for b in BEARINGS {
            if self.peak(&format!("{b}_inner_race_pressure"))? > 0.0 {
                rolling.push(b);
            }
        }
        Ok(rolling)
    }

    /// One quantity; `part` and `over` as [`Quantity`] says, `window` where it asks for one.
    pub fn quantity(
        &self,
        q: Quantity,
        part: Option<&str>,
        over: Option<&str>,
        window: Option<Window>,
    ) -> anyhow::Result<f64> {
        let part = || part.ok_or_else(|| anyhow!("{q:?} needs a part"));
        let window = || window.ok_or_else(|| anyhow!("{q:?} needs a window"));
        let planet = |side: &str| Ok::<_, anyhow::Error>(format!("planet_{}_{side}_radial_load", part()?));
        Ok(match q {
            Quantity::BearingPressure => self.most(&format!("{}_inner_race_pressure", part()?), window()?)? / 1e9,
            Quantity::BearingLoadRise => self.rise(&format!("{}_radial_load", part()?))?,
            Quantity::FewestRollers => self.fewest(&format!("{}_rollers_in_contact", part()?), window()?)?,
            Quantity::MostRollers => self.most(&format!("{}_rollers_in_contact", part()?), window()?)?,
            Quantity::UpwindOverDownwindPeak => {
                self.most(&planet("uw")?, window()?)? / self.most(&planet("dw")?, window()?)?
            }
            Quantity::UpwindOverDownwindMean => {
                self.mean(&planet("uw")?, window()?)? / self.mean(&planet("dw")?, window()?)?
            }
            Quantity::MeshPressureRatio => {
                let over = over.ok_or_else(|| anyhow!("{q:?} needs `over`"))?;
                let pressure = |m: &str| self.most(&format!("max_contact_pressure_{m}"), Window::Normal);
                pressure(part()?)? / pressure(over)?
            }
            Quantity::MeshPressure => self.most(&format!("max_contact_pressure_{}", part()?), window()?)? / 1e6,
            Quantity::SliceLoadRise => self.rise(&format!("max_slice_load_{}", part()?))?,
            Quantity::SmallestLoadRise => {
                let mut rises = vec![];
                for m in MESHES {
                    rises.push(self.rise(&format!("max_slice_load_{m}"))?);
                }
                for b in ["planet_1_uw", "planet_2_uw", "planet_3_uw", "hss_a", "hss_b", "hss_c"] {
                    rises.push(self.rise(&format!("{b}_radial_load"))?);
                }
                rises.into_iter().fold(f64::MAX, f64::min)
            }
            Quantity::MeshShearDepth => self.peak(&format!("max_shear_depth_{}", part()?))? * 1e3,
            Quantity::HssGearDepthOverOthers => {
                let depth = |m: &str| self.peak(&format!("max_shear_depth_{m}"));
                let mut others = f64::MAX;
                for m in &MESHES[..3] {
                    others = others.min(depth(m)?);
                }
                depth(MESHES[3])? / others
            }
            Quantity::PlanetBearingDepthOverOthers => {
                let (mut planets, mut others) = (f64::MAX, f64::MAX);
                for b in self.rolling()? {
                    let d = self.peak(&format!("{b}_max_shear_depth"))?;
                    if b.starts_with("planet_") {
                        planets = planets.min(d);
                    } else {
                        others = others.min(d);
                    }
                }
                planets / others
            }
        })
    }
}
