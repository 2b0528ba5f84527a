//! Generators of drivetrains A–D (thesis Table 4.6) and the typical values the
//! sources leave out. Per unit on the generator's rated power and voltage:
//!
//! | | A | B | C | D |
//! |---|---|---|---|---|
//! | thesis type | PMG | DFIG | DFIG | DFIG |
//! | poles | 10 | 4 | 4 | 4 |
//! | L_m / L_ls / line (pu) | 0.32 / 0.64 / 0.09 | 3.0 / 0.1 / 0.09 | 3.0 / 0.1 / 0.1 | 2.56 / 0.016 / 0.06 |
//!
//! Typical (not in the sources, parameters of the FMU): R_s = R_r = 0.005 pu (MW-class machines:
//! 0.005–0.01), L_lr = 0.1 pu, current
//! loop bandwidth 1000 rad/s, 60 Hz grid. The line inductance is in series with the stator of the
//! grid-connected machines (`fixed`, `dfig`); the PMG's converter decouples it from the machine.
//! The PMG's synchronous inductance is L_m + L_ls. Torque-law defaults: region 2 at the analytic
//! rotor's optimal tip-speed ratio, cut-in at the minimum rotor speed (thesis Table 3.1), region 2½
//! over 10 % slip, region 3 at 99 % of rated speed, torque ≤ 1.1 × rated, speed filter 0.25 Hz
//! (the NREL 5 MW baseline controller's choices, Jonkman's DISCON).

use super::control::{SpeedRegulator, TorqueControl, TorqueLaw};
use super::induction::Induction;
use super::pmg::Pmg;
use super::{Generator, Machine, SpringGenerator};
use crate::physics::aero::{AIR_DENSITY, optimum};
use crate::physics::drivetrain::Drivetrain;
use crate::physics::rotor::preset_rotor;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Kind {
    Spring,
    Fixed,
    Dfig,
    Pmg,
}

impl Kind {
    pub fn parse(s: &str) -> Option<Kind> {
        match s.trim().to_ascii_lowercase().as_str() {
            "spring" => Some(Kind::Spring),
            "fixed" => Some(Kind::Fixed),
            "dfig" => Some(Kind::Dfig),
            "pmg" => Some(Kind::Pmg),
            _ => None,
        }
    }
}

/// Table 4.6 per preset: (poles, L_m, L_ls, line inductance), pu.
fn table_4_6(name: &str) -> (u32, f64, f64, f64) {
    match name {
        "A" => (10, 0.32, 0.64, 0.09),
        "B" => (4, 3.0, 0.1, 0.09),
        // P: the paper's FAST model has no electrical machine (a torque–speed law); C's DFIG values
        "C" | "P" => (4, 3.0, 0.1, 0.1),
        _ => (4, 2.56, 0.016, 0.06),
    }
}

/// Minimum rotor speed (thesis Table 3.1), rad/s.
fn min_rotor_speed(name: &str) -> f64 {
    crate::physics::drivetrain::operating_speed_range_rpm(name).map_or(0.0, |r| r.0) * PI / 30.0
}

/// Everything a user may set; zero (or empty) means "the preset's value".
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Overrides {
    pub stiffness: f64,
    pub damping: f64,
    pub synchronous_speed: f64,
    pub poles: i32,
    pub frequency: f64,
    pub stator_resistance: f64,
    pub rotor_resistance: f64,
    pub stator_leakage: f64,
    pub rotor_leakage: f64,
    pub mutual_inductance: f64,
    pub line_inductance: f64,
    pub current_bandwidth: f64,
    /// "law" or "speed".
    pub torque_control: String,
    pub reference_speed: f64,
    pub region2_gain: f64,
    pub cut_in_speed: f64,
    pub transition_slip: f64,
    pub max_torque: f64,
    pub speed_filter_frequency: f64,
    pub speed_bandwidth: f64,
}

