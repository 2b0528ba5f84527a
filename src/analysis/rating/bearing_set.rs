//! Every rolling bearing of a gearbox rated from one series of the `gearbox6dof` FMU, the ISO 281 way:
//! the basic dynamic load rating C from the roller set the gearbox description gives, the dynamic
//! equivalent load P from each sample's radial and axial load, the revolutions of the bearing's rings
//! against each other from the gearbox's kinematics, and Miner's sum of revolutions over the basic
//! rating life L10 = (C/P)^(10/3) million revolutions, sample by sample. Beside it, for comparison, the
//! thesis's count (its ch. 5.4): rainflow cycles of the load, each a load cycle at its range, over the
//! same life law, which weighs a shutdown's few large swings far above hours of turning. And the
//! modified rating life L_nm = a_ISO·L10 sample by sample ([`life_modification`]: lubrication,
//! contamination and the fatigue load limit at each sample's speed and load).

use crate::analysis::fatigue::ldd::sample_revolutions;
use crate::analysis::fatigue::rainflow::cycles;
use crate::analysis::fatigue::sn_curve::bearing_l10;
use crate::analysis::rating::life_modification::{self, Lubrication};
use crate::analysis::signal::series::{self, SeriesError};
use crate::physics::gearbox::Gearbox;
use crate::physics::gearbox::description::{Contact, Description, Rollers};
use serde::Serialize;
use std::path::Path;

/// The radial roller bearing types ISO 281 rates, as the description's roller set says.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum RollerKind {
    /// Line contact, α = 0.
    Cylindrical,
    /// Line contact, α ≠ 0.
    Tapered,
    /// Point contact (`contact = "point"`).
    Spherical,
}

impl RollerKind {
    /// Its name, as it serialises.
    pub fn name(self) -> &'static str {
        match self {
            RollerKind::Cylindrical => "cylindrical",
            RollerKind::Tapered => "tapered",
            RollerKind::Spherical => "spherical",
        }
    }

    pub fn of(r: &Rollers) -> RollerKind {
        match (r.contact, r.contact_angle_deg) {
            (Contact::Point, _) => RollerKind::Spherical,
            (Contact::Line, a) if a != 0.0 => RollerKind::Tapered,
            _ => RollerKind::Cylindrical,
        }
    }

    /// ISO 281:2007 Table 1, b_m of radial roller bearings (the rating of modern, hardened steel
    /// relative to the Lundberg–Palmgren base).
    fn material_factor(self) -> f64 {
        match self {
            RollerKind::Cylindrical | RollerKind::Tapered => 1.1,
            RollerKind::Spherical => 1.15,
        }
    }
}

/// ISO 281 factor f_c of radial roller bearings at γ = D_we·cos α / D_pw, in the closed form of its
/// Lundberg–Palmgren derivation (it gives ISO 281 Table 7 to the table's rounding; tested below).
pub fn roller_factor(gamma: f64) -> f64 {
    let g = gamma;
    let edge = (1.04 * ((1.0 - g) / (1.0 + g)).powf(143.0 / 108.0)).powf(4.5);
    207.9
        * 0.83
        * g.powf(2.0 / 9.0)
        * (1.0 - g).powf(29.0 / 27.0)
        * (1.0 + g).powf(-0.25)
        * (1.0 + edge).powf(-2.0 / 9.0)
}

/// ISO 281 basic dynamic radial load rating C_r of a roller set, N:
/// b_m·f_c·(i·L_we·cos α)^(7/9)·Z^(3/4)·D_we^(29/27), lengths in mm.
pub fn dynamic_load_rating(r: &Rollers) -> f64 {
    let cos = r.contact_angle_deg.to_radians().cos();
    let gamma = r.diameter_mm * cos / r.pitch_diameter_mm;
    RollerKind::of(r).material_factor()
        * roller_factor(gamma)
        * (f64::from(r.rows) * r.length_mm * cos).powf(7.0 / 9.0)
        * f64::from(r.count).powf(0.75)
        * r.diameter_mm.powf(29.0 / 27.0)
}

