//! A scene's reference (its coupled equations converged every 0.25 ms step) against an exact answer,
//! and the co-simulation converging to it as the macro step shrinks; `windrive chart work-precision`
//! and `windrive fidelity` through the command line.

use crate::common;

use windrive::analysis::signal::quantities::{self, relative_error};
use windrive::cosim::{Algorithm, Options, Scene};
use windrive::reference::grid_step::exact_generator_torque;
use windrive::reference::scene::{compute, run_quantities};

/// d-grid-step has an exact modal solution. Its reference's quantities (generator torque peak, RMS,
/// the coupled mode's frequency) match the same quantities of the exact series sampled at the same
/// times within 2e-5 (measured 1.6e-7 and 6.4e-7, the frequency exactly: second order, 0.25 ms against
/// a 5.89 Hz mode), and its step-doubling estimate is within 10x of its error or below 1e-4.
#[test]
fn the_reference_matches_the_exact_solution() {
    let (_guard, dir) = common::scene_copy("d-grid-step");
    let scene = Scene::open(&dir).unwrap();
    let qs = quantities::load(&dir.join(quantities::FILE_NAME)).unwrap();
    let r = compute(&scene, &[], &qs, 2.5e-4, 5.0).unwrap();
    assert_eq!(r.unconverged, 0);
    let t: Vec<f64> = (0..=20_000).map(|k| k as f64 * 2.5e-4).collect();
    let exact = exact_generator_torque(&t);
    let channels = quantities::channels(&qs);
    let exact_values = quantities::evaluate_all(&qs, &channels, &[t, exact]).unwrap();
    for (i, q) in qs.iter().enumerate() {
        let error = relative_error(r.values[i], exact_values[i]);
        assert!(
            error < 2e-5,
            "{}: reference {} exact {} ({error:.2e})",
            q.name,
            r.values[i],
            exact_values[i]
        );
        eprintln!("{}: error {error:.2e}, estimate {:.2e}", q.name, r.own_error(i));
        assert!(
            r.own_error(i) < (10.0 * error).max(1e-4),
            "{}: estimate {:.2e}, error {error:.2e}",
            q.name,
            r.own_error(i)
        );
    }
}

/// Gauss–Seidel with hold converges to the reference at first order as the macro step halves (4, 2,
/// 1 ms: each error at most 0.65 of the one before), and is within every tolerance at 1 ms.
#[test]
fn gauss_seidel_converges_to_the_reference() {
    let (_guard, dir) = common::scene_copy("d-grid-step");
    let scene = Scene::open(&dir).unwrap();
    let qs = quantities::load(&dir.join(quantities::FILE_NAME)).unwrap();
    let r = compute(&scene, &[], &qs, 2.5e-4, 5.0).unwrap();
    let errors: Vec<f64> = [4e-3, 2e-3, 1e-3]
        .iter()
        .map(|&h| {
            let (v, _) = run_quantities(&scene, &[], &qs, Options::new(Algorithm::GaussSeidel, h, 5.0)).unwrap();
            // the peak's error: the quantity every step size moves
            relative_error(v[0], r.values[0])
        })
        .collect();
    assert!(
        errors[1] < 0.65 * errors[0] && errors[2] < 0.65 * errors[1],
        "{errors:?}"
    );
    let (v, _) = run_quantities(&scene, &[], &qs, Options::new(Algorithm::GaussSeidel, 1e-3, 5.0)).unwrap();
    for (i, q) in qs.iter().enumerate() {
        assert!(relative_error(v[i], r.values[i]) < q.tolerance, "{}", q.name);
    }
}

fn windrive(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_windrive"))
        .args(args)
        .output()
        .unwrap()
}

/// The chart command writes PNG, SVG and a CSV with one row per run and one error column per
/// quantity; the runs on the Pareto front are named.
#[test]
fn work_precision_chart_writes_its_files() {
    let (guard, dir) = common::scene_copy("d-grid-step");
    let stem = guard.path().join("out").join("wp");
    let out = windrive(&[
        "chart",
        "work-precision",
        dir.to_str().unwrap(),
        "--vary",
        "order",
        "--steps",
        "1,4",
        "--repeat",
        "1",
        "--stop-time",
        "2",
        "--out",
        stem.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("Pareto front") && stdout.contains("gauss-seidel order 2"),
        "{stdout}"
    );
    for ext in ["png", "svg"] {
        assert!(std::fs::metadata(stem.with_extension(ext)).unwrap().len() > 1000);
    }
    let csv = std::fs::read_to_string(stem.with_extension("csv")).unwrap();
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows.len(), 1 + 6, "{csv}");
    assert!(
        rows[0].starts_with("method,setting,cpu_s,max_relative_error,within_tolerance,error generator torque peak")
    );
    // order 0 at 4 ms is further from the reference than at 1 ms
    let err = |row: &str| row.split(',').nth(3).unwrap().parse::<f64>().unwrap();
    assert!(err(rows[2]) > err(rows[1]), "{csv}");
}

