//! The dynamic factor K_v of every mesh of a 6-DOF gearbox at a steady operating point (`windrive
//! gearbox --dynamic-factor`), from the model and from ISO 6336-1:2006 method B (§6.3), side by side.
//!
//! The model's K_v is what the standard means by it: the largest tooth load with the internal
//! dynamics of the mesh over the largest without them. The gearbox runs twice at constant rotor and
//! generator torque from the same static equilibrium: once with each slice's stiffness switching
//! between one and two tooth pairs as its contact line rolls (`mesh_stiffness = "varying"`), once at
//! the mean stiffness. Each mesh's K_v is its largest force over the measured window of the first run
//! over that of the second, so the carrier's slow swing (gravity, the rotor's weight) divides out.
//! The teeth are perfect and unrelieved in both, so method B's counterpart is the same gear:
//! B_p = B_f = 0 (no pitch or profile deviation) and B_k = 1 (no tip relief), with the model's mean
//! mesh stiffness (the description's, or ISO's c_γα·b) and ISO's reduced mass from the model's wheels
//! (the sun's shared by its planets, a housing ring infinitely heavy).
//!
//! Integration: Newmark's rule (no numerical damping, which would take the mesh response the
//! factor measures) at a step of a fortieth of the stiffest mesh's natural period or a hundredth of
//! its fastest mesh period, whichever is shorter. The start transient (the first switch of every
//! slice from equilibrium) decays over [`Timing::settle_s`] at the meshes' damping before the window.

use crate::physics::gearbox::statics::equilibrium;
use crate::physics::gearbox::{Description, Gearbox, description::MeshStiffnessModel};
use crate::solver::alpha::Alpha;
use crate::solver::{Driver, DynState, Method};
use anyhow::anyhow;
use serde::Serialize;
use std::f64::consts::TAU;
use std::fmt;

/// The runs' timing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Timing {
    /// The integration step, s; None: a fortieth of the stiffest pair's natural period or a
    /// hundredth of the fastest mesh period, whichever is shorter.
    pub step_s: Option<f64>,
    /// Time left to the start transient before the window, s.
    pub settle_s: f64,
    /// Shortest measured window, s; longer when the slowest mesh needs it for `mesh_periods` periods.
    pub window_s: f64,
    pub mesh_periods: f64,
}

impl Default for Timing {
    /// 0.2 s to settle (the damped start transient is gone in a few hundredths), then at least 0.3 s
    /// and eight periods of the slowest mesh.
    fn default() -> Self {
        Timing {
            step_s: None,
            settle_s: 0.2,
            window_s: 0.3,
            mesh_periods: 8.0,
        }
    }
}

/// One mesh's dynamic factor.
#[derive(Debug, Clone, Serialize)]
pub struct MeshDynamics {
    pub mesh: String,
    /// Tooth-mesh frequency z·n (relative to the carrier in a planetary stage), Hz.
    pub mesh_frequency_hz: f64,
    /// The pair's own natural frequency √(c_γα·b / m_red)/2π (ISO 6336-1 Eq. 9's n_E1 · z₁/60), Hz.
    pub natural_frequency_hz: f64,
    /// Resonance ratio N = mesh frequency / natural frequency.
    pub resonance_ratio: f64,
    /// Total contact ratio ε_γ = ε_α + ε_β.
    pub total_contact_ratio: f64,
    /// Spur teeth (β = 0): every slice changes its pair count at once, a rectangular stiffness wave
    /// whose instant doubling doubles the force at any speed. The model's K_v is then the
    /// idealisation's, not the gear's; ISO's is the one to use.
    pub spur: bool,
    /// The largest normal mesh force in the window at mean stiffness, N.
    pub quasi_static_n: f64,
    /// The same with the tooth pairs' stiffness varying, N.
    pub dynamic_n: f64,
    /// dynamic_n / quasi_static_n.
    pub k_v_model: f64,
    /// ISO 6336-1 method B for the same perfect, unrelieved pair.
    pub k_v_iso: f64,
}

/// Every mesh's dynamic factor at one operating point.
#[derive(Debug, Clone, Serialize)]
pub struct DynamicFactors {
    pub gearbox: String,
    pub rotor_torque_nm: f64,
    pub rotor_speed_rad_s: f64,
    pub step_s: f64,
    pub settle_s: f64,
    pub window_s: f64,
    pub meshes: Vec<MeshDynamics>,
}

