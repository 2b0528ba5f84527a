//! `windrive chart integrators`: where the torsional model's integrators are stable as the internal
//! step crosses RK4's limit (2.785/ω_max) and the mesh stiffness moves ω_max, and how much the
//! implicit methods damp the top modes there. Runs: the full model of a preset, undamped, turning at
//! rated speed in its loaded equilibrium, then a balanced 10 % torque step (every shaft and mesh mode
//! rings, nothing accelerates), 4000 internal steps; unstable when the step fails, the state stops
//! being finite or the energy above the rigid rotation's peaks over the last quarter at more than twice
//! the first quarter's. Theory: RK4's limit line, and the implicit methods'
//! amplification-matrix radius per step at the top mode's h·ω.

use crate::physics::drivetrain::{Drivetrain, Stage};
use crate::physics::torsional::{Fidelity, INPUT_COUNT, ModelOptions, TorsionalModel};
use crate::solver::alpha::Alpha;
use crate::solver::rk4::STABILITY_BOUND;
use crate::solver::{Driver, DynState, Method, SecondOrderSystem};
use anyhow::{Context, anyhow};
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(clap::Args)]
#[command(after_help = "Examples:\n  \
    windrive chart integrators                       drivetrain C, results/integrator-stability.{png,svg,csv} (about 10 s)\n  \
    windrive chart integrators --preset D --out /tmp/integrators-d")]
pub struct IntegratorsArgs {
    /// Drivetrain preset: A, B, C or D
    #[arg(long, default_value = "C")]
    pub preset: String,
    /// Output stem: STEM.png, STEM.svg, STEM.csv
    #[arg(long, default_value = "results/integrator-stability")]
    pub out: PathBuf,
}

/// Mesh-stiffness factors and internal steps (as fractions of RK4's limit at factor 1) of the grid.
const SCALES: [f64; 5] = [0.25, 0.5, 1.0, 2.0, 4.0];
const STEP_FRACTIONS: [f64; 9] = [0.25, 0.4, 0.6, 0.8, 0.95, 1.05, 1.5, 2.5, 4.0];
const STEPS: usize = 4000;

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

fn model(preset: &str, scale: f64) -> anyhow::Result<(Drivetrain, TorsionalModel)> {
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

pub fn run(args: &IntegratorsArgs) -> anyhow::Result<()> {
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create the output folder", dir.display()))?;
    }
    let hht = Alpha::hht(0.6).map_err(|e| anyhow!(e))?;
    let gen_alpha = Alpha::generalised(0.3).map_err(|e| anyhow!(e))?;
    let methods: [(&str, Method); 3] = [
        (
            "rk4",
            Method::Rk4 {
                stability_limit: f64::INFINITY,
            },
        ),
        ("implicit (Newmark)", Method::Implicit(Alpha::NEWMARK)),
        ("hht rho=0.6", Method::Implicit(hht)),
    ];
    let (_, nominal) = model(&args.preset, 1.0)?;
    let limit_1 = STABILITY_BOUND / nominal.max_angular_frequency();
    println!(
        "drivetrain {} full model, undamped, at rated speed and torque, a 10 % torque step, {STEPS} internal steps per run;\n\
         unstable = failed, non-finite, or the elastic energy doubled (last quarter against first)\n",
        args.preset
    );
    println!("{:>48} {:>17} {:>17}", "", "top mode kept per step at", "");
    println!(
        "{:>10} {:>12} {:>12} {:>12} {:>17} {:>17}",
        "mesh k ×", "top mode Hz", "RK4 limit", "RK4 runs", "RK4 limit: α, gα", "1 ms: α, gα"
    );
    let mut csv = String::from("method,mesh_stiffness_factor,step_s,h_omega_max,stable\n");
    let mut panels: Vec<super::plot::StabilityPanel> = methods
        .iter()
        .map(|(name, _)| super::plot::StabilityPanel {
            title: name.to_string(),
            stable: Vec::new(),
            unstable: Vec::new(),
            boundary: Vec::new(),
        })
        .collect();
    for &scale in &SCALES {
        let (dt, m) = model(&args.preset, scale)?;
        let w = m.max_angular_frequency();
        let limit = STABILITY_BOUND / w;
        let mut rk4_limit_runs = None;
        let mut rk4_failed = false;
        for &f in &STEP_FRACTIONS {
            let h = f * limit_1;
            for (k, (name, method)) in methods.iter().enumerate() {
                let ok = stays_bounded(&dt, &m, *method, h);
                if ok {
                    panels[k].stable.push((h, scale));
                } else {
                    panels[k].unstable.push((h, scale));
                }
                if k == 0 {
                    rk4_failed |= !ok;
                    if !rk4_failed {
                        rk4_limit_runs = Some(h);
                    }
                }
                writeln!(csv, "{name},{scale},{h},{},{ok}", h * w)?;
            }
        }
        // what HHT-α and generalised-α leave of the top mode per step, at RK4's limit and at 1 ms
        let kept = |h: f64| {
            format!(
                "{:.3}, {:.3}",
                hht.amplification_radius(h * w),
                gen_alpha.amplification_radius(h * w)
            )
        };
        println!(
            "{scale:>10} {:>12.0} {:>12} {:>12} {:>17} {:>17}",
            w / std::f64::consts::TAU,
            format!("{:.1} µs", limit * 1e6),
            rk4_limit_runs.map_or("none".into(), |h: f64| format!("{:.1} µs", h * 1e6)),
            kept(limit),
            kept(1e-3)
        );
    }
    // RK4's theoretical limit as a line over the stiffness factor (ω_max ∝ √k where the meshes dominate)
    let fine: Vec<f64> = (0..=32).map(|i| 0.2 * 10f64.powf(i as f64 / 24.0)).collect();
    for &scale in &fine {
        let (_, m) = model(&args.preset, scale)?;
        panels[0]
            .boundary
            .push((STABILITY_BOUND / m.max_angular_frequency(), scale));
    }
    println!(
        "\nα = HHT-α with ρ∞ = 0.6, gα = generalised-α with ρ∞ = 0.3 (amplification-matrix radius at the top mode's h·ω);\n\
         Newmark keeps every mode at any step (radius 1), stable everywhere above as HHT-α is. At 1 ms HHT-α leaves the\n\
         2.5 Hz mode within {:.1e} per step, generalised-α within {:.1e}: they damp the mesh modes, not the drivetrain's.",
        1.0 - hht.amplification_radius(1e-3 * std::f64::consts::TAU * 2.5),
        1.0 - gen_alpha.amplification_radius(1e-3 * std::f64::consts::TAU * 2.5)
    );
    let title = format!(
        "Integrator stability, drivetrain {} (full, undamped): dots = runs, line = RK4's limit 2.785/ω_max",
        args.preset
    );
    super::stability::write_map(
        &args.out,
        &csv,
        &title,
        ("internal step h [s]", "mesh stiffness ×"),
        &panels,
    )
}