/// What the commands refuse, and how they say it.
#[test]
fn study_commands_name_their_mistakes() {
    let (guard, dir) = common::scene_copy("d-grid-step");
    let d = dir.to_str().unwrap();
    let stem = guard.path().join("x").join("wp");
    let s = stem.to_str().unwrap();
    let cases: [(&[&str], &str); 8] = [
        (
            &["chart", "work-precision", d, "--vary", "colour", "--out", s],
            "--vary colour: use one of algorithm",
        ),
        (
            &[
                "chart",
                "work-precision",
                d,
                "--vary",
                "slices",
                "--stop-time",
                "0.5",
                "--out",
                s,
            ],
            "has no gearbox6dof component",
        ),
        (
            &[
                "chart",
                "work-precision",
                d,
                "--vary",
                "order",
                "--steps",
                "0,1",
                "--stop-time",
                "0.5",
                "--out",
                s,
            ],
            "--steps",
        ),
        (
            &["fidelity", d, "--quantities", "/nonexistent/q.toml"],
            "/nonexistent/q.toml",
        ),
        (&["chart", "stability", "--growth", "0.5", "--out", s], "--growth 0.5"),
        (
            &["chart", "integrators", "--preset", "Q", "--out", s],
            "unknown preset \"Q\"",
        ),
        (&["chart", "non-smooth", "--backlash=-1", "--out", s], "--backlash -1"),
        (
            &["chart", "non-smooth", "--scene", "/nonexistent/scene", "--out", s],
            "/nonexistent/scene",
        ),
    ];
    for (args, expected) in cases {
        let out = windrive(args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert!(
            !stderr.contains("panicked") && !stderr.contains("backtrace"),
            "{stderr}"
        );
    }
}

/// `windrive fidelity --json` on d-grid-step (drivetrain D on its generator spring): the ladder's three
/// levels, each with CPU time and error, and a recommendation that is one of them and within tolerance.
#[test]
fn fidelity_json_names_a_level_within_tolerance() {
    let (_guard, dir) = common::scene_copy("d-grid-step");
    let out = windrive(&[
        "fidelity",
        dir.to_str().unwrap(),
        "--json",
        "--repeat",
        "1",
        "--stop-time",
        "2",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let levels = v["levels"].as_array().unwrap();
    let names: Vec<&str> = levels.iter().map(|l| l["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["2-mass", "5-mass", "full torsional"]);
    for l in levels {
        assert!(l["cpu_s"].as_f64().unwrap() > 0.0 && l["error"].as_f64().unwrap() >= 0.0);
    }
    let recommended = v["recommended"].as_str().unwrap();
    let level = levels.iter().find(|l| l["name"] == recommended).unwrap();
    assert_eq!(level["within_tolerance"], true);
    assert!(v["modes_hz"]["full torsional"].as_array().unwrap().len() > 5);
}

/// `windrive chart stability` over 5 s runs: the runs agree with the theory's macro-step map on at
/// least 85 % of the grid for every algorithm (measured: 39 of 45 for ZOH Jacobi at 5 s, whose growth is
/// slowest near the boundary; 41 to 45 of 45 at 20 s), IQN-ILS holds
/// everywhere, and the files are written.
#[test]
fn stability_map_runs_agree_with_the_theory() {
    let tmp = windrive::fmi2::host::archive::TempDir::new("windrive-test-stability").unwrap();
    let stem = tmp.path().join("map");
    let out = windrive(&[
        "chart",
        "stability",
        "--stop-time",
        "5",
        "--out",
        stem.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let csv = std::fs::read_to_string(stem.with_extension("csv")).unwrap();
    let mut by_algorithm: std::collections::BTreeMap<String, (usize, usize)> = Default::default();
    for row in csv.lines().skip(1) {
        let f: Vec<&str> = row.split(',').collect();
        let e = by_algorithm.entry(f[0].to_string()).or_default();
        e.0 += usize::from(f[4] == f[5]);
        e.1 += 1;
        if f[0] == "iterative iqn-ils" {
            assert_eq!(f[4], "true", "{row}");
        }
    }
    assert_eq!(by_algorithm.len(), 8);
    for (a, (agree, total)) in by_algorithm {
        assert!(agree * 100 >= total * 85, "{a}: {agree}/{total}");
    }
    assert!(std::fs::metadata(stem.with_extension("png")).unwrap().len() > 10_000);
}

/// `windrive chart integrators` (drivetrain C, undamped, mesh stiffness 0.25-4x): every RK4 run below
/// 2.785/omega_max of its model holds and every run above 1.25x of it grows (the grid brackets the
/// limit as it moves with the mesh stiffness); Newmark and HHT-alpha hold at every step.
#[test]
fn integrator_stability_runs_follow_rk4s_limit() {
    let tmp = windrive::fmi2::host::archive::TempDir::new("windrive-test-integrators").unwrap();
    let stem = tmp.path().join("map");
    let out = windrive(&["chart", "integrators", "--out", stem.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let csv = std::fs::read_to_string(stem.with_extension("csv")).unwrap();
    let mut rk4 = 0;
    for row in csv.lines().skip(1) {
        let f: Vec<&str> = row.split(',').collect();
        let (h_omega, stable) = (f[3].parse::<f64>().unwrap(), f[4] == "true");
        if f[0] == "rk4" {
            rk4 += 1;
            if h_omega < 2.785 {
                assert!(stable, "{row}");
            } else if h_omega > 1.25 * 2.785 {
                assert!(!stable, "{row}");
            }
        } else {
            assert!(stable, "{row}");
        }
    }
    assert_eq!(rk4, 45);
    assert!(stdout.contains("7748") && stdout.contains("57.2 µs"), "{stdout}");
}