/// ISO 6336-1:2006 method B (§6.3.2) for a pair without pitch or profile deviations and without tip
/// relief (B_p = B_f = 0, B_k = 1) at resonance ratio `n`, total contact ratio `eps_gamma` and line
/// load F_t·K_A/b `line_load` (N/mm, which sets the lower end of the main resonance range).
pub fn iso_method_b_perfect(n: f64, eps_gamma: f64, line_load: f64) -> f64 {
    let n_s = if line_load < 100.0 {
        0.5 + 0.35 * (line_load / 100.0).sqrt()
    } else {
        0.85
    };
    // C_v3, C_v4 (ISO 6336-1 Table 8) for the B_k term; C_v7 for the supercritical range
    let (c_v3, c_v4) = if eps_gamma <= 2.0 {
        (0.23, 0.90)
    } else {
        (
            0.096 / (eps_gamma - 1.56),
            (0.57 - 0.05 * eps_gamma) / (eps_gamma - 1.44),
        )
    };
    let c_v7 = if eps_gamma <= 1.5 {
        0.75
    } else if eps_gamma <= 2.5 {
        0.125 * (std::f64::consts::PI * (eps_gamma - 2.0)).sin() + 0.875
    } else {
        1.0
    };
    let main = 1.0 + c_v4;
    if n <= n_s {
        1.0 + n * c_v3
    } else if n <= 1.15 {
        main
    } else if n < 1.5 {
        // linear between the main resonance range's end and the supercritical range's start
        c_v7 + (main - c_v7) * (1.5 - n) / 0.35
    } else {
        c_v7
    }
}

/// How many meshes share `name`'s stage and kind (`sun_planet2_3` → the `sun_planet2_*` meshes): a
/// planetary stage's planets.
fn siblings(g: &Gearbox, name: &str) -> usize {
    let stem = |n: &str| n.rsplit_once('_').map_or(n.to_string(), |(s, _)| s.to_string());
    g.meshes.iter().filter(|m| stem(&m.name) == stem(name)).count()
}

/// ISO's reduced mass of a mesh along its line of action, kg: the two wheels in series, a sun's
/// shared by the planets it drives (ISO 6336-1 §6.3.2 for planetary stages).
fn reduced_mass(g: &Gearbox, mesh: usize) -> f64 {
    let m = &g.meshes[mesh];
    let [driver, driven] = m.line_masses;
    let share = if m.name.starts_with("sun_planet") {
        siblings(g, &m.name) as f64
    } else {
        1.0
    };
    1.0 / (1.0 / driver + share / driven)
}

/// Run `g` at constant inputs `u` from its static equilibrium at `speed` and return each mesh's
/// largest force magnitude in [settle, settle + window].
fn largest_forces(
    g: &Gearbox,
    u: &[f64; 3],
    speed: f64,
    step: f64,
    settle: f64,
    window: f64,
) -> anyhow::Result<Vec<f64>> {
    let (q, v) = equilibrium(g, u, speed).map_err(|e| anyhow!("{}: static equilibrium: {e}", g.name))?;
    let mut st = DynState::new(q, v);
    let mut driver = Driver::new(Method::Implicit(Alpha::NEWMARK));
    let mut slices = vec![0.0; g.slice_count()];
    let mut largest = vec![0.0f64; g.meshes.len()];
    let (start, steps) = (
        (settle / step).round() as usize,
        ((settle + window) / step).round() as usize,
    );
    for k in 0..steps {
        driver
            .advance(g, &mut st, k as f64 * step, step, step, 3, |_, out| {
                out.copy_from_slice(u)
            })
            .map_err(|e| anyhow!("{}: step {k} (t = {:.6} s): {e}", g.name, k as f64 * step))?;
        if k + 1 >= start {
            for (l, f) in largest.iter_mut().zip(g.mesh_loads(&st.q, &st.v, &mut slices)) {
                *l = l.max((f[0].force - f[1].force).abs());
            }
        }
    }
    Ok(largest)
}