/// ISO 281 dynamic equivalent radial load P_r of radial roller bearings from the radial and axial load
/// (N): F_r at α = 0 (a cylindrical bearing's ribs carry axial load outside the rating); at α ≠ 0 with
/// e = 1.5·tan α, one row X = 1, Y = 0 up to F_a/F_r = e, beyond it X = 0.4, Y = 0.4·cot α; two rows
/// X = 1, Y = 0.45·cot α, beyond it X = 0.67, Y = 0.67·cot α.
pub fn equivalent_load(r: &Rollers, radial: f64, axial: f64) -> f64 {
    let (fr, fa) = (radial.abs(), axial.abs());
    let alpha = r.contact_angle_deg.abs().to_radians();
    if alpha == 0.0 {
        return fr;
    }
    let (e, cot) = (1.5 * alpha.tan(), 1.0 / alpha.tan());
    let beyond = fa > e * fr;
    let (x, y) = match (r.rows >= 2, beyond) {
        (false, false) => (1.0, 0.0),
        (false, true) => (0.4, 0.4 * cot),
        (true, false) => (1.0, 0.45 * cot),
        (true, true) => (0.67, 0.67 * cot),
    };
    x * fr + y * fa
}

/// One rated bearing: its roller set, its rating, its load channels and how fast its rings turn.
#[derive(Debug, Clone, PartialEq)]
pub struct RatedBearing {
    /// The FMU's name for it (`planet_1_uw`, `hss_a`).
    pub name: String,
    pub rollers: Rollers,
    /// C_r, N.
    pub rating: f64,
    /// ISO 281's fatigue load limit C_u, N.
    pub fatigue_limit: f64,
    pub radial: String,
    pub axial: String,
    /// Relative speed of its rings over the input (rotor) speed.
    pub speed_ratio: f64,
}

/// Every rated bearing of a gearbox, and the speed channels its series must have: the rotor's (the
/// rings' revolutions) and the generator's (the check that the series is this gearbox's).
#[derive(Debug, Clone, PartialEq)]
pub struct BearingTable {
    /// The description's name, for errors.
    pub gearbox: String,
    /// Generator speed over rotor speed.
    pub gear_ratio: f64,
    pub rotor_speed: String,
    pub generator_speed: String,
    pub bearings: Vec<RatedBearing>,
    /// The oil and its cleanliness every bearing's a_ISO is taken with.
    pub lubrication: Lubrication,
}

/// A bearing's result over one series.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BearingDamage {
    pub name: String,
    pub kind: RollerKind,
    pub rollers: u32,
    pub rows: u32,
    pub contact_angle_deg: f64,
    /// Basic dynamic load rating C_r, N.
    pub dynamic_load_rating: f64,
    /// Revolutions of the rings against each other per rotor revolution, and in the window.
    pub speed_ratio: f64,
    pub revolutions: f64,
    /// Largest dynamic equivalent load in the window, and the window's equivalent
    /// (Σ n_j P_j^(10/3) / Σ n_j)^(3/10), N.
    pub max_equivalent_load: f64,
    pub equivalent_load: f64,
    /// Miner damage in the window (revolutions over L10) and scaled to one day.
    pub damage: f64,
    pub damage_per_day: f64,
    /// ISO 281's fatigue load limit C_u, N.
    pub fatigue_load_limit: f64,
    /// The viscosity ratio κ at the window's mean speed (revolutions over time).
    pub viscosity_ratio: f64,
    /// Miner damage over the modified rating life a_ISO·L10 at each sample's speed and load, in the
    /// window and per day.
    pub modified_damage: f64,
    pub modified_damage_per_day: f64,
    /// Hours to a damage of 1 (the L10 life) if the window repeated: the window's L10h.
    pub life_hours: f64,
    /// The thesis's damage (its Eqs. 5.25–5.26): Σ n_i / (10⁶·(C/ΔP_i)^(10/3)) over the rainflow cycles
    /// (n_i, ΔP_i) of the equivalent load, a load cycle counted as a revolution; in the window and per
    /// day. Not ISO 281, which counts revolutions: kept to show where the thesis's shutdown share comes from.
    pub thesis_damage: f64,
    pub thesis_damage_per_day: f64,
}

#[derive(Debug, thiserror::Error)]
pub enum BearingSetError {
    #[error(transparent)]
    Series(#[from] SeriesError),
    #[error("gearbox {0}: {1}")]
    Gearbox(String, String),
    #[error(
        "{path}: generator over rotor speed is {measured:.4}, gearbox {gearbox} turns {expected:.4}; the series is not from this gearbox"
    )]
    WrongGearbox {
        path: String,
        gearbox: String,
        measured: f64,
        expected: f64,
    },
}

