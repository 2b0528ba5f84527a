//! A 6-DOF gearbox at a steady operating point (`windrive gearbox` prints it): static equilibrium
//! under rotor torque, gravity, the rotor's moments and thrust, the chain turning at its speed; every
//! bearing's loads, rollers in contact and race stresses, every mesh's slice loads and contact stress,
//! and each roller set's stiffness there beside the linear value of its description. And the fit of a
//! planetary stage's carrier-web stiffness to a measured load split between its planets' bearings.

use crate::physics::gearbox::description::Stage;
use crate::physics::gearbox::statics::equilibrium;
use crate::physics::gearbox::{Description, Gearbox};
use anyhow::anyhow;
use serde::Serialize;
use std::fmt;

/// The operating point, as ratios of the description's rated values and the rotor's loads.
#[derive(Debug, Clone, Copy)]
pub struct OperatingPoint {
    /// Rotor torque over the description's rated rotor torque.
    pub torque_ratio: f64,
    /// Rotor speed over the rated speed (the frames' centripetal and gyroscopic loads).
    pub speed_ratio: f64,
    /// The rotor's pitching (tilt) and yawing moments on the main shaft, N·m.
    pub tilt_moment_nm: f64,
    pub yaw_moment_nm: f64,
    /// Rotor thrust, N (positive downwind).
    pub thrust_n: f64,
}

#[derive(Serialize)]
pub struct BearingRow {
    pub name: String,
    pub model: &'static str,
    pub radial_n: f64,
    pub axial_n: f64,
    pub tilting_nm: f64,
    pub rollers_in_contact: usize,
    pub max_roller_load_n: f64,
    pub inner_race_pressure_pa: f64,
    pub outer_race_pressure_pa: f64,
    pub max_subsurface_shear_pa: f64,
    pub max_shear_depth_m: f64,
    /// The roller set's radial stiffness along the load (N/m), and the description's linear one.
    pub radial_stiffness_n_per_m: Option<f64>,
    pub linear_radial_stiffness_n_per_m: f64,
}

#[derive(Serialize)]
pub struct MeshRow {
    pub name: String,
    pub force_n: f64,
    pub max_slice_load_n: f64,
    pub face_load_factor: f64,
    pub contact_pressure_pa: f64,
    pub max_subsurface_shear_pa: f64,
    pub max_shear_depth_m: f64,
}

#[derive(Serialize)]
pub struct Report {
    pub gearbox: String,
    pub rotor_torque_nm: f64,
    pub rotor_speed_rad_s: f64,
    pub bearings: Vec<BearingRow>,
    pub meshes: Vec<MeshRow>,
    pub load_sharing_factor: Option<f64>,
}

/// The tables `windrive gearbox` prints: the operating point, then a row per bearing and per mesh.
impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        writeln!(
            f,
            "{}: static equilibrium at {:.0} kN·m rotor torque, {:.3} rad/s{}",
            self.gearbox,
            self.rotor_torque_nm / 1e3,
            self.rotor_speed_rad_s,
            self.load_sharing_factor
                .map_or(String::new(), |k| format!(", K_γ = {k:.3}"))
        )?;
        writeln!(
            f,
            "\n{:<14} {:>7} {:>10} {:>9} {:>10} {:>7} {:>9} {:>8} {:>8} {:>8} {:>7} {:>11} {:>11}",
            "bearing",
            "model",
            "radial kN",
            "axial kN",
            "tilt kN·m",
            "rollers",
            "Q_max kN",
            "p_i MPa",
            "p_o MPa",
            "τ MPa",
            "z mm",
            "k_r GN/m",
            "linear GN/m"
        )?;
        for b in &self.bearings {
            writeln!(
                f,
                "{:<14} {:>7} {:>10.1} {:>9.1} {:>10.2} {:>7} {:>9.2} {:>8.0} {:>8.0} {:>8.0} {:>7.3} {:>11} {:>11.2}",
                b.name,
                b.model,
                b.radial_n / 1e3,
                b.axial_n / 1e3,
                b.tilting_nm / 1e3,
                b.rollers_in_contact,
                b.max_roller_load_n / 1e3,
                b.inner_race_pressure_pa / 1e6,
                b.outer_race_pressure_pa / 1e6,
                b.max_subsurface_shear_pa / 1e6,
                b.max_shear_depth_m * 1e3,
                b.radial_stiffness_n_per_m
                    .map_or("-".into(), |k| format!("{:.2}", k / 1e9)),
                b.linear_radial_stiffness_n_per_m / 1e9
            )?;
        }
        writeln!(
            f,
            "\n{:<18} {:>10} {:>14} {:>7} {:>9} {:>8} {:>7}",
            "mesh", "force kN", "max slice kN", "K_Hβ", "p_H MPa", "τ MPa", "z mm"
        )?;
        for m in &self.meshes {
            writeln!(
                f,
                "{:<18} {:>10.1} {:>14.2} {:>7.3} {:>9.0} {:>8.0} {:>7.3}",
                m.name,
                m.force_n / 1e3,
                m.max_slice_load_n / 1e3,
                m.face_load_factor,
                m.contact_pressure_pa / 1e6,
                m.max_subsurface_shear_pa / 1e6,
                m.max_shear_depth_m * 1e3
            )?;
        }
        Ok(())
    }
}

