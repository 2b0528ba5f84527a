//! ISO 281:2007's modified rating life of roller bearings, L_nm = a_1·a_ISO·L10 (its §9.3): the life
//! modification factor a_ISO from the lubrication (the viscosity ratio κ = ν/ν₁), the oil's cleanliness
//! (the contamination factor e_C) and the bearing's fatigue load limit C_u against the load P. The
//! basic life L10 assumes none of them; a certification engineer reads L_nm.
//!
//! The formulas are the standard's (ISO 281:2007 §9.3.3 and Annex B, ISO 76:2006 §6.1.2 for C_0); the
//! operating conditions are not ours to know for the thesis's and NREL's gearboxes, so
//! [`Lubrication::default`] is a documented estimate with the range `windrive bearings` lets a user
//! vary (docs/CAMPAIGNS.md, "What the bearing damage is, and is not").

use crate::physics::gearbox::description::Rollers;

/// The oil a gearbox's bearings run in, and how clean it is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lubrication {
    /// Kinematic viscosity at 40 °C (the ISO VG grade), mm²/s.
    pub viscosity_40: f64,
    /// Kinematic viscosity at 100 °C, mm²/s.
    pub viscosity_100: f64,
    /// The bearings' operating temperature, °C.
    pub temperature_c: f64,
    /// ISO 281's contamination factor e_C (1: perfectly clean, 0: severely contaminated).
    pub contamination: f64,
}

impl Default for Lubrication {
    /// The estimate this project rates with (no source gives the thesis's or the GRC's operating
    /// conditions): an ISO VG 320 mineral gear oil, the grade wind-turbine gearboxes run on (320 mm²/s
    /// at 40 °C, 24 at 100 °C, viscosity index about 95); bearings at 65 °C (range 50–80 °C: sump to
    /// loaded-bearing temperature); e_C = 0.5, within ISO 281's guideline values for bearings of
    /// D_pw ≥ 100 mm between "normal cleanliness" (0.8–0.6) and "slight contamination" (0.6–0.4)
    /// (range 0.2–0.8).
    fn default() -> Self {
        Self {
            viscosity_40: 320.0,
            viscosity_100: 24.0,
            temperature_c: 65.0,
            contamination: 0.5,
        }
    }
}

impl Lubrication {
    /// The oil as given, each setting left out taking [`Lubrication::default`]'s, checked: what
    /// `windrive bearings`' flags and a campaign's `[bearings]` both give.
    pub fn given(
        viscosity: Option<[f64; 2]>,
        temperature_c: Option<f64>,
        contamination: Option<f64>,
    ) -> Result<Self, String> {
        let d = Self::default();
        let [viscosity_40, viscosity_100] = viscosity.unwrap_or([d.viscosity_40, d.viscosity_100]);
        let oil = Self {
            viscosity_40,
            viscosity_100,
            temperature_c: temperature_c.unwrap_or(d.temperature_c),
            contamination: contamination.unwrap_or(d.contamination),
        };
        oil.check()?;
        Ok(oil)
    }

    /// Refuses conditions the formulas do not hold for, naming the value.
    pub fn check(&self) -> Result<(), String> {
        let Self {
            viscosity_40: v40,
            viscosity_100: v100,
            temperature_c: temp,
            contamination: e,
        } = *self;
        if !(v40.is_finite() && v100.is_finite() && v100 > 0.0 && v40 > v100) {
            return Err(format!(
                "oil viscosity {v40} mm²/s at 40 °C and {v100} at 100 °C: both positive, the first the larger"
            ));
        }
        if !(-30.0..=150.0).contains(&temp) {
            return Err(format!("oil temperature {temp} °C: outside -30 to 150 °C"));
        }
        if !(0.0..=1.0).contains(&e) {
            return Err(format!("contamination factor e_C {e}: ISO 281's lies in 0 to 1"));
        }
        Ok(())
    }

    /// The oil's kinematic viscosity at the operating temperature, mm²/s, by ASTM D341's
    /// viscosity–temperature line (Walther's equation, log log (ν + 0.7) linear in log T) through the
    /// 40 °C and 100 °C values.
    pub fn operating_viscosity(&self) -> f64 {
        let walther = |nu: f64| (nu + 0.7).log10().log10();
        let log_t = |celsius: f64| (celsius + 273.15).log10();
        let (y40, y100) = (walther(self.viscosity_40), walther(self.viscosity_100));
        let slope = (y100 - y40) / (log_t(100.0) - log_t(40.0));
        let y = y40 + slope * (log_t(self.temperature_c) - log_t(40.0));
        10f64.powf(10f64.powf(y)) - 0.7
    }

    /// The oil at its operating temperature, its viscosity computed once for a rating's every sample.
    pub fn in_service(&self) -> InService {
        InService {
            viscosity: self.operating_viscosity(),
            contamination: self.contamination,
        }
    }
}

/// An oil at its operating temperature: what a_ISO reads at each sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InService {
    /// Kinematic viscosity, mm²/s.
    pub viscosity: f64,
    /// e_C.
    pub contamination: f64,
}

