//! `windrive chart integrators`: where the torsional model's integrators are stable as the internal
//! step crosses RK4's limit and the mesh stiffness moves it (the study:
//! [`crate::studies::integrators`]), and how much the implicit methods damp the top modes there
//! (their amplification-matrix radius per step at the top mode's h·ω).

use crate::solver::Method;
use crate::solver::alpha::Alpha;
use crate::studies::integrators::{STEPS, grid};
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
    let only: Vec<Method> = methods.iter().map(|(_, m)| *m).collect();
    let grid = grid(&args.preset, &only, |row| {
        let w = row.omega_max;
        // what HHT-α and generalised-α leave of the top mode per step, at RK4's limit and at 1 ms
        let kept = |h: f64| {
            format!(
                "{:.3}, {:.3}",
                hht.amplification_radius(h * w),
                gen_alpha.amplification_radius(h * w)
            )
        };
        println!(
            "{:>10} {:>12.0} {:>12} {:>12} {:>17} {:>17}",
            row.scale,
            w / std::f64::consts::TAU,
            format!("{:.1} µs", row.rk4_limit * 1e6),
            row.rk4_limit_runs
                .map_or("none".into(), |h: f64| format!("{:.1} µs", h * 1e6)),
            kept(row.rk4_limit),
            kept(1e-3)
        );
    })?;
    let mut csv = String::from("method,mesh_stiffness_factor,step_s,h_omega_max,stable\n");
    let mut panels: Vec<crate::plot::StabilityPanel> = methods
        .iter()
        .map(|(name, _)| crate::plot::StabilityPanel {
            title: name.to_string(),
            stable: Vec::new(),
            unstable: Vec::new(),
            boundary: Vec::new(),
        })
        .collect();
    for row in &grid.rows {
        for (h, ok) in &row.runs {
            for (k, ((name, _), ok)) in methods.iter().zip(ok).enumerate() {
                if *ok {
                    panels[k].stable.push((*h, row.scale));
                } else {
                    panels[k].unstable.push((*h, row.scale));
                }
                writeln!(csv, "{name},{},{h},{},{ok}", row.scale, h * row.omega_max)?;
            }
        }
    }
    panels[0].boundary = grid.rk4_line;
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
    crate::plot::write_stability_map(
        &args.out,
        &csv,
        &title,
        ("internal step h [s]", "mesh stiffness ×"),
        &panels,
    )
}