/// The gearbox `d` (named `name` in messages) in static equilibrium at `point`, every bearing's and
/// mesh's loads and stresses there.
pub fn report(name: &str, d: &Description, point: &OperatingPoint) -> anyhow::Result<Report> {
    let mut g = Gearbox::new(d).map_err(|e| anyhow!("{name}: {e}"))?;
    g.external_moment = [point.tilt_moment_nm, point.yaw_moment_nm];
    g.thrust = point.thrust_n;
    let rated = g
        .rated_rotor_torque
        .ok_or_else(|| anyhow!("{name}: the description gives no rated power and speed"))?;
    let torque = point.torque_ratio * rated;
    let speed = point.speed_ratio * d.rated_rotor_speed_rpm.unwrap_or(0.0) * std::f64::consts::TAU / 60.0;
    let (q, v) = equilibrium(&g, &[torque, torque / g.gear_ratio, 0.0], speed)
        .map_err(|e| anyhow!("{name}: static equilibrium at {torque:.0} N·m: {e}"))?;
    let loads = g.loads(&q, &v);
    let bearings = g
        .bearings
        .iter()
        .zip(&loads.bearings)
        .map(|(b, l)| {
            let stiffness = b.rollers.map(|i| g.rollers[i].radial_stiffness(&q, &v));
            BearingRow {
                name: b.name.clone(),
                model: if b.rollers.is_some() { "lamina" } else { "linear" },
                radial_n: l.radial,
                axial_n: l.axial,
                tilting_nm: l.tilting,
                rollers_in_contact: l.rollers_in_contact,
                max_roller_load_n: l.max_roller_load,
                inner_race_pressure_pa: l.stresses.inner_pressure,
                outer_race_pressure_pa: l.stresses.outer_pressure,
                max_subsurface_shear_pa: l.stresses.max_shear,
                max_shear_depth_m: l.stresses.max_shear_depth,
                radial_stiffness_n_per_m: stiffness,
                linear_radial_stiffness_n_per_m: g.springs[b.springs[0]].stiffness,
            }
        })
        .collect();
    let meshes = g
        .meshes
        .iter()
        .zip(&loads.meshes)
        .map(|(m, r)| MeshRow {
            name: m.name.clone(),
            force_n: r.force,
            max_slice_load_n: r.max_slice,
            face_load_factor: r.face_load_factor,
            contact_pressure_pa: r.contact.pressure,
            max_subsurface_shear_pa: r.contact.max_shear,
            max_shear_depth_m: r.contact.max_shear_depth,
        })
        .collect();
    Ok(Report {
        gearbox: d.name.clone(),
        rotor_torque_nm: torque,
        rotor_speed_rad_s: speed,
        bearings,
        meshes,
        load_sharing_factor: g.load_sharing(&loads, ""),
    })
}

/// Mean radial load of the first stage's planets' upwind bearings over their downwind ones'.
pub fn upwind_over_downwind(r: &Report) -> Option<f64> {
    let mean = |end: &str| {
        let loads: Vec<f64> = r
            .bearings
            .iter()
            .filter(|b| b.name.starts_with("planet_") && b.name.ends_with(end))
            .map(|b| b.radial_n)
            .collect();
        (!loads.is_empty()).then(|| loads.iter().sum::<f64>() / loads.len() as f64)
    };
    Some(mean("_uw")? / mean("_dw")?)
}

/// The first planetary stage's carrier-web torsional stiffness, N·m/rad, at which its planets'
/// upwind bearings carry `target` times the downwind ones' mean radial load at `point`, and the ratio
/// reached there: bisection on log k (a stiffer carrier shares the load more evenly).
pub fn fit_carrier_webs(
    name: &str,
    base: &Description,
    point: &OperatingPoint,
    target: f64,
) -> anyhow::Result<(f64, f64)> {
    let ratio_at = |k: f64| -> anyhow::Result<f64> {
        let mut d = base.clone();
        let Some(Stage::Planetary(p)) = d.stages.first_mut() else {
            return Err(anyhow!("{name}: the first stage is not planetary"));
        };
        let webs = p
            .carrier_webs
            .as_mut()
            .ok_or_else(|| anyhow!("{name}: the first planetary stage has no [stage.planetary.carrier_webs] to fit"))?;
        webs.torsional = k;
        let r = report(name, &d, point)?;
        upwind_over_downwind(&r).ok_or_else(|| anyhow!("{name}: no planet bearings named *_uw and *_dw"))
    };
    let (mut lo, mut hi) = (1e6f64.ln(), 1e12f64.ln());
    let (r_soft, r_stiff) = (ratio_at(lo.exp())?, ratio_at(hi.exp())?);
    if !(r_stiff..=r_soft).contains(&target) {
        return Err(anyhow!(
            "upwind/downwind {target} is outside what the webs can give here ({r_stiff:.3} rigid to {r_soft:.3} at 1e6 N·m/rad)"
        ));
    }
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if ratio_at(mid.exp())? > target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let k = (0.5 * (lo + hi)).exp();
    Ok((k, ratio_at(k)?))
}