/// The dynamic factor of every mesh of `d` at rotor torque `torque_nm` (the generator reacting it
/// at the gear ratio) and rotor speed `speed_rad_s`.
pub fn dynamic_factors(
    d: &Description,
    torque_nm: f64,
    speed_rad_s: f64,
    timing: &Timing,
) -> anyhow::Result<DynamicFactors> {
    if !(speed_rad_s > 0.0 && speed_rad_s.is_finite()) {
        return Err(anyhow!(
            "{}: the dynamic factor needs a positive speed, not {speed_rad_s} rad/s",
            d.name
        ));
    }
    let with = |model| -> anyhow::Result<Gearbox> {
        let mut d = d.clone();
        d.model.mesh_stiffness = model;
        Gearbox::new(&d).map_err(|e| anyhow!("{}: {e}", d.name))
    };
    let (varying, mean) = (with(MeshStiffnessModel::Varying)?, with(MeshStiffnessModel::Mean)?);
    if varying.meshes.is_empty() {
        return Err(anyhow!("{}: no meshes", d.name));
    }
    let u = [torque_nm, torque_nm / varying.gear_ratio, 0.0];
    // mesh frequencies at the rigid rotation that carries the rotor speed
    let rigid: Vec<f64> = varying
        .rigid
        .as_ref()
        .ok_or_else(|| anyhow!("{}: no rigid-body rotation to turn the gearbox at speed", d.name))?
        .iter()
        .map(|x| x * speed_rad_s)
        .collect();
    let mut rows = Vec::new();
    for (i, m) in varying.meshes.iter().enumerate() {
        let f_z = m
            .mesh_frequency(&rigid)
            .ok_or_else(|| anyhow!("{}: mesh {} has no roll phase", d.name, m.name))?;
        let k = m.k_slice * m.slices() as f64;
        let f_e = (k / reduced_mass(&varying, i)).sqrt() / TAU;
        let g = &varying.geometry[i];
        // transverse tangential force per normal force, for the line load
        let tangential = g.base_helix.cos() * g.pressure_angle.cos();
        rows.push((
            f_z,
            f_e,
            g.contact_ratio + g.overlap_ratio,
            tangential,
            g.base_helix == 0.0,
        ));
    }
    let fastest_mesh = rows.iter().map(|r| r.0).fold(0.0, f64::max);
    let stiffest = rows.iter().map(|r| r.1).fold(0.0, f64::max);
    let step = timing
        .step_s
        .unwrap_or((1.0 / (40.0 * stiffest)).min(1.0 / (100.0 * fastest_mesh)));
    if !(step > 0.0 && step.is_finite()) || fastest_mesh <= 0.0 || step > 0.25 / fastest_mesh {
        return Err(anyhow!(
            "{}: step {step} s: it must be positive and resolve the fastest mesh frequency, {fastest_mesh:.1} Hz \
             (at most {:.3e} s)",
            d.name,
            0.25 / fastest_mesh
        ));
    }
    let slowest = rows.iter().map(|r| r.0).fold(f64::INFINITY, f64::min);
    let window = timing.window_s.max(timing.mesh_periods / slowest);
    if !(timing.settle_s >= 0.0 && window > 0.0 && window.is_finite()) {
        return Err(anyhow!(
            "{}: settle {} s and window {window} s: both must be positive",
            d.name,
            timing.settle_s
        ));
    }
    let dynamic = largest_forces(&varying, &u, speed_rad_s, step, timing.settle_s, window)?;
    let quasi_static = largest_forces(&mean, &u, speed_rad_s, step, timing.settle_s, window)?;
    let meshes = varying
        .meshes
        .iter()
        .zip(rows)
        .zip(dynamic.iter().zip(&quasi_static))
        .map(|((m, (f_z, f_e, eps_gamma, tangential, spur)), (&dyn_, &stat))| {
            let n = f_z / f_e;
            // line load F_t/b in N/mm (K_A = 1: the load is the one applied)
            let line_load = stat * tangential / (m.face_width * 1e3);
            MeshDynamics {
                mesh: m.name.clone(),
                mesh_frequency_hz: f_z,
                natural_frequency_hz: f_e,
                resonance_ratio: n,
                total_contact_ratio: eps_gamma,
                spur,
                quasi_static_n: stat,
                dynamic_n: dyn_,
                k_v_model: dyn_ / stat,
                k_v_iso: iso_method_b_perfect(n, eps_gamma, line_load),
            }
        })
        .collect();
    Ok(DynamicFactors {
        gearbox: d.name.clone(),
        rotor_torque_nm: torque_nm,
        rotor_speed_rad_s: speed_rad_s,
        step_s: step,
        settle_s: timing.settle_s,
        window_s: window,
        meshes,
    })
}