impl InService {
    /// The viscosity ratio κ = ν/ν₁ of a bearing of pitch diameter `pitch_mm` turning at `rpm`.
    pub fn viscosity_ratio(&self, rpm: f64, pitch_mm: f64) -> f64 {
        self.viscosity / reference_viscosity(rpm, pitch_mm)
    }

    /// The life modification factor a_ISO of a roller bearing of fatigue load limit `fatigue_limit`
    /// (N) under equivalent load `load` (N), its rings turning at `rpm`, pitch diameter `pitch_mm`.
    pub fn factor(&self, rpm: f64, pitch_mm: f64, fatigue_limit: f64, load: f64) -> f64 {
        life_modification(
            self.viscosity_ratio(rpm, pitch_mm),
            self.contamination * fatigue_limit / load,
        )
    }
}

/// ISO 281's reference viscosity ν₁ (mm²/s), the viscosity that just separates the surfaces of a
/// bearing of pitch diameter `pitch_mm` turning at `rpm`: 45 000·n^−0.83·D_pw^−0.5 below 1000 r/min,
/// 4500·n^−0.5·D_pw^−0.5 from there (the two meet within 2.4 % at 1000 r/min). Infinite at rest.
pub fn reference_viscosity(rpm: f64, pitch_mm: f64) -> f64 {
    let n = rpm.abs();
    if n < 1000.0 {
        45_000.0 * n.powf(-0.83) / pitch_mm.sqrt()
    } else {
        4_500.0 / (n.sqrt() * pitch_mm.sqrt())
    }
}

/// ISO 281:2007 §9.3.3's a_ISO of radial and thrust roller bearings at viscosity ratio `kappa` and
/// e_C·C_u/P = `ec_cu_over_p`: 0.1·[1 − (1.5859 − b/κ^c)·(e_C·C_u/P)^0.4]^−9.185, with (b, c) =
/// (1.3993, 0.054381) for 0.1 ≤ κ < 0.4, (1.2348, 0.19087) for 0.4 ≤ κ < 1, (1.2348, 0.071739) for
/// 1 ≤ κ ≤ 4. κ above 4 counts as 4 and below 0.1 as 0.1 (the standard's range; a bearing that slow is
/// nearly at rest and turns few revolutions); a_ISO is at most 50, which the standard takes as the
/// limit of the method.
pub fn life_modification(kappa: f64, ec_cu_over_p: f64) -> f64 {
    const LIMIT: f64 = 50.0;
    let k = kappa.clamp(0.1, 4.0);
    let (b, c) = if k < 0.4 {
        (1.3993, 0.054381)
    } else if k < 1.0 {
        (1.2348, 0.19087)
    } else {
        (1.2348, 0.071739)
    };
    let inner = 1.0 - (1.5859 - b / k.powf(c)) * ec_cu_over_p.max(0.0).powf(0.4);
    if inner <= 0.0 {
        return LIMIT;
    }
    (0.1 * inner.powf(-9.185)).min(LIMIT)
}

/// ISO 76:2006's basic static radial load rating C_0r of a radial roller set, N: 44·(1 − D_we·cos α /
/// D_pw)·i·Z·L_we·D_we·cos α, lengths in mm (the load that gives 4000 MPa at the most loaded contact).
pub fn static_load_rating(r: &Rollers) -> f64 {
    let cos = r.contact_angle_deg.to_radians().cos();
    44.0 * (1.0 - r.diameter_mm * cos / r.pitch_diameter_mm)
        * f64::from(r.rows)
        * f64::from(r.count)
        * r.length_mm
        * r.diameter_mm
        * cos
}

