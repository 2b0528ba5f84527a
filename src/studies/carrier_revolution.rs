//! One carrier revolution of a 6-DOF gearbox at a steady operating point (`windrive gearbox
//! --revolution`): where each planet's upwind bearing load peaks as the carrier turns, and how far
//! it swings. Thesis §7.1.1–7.1.2 (Figs. 7.1–7.3, 7.8) finds that the GRC's upwind planet bearings
//! peak when the planet passes the horizontal to the right of the sun seen from upwind, at rated
//! torque on NREL's dynamometer; this is where we compare (docs/GEARBOX.md). The run starts from the
//! static equilibrium and integrates with Newmark's rule at 1 ms (no numerical damping: the swing is
//! once per revolution, far below every mode the step could damp).

use crate::physics::gearbox::model::SPIN;
use crate::physics::gearbox::statics::equilibrium;
use crate::physics::gearbox::{Description, Gearbox};
use crate::solver::alpha::Alpha;
use crate::solver::{Driver, DynState, Method};
use anyhow::anyhow;
use serde::Serialize;
use std::f64::consts::{PI, TAU};
use std::fmt;

/// The integrator's step, s.
pub const STEP_S: f64 = 1e-3;

/// Each planet's upwind bearing over one carrier revolution (and a little more, so a peak at the
/// start is seen whole).
#[derive(Debug, Clone, Serialize)]
pub struct Revolution {
    pub gearbox: String,
    pub rotor_mass_kg: f64,
    pub rotor_torque_nm: f64,
    pub rotor_speed_rad_s: f64,
    /// Per planet: where its upwind bearing's radial load peaks, degrees from the horizontal to the
    /// right of the sun seen from upwind, counted the way the carrier turns (clockwise seen from
    /// upwind: 90 below the sun, 180 left of it, 270 above it).
    pub peak_deg: Vec<f64>,
    /// Per planet: largest over smallest radial load of its upwind bearing in the revolution.
    pub swing: Vec<f64>,
    /// The radial load of the probed bearing, if one was named, every step.
    #[serde(skip)]
    pub probe: Vec<f64>,
    /// The output body's speed at the end, rad/s.
    #[serde(skip)]
    pub output_speed_rad_s: f64,
}

impl Revolution {
    /// Angular distance of each planet's peak from the right horizontal, 0–180° either way.
    pub fn peak_from_right_deg(&self) -> Vec<f64> {
        self.peak_deg.iter().map(|&a| a.min(360.0 - a)).collect()
    }
}

