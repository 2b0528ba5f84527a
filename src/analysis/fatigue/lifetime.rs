//! A component's lifetime fatigue from one normal-operation and one shutdown series, as the thesis
//! does it (Ch. 7.2.4): normal operation scaled to the operating hours of a wind climate, the shutdown
//! repeated once per shutdown (Germanischer Lloyd: 1000 at cut-in, 50 at cut-out, 50 at rated = 1100 a
//! year). From it: lifetime DELs with the shutdowns' share, ISO 6336 flank and root damage of a gear
//! tooth (stress bins with their load cycles from the speed, ISO 6336-6 style), and the ISO 281 Miner
//! damage of a bearing over its load spectrum.

use crate::analysis::fatigue::damage;
use crate::analysis::fatigue::ldd;
use crate::analysis::fatigue::operating_hours::{HOURS_PER_YEAR, WindDistribution, time_factor};
use crate::analysis::fatigue::rainflow;
use crate::analysis::fatigue::sn_curve;
use crate::analysis::rating::gear::{self, Factors, GearPair, MeshForce, Tooth, ToothStress};
use crate::analysis::rating::limits::{BENDING_LIMIT_EH_MQ, CONTACT_LIMIT_EH_MQ};
use crate::analysis::rating::tooth_root::{BasicRack, LoadPoint, root_form};
use crate::analysis::signal::series::{self, SeriesError};
use serde::Serialize;
use std::path::Path;

#[derive(Debug, thiserror::Error)]
pub enum LifeError {
    #[error(transparent)]
    Series(#[from] SeriesError),
    #[error("{path}: the series lasts {seconds} s")]
    NoDuration { path: String, seconds: f64 },
    #[error("{quantity} = {value}: {requirement}")]
    Invalid {
        quantity: &'static str,
        value: f64,
        requirement: &'static str,
    },
    #[error("the {what} needs a speed channel: its life is counted in its revolutions")]
    NeedsSpeed { what: &'static str },
    #[error("gear {z1}/{z2}, member {member}: {message}")]
    RootForm {
        z1: u32,
        z2: u32,
        member: u8,
        message: String,
    },
}

fn require(ok: bool, quantity: &'static str, value: f64, requirement: &'static str) -> Result<(), LifeError> {
    if ok {
        Ok(())
    } else {
        Err(LifeError::Invalid {
            quantity,
            value,
            requirement,
        })
    }
}

/// Where the operating hours come from: a wind distribution, cut-in and cut-out, and the width of the
/// wind-speed bins a load case stands for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Climate {
    pub wind: WindDistribution,
    pub cut_in: f64,
    pub cut_out: f64,
    /// Bins are named by their upper edge, (v − width, v], as thesis Table 7.1 tabulates them, so the
    /// cut-in bin holds the winds just below cut-in: 20 years at a Rayleigh mean of 10 m/s then give
    /// the thesis's 161 950 h. 0 counts exactly cut-in..cut-out (153 218 h there).
    pub bin_width: f64,
}

impl Climate {
    pub fn validate(&self) -> Result<(), LifeError> {
        require(self.cut_in >= 0.0, "cut-in", self.cut_in, "must be ≥ 0")?;
        require(
            self.cut_in < self.cut_out,
            "cut-in",
            self.cut_in,
            "must be below cut-out",
        )?;
        require(self.bin_width >= 0.0, "bin width", self.bin_width, "must be ≥ 0")
    }

    /// Hours in operation out of `total_hours`: the probability of a wind in the bins cut-in to
    /// cut-out, (cut_in − bin_width, cut_out].
    pub fn operating_hours(&self, total_hours: f64) -> f64 {
        total_hours * (self.wind.cdf(self.cut_out) - self.wind.cdf(self.cut_in - self.bin_width))
    }
}

/// One recorded load case: time, the load channel and, when a speed is named, the speed of the
/// component whose revolutions count the load cycles.
#[derive(Debug, Clone)]
pub struct Case {
    pub t: Vec<f64>,
    pub load: Vec<f64>,
    pub speed: Option<Vec<f64>>,
    pub seconds: f64,
}

impl Case {
    /// Reads the load channel and, when given, the speed channel less `relative_to` (sun and planet
    /// speeds relative to the carrier) from one CSV file, in one pass.
    pub fn read(path: &Path, load: &str, speed: Option<&str>, relative_to: Option<&str>) -> Result<Case, LifeError> {
        let mut names = vec![load];
        if let Some(speed) = speed {
            names.push(speed);
            names.extend(relative_to);
        }
        let (t, columns) = series::read_channels(path, &names)?;
        let mut columns = columns.into_iter();
        let load = columns.next().unwrap_or_default();
        let speed = columns.next().map(|w| match columns.next() {
            Some(carrier) => w.iter().zip(&carrier).map(|(a, b)| a - b).collect(),
            None => w,
        });
        Case::new(path, t, load, speed)
    }

