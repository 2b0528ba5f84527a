//! Where the torsional model's integrators are stable as the internal step crosses RK4's limit
//! (2.785/ω_max) and the mesh stiffness moves ω_max (`windrive chart integrators` prints and draws
//! it). Runs: the full model of a preset, undamped, turning at rated speed in its loaded equilibrium,
//! then a balanced 10 % torque step (every shaft and mesh mode rings, nothing accelerates), 4000
//! internal steps; unstable when the step fails, the state stops being finite or the energy above the
//! rigid rotation's peaks over the last quarter at more than twice the first quarter's. Theory: RK4's
//! limit line.

use crate::physics::drivetrain::{Drivetrain, Stage};
use crate::physics::torsional::{Fidelity, INPUT_COUNT, ModelOptions, TorsionalModel};
use crate::solver::rk4::STABILITY_BOUND;
use crate::solver::{Driver, DynState, Method, SecondOrderSystem};
use anyhow::anyhow;

/// Mesh-stiffness factors and internal steps (as fractions of RK4's limit at factor 1) of the grid.
pub const SCALES: [f64; 5] = [0.25, 0.5, 1.0, 2.0, 4.0];
pub const STEP_FRACTIONS: [f64; 9] = [0.25, 0.4, 0.6, 0.8, 0.95, 1.05, 1.5, 2.5, 4.0];
pub const STEPS: usize = 4000;

/// The preset with every gear mesh's stiffness times `scale`.
fn with_mesh_stiffness(preset: &str, scale: f64) -> anyhow::Result<Drivetrain> {
    let mut dt = Drivetrain::preset(preset).ok_or_else(|| anyhow!("unknown preset {preset:?}: use A, B, C, D or P"))?;
    for stage in &mut dt.stages {
        match stage {
            Stage::Planetary(p) => {
                p.k_ring_planet *= scale;
                p.k_sun_planet *= scale;
            }
            Stage::Parallel(p) => p.k_mesh *= scale,
        }
    }
    Ok(dt)
}

/// The preset's full model, undamped, with its mesh stiffness times `scale`.
pub fn model(preset: &str, scale: f64) -> anyhow::Result<(Drivetrain, TorsionalModel)> {
    let dt = with_mesh_stiffness(preset, scale)?;
    let options = ModelOptions {
        damping_scale: 0.0,
        ..ModelOptions::default()
    };
    let m = TorsionalModel::new(&dt, Fidelity::Full, &options).map_err(|e| anyhow!(e))?;
    Ok((dt, m))
}

/// Whether `method` at internal step `h` keeps the ringing bounded.
fn stays_bounded(dt: &Drivetrain, m: &TorsionalModel, method: Method, h: f64) -> bool {
    // turning at rated speed in the loaded equilibrium, then a 10 % torque step: every mode rings, the
    // stored energy stays within a few percent of the static one unless the integration grows
    let torque = dt.rated_rotor_torque();
    let Ok(q) = m.static_deflection(torque) else {
        return false;
    };
    let ratios = m
        .rigid_mode()
        .map(|(r, _)| r.to_vec())
        .unwrap_or_else(|| vec![1.0; m.dofs()]);
    let v = ratios.iter().map(|r| r * dt.rated_rotor_speed).collect();
    let mut st = DynState::new(q, v);
    let mut driver = Driver::new(method);
    let inputs = |_: f64, u: &mut [f64]| {
        u[0] = 1.1 * torque;
        u[1] = 1.1 * torque / dt.gear_ratio();
        u[2] = 0.0;
    };
    let rigid_energy = m.stored_energy(&vec![0.0; st.q.len()], &st.v, (0.0, 0.0));
    let mut energy = Vec::with_capacity(STEPS);
    for k in 0..STEPS {
        if driver
            .advance(m, &mut st, k as f64 * h, h, h, INPUT_COUNT, inputs)
            .is_err()
        {
            return false;
        }
        // elastic energy only: the rigid rotation's kinetic energy is constant and would hide growth
        energy.push(m.stored_energy(&st.q, &st.v, (0.0, 0.0)) - rigid_energy);
    }
    let peak = |r: std::ops::Range<usize>| energy[r].iter().cloned().fold(0.0, f64::max);
    peak(3 * STEPS / 4..STEPS) <= 2.0 * peak(0..STEPS / 4)
}

/// The runs at one mesh-stiffness factor.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub scale: f64,
    /// Top angular frequency of the model, rad/s, and RK4's limit 2.785/ω_max, s.
    pub omega_max: f64,
    pub rk4_limit: f64,
    /// Per step of [`STEP_FRACTIONS`] (times RK4's limit at factor 1): the step, and whether each
    /// method stayed bounded (in the order given).
    pub runs: Vec<(f64, Vec<bool>)>,
    /// The largest step below which every RK4 run (the first method) stayed bounded.
    pub rk4_limit_runs: Option<f64>,
}

/// The study's result.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    pub rows: Vec<Row>,
    /// RK4's limit as a line: (step, mesh-stiffness factor) on a fine sweep of factors.
    pub rk4_line: Vec<(f64, f64)>,
}

/// Every run of the grid: mesh-stiffness factors [`SCALES`] × steps, each of `methods`, calling
/// `on_row` as each factor is done; and RK4's limit line.
pub fn grid(preset: &str, methods: &[Method], mut on_row: impl FnMut(&Row)) -> anyhow::Result<Grid> {
    let (_, nominal) = model(preset, 1.0)?;
    let limit_1 = STABILITY_BOUND / nominal.max_angular_frequency();
    let mut rows = Vec::new();
    for &scale in &SCALES {
        let (dt, m) = model(preset, scale)?;
        let omega_max = m.max_angular_frequency();
        let mut rk4_limit_runs = None;
        let mut rk4_failed = false;
        let mut runs = Vec::new();
        for &f in &STEP_FRACTIONS {
            let h = f * limit_1;
            let ok: Vec<bool> = methods
                .iter()
                .map(|method| stays_bounded(&dt, &m, *method, h))
                .collect();
            rk4_failed |= !ok[0];
            if !rk4_failed {
                rk4_limit_runs = Some(h);
            }
            runs.push((h, ok));
        }
        let row = Row {
            scale,
            omega_max,
            rk4_limit: STABILITY_BOUND / omega_max,
            runs,
            rk4_limit_runs,
        };
        on_row(&row);
        rows.push(row);
    }
    // RK4's theoretical limit as a line over the stiffness factor (ω_max ∝ √k where the meshes dominate)
    let fine: Vec<f64> = (0..=32).map(|i| 0.2 * 10f64.powf(i as f64 / 24.0)).collect();
    let mut line = Vec::new();
    for &scale in &fine {
        let (_, m) = model(preset, scale)?;
        line.push((STABILITY_BOUND / m.max_angular_frequency(), scale));
    }
    Ok(Grid { rows, rk4_line: line })
}
