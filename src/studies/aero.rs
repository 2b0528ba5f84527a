//! The rotor's blade-element momentum model over tip-speed ratios and pitch angles (`windrive aero`
//! prints it as JSON): C_P, C_Q, C_T, torque and thrust per point, optionally every element's loads,
//! the blade's stations, and the rated point the blade reaches at a rotor's rated power and speed.

use crate::physics::aero::AIR_DENSITY;
use crate::physics::bem::BemRotor;
use crate::physics::rotor::{Aerodynamics, rated_wind_speed};
use serde_json::{Value, json};

/// The points asked for: every pitch angle (deg, finite) at every tip-speed ratio (finite), at the
/// hub-height wind speed `wind` m/s; with `elements` every station's loads too.
pub struct Sweep<'a> {
    pub tsr: &'a [f64],
    pub pitch_deg: &'a [f64],
    pub wind: f64,
    pub elements: bool,
}

/// The rated point of `rotor` (tip radius `radius` m) at `power` W and rotor speed `speed` rad/s: the
/// wind speed whose power at fine pitch is rated, and the tip-speed ratio and C_P there.
pub fn rated_point(rotor: &BemRotor, radius: f64, power: f64, speed: f64) -> Result<Value, String> {
    let v = rated_wind_speed(&Aerodynamics::Bem(rotor.clone()), power, speed)?;
    let tsr = speed * radius / v;
    Ok(json!({
        "power_w": power,
        "rotor_speed_rpm": speed * 30.0 / std::f64::consts::PI,
        "wind_m_s": v,
        "tsr": tsr,
        "cp": rotor.coefficients(tsr, 0.0, v).cp,
        "pitch_deg": 0.0,
    }))
}

/// `rotor` (tip radius `radius` m, its blade `blade` read from `blade_dir`) over `sweep`, with its
/// stations, its options and its `rated` point ([`rated_point`]).
pub fn report(
    blade: &str,
    blade_dir: &str,
    rotor: &BemRotor,
    radius: f64,
    rated: Option<Value>,
    sweep: &Sweep,
) -> anyhow::Result<Value> {
    let wind = sweep.wind;
    let mut points = Vec::new();
    for &pitch_deg in sweep.pitch_deg {
        for &tsr in sweep.tsr {
            let pitch = pitch_deg.to_radians();
            let c = rotor.coefficients(tsr, pitch, wind);
            let omega = tsr * wind / radius;
            let loads = rotor.loads(wind, omega, pitch);
            let mut point = json!({
                "tsr": tsr,
                "pitch_deg": pitch_deg,
                "cp": c.cp,
                "cq": c.cq,
                "ct": c.ct,
                "rotor_speed_rad_s": omega,
                "torque_nm": loads.torque,
                "thrust_n": loads.thrust,
                "converged": loads.elements.iter().all(|e| e.converged),
            });
            if sweep.elements {
                point["elements"] = serde_json::to_value(&loads.elements)?;
            }
            points.push(point);
        }
    }
    let stations: Vec<_> = rotor
        .stations
        .iter()
        .map(|s| {
            json!({
                "radius_m": s.radius,
                "chord_m": s.chord,
                "twist_deg": s.twist.to_degrees(),
                "airfoil": rotor.blade.polars[s.airfoil].name,
            })
        })
        .collect();
    Ok(json!({
        "blade": blade,
        "blade_dir": blade_dir,
        "radius_m": radius,
        "hub_radius_m": rotor.blade.hub_radius,
        "blades": rotor.blade.blades,
        "air_density_kg_m3": AIR_DENSITY,
        "wind_m_s": wind,
        "options": {
            "tip_loss": rotor.options.tip_loss,
            "hub_loss": rotor.options.hub_loss,
            "wake_rotation": rotor.options.wake_rotation,
            "use_cd": rotor.options.use_cd,
        },
        "stations": stations,
        "rated": rated,
        "points": points,
    }))
}