    /// A case from series already read from `path` (named in errors): time, load and speed (rad/s).
    pub fn new(path: &Path, t: Vec<f64>, load: Vec<f64>, speed: Option<Vec<f64>>) -> Result<Case, LifeError> {
        let seconds = t[t.len() - 1] - t[0];
        if seconds <= 0.0 {
            return Err(LifeError::NoDuration {
                path: path.display().to_string(),
                seconds,
            });
        }
        Ok(Case {
            t,
            load,
            speed,
            seconds,
        })
    }

    fn speed(&self, what: &'static str) -> Result<&[f64], LifeError> {
        self.speed.as_deref().ok_or(LifeError::NeedsSpeed { what })
    }
}

/// What every component's life is made of: normal operation scaled to the operating hours, and the
/// shutdown repeated once per shutdown.
#[derive(Debug, Clone)]
pub struct Lifetime {
    pub normal: Case,
    pub shutdown: Option<Case>,
    pub years: f64,
    pub operating_hours: f64,
    pub shutdowns: f64,
}

/// The lifetime DEL of one Wöhler slope and the share of Σ n S^m that the shutdowns bring.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LifetimeDel {
    pub m: f64,
    pub del: f64,
    pub shutdown_share: f64,
}

impl Lifetime {
    pub fn new(
        normal: Case,
        shutdown: Option<Case>,
        climate: &Climate,
        years: f64,
        shutdowns_per_year: f64,
    ) -> Result<Self, LifeError> {
        climate.validate()?;
        require(years > 0.0, "years", years, "must be positive")?;
        require(
            shutdowns_per_year >= 0.0,
            "shutdowns per year",
            shutdowns_per_year,
            "must be ≥ 0",
        )?;
        Ok(Self {
            normal,
            shutdown,
            years,
            operating_hours: climate.operating_hours(years * HOURS_PER_YEAR),
            shutdowns: shutdowns_per_year * years,
        })
    }

    pub fn life_hours(&self) -> f64 {
        self.years * HOURS_PER_YEAR
    }

    /// How often the normal-operation series repeats in the operating hours.
    pub fn normal_factor(&self) -> f64 {
        time_factor(self.operating_hours, self.normal.seconds)
    }

    /// Each case with its name and how often it repeats in the lifetime.
    pub fn cases(&self) -> Vec<(&'static str, &Case, f64)> {
        let mut cases = vec![("normal", &self.normal, self.normal_factor())];
        if let Some(s) = &self.shutdown {
            cases.push(("shutdown", s, self.shutdowns));
        }
        cases
    }

    /// Lifetime DELs at the equivalent frequency `feq` [Hz] over the whole life: Σ n S^m of each case
    /// times its repetitions.
    pub fn dels(&self, slopes: &[f64], feq: f64) -> Result<Vec<LifetimeDel>, LifeError> {
        require(feq > 0.0, "equivalent frequency", feq, "must be positive")?;
        if let Some(m) = slopes.iter().find(|m| m.is_nan() || **m <= 0.0) {
            require(false, "Wöhler slope m", *m, "must be positive")?;
        }
        let sums = |x: &[f64]| {
            let mut s = damage::DamageSums::new(slopes);
            let mut counter = rainflow::Counter::new();
            counter.extend(x, &mut |c| s.add(&c));
            counter.finish(&mut |c| s.add(&c));
            s.sums()
        };
        let n_sums = sums(&self.normal.load);
        let s_sums = self
            .shutdown
            .as_ref()
            .map_or(vec![0.0; slopes.len()], |s| sums(&s.load));
        let life_seconds = self.life_hours() * 3600.0;
        Ok(slopes
            .iter()
            .enumerate()
            .map(|(i, m)| {
                let (a, b) = (n_sums[i] * self.normal_factor(), s_sums[i] * self.shutdowns);
                LifetimeDel {
                    m: *m,
                    del: ((a + b) / (feq * life_seconds)).powf(1.0 / m),
                    shutdown_share: b / (a + b),
                }
            })
            .collect())
    }