/// One revolution of `g` (built from `d`) under rotor torque `torque_nm` (the generator reacting it
/// at the gear ratio) at `speed_rad_s`, with the gearbox's own external moments and thrust; the
/// radial load of bearing `probe`, if named, recorded every step.
pub fn revolution(
    d: &Description,
    g: &Gearbox,
    torque_nm: f64,
    speed_rad_s: f64,
    probe: Option<&str>,
) -> anyhow::Result<Revolution> {
    if speed_rad_s.is_nan() || speed_rad_s <= 0.0 {
        return Err(anyhow!(
            "{}: a revolution needs a positive speed, not {speed_rad_s} rad/s",
            g.name
        ));
    }
    let bearing = |name: &str| {
        g.bearings
            .iter()
            .position(|b| b.name == name)
            .ok_or_else(|| anyhow!("{}: no bearing {name}", g.name))
    };
    let planets = (1..)
        .map(|p| format!("planet_{p}_uw"))
        .take_while(|n| g.bearings.iter().any(|b| &b.name == n))
        .map(|n| bearing(&n))
        .collect::<anyhow::Result<Vec<_>>>()?;
    if planets.is_empty() {
        return Err(anyhow!("{}: no upwind planet bearings (planet_1_uw, ...)", g.name));
    }
    let probe = probe.map(bearing).transpose()?;
    let carrier = g
        .body("carrier_1")
        .and_then(|b| g.bodies[b].first)
        .ok_or_else(|| anyhow!("{}: no first carrier (carrier_1)", g.name))?;
    let u = [torque_nm, torque_nm / g.gear_ratio, 0.0];
    let (q, v) = equilibrium(g, &u, speed_rad_s).map_err(|e| anyhow!("{}: static equilibrium: {e}", g.name))?;
    let mut st = DynState::new(q, v);
    let mut driver = Driver::new(Method::Implicit(Alpha::NEWMARK));
    let steps = (1.05 * TAU / speed_rad_s / STEP_S) as usize;
    let (mut angle, mut loads, mut probe_load) = (Vec::new(), vec![Vec::new(); planets.len()], Vec::new());
    for k in 0..steps {
        driver
            .advance(g, &mut st, k as f64 * STEP_S, STEP_S, 5e-4, 3, |_, out| {
                out.copy_from_slice(&u)
            })
            .map_err(|e| anyhow!("{}: step {k}: {e}", g.name))?;
        let l = g.loads(&st.q, &st.v);
        angle.push(st.q[carrier + SPIN]);
        for (s, &b) in loads.iter_mut().zip(&planets) {
            s.push(l.bearings[b].radial);
        }
        if let Some(b) = probe {
            probe_load.push(l.bearings[b].radial);
        }
    }
    let n = planets.len() as f64;
    let (mut peak_deg, mut swing) = (Vec::new(), Vec::new());
    for (p, s) in loads.iter().enumerate() {
        let k = (0..s.len()).max_by(|&a, &b| s[a].total_cmp(&s[b])).unwrap_or(0);
        swing.push(s[k] / s.iter().cloned().fold(f64::MAX, f64::min));
        // the planet's place in the housing: its start (evenly spaced, clockwise seen from
        // downwind from the top) turned by the carrier's angle; the right of the sun seen from
        // upwind is −x, and the carrier's positive turn is clockwise seen from upwind
        let start = TAU * p as f64 / n;
        let (x, y) = (start.sin(), start.cos());
        let (s_, c_) = angle[k].sin_cos();
        let at = (x * s_ + y * c_).atan2(x * c_ - y * s_);
        peak_deg.push((at - PI).rem_euclid(TAU).to_degrees());
    }
    Ok(Revolution {
        gearbox: d.name.clone(),
        rotor_mass_kg: d.rotor.as_ref().and_then(|r| r.mass).unwrap_or(0.0),
        rotor_torque_nm: torque_nm,
        rotor_speed_rad_s: speed_rad_s,
        peak_deg,
        swing,
        probe: probe_load,
        output_speed_rad_s: g.speed(g.output_body, &st.v),
    })
}

/// The table `windrive gearbox --revolution` prints.
impl fmt::Display for Revolution {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        writeln!(
            f,
            "{} (rotor mass {} kg): one carrier revolution at {:.1} kN·m rotor torque, {:.3} rad/s (Newmark, {} ms)",
            self.gearbox,
            self.rotor_mass_kg,
            self.rotor_torque_nm / 1e3,
            self.rotor_speed_rad_s,
            STEP_S * 1e3
        )?;
        writeln!(
            f,
            "upwind planet bearing's peak: degrees from the horizontal right of the sun seen from upwind,\n\
             counted the way the carrier turns (clockwise seen from upwind: 90 below the sun, 180 left, 270 above)"
        )?;
        writeln!(
            f,
            "{:<8} {:>8} {:>16} {:>9}",
            "planet", "peak °", "from right, ±°", "max/min"
        )?;
        for (p, ((a, d), s)) in self
            .peak_deg
            .iter()
            .zip(self.peak_from_right_deg())
            .zip(&self.swing)
            .enumerate()
        {
            writeln!(f, "{:<8} {:>8.1} {:>16.1} {:>9.3}", p + 1, a, d, s)?;
        }
        Ok(())
    }
}