/// ISO 281:2007 Annex B's approximate fatigue load limit C_u of a roller bearing, N: C_0/8.2, and for
/// pitch diameters above 100 mm C_0/8.2·(100/D_pw)^0.3 (the load at which the most loaded contact
/// reaches the 1500 MPa fatigue limit, derated for size).
pub fn fatigue_load_limit(r: &Rollers) -> f64 {
    let c0 = static_load_rating(r) / 8.2;
    if r.pitch_diameter_mm > 100.0 {
        c0 * (100.0 / r.pitch_diameter_mm).powf(0.3)
    } else {
        c0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::rating::bearing_set::tests::cylindrical;
    use crate::physics::hertz::{LineContact, effective_modulus};

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a / b - 1.0).abs() <= rel
    }

    /// The GRC's planet bearing estimate (20 × Ø34 × 60 mm on 225 mm).
    fn planet() -> Rollers {
        cylindrical(20, 34.0, 60.0, 225.0)
    }

    /// The three κ branches meet where they change (a mistyped constant would open a step), and the
    /// factor behaves as the standard's chart: 0.1 without fatigue limit (e_C·C_u/P → 0), rising with κ
    /// and with e_C·C_u/P, capped at 50.
    #[test]
    fn branches_meet_and_the_factor_is_monotone() {
        for x in [0.01, 0.1, 0.3, 1.0] {
            for kappa in [0.4, 1.0] {
                let (below, at) = (life_modification(kappa * (1.0 - 1e-12), x), life_modification(kappa, x));
                assert!(close(below, at, 1e-4), "κ = {kappa}, x = {x}: {below} against {at}");
            }
        }
        assert!(close(life_modification(1.0, 1e-12), 0.1, 1e-3));
        let mut last = 0.0;
        for kappa in [0.1, 0.2, 0.4, 0.7, 1.0, 2.0, 4.0] {
            let a = life_modification(kappa, 0.2);
            assert!(a > last, "a_ISO not rising with κ at {kappa}: {a}");
            last = a;
        }
        assert!(life_modification(4.0, 0.2) == life_modification(10.0, 0.2));
        assert!(life_modification(0.1, 0.2) == life_modification(0.01, 0.2));
        assert!(life_modification(4.0, 5.0) == 50.0);
        assert!(life_modification(0.5, 0.05) < life_modification(0.5, 0.5));
    }

    /// A point read off by hand from the formula: κ = 1, e_C·C_u/P = 0.1 gives
    /// 0.1·(1 − 0.3511·0.1^0.4)^−9.185 = 0.3986.
    #[test]
    fn a_point_by_hand() {
        assert!(close(life_modification(1.0, 0.1), 0.3986, 1e-3));
    }

    /// Walther's line goes through both given viscosities, and gives a VG 320 mineral oil about
    /// 86 mm²/s at 65 °C (by hand from the same equation; oil makers' charts read 80–90).
    #[test]
    fn viscosity_temperature_line() {
        let mut oil = Lubrication::default();
        for (t, nu) in [(40.0, 320.0), (100.0, 24.0)] {
            oil.temperature_c = t;
            assert!(close(oil.operating_viscosity(), nu, 1e-9), "{t} °C");
        }
        oil.temperature_c = 65.0;
        assert!(
            close(oil.operating_viscosity(), 85.9, 5e-3),
            "{}",
            oil.operating_viscosity()
        );
        oil.temperature_c = 80.0;
        assert!(oil.operating_viscosity() < 85.9);
    }

    /// ν₁'s two speed ranges meet within 2.4 % at 1000 r/min, and κ falls as the bearing slows.
    #[test]
    fn reference_viscosity_ranges() {
        let (below, above) = (reference_viscosity(999.999, 150.0), reference_viscosity(1000.0, 150.0));
        assert!(close(below, above, 0.024), "{below} against {above}");
        assert!(reference_viscosity(0.0, 150.0).is_infinite());
        let oil = Lubrication::default().in_service();
        assert!(oil.viscosity_ratio(50.0, 225.0) < oil.viscosity_ratio(500.0, 225.0));
    }

    /// ISO 76's 44 is Hertz's 4000 MPa: the most loaded roller of a set under C_0 (Stribeck's
    /// Q_max = 5·F_r/(i·Z·cos α)) presses its inner race at 4000 MPa within 1.5 % (steel, E = 207 GPa,
    /// ν = 0.3), and C_u = C_0/8.2 stays below the load that reaches 1500 MPa there, C_0·(1500/4000)²,
    /// by ISO's own margin (7.1/8.2).
    #[test]
    fn static_rating_is_hertz_at_4000_mpa() {
        let r = planet();
        let c0 = static_load_rating(&r);
        let q_max = 5.0 * c0 / f64::from(r.count);
        let (d, dm) = (r.diameter_mm * 1e-3, r.pitch_diameter_mm * 1e-3);
        let r_eff = 1.0 / (2.0 / d + 2.0 / (dm - d));
        let e_star = effective_modulus(207e9, 0.3, 207e9, 0.3);
        let p = LineContact::new(q_max / (r.length_mm * 1e-3), r_eff, e_star).max_pressure;
        assert!(close(p, 4000e6, 0.015), "{} MPa", p / 1e6);
        let at_limit = c0 * (1500.0f64 / 4000.0).powi(2);
        let small = Rollers {
            pitch_diameter_mm: 100.0,
            ..r
        };
        let cu = fatigue_load_limit(&small);
        assert!(close(
            cu / (static_load_rating(&small) * (1500.0f64 / 4000.0).powi(2)),
            7.111 / 8.2,
            1e-3
        ));
        assert!(fatigue_load_limit(&r) < at_limit);
    }

    #[test]
    fn conditions_are_checked() {
        assert!(Lubrication::default().check().is_ok());
        for bad in [
            Lubrication {
                viscosity_100: 400.0,
                ..Default::default()
            },
            Lubrication {
                temperature_c: f64::NAN,
                ..Default::default()
            },
            Lubrication {
                contamination: 1.5,
                ..Default::default()
            },
            Lubrication {
                viscosity_40: f64::INFINITY,
                ..Default::default()
            },
        ] {
            assert!(bad.check().is_err(), "{bad:?}");
        }
    }
}