    /// ISO 281 basic rating life of a bearing loaded by the channel (its equivalent dynamic load P):
    /// each case's load spectrum (every sample's |P| with the revolutions until the next sample, no
    /// binning error) summed by Miner's rule against L10(P) = (C/P)^p 10⁶ revolutions.
    pub fn bearing(&self, capacity: f64, roller: bool) -> Result<BearingLife, LifeError> {
        require(
            capacity.is_finite() && capacity > 0.0,
            "dynamic load rating C",
            capacity,
            "must be a positive number of newtons",
        )?;
        let p = if roller { 10.0 / 3.0 } else { 3.0 };
        let mut cases = Vec::new();
        let (mut damage, mut revolutions, mut weighted, mut shutdown_damage) = (0.0, 0.0, 0.0, 0.0);
        for (name, case, repeat) in self.cases() {
            let w = case.speed("bearing")?;
            let spectrum: Vec<(f64, f64)> = ldd::sample_revolutions(&case.t, w)
                .zip(&case.load)
                .map(|((_, revolutions), load)| (load.abs(), revolutions))
                .collect();
            let d = sn_curve::bearing_damage(capacity, &spectrum, roller) * repeat;
            let n: f64 = spectrum.iter().map(|(_, n)| n).sum::<f64>() * repeat;
            weighted += spectrum.iter().map(|(load, n)| n * load.powf(p)).sum::<f64>() * repeat;
            let max_load = case.load.iter().map(|v| v.abs()).fold(0.0, f64::max);
            cases.push(BearingCase {
                case: name,
                max_load,
                revolutions: n,
                damage: d,
            });
            (damage, revolutions) = (damage + d, revolutions + n);
            if name == "shutdown" {
                shutdown_damage = d;
            }
        }
        let equivalent_load = (weighted / revolutions.max(1e-300)).powf(1.0 / p);
        Ok(BearingLife {
            roller,
            capacity,
            cases,
            revolutions,
            equivalent_load,
            l10_revolutions: sn_curve::bearing_l10(capacity, equivalent_load, roller) * 1e6,
            damage,
            shutdown_share: shutdown_damage / damage.max(1e-300),
            l10_years: self.years / damage.max(1e-300),
        })
    }

    /// ISO 6336 flank and root stresses of a gear tooth from the mesh force (the channel, along the
    /// line of action), the allowable stresses at the lifetime's load cycles, and the Miner damage of
    /// flank and root: stress bins (LDD) with their load cycles from the speed, N_i from the S-N curve
    /// at σ_i/limit.
    pub fn gear(&self, spec: &GearSpec) -> Result<GearLife, LifeError> {
        let pair = spec.pair;
        let (y_f, y_s, root) = match spec.y_fs {
            Some((y_f, y_s)) => (y_f, y_s, None),
            None => {
                require(
                    spec.rack.dedendum > 0.0,
                    "basic rack dedendum h_fP",
                    spec.rack.dedendum,
                    "must be positive",
                )?;
                require(
                    spec.rack.root_radius >= 0.0 && spec.rack.root_radius < spec.rack.dedendum,
                    "basic rack root radius ρ_fP",
                    spec.rack.root_radius,
                    "must be ≥ 0 and below the dedendum h_fP",
                )?;
                let r = root_form(&pair, spec.member, &spec.rack, LoadPoint::SinglePairContact).map_err(|message| {
                    LifeError::RootForm {
                        z1: pair.z1,
                        z2: pair.z2,
                        member: spec.member,
                        message,
                    }
                })?;
                (r.form_factor, r.stress_correction, Some(r))
            }
        };
        let factors = Factors {
            k_a: spec.k_a,
            k_gamma: spec.k_gamma,
            y_f,
            y_s,
            ..Factors::default()
        };
        let st = ToothStress::steel(pair, factors);
        let per_rev = spec.tooth.load_cycles(1.0, spec.planets);
        let sigma_hlim = CONTACT_LIMIT_EH_MQ;
        let sigma_fe = 2.0 * BENDING_LIMIT_EH_MQ * spec.tooth.mean_stress_factor();
        let mut cases = Vec::new();
        let (mut total_h, mut total_f, mut total_cycles, mut shut_h, mut shut_f) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for (name, case, repeat) in self.cases() {
            let w = case.speed("gear")?;
            let ft: Vec<f64> = case.load.iter().map(|f| st.tangential(*f, spec.force)).collect();
            let sh: Vec<f64> = ft.iter().map(|f| st.contact(*f)).collect();
            let sf: Vec<f64> = ft.iter().map(|f| st.bending(*f)).collect();
            let (dh, n) = stress_damage(&case.t, &sh, w, per_rev, sigma_hlim, gear::contact_cycles_to_failure);
            let (df, _) = stress_damage(&case.t, &sf, w, per_rev, sigma_fe, gear::bending_cycles_to_failure);
            let max = |v: &[f64]| v.iter().cloned().fold(0.0, f64::max);
            cases.push(GearCase {
                case: name,
                max_contact_stress: max(&sh),
                max_root_stress: max(&sf),
                load_cycles: n * repeat,
                flank_damage: dh * repeat,
                root_damage: df * repeat,
            });
            total_h += dh * repeat;
            total_f += df * repeat;
            total_cycles += n * repeat;
            if name == "shutdown" {
                shut_h = dh * repeat;
                shut_f = df * repeat;
            }
        }
        let z_nt = gear::contact_life_factor(total_cycles);
        let y_nt = gear::bending_life_factor(total_cycles);
        Ok(GearLife {
            cycles_per_revolution: per_rev,
            root,
            allowable_contact_stress: sigma_hlim * z_nt,
            allowable_root_stress: sigma_fe * y_nt,
            cases,
            load_cycles: total_cycles,
            y_f,
            y_s,
            z_nt,
            y_nt,
            flank_damage: total_h,
            root_damage: total_f,
            flank_shutdown_share: shut_h / total_h.max(1e-300),
            root_shutdown_share: shut_f / total_f.max(1e-300),
        })
    }
}