impl Default for Overrides {
    fn default() -> Self {
        Overrides {
            stiffness: 0.0,
            damping: 0.0,
            synchronous_speed: 0.0,
            poles: 0,
            frequency: 60.0,
            stator_resistance: 0.005,
            rotor_resistance: 0.005,
            stator_leakage: 0.0,
            rotor_leakage: 0.1,
            mutual_inductance: 0.0,
            line_inductance: -1.0,
            current_bandwidth: 1000.0,
            torque_control: "law".into(),
            reference_speed: 0.0,
            region2_gain: 0.0,
            cut_in_speed: 0.0,
            transition_slip: 0.1,
            max_torque: 0.0,
            speed_filter_frequency: PI / 2.0,
            speed_bandwidth: 0.6,
        }
    }
}

fn pick(x: f64, default: f64) -> f64 {
    if x > 0.0 { x } else { default }
}

fn positive(name: &str, x: f64) -> Result<f64, String> {
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(format!("parameter {name} = {x}: must be a positive number"))
    }
}

/// Optimal-λ region-2 gain at the generator shaft: k = ½ρπR⁵C_p,max/λ_opt³ / N³.
pub fn optimal_region2_gain(dt: &Drivetrain, name: &str) -> f64 {
    let (radius, _) = preset_rotor(dt, name);
    let (lambda, cp) = optimum(0.0);
    0.5 * AIR_DENSITY * PI * radius.powi(5) * cp / lambda.powi(3) / dt.gear_ratio().powi(3)
}