/// The bearings of `description` that describe a roller set, rated from the outputs of the FMU named
/// `component` in the series. Bearings without rollers (no geometry, no rating) are left out.
pub fn bearing_table(description: &Description, component: &str) -> Result<BearingTable, BearingSetError> {
    let name = || description.name.clone();
    let model = Gearbox::new(description).map_err(|e| BearingSetError::Gearbox(name(), e))?;
    let ratios = model
        .bearing_speed_ratios()
        .ok_or_else(|| BearingSetError::Gearbox(name(), "its chain is held; no bearing turns".into()))?;
    let bearings = model
        .bearings
        .iter()
        .zip(ratios)
        .filter_map(|(b, speed_ratio)| {
            let rollers = b.geometry?;
            Some(RatedBearing {
                name: b.name.clone(),
                rollers,
                rating: dynamic_load_rating(&rollers),
                fatigue_limit: life_modification::fatigue_load_limit(&rollers),
                radial: format!("{component}.{}_radial_load", b.name),
                axial: format!("{component}.{}_axial_load", b.name),
                speed_ratio,
            })
        })
        .collect();
    Ok(BearingTable {
        gearbox: name(),
        gear_ratio: model.gear_ratio,
        rotor_speed: format!("{component}.rotor_speed"),
        generator_speed: format!("{component}.generator_speed"),
        bearings,
        lubrication: Lubrication::default(),
    })
}

impl RatedBearing {
    /// Rates the bearing over time `t` with its load channels and the rotor speed, its a_ISO with `oil`.
    pub fn rate(&self, t: &[f64], radial: &[f64], axial: &[f64], speed: &[f64], oil: &Lubrication) -> BearingDamage {
        const P: f64 = 10.0 / 3.0;
        let (mut revolutions, mut damage, mut weighted, mut max_load) = (0.0, 0.0, 0.0, 0.0f64);
        let mut modified = 0.0;
        let pitch = self.rollers.pitch_diameter_mm;
        let oil = oil.in_service();
        let loads: Vec<f64> = radial
            .iter()
            .zip(axial)
            .map(|(&r, &a)| equivalent_load(&self.rollers, r, a))
            .collect();
        for (j, (dt, revs)) in sample_revolutions(t, speed).enumerate() {
            let n = revs * self.speed_ratio;
            let load = loads[j];
            max_load = max_load.max(load);
            revolutions += n;
            weighted += n * load.powf(P);
            if load > 0.0 && n > 0.0 {
                let d = n / (bearing_l10(self.rating, load, true) * 1e6);
                damage += d;
                modified += d / oil.factor(n / dt * 60.0, pitch, self.fatigue_limit, load);
            }
        }
        let thesis_damage: f64 = cycles(&loads)
            .iter()
            .filter(|c| c.range > 0.0)
            .map(|c| c.count / (bearing_l10(self.rating, c.range, true) * 1e6))
            .sum();
        let seconds = t[t.len() - 1] - t[0];
        let mean_rpm = revolutions / seconds * 60.0;
        BearingDamage {
            name: self.name.clone(),
            kind: RollerKind::of(&self.rollers),
            rollers: self.rollers.count,
            rows: self.rollers.rows,
            contact_angle_deg: self.rollers.contact_angle_deg,
            dynamic_load_rating: self.rating,
            speed_ratio: self.speed_ratio,
            revolutions,
            max_equivalent_load: max_load,
            equivalent_load: if revolutions > 0.0 {
                (weighted / revolutions).powf(1.0 / P)
            } else {
                0.0
            },
            damage,
            damage_per_day: damage * 86400.0 / seconds,
            fatigue_load_limit: self.fatigue_limit,
            viscosity_ratio: oil.viscosity_ratio(mean_rpm, pitch),
            modified_damage: modified,
            modified_damage_per_day: modified * 86400.0 / seconds,
            life_hours: seconds / damage / 3600.0,
            thesis_damage,
            thesis_damage_per_day: thesis_damage * 86400.0 / seconds,
        }
    }
}

/// One bearing's series: time (s), dynamic equivalent load P (N), its rings' relative speed (rad/s).
pub struct BearingSeries {
    pub t: Vec<f64>,
    pub load: Vec<f64>,
    pub speed: Vec<f64>,
}