/// Miner damage of one series' stress with load cycles from its speed, sample by sample: each sample's
/// σ_j holds for n_j = revolutions to the next sample × `cycles_per_rev` load cycles, N_j from the S-N
/// curve at σ_j/limit (no binning error, as `windrive gears` and the bearing life sum). Returns
/// (damage, load cycles).
fn stress_damage(
    t: &[f64],
    stress: &[f64],
    speed: &[f64],
    cycles_per_rev: f64,
    limit: f64,
    sn: fn(f64) -> f64,
) -> (f64, f64) {
    let (mut damage, mut cycles) = (0.0, 0.0);
    for ((_, revolutions), &s) in ldd::sample_revolutions(t, speed).zip(stress) {
        let n = revolutions * cycles_per_rev;
        cycles += n;
        if n > 0.0 && s > 0.0 {
            damage += n / sn(s / limit);
        }
    }
    (damage, cycles)
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BearingCase {
    pub case: &'static str,
    pub max_load: f64,
    pub revolutions: f64,
    pub damage: f64,
}

/// A bearing's lifetime: the Miner damage of every case, the equivalent load P_eq over the lifetime's
/// revolutions and its L10.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BearingLife {
    #[serde(skip)]
    pub roller: bool,
    /// The basic dynamic load rating C, N.
    pub capacity: f64,
    pub cases: Vec<BearingCase>,
    pub revolutions: f64,
    pub equivalent_load: f64,
    pub l10_revolutions: f64,
    pub damage: f64,
    pub shutdown_share: f64,
    pub l10_years: f64,
}

/// The gear tooth whose life is asked for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GearSpec {
    pub pair: GearPair,
    pub tooth: Tooth,
    /// Which member of the pair the tooth is: 1 or 2.
    pub member: u8,
    /// Tooth form and stress correction factors; None = from the root geometry (ISO 6336-3 method B).
    pub y_fs: Option<(f64, f64)>,
    /// The hob's basic rack, for the root geometry.
    pub rack: BasicRack,
    /// Planets of the stage (load cycles of sun and ring teeth).
    pub planets: u32,
    pub k_a: f64,
    pub k_gamma: f64,
    /// What the load channel holds: the torsional FMU's transverse mesh force or the gearbox6dof's normal.
    pub force: MeshForce,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GearCase {
    pub case: &'static str,
    pub max_contact_stress: f64,
    pub max_root_stress: f64,
    pub load_cycles: f64,
    pub flank_damage: f64,
    pub root_damage: f64,
}