/// The table `windrive gearbox --dynamic-factor` prints.
impl fmt::Display for DynamicFactors {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        writeln!(
            f,
            "{}: dynamic factor K_v at {:.1} kN·m rotor torque, {:.3} rad/s (Newmark, {:.1} µs, window {:.2} s after {:.2} s)",
            self.gearbox,
            self.rotor_torque_nm / 1e3,
            self.rotor_speed_rad_s,
            self.step_s * 1e6,
            self.window_s,
            self.settle_s
        )?;
        writeln!(
            f,
            "model: largest mesh force with the tooth pairs' stiffness varying over the largest at mean stiffness;\n\
             ISO 6336-1 method B for the same perfect, unrelieved teeth (B_p = B_f = 0, B_k = 1)"
        )?;
        writeln!(
            f,
            "{:<16} {:>10} {:>11} {:>7} {:>7} {:>11} {:>11} {:>9} {:>9}",
            "mesh", "f_mesh Hz", "f_pair Hz", "N", "eps_g", "F mean kN", "F vary kN", "K_v model", "K_v ISO"
        )?;
        for m in &self.meshes {
            writeln!(
                f,
                "{:<16} {:>10.1} {:>11.1} {:>7.3} {:>7.3} {:>11.2} {:>11.2} {:>9.4}{} {:>8.4}",
                m.mesh,
                m.mesh_frequency_hz,
                m.natural_frequency_hz,
                m.resonance_ratio,
                m.total_contact_ratio,
                m.quasi_static_n / 1e3,
                m.dynamic_n / 1e3,
                m.k_v_model,
                if m.spur { "*" } else { " " },
                m.k_v_iso
            )?;
        }
        if self.meshes.iter().any(|m| m.spur) {
            writeln!(
                f,
                "* spur teeth: every slice changes its pair count at once, and the instant stiffness step\n  \
                 raises the force by the pair-count ratio at any speed: the rectangular idealisation's K_v,\n  \
                 not the gear's (ISO's is the one to use)"
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::iso_method_b_perfect;

    /// ISO 6336-1:2006 §6.3.2 by hand for B_p = B_f = 0, B_k = 1: K_v = 1 + N·C_v3 below N_S (C_v3 0.23
    /// up to ε_γ = 2, 0.096/(ε_γ − 1.56) above), 1 + C_v4 in the main resonance range, C_v7 beyond 1.5,
    /// a straight line between 1.15 and 1.5; N_S = 0.5 + 0.35·√(F_t K_A/b / 100) below 100 N/mm.
    #[test]
    fn method_b_for_perfect_unrelieved_teeth_is_the_standards() {
        let close = |a: f64, b: f64| assert!((a - b).abs() < 1e-12, "{a} vs {b}");
        close(iso_method_b_perfect(0.5, 1.5, 400.0), 1.115);
        close(iso_method_b_perfect(0.2, 3.0, 400.0), 1.0 + 0.2 * 0.096 / 1.44);
        close(iso_method_b_perfect(0.0, 2.5, 400.0), 1.0);
        close(iso_method_b_perfect(1.0, 1.5, 400.0), 1.9);
        close(iso_method_b_perfect(1.0, 3.0, 400.0), 1.0 + (0.57 - 0.15) / 1.56);
        close(iso_method_b_perfect(2.0, 1.5, 400.0), 0.75);
        close(
            iso_method_b_perfect(2.0, 2.25, 400.0),
            0.125 * (std::f64::consts::PI * 0.25).sin() + 0.875,
        );
        close(iso_method_b_perfect(2.0, 3.0, 400.0), 1.0);
        // halfway between 1.15 and 1.5: the mean of 1 + C_v4 and C_v7
        close(iso_method_b_perfect(1.325, 1.5, 400.0), 0.5 * (1.9 + 0.75));
        // at 25 N/mm the main resonance starts at N_S = 0.675: N = 0.7 is in it, 0.6 below it
        close(iso_method_b_perfect(0.7, 1.5, 25.0), 1.9);
        close(iso_method_b_perfect(0.6, 1.5, 25.0), 1.0 + 0.6 * 0.23);
        close(iso_method_b_perfect(0.7, 1.5, 400.0), 1.0 + 0.7 * 0.23);
    }
}