impl BearingTable {
    /// The channels the table reads, each once: every bearing's radial and axial load, the rotor speed,
    /// the generator speed.
    pub fn channels(&self) -> Vec<&str> {
        let mut names: Vec<&str> = Vec::new();
        for b in &self.bearings {
            names.extend([b.radial.as_str(), b.axial.as_str()]);
        }
        names.extend([self.rotor_speed.as_str(), self.generator_speed.as_str()]);
        names
    }

    /// Refuses a series whose generator turns at another ratio to its rotor than this gearbox's by
    /// more than 5 %: rated with another gearbox's rollers and kinematics, its damage would be wrong.
    /// The ratio is read where the rotor turns at half its fastest or more: a stopped, braked rotor
    /// rocks on the shafts' compliance while the generator is held, which says nothing about the gears.
    fn check(&self, source: &str, rotor: &[f64], generator: &[f64]) -> Result<(), BearingSetError> {
        let fastest = rotor.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let (mut rotor_sum, mut generator_sum) = (0.0, 0.0);
        for (r, g) in rotor.iter().zip(generator) {
            if r.abs() >= 0.5 * fastest {
                rotor_sum += r.abs();
                generator_sum += g.abs();
            }
        }
        // a stopped series says nothing about its gearbox
        if rotor_sum > 0.0 && generator_sum > 0.0 {
            let measured = generator_sum / rotor_sum;
            if (measured / self.gear_ratio - 1.0).abs() > 0.05 {
                return Err(BearingSetError::WrongGearbox {
                    path: source.to_string(),
                    gearbox: self.gearbox.clone(),
                    measured,
                    expected: self.gear_ratio,
                });
            }
        }
        Ok(())
    }

    /// Rates every bearing over the series in `path` after `transient` seconds, once the series shows
    /// it is this gearbox's.
    pub fn rate_series(&self, path: &Path, transient: f64) -> Result<Vec<BearingDamage>, BearingSetError> {
        let names = self.channels();
        let (t, columns) = series::read_after(path, &names, transient)?;
        let column = |name: &str| &columns[names.iter().position(|n| *n == name).expect("listed above")][..];
        self.rate_columns(&path.display().to_string(), &t, column)
    }

    /// As [`BearingTable::rate_series`] over a series already in memory: `column` gives each of
    /// [`BearingTable::channels`]'s columns, sampled at `t`; `source` names the series in errors.
    pub fn rate_columns<'a>(
        &self,
        source: &str,
        t: &[f64],
        column: impl Fn(&str) -> &'a [f64],
    ) -> Result<Vec<BearingDamage>, BearingSetError> {
        let rotor = column(&self.rotor_speed);
        self.check(source, rotor, column(&self.generator_speed))?;
        Ok(self
            .bearings
            .iter()
            .map(|b| b.rate(t, column(&b.radial), column(&b.axial), rotor, &self.lubrication))
            .collect())
    }

    /// The bearing table of a gearbox6dof preset or description file read by `component`'s channels;
    /// an error when it cannot be read or no bearing has a roller set (nothing to rate).
    pub fn load(gearbox: &str, component: &str) -> Result<BearingTable, BearingSetError> {
        let description =
            Description::load(gearbox).map_err(|e| BearingSetError::Gearbox(gearbox.into(), e.to_string()))?;
        let table = bearing_table(&description, component)?;
        if table.bearings.is_empty() {
            return Err(BearingSetError::Gearbox(
                gearbox.into(),
                "no bearing has a roller set (`rollers = { count, diameter_mm, length_mm, pitch_diameter_mm }`), \
                 so none has an ISO 281 rating"
                    .into(),
            ));
        }
        Ok(table)
    }

    /// Bearing `b`'s series in `path`, checked as [`BearingTable::rate_series`] checks: time, its dynamic
    /// equivalent load P per sample (N) and its rings' speed against each other (rad/s). What
    /// `windrive life --bearing-of` scales to a lifetime.
    pub fn load_and_speed(&self, b: &RatedBearing, path: &Path) -> Result<BearingSeries, BearingSetError> {
        let names = [
            b.radial.as_str(),
            b.axial.as_str(),
            self.rotor_speed.as_str(),
            self.generator_speed.as_str(),
        ];
        let (t, columns) = series::read_channels(path, &names)?;
        self.check(&path.display().to_string(), &columns[2], &columns[3])?;
        let load = columns[0]
            .iter()
            .zip(&columns[1])
            .map(|(&r, &a)| equivalent_load(&b.rollers, r, a))
            .collect();
        let speed = columns[2].iter().map(|w| w * b.speed_ratio).collect();
        Ok(BearingSeries { t, load, speed })
    }
}