/// A gear tooth's lifetime: stresses, allowables at the lifetime's load cycles and Miner damage.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GearLife {
    #[serde(skip)]
    pub cycles_per_revolution: f64,
    /// The root geometry the factors came from (None when they were given).
    #[serde(skip)]
    pub root: Option<crate::analysis::rating::tooth_root::RootForm>,
    /// σ_Hlim·Z_NT and σ_FE·Y_M·Y_NT, Pa.
    #[serde(skip)]
    pub allowable_contact_stress: f64,
    #[serde(skip)]
    pub allowable_root_stress: f64,
    pub cases: Vec<GearCase>,
    pub load_cycles: f64,
    pub y_f: f64,
    pub y_s: f64,
    pub z_nt: f64,
    pub y_nt: f64,
    pub flank_damage: f64,
    pub root_damage: f64,
    pub flank_shutdown_share: f64,
    pub root_shutdown_share: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sample by sample: two stress levels held for known revolutions give n₁/N(σ₁) + n₂/N(σ₂) exactly,
    /// whatever the levels (a 200-bin LDD put them at its bin centres).
    #[test]
    fn stress_damage_sums_every_sample() {
        let t: Vec<f64> = (0..=1000).map(|i| i as f64 * 0.01).collect();
        let stress: Vec<f64> = (0..=1000).map(|i| if i < 300 { 1.13e9 } else { 1.37e9 }).collect();
        let speed = vec![3.0; t.len()];
        let (d, n) = stress_damage(&t, &stress, &speed, 2.0, 1.5e9, gear::contact_cycles_to_failure);
        let per_sample = 0.01 * 3.0 / std::f64::consts::TAU * 2.0;
        let (n1, n2) = (300.0 * per_sample, 700.0 * per_sample);
        let by_hand =
            n1 / gear::contact_cycles_to_failure(1.13 / 1.5) + n2 / gear::contact_cycles_to_failure(1.37 / 1.5);
        assert!((n / (n1 + n2) - 1.0).abs() < 1e-12);
        assert!((d / by_hand - 1.0).abs() < 1e-12, "{d} vs {by_hand}");
    }

    /// Thesis Ch. 7.2.4 / Table 7.1: 20 years of a Rayleigh climate of mean 10 m/s between cut-in 4 and
    /// cut-out 25 m/s are 161 950 h in operation, counting the 1 m/s bins (v − 1, v] from 4 to 25 m/s
    /// (the table's rounding to whole hours per bin allows 0.05 %); the exact interval 4–25 m/s is
    /// the cut-in bin (8 733 h) shorter.
    #[test]
    fn operating_hours_match_the_thesis() {
        let mut climate = Climate {
            wind: WindDistribution::Rayleigh { mean: 10.0 },
            cut_in: 4.0,
            cut_out: 25.0,
            bin_width: 1.0,
        };
        let hours = climate.operating_hours(20.0 * HOURS_PER_YEAR);
        assert!((hours / 161_950.0 - 1.0).abs() < 5e-4, "{hours}");
        climate.bin_width = 0.0;
        let exact = climate.operating_hours(20.0 * HOURS_PER_YEAR);
        assert!((hours - exact - 8733.0).abs() < 0.6, "{exact}");
        climate.bin_width = -1.0;
        assert!(matches!(
            climate.validate(),
            Err(LifeError::Invalid {
                quantity: "bin width",
                ..
            })
        ));
    }

    fn case(load: Vec<f64>, speed: f64) -> Case {
        let t: Vec<f64> = (0..load.len()).map(|i| i as f64 * 0.1).collect();
        Case {
            speed: Some(vec![speed; t.len()]),
            seconds: t[t.len() - 1],
            t,
            load,
        }
    }

    /// A lifetime of normal operation only has no shutdown share; adding a shutdown that repeats the
    /// same series N times adds N times its Σ n S^m; the bearing damage scales the same way.
    #[test]
    fn cases_add_up_with_their_repetitions() {
        let climate = Climate {
            wind: WindDistribution::Rayleigh { mean: 10.0 },
            cut_in: 4.0,
            cut_out: 25.0,
            bin_width: 1.0,
        };
        let x: Vec<f64> = (0..101).map(|i| 100.0 + 50.0 * (i as f64 * 0.7).sin()).collect();
        let alone = Lifetime::new(case(x.clone(), 2.0), None, &climate, 25.0, 1100.0).unwrap();
        let both = Lifetime::new(case(x.clone(), 2.0), Some(case(x, 2.0)), &climate, 25.0, 1100.0).unwrap();
        let (a, b) = (alone.dels(&[3.0], 1.0).unwrap()[0], both.dels(&[3.0], 1.0).unwrap()[0]);
        assert_eq!(a.shutdown_share, 0.0);
        let ratio = (b.del / a.del).powi(3);
        let expected = 1.0 + both.shutdowns / both.normal_factor();
        assert!((ratio / expected - 1.0).abs() < 1e-12, "{ratio} vs {expected}");
        let (da, db) = (alone.bearing(1e4, true).unwrap(), both.bearing(1e4, true).unwrap());
        assert!((db.damage / da.damage / expected - 1.0).abs() < 1e-12);
        assert!((db.l10_years - 25.0 / db.damage).abs() < 1e-9 * db.l10_years);
        assert!(matches!(
            Lifetime::new(both.normal.clone(), None, &climate, 0.0, 1.0),
            Err(LifeError::Invalid { quantity: "years", .. })
        ));
        let mut no_speed = both.clone();
        no_speed.normal.speed = None;
        assert!(matches!(
            no_speed.bearing(1e4, true),
            Err(LifeError::NeedsSpeed { what: "bearing" })
        ));
    }
}