/// The generator of preset `name` (A–D) of the given kind with the user's overrides.
pub fn build(name: &str, kind: Kind, o: &Overrides) -> Result<Generator, String> {
    let name = name.trim().to_ascii_uppercase();
    let dt = Drivetrain::preset(&name)
        .ok_or_else(|| format!("parameter preset = {name:?}: unknown drivetrain, use A, B, C, D or P"))?;
    let rated_speed = dt.rated_rotor_speed * dt.gear_ratio();
    let (poles, l_m, l_ls, line) = table_4_6(&name);
    let poles = if o.poles > 0 { o.poles as u32 } else { poles };
    if poles % 2 == 1 {
        return Err(format!(
            "parameter poles = {poles}: a machine has an even number of poles"
        ));
    }
    let frequency = positive("frequency", o.frequency)?;
    let r_s = positive("stator_resistance", o.stator_resistance)?;
    let r_r = positive("rotor_resistance", o.rotor_resistance)?;
    let l_lr = positive("rotor_leakage", o.rotor_leakage)?;
    let l_m = pick(o.mutual_inductance, l_m);
    let l_ls = pick(o.stator_leakage, l_ls);
    let line = if o.line_inductance >= 0.0 {
        o.line_inductance
    } else {
        line
    };
    let alpha = positive("current_bandwidth", o.current_bandwidth)?;
    let rated_torque = dt.rated_power / rated_speed;
    let max_torque = pick(o.max_torque, 1.1 * rated_torque);
    let reference = pick(o.reference_speed, rated_speed);
    let control = match o.torque_control.trim() {
        "law" => TorqueControl::Law(TorqueLaw::new(
            dt.rated_power,
            0.99 * reference,
            pick(o.region2_gain, optimal_region2_gain(&dt, &name)),
            pick(o.cut_in_speed, min_rotor_speed(&name) * dt.gear_ratio()),
            positive("transition_slip", o.transition_slip)?,
            max_torque,
        )),
        "speed" => {
            let inertia = dt.j_generator + dt.j_rotor / dt.gear_ratio().powi(2);
            TorqueControl::Speed(SpeedRegulator::new(
                reference,
                inertia,
                positive("speed_bandwidth", o.speed_bandwidth)?,
                max_torque,
            ))
        }
        other => return Err(format!("parameter torque_control = {other:?}: use law or speed")),
    };
    let grid_sync = 2.0 * PI * frequency / (poles / 2) as f64;
    let induction = |bandwidth| Induction {
        omega_base: 2.0 * PI * frequency,
        r_s,
        r_r,
        l_ls: l_ls + line,
        l_lr,
        l_m,
        current_bandwidth: bandwidth,
    };
    let spring_sync = pick(o.synchronous_speed, rated_speed);
    let (machine, base_speed, control) = match kind {
        Kind::Spring => (
            Machine::Spring(SpringGenerator {
                stiffness: pick(o.stiffness, dt.k_generator),
                damping: o.damping,
                synchronous_speed: spring_sync,
            }),
            spring_sync,
            None,
        ),
        // The cage machine runs at the grid's synchronous speed plus its slip: D's 1809 rpm is a
        // 4-pole, 60 Hz machine's 1800 rpm plus its rated slip.
        Kind::Fixed => (
            Machine::Induction(induction(None)),
            pick(o.synchronous_speed, grid_sync),
            None,
        ),
        Kind::Dfig => (Machine::Induction(induction(Some(alpha))), grid_sync, Some(control)),
        Kind::Pmg => (
            Machine::Pmg(Pmg {
                omega_base: (poles / 2) as f64 * rated_speed,
                r_s,
                l: l_m + l_ls,
                psi_m: 1.0,
                current_bandwidth: alpha,
            }),
            rated_speed,
            Some(control),
        ),
    };
    Ok(Generator {
        machine,
        base_speed,
        base_power: dt.rated_power,
        control,
        filter_corner: positive("speed_filter_frequency", o.speed_filter_frequency)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every preset and kind builds, starts in equilibrium at rated speed and delivers rated torque
    /// there (the spring through its initial twist, the controlled kinds through the law's region 3).
    #[test]
    fn presets_start_in_equilibrium_at_rated() {
        for name in ["A", "B", "C", "D"] {
            let dt = Drivetrain::preset(name).unwrap();
            let w = dt.rated_rotor_speed * dt.gear_ratio();
            let rated = dt.rated_power / w;
            for kind in [Kind::Spring, Kind::Dfig, Kind::Pmg] {
                let g = build(name, kind, &Overrides::default()).unwrap();
                let st = g.initial_state(w, rated);
                let d = g.derivative(&st.x, w);
                assert!(d.iter().all(|v| v.abs() < 1e-6), "{name} {kind:?}: {d:?}");
                let t = g.outputs(&st, w).torque;
                assert!((t / rated - 1.0).abs() < 1e-6, "{name} {kind:?}: {t} vs {rated}");
            }
        }
    }

    /// D's cage machine on its 60 Hz grid (1800 rpm synchronous) delivers rated torque near the 1809 rpm
    /// the thesis simulated: its rated slip with the typical R_r = 0.005 pu.
    #[test]
    fn fixed_speed_d_is_rated_near_1809_rpm() {
        let dt = Drivetrain::preset("D").unwrap();
        let g = build("D", Kind::Fixed, &Overrides::default()).unwrap();
        let rated = dt.rated_generator_torque();
        let torque = |rpm: f64| {
            let w = rpm * PI / 30.0;
            g.outputs(&g.initial_state(w, 0.0), w).torque
        };
        let (mut lo, mut hi) = (1800.0, 1900.0);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if torque(mid) < rated { lo = mid } else { hi = mid }
        }
        eprintln!("D fixed: rated torque {rated:.1} N·m at {lo:.2} rpm");
        assert!((lo - 1809.0).abs() < 3.0, "rated torque at {lo} rpm");
    }

    #[test]
    fn bad_overrides_name_the_parameter() {
        let o = Overrides {
            current_bandwidth: -3.0,
            ..Overrides::default()
        };
        assert!(build("C", Kind::Dfig, &o).unwrap_err().contains("current_bandwidth"));
        let o = Overrides {
            poles: 5,
            ..Overrides::default()
        };
        assert!(build("C", Kind::Dfig, &o).unwrap_err().contains("poles"));
        assert!(
            build("E", Kind::Dfig, &Overrides::default())
                .unwrap_err()
                .contains("preset")
        );
    }
}