/// The table `windrive bearings` prints: a row per rated bearing (type, rating, loads, revolutions,
/// damage per day and L10 life, the modified life's κ, C_u and damage per day, and the thesis's count).
pub fn table(rated: &[BearingDamage]) -> String {
    // the columns' widths; the first two left-aligned, the rest right-aligned
    const WIDTHS: [usize; 15] = [14, 12, 3, 6, 8, 8, 9, 9, 11, 11, 11, 6, 7, 11, 11];
    let line = |cells: [&str; 15]| {
        let mut row = String::new();
        for (k, (cell, width)) in cells.iter().zip(WIDTHS).enumerate() {
            let sep = if k == 0 { "" } else { " " };
            if k < 2 {
                row.push_str(&format!("{sep}{cell:<width$}"));
            } else {
                row.push_str(&format!("{sep}{cell:>width$}"));
            }
        }
        row + "\n"
    };
    let mut s = line([
        "bearing",
        "type",
        "Z",
        "α",
        "C_r",
        "n/n_rot",
        "P_eq",
        "P_max",
        "revolutions",
        "D/day",
        "L10h",
        "κ",
        "C_u",
        "D_nm/day",
        "thesis/day",
    ]);
    s.push_str(&line([
        "", "", "", "deg", "kN", "", "kN", "kN", "", "", "h", "", "kN", "", "",
    ]));
    for r in rated {
        let rows = if r.rows > 1 {
            format!("{}×", r.rows)
        } else {
            String::new()
        };
        s.push_str(&line([
            &r.name,
            &format!("{rows}{}", r.kind.name()),
            &r.rollers.to_string(),
            &format!("{:.1}", r.contact_angle_deg),
            &format!("{:.0}", r.dynamic_load_rating / 1e3),
            &format!("{:.3}", r.speed_ratio),
            &format!("{:.1}", r.equivalent_load / 1e3),
            &format!("{:.1}", r.max_equivalent_load / 1e3),
            &format!("{:.4e}", r.revolutions),
            &format!("{:.4e}", r.damage_per_day),
            &format!("{:.4e}", r.life_hours),
            &format!("{:.2}", r.viscosity_ratio),
            &format!("{:.0}", r.fatigue_load_limit / 1e3),
            &format!("{:.4e}", r.modified_damage_per_day),
            &format!("{:.4e}", r.thesis_damage_per_day),
        ]));
    }
    s.push_str(
        "D_nm: Miner over ISO 281's modified life a_ISO·L10 at each sample's speed and load (κ at the window's mean \
         speed; the oil and e_C as given, estimates by default)\n",
    );
    s
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A one-row cylindrical roller set of `count` rollers, Ø`d` × `l` mm on pitch diameter `dm` mm.
    pub(crate) fn cylindrical(count: u32, d: f64, l: f64, dm: f64) -> Rollers {
        Rollers {
            count,
            diameter_mm: d,
            length_mm: l,
            pitch_diameter_mm: dm,
            contact_angle_deg: 0.0,
            rows: 1,
            row_spacing_mm: 0.0,
            clearance_um: 0.0,
            axial_clearance_um: 0.0,
            laminae: 10,
            contact: Contact::Line,
            roller_stiffness: None,
            profile_radius_mm: None,
            race_profile_radii_mm: None,
            crowning_um: 0.0,
        }
    }

    /// ISO 281:2007 Table 7 (f_c of radial roller bearings), every tenth of γ = 0.01 … 0.30, to its
    /// rounding of 0.1 (the closed form is the table's source; 0.05 allows the rounding).
    #[test]
    fn roller_factor_is_iso_281_table_7() {
        let table = [
            52.1, 60.8, 66.5, 70.7, 74.1, 76.9, 79.2, 81.2, 82.8, 84.2, 85.4, 86.4, 87.1, 87.7, 88.2, 88.5, 88.7, 88.8,
            88.8, 88.7, 88.5, 88.2, 87.9, 87.5, 87.0, 86.4, 85.8, 85.2, 84.5, 83.8,
        ];
        for (i, want) in table.iter().enumerate() {
            let gamma = (i + 1) as f64 / 100.0;
            let got = roller_factor(gamma);
            assert!((got - want).abs() <= 0.05 + 1e-9, "γ = {gamma}: {got} vs {want}");
        }
    }

    /// C_r by hand for the GRC's planet bearing estimate (20 × 34 × 60 mm on 225 mm):
    /// γ = 0.1511, f_c = 88.25, C = 1.1·88.25·60^(7/9)·20^(3/4)·34^(29/27) ≈ 979 kN; a full-complement
    /// CRB of that envelope (160 × 290 mm) is catalogued at 1–1.5 MN, so the estimate is of that order.
    /// Doubling the rows multiplies C by 2^(7/9) (ISO 281's rule for multi-row bearings).
    #[test]
    fn rating_from_roller_geometry() {
        let planet = cylindrical(20, 34.0, 60.0, 225.0);
        let gamma: f64 = 34.0 / 225.0;
        let by_hand = 1.1 * roller_factor(gamma) * 60f64.powf(7.0 / 9.0) * 20f64.powf(0.75) * 34f64.powf(29.0 / 27.0);
        let c = dynamic_load_rating(&planet);
        assert!((c / by_hand - 1.0).abs() < 1e-12);
        assert!((c - 979e3).abs() < 5e3, "{c}");
        let two = Rollers { rows: 2, ..planet };
        assert!((dynamic_load_rating(&two) / c - 2f64.powf(7.0 / 9.0)).abs() < 1e-12);
        let spherical = Rollers {
            contact: Contact::Point,
            ..planet
        };
        assert!((dynamic_load_rating(&spherical) / c - 1.15 / 1.1).abs() < 1e-12);
    }

    /// X and Y switch at e = 1.5·tan α; a cylindrical bearing's P is its radial load alone.
    #[test]
    fn equivalent_load_of_iso_281() {
        let crb = cylindrical(20, 34.0, 60.0, 225.0);
        assert_eq!(equivalent_load(&crb, -10e3, 50e3), 10e3);
        let trb = Rollers {
            contact_angle_deg: -13.0,
            ..crb
        };
        let e = 1.5 * 13f64.to_radians().tan();
        let cot = 1.0 / 13f64.to_radians().tan();
        assert_eq!(equivalent_load(&trb, 10e3, 0.99 * e * 10e3), 10e3);
        let beyond = equivalent_load(&trb, 10e3, 2.0 * e * 10e3);
        assert!((beyond - (0.4 * 10e3 + 0.4 * cot * 2.0 * e * 10e3)).abs() < 1e-6);
        let pair = Rollers { rows: 2, ..trb };
        assert!((equivalent_load(&pair, 10e3, 1e3) - (10e3 + 0.45 * cot * 1e3)).abs() < 1e-6);
        assert!((equivalent_load(&pair, 10e3, 1e5) - (0.67 * 10e3 + 0.67 * cot * 1e5)).abs() < 1e-6);
    }

    /// A constant load for a known number of revolutions: damage = revolutions / L10, the window's
    /// equivalent load is that load, and the life in hours is L10 over the revolutions per hour.
    #[test]
    fn constant_load_damage_is_revolutions_over_l10() {
        let r = cylindrical(20, 34.0, 60.0, 225.0);
        let b = RatedBearing {
            name: "x".into(),
            rollers: r,
            rating: dynamic_load_rating(&r),
            fatigue_limit: life_modification::fatigue_load_limit(&r),
            radial: String::new(),
            axial: String::new(),
            speed_ratio: 3.5,
        };
        let n = 1001;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 0.01).collect();
        let load = vec![150e3; n];
        let speed = vec![2.0; n];
        let oil = Lubrication::default();
        let d = b.rate(&t, &load, &vec![0.0; n], &speed, &oil);
        let revs = 10.0 * 2.0 / std::f64::consts::TAU * 3.5;
        assert!((d.revolutions / revs - 1.0).abs() < 1e-12);
        let l10 = (b.rating / 150e3).powf(10.0 / 3.0) * 1e6;
        assert!((d.damage / (revs / l10) - 1.0).abs() < 1e-12);
        assert!((d.equivalent_load / 150e3 - 1.0).abs() < 1e-12);
        assert!((d.life_hours / (l10 / (revs / 10.0) / 3600.0) - 1.0).abs() < 1e-9);
        assert!((d.damage_per_day / (d.damage * 8640.0) - 1.0).abs() < 1e-12);
        assert_eq!(d.thesis_damage, 0.0, "a constant load has no load cycles");
        // L_nm at one speed and load: the damage over a_ISO at the rings' 66.8 r/min, κ at that speed
        let rpm = 2.0 * 3.5 * 60.0 / std::f64::consts::TAU;
        let film = oil.in_service();
        let a = film.factor(rpm, 225.0, b.fatigue_limit, 150e3);
        assert!((d.modified_damage / (d.damage / a) - 1.0).abs() < 1e-9);
        assert!((d.viscosity_ratio / film.viscosity_ratio(rpm, 225.0) - 1.0).abs() < 1e-9);
        assert!((d.modified_damage_per_day / (d.modified_damage * 8640.0) - 1.0).abs() < 1e-12);
        // the thesis's count: 500 full cycles between 0 and 150 kN (rainflow: 499.5 + the residue's
        // half cycles), each over (C/150 kN)^(10/3) million cycles
        let square: Vec<f64> = (0..n).map(|i| if i % 2 == 0 { 0.0 } else { 150e3 }).collect();
        let d = b.rate(&t, &square, &vec![0.0; n], &speed, &oil);
        let counted: f64 = cycles(&square).iter().map(|c| c.count).sum();
        assert!((counted - 500.0).abs() <= 0.5, "{counted}");
        assert!((d.thesis_damage / (counted / l10) - 1.0).abs() < 1e-12);
    }

    /// The GRC's bearings turn as its kinematics say: the carrier's at rotor speed, the LSS gear's at
    /// the planetary ratio 1 + z_r/z_s, each planet against its carrier at (z_r/z_p)·ω_carrier, the HSS
    /// at the gearbox ratio.
    #[test]
    fn grc_bearings_turn_with_the_gear_ratios() {
        let d = Description::load("grc750").unwrap();
        let table = bearing_table(&d, "gearbox").unwrap();
        let ratio = |n: &str| table.bearings.iter().find(|b| b.name == n).unwrap().speed_ratio;
        let p = d.stages.iter().find_map(|s| match s {
            crate::physics::gearbox::description::Stage::Planetary(p) => Some(p.clone()),
            _ => None,
        });
        let p = p.unwrap();
        let (zs, zp, zr) = (
            f64::from(p.teeth.sun),
            f64::from(p.teeth.planet),
            f64::from(p.teeth.ring),
        );
        assert!((ratio("carrier_a") - 1.0).abs() < 1e-9);
        assert!((ratio("lss_a") - (1.0 + zr / zs)).abs() < 1e-9, "{}", ratio("lss_a"));
        assert!(
            (ratio("planet_2_dw") - zr / zp).abs() < 1e-9,
            "{}",
            ratio("planet_2_dw")
        );
        let model = Gearbox::new(&d).unwrap();
        assert!((ratio("hss_b") / model.gear_ratio - 1.0).abs() < 1e-9);
        assert_eq!(
            table.bearings.len(),
            16,
            "every GRC gearbox bearing (2 carrier, 6 planet, 8 shaft) has a roller set"
        );
        assert_eq!(table.bearings[0].radial, "gearbox.carrier_a_radial_load");
        assert!((table.gear_ratio / model.gear_ratio - 1.0).abs() < 1e-15);
    }

    /// A braked stop: the rotor turns at the gearbox ratio to the generator, then rocks on the shafts
    /// while the brake holds the generator. The rocking says nothing about the gears, so the series
    /// is the gearbox's; the same series at another ratio is refused.
    #[test]
    fn a_braked_rotor_rocking_is_not_another_gearbox() {
        let d = Description::load("grc750").unwrap();
        let table = bearing_table(&d, "gearbox").unwrap();
        let ratio = table.gear_ratio;
        let n = 2000;
        let rotor: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64 * 0.01;
                if t < 5.0 {
                    2.0 * (1.0 - t / 5.0)
                } else {
                    0.3 * (10.0 * t).sin()
                }
            })
            .collect();
        let generator: Vec<f64> = rotor
            .iter()
            .enumerate()
            .map(|(i, w)| if i < 500 { ratio * w } else { 0.0 })
            .collect();
        let path = "stop.csv";
        table.check(path, &rotor, &generator).unwrap();
        let other: Vec<f64> = generator.iter().map(|g| 1.1 * g).collect();
        assert!(matches!(
            table.check(path, &rotor, &other),
            Err(BearingSetError::WrongGearbox { .. })
        ));
    }
}
