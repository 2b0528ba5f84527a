//! Every error class of the master names what is wrong: scene files, FMUs, connections, types,
//! algebraic loops, capabilities, and FMUs that fail mid-run (partial CSV kept, exit non-zero).

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;
use windrive::cosim::{Algorithm, Master, Options, Record, Scene, System};

fn ssd(dir: &Path) -> PathBuf {
    dir.join("SystemStructure.ssd")
}

fn edit(path: &Path, from: &str, to: &str) {
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.contains(from), "{} does not contain {from:?}", path.display());
    std::fs::write(path, text.replacen(from, to, 1)).unwrap();
}

/// The scene's checks, as one error message.
fn build_error(dir: &Path) -> String {
    let scene = match Scene::open(dir) {
        Ok(s) => s,
        Err(e) => return e.to_string(),
    };
    match System::build(&scene, &[], &Record::Outputs) {
        Ok(_) => panic!("the scene in {} was accepted", dir.display()),
        Err(e) => e.to_string(),
    }
}

fn assert_contains(message: &str, parts: &[&str]) {
    for p in parts {
        assert!(message.contains(p), "{message:?} does not name {p:?}");
    }
}

/// Unpacks one of the scene's FMUs into a folder FMU (resources/<name>-dir) and points the scene at it.
fn unpack_fmu(dir: &Path, name: &str) -> PathBuf {
    let out = dir.join("resources").join(format!("{name}-dir"));
    windrive::fmi2::host::archive::unzip(&dir.join("resources").join(format!("{name}.fmu")), &out).unwrap();
    edit(
        &ssd(dir),
        &format!("resources/{name}.fmu"),
        &format!("resources/{name}-dir"),
    );
    out
}

#[test]
fn connection_errors_name_the_connection_and_the_element() {
    let cases: [(&str, &str, &[&str]); 5] = [
        (
            r#"endElement="generator""#,
            r#"endElement="genrator""#,
            &["unknown component genrator", "torsional, generator"],
        ),
        (
            r#"endConnector="generator_speed""#,
            r#"endConnector="generator_sped""#,
            &["no variable generator_sped"],
        ),
        (
            r#"startConnector="generator_speed""#,
            r#"startConnector="brake_locked""#,
            &[
                "type mismatch",
                "Boolean output to Real input",
                "torsional.brake_locked -> generator.generator_speed",
            ],
        ),
        (
            r#"startConnector="generator_speed""#,
            r#"startConnector="rotor_torque""#,
            &["torsional.rotor_torque is input, not an output"],
        ),
        (
            "</ssd:Connections>",
            r#"<ssd:Connection startElement="torsional" startConnector="rotor_speed" endElement="generator" endConnector="generator_speed"/></ssd:Connections>"#,
            &["generator.generator_speed is connected twice"],
        ),
    ];
    for (from, to, parts) in cases {
        let (_guard, dir) = common::scene_copy("d-grid-step");
        edit(&ssd(&dir), from, to);
        let message = build_error(&dir);
        assert_contains(&message, parts);
        assert_contains(&message, &["SystemStructure.ssd:"]);
    }
}

#[test]
fn file_errors_name_the_file() {
    // XML that does not parse
    let (_g1, dir) = common::scene_copy("d-grid-step");
    edit(&ssd(&dir), "</ssd:Elements>", "");
    assert_contains(&build_error(&dir), &["SystemStructure.ssd"]);
    // a component FMU that is missing
    let (_g2, dir) = common::scene_copy("d-grid-step");
    edit(&ssd(&dir), "resources/generator.fmu", "resources/missing.fmu");
    assert_contains(&build_error(&dir), &["component generator", "missing.fmu not found"]);
    // a component FMU that is not a zip archive
    let (_g3, dir) = common::scene_copy("d-grid-step");
    std::fs::write(dir.join("resources/generator.fmu"), b"not a zip").unwrap();
    assert_contains(&build_error(&dir), &["component generator", "not a valid zip archive"]);
    // an FMU without its binary
    let (_g4, dir) = common::scene_copy("d-grid-step");
    let unpacked = unpack_fmu(&dir, "generator");
    std::fs::remove_file(unpacked.join("binaries/linux64/generator.so")).unwrap();
    assert_contains(
        &build_error(&dir),
        &[
            "component generator",
            "no binaries/linux64/generator.so",
            "binaries/linux64 holds nothing",
        ],
    );
    // an FMU whose modelDescription.xml does not parse
    let (_g8, dir) = common::scene_copy("d-grid-step");
    let unpacked = unpack_fmu(&dir, "generator");
    edit(&unpacked.join("modelDescription.xml"), "</ModelVariables>", "");
    assert_contains(&build_error(&dir), &["component generator", "modelDescription.xml"]);
    // a corrupt .ssp archive
    let (_g5, dir) = common::scene_copy("d-grid-step");
    let ssp = dir.join("corrupt.ssp");
    std::fs::write(&ssp, b"PK\x03\x04 truncated").unwrap();
    assert_contains(&build_error(&ssp), &["corrupt.ssp", "zip"]);
    // a parameter the FMU does not have, and a value of the wrong type
    let (_g6, dir) = common::scene_copy("d-grid-step");
    edit(
        &dir.join("torsional.ssv"),
        r#"name="damping_scale""#,
        r#"name="damping_scal""#,
    );
    assert_contains(&build_error(&dir), &["torsional.ssv", "no variable damping_scal"]);
    let (_g7, dir) = common::scene_copy("d-grid-step");
    edit(
        &dir.join("torsional.ssv"),
        r#"<ssv:String value="2"/>"#,
        r#"<ssv:Boolean value="true"/>"#,
    );
    assert_contains(&build_error(&dir), &["fidelity is String but the value is Boolean"]);
}

#[test]
fn an_unconnected_input_without_start_value_is_refused() {
    let (_guard, dir) = common::scene_copy("d-grid-step");
    let fmu = unpack_fmu(&dir, "generator");
    edit(
        &fmu.join("modelDescription.xml"),
        r#"<Real start="0" unit="rad/s"/>"#,
        r#"<Real unit="rad/s"/>"#,
    );
    edit(
        &ssd(&dir),
        r#"<ssd:Connection startElement="torsional" startConnector="generator_speed" endElement="generator" endConnector="generator_speed"/>"#,
        "",
    );
    edit(
        &ssd(&dir),
        r#"<ssd:Connector name="generator_speed" kind="input"><ssc:Real/></ssd:Connector>"#,
        "",
    );
    assert_contains(
        &build_error(&dir),
        &["input generator.generator_speed is not connected and has no start value"],
    );
}

/// The generator's torque feeds through from its speed (declared in its ModelStructure); a torsional
/// FMU whose speed output declared feedthrough from its torque input would close the loop.
#[test]
fn a_declared_algebraic_loop_is_refused_with_its_path() {
    let (_guard, dir) = common::scene_copy("d-grid-step");
    let fmu = unpack_fmu(&dir, "torsional");
    // index 24 = generator_speed (output), index 16 = generator_torque (input)
    edit(
        &fmu.join("modelDescription.xml"),
        r#"<Unknown index="24" dependencies=""/>"#,
        r#"<Unknown index="24" dependencies="16"/>"#,
    );
    assert_contains(
        &build_error(&dir),
        &[
            "algebraic loop",
            "torsional.generator_speed -> generator.generator_torque -> torsional.generator_speed",
        ],
    );
}

#[test]
fn rollback_algorithms_refuse_fmus_without_state_saving() {
    let (_guard, dir) = common::scene_copy("d-grid-step");
    let fmu = unpack_fmu(&dir, "generator");
    edit(
        &fmu.join("modelDescription.xml"),
        r#"canGetAndSetFMUstate="true""#,
        r#"canGetAndSetFMUstate="false""#,
    );
    let scene = Scene::open(&dir).unwrap();
    for algorithm in [Algorithm::Iterative, Algorithm::Adaptive] {
        let mut system = System::build(&scene, &[], &Record::Outputs).unwrap();
        system.initialize(Some(1.0)).unwrap();
        let message = Master::new(&mut system, Options::new(algorithm, 1e-3, 1.0))
            .err()
            .unwrap()
            .to_string();
        assert_contains(
            &message,
            &["rolls steps back", "generator", "canGetAndSetFMUstate=false"],
        );
    }
}

fn windrive(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_windrive"))
        .args(args)
        .env("RUST_BACKTRACE", "0")
        .output()
        .unwrap()
}

/// Zero-order-hold Jacobi at 50 ms drives the undamped coupling to infinity: the master stops at
/// the first non-finite output, keeps every row before it, names the variable and time, exits 1.
#[test]
fn a_run_that_blows_up_keeps_its_rows_and_exits_nonzero() {
    // Jacobi at 50 ms on the stiff generator spring (H·ω = 1.85) grows geometrically: the divergence
    // watch stops it naming the coupling and the remedy; with the watch off the values overflow and
    // the non-finite check stops it. Either way the rows so far are kept, all finite.
    let cases: [(&[&str], &[&str]); 2] = [
        (
            &[],
            &[
                "the coupling torsional.generator_speed -> generator diverges",
                "--step",
                "iqn-ils",
                "results up to t = ",
            ],
        ),
        (
            &["--divergence-growth", "inf"],
            &["not finite", " at t = ", "results up to t = "],
        ),
    ];
    let mut stopped_at = Vec::new();
    for (extra, expected) in cases {
        let (_guard, dir) = common::scene_copy("d-grid-step");
        let csv = dir.join("out.csv");
        let mut args = vec![
            "run",
            dir.to_str().unwrap(),
            "--algorithm",
            "jacobi",
            "--step",
            "0.05",
            "--stop-time",
            "1000",
            "--out",
            csv.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let out = windrive(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{stderr}");
        assert_contains(&stderr, expected);
        let text = std::fs::read_to_string(&csv).unwrap();
        let rows: Vec<&str> = text.lines().collect();
        assert!(rows[0].starts_with("time,torsional.") && rows[0].contains(",generator.generator_torque,"));
        // every kept row is finite and the last one is the step before the failure
        let last_time: f64 = rows.last().unwrap().split(',').next().unwrap().parse().unwrap();
        assert!(rows.len() > 10 && last_time < 1000.0);
        assert!(
            rows[1..]
                .iter()
                .all(|r| r.split(',').all(|v| v.parse::<f64>().unwrap().is_finite()))
        );
        assert!(stderr.contains(&format!("results up to t = {last_time} s")), "{stderr}");
        stopped_at.push(last_time);
    }
    // the watch stops the run long before the overflow
    assert!(stopped_at[0] < stopped_at[1] / 5.0, "{stopped_at:?}");
}

/// The same scene as a folder and packed to .ssp (by `windrive pack-scene`) gives the same bytes;
/// a parameter set on the command line overrides the scene's binding.
#[test]
fn folder_and_ssp_archive_run_identically_and_params_override() {
    let (_guard, dir) = common::scene_copy("d-grid-step");
    let ssp = dir.join("scene.ssp");
    let packed = windrive(&["pack-scene", dir.to_str().unwrap(), "--out", ssp.to_str().unwrap()]);
    assert!(packed.status.success(), "{}", String::from_utf8_lossy(&packed.stderr));
    let run = |scene: &Path, csv: &Path, extra: &[&str]| {
        let mut args = vec![
            "run",
            scene.to_str().unwrap(),
            "--stop-time",
            "0.5",
            "--out",
            csv.to_str().unwrap(),
            "--quiet",
        ];
        args.extend_from_slice(extra);
        let out = windrive(&args);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        std::fs::read_to_string(csv).unwrap()
    };
    let a = run(&dir, &dir.join("a.csv"), &[]);
    let b = run(&ssp, &dir.join("b.csv"), &[]);
    assert_eq!(a, b);
    let c = run(
        &dir,
        &dir.join("c.csv"),
        &[
            "--param",
            "generator.stiffness=1e5",
            "--record",
            "generator.stiffness_used,torsional.rotor_torque",
        ],
    );
    let row: Vec<&str> = c.lines().nth(1).unwrap().split(',').collect();
    assert_eq!(row[1].parse::<f64>().unwrap(), 1e5);
    assert_eq!(
        row[2].parse::<f64>().unwrap(),
        385_000.0,
        "the .ssv binding reaches the input"
    );
}

/// `--out FILE.parquet` records what `--out FILE.csv` does, column for column and bit for bit, read back
/// through the readers every analysis command uses; a run that fails still leaves a complete Parquet
/// file holding every row up to its last good step.
#[test]
fn parquet_results_hold_the_csv_values_to_the_bit_even_after_a_failed_run() {
    use windrive::analysis::signal::series::read_channels;
    let (_guard, dir) = common::scene_copy("d-grid-step");
    let failing: &[&str] = &["--algorithm", "jacobi", "--step", "0.05", "--divergence-growth", "inf"];
    for (stop, extra, code) in [("0.5", &[][..], 0), ("1000", failing, 1)] {
        let mut files = Vec::new();
        for name in ["out.csv", "out.parquet"] {
            let path = dir.join(name);
            let mut args = vec!["run", dir.to_str().unwrap(), "--stop-time", stop, "--quiet", "--out"];
            args.push(path.to_str().unwrap());
            args.extend_from_slice(extra);
            let out = windrive(&args);
            assert_eq!(
                out.status.code(),
                Some(code),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            files.push(path);
        }
        let text = std::fs::read_to_string(&files[0]).unwrap();
        let header: Vec<&str> = text.lines().next().unwrap().split(',').skip(1).collect();
        let (t_csv, csv) = read_channels(&files[0], &header).unwrap();
        let (t_parquet, parquet) = read_channels(&files[1], &header).unwrap();
        assert!(t_csv.len() > 5, "stop {stop}: {} rows", t_csv.len());
        assert_eq!(t_csv, t_parquet, "stop {stop}: time");
        for ((name, a), b) in header.iter().zip(&csv).zip(&parquet) {
            assert_eq!(a, b, "stop {stop}: {name}");
        }
        let missing = read_channels(&files[1], &["torsional.no_such_output"])
            .unwrap_err()
            .to_string();
        assert!(
            missing.contains("no column") && missing.contains("torsional.hss_torque"),
            "{missing}"
        );
    }
}

/// `run --profile` names every FMU with its steps and recorded reads, the recorder, the master and the
/// writer thread's CPU (Parquet), after a summary that gives wall and CPU time; a run without it prints
/// no profile. Shares are not checked: they are the machine's.
#[test]
fn a_profiled_run_says_where_its_time_went() {
    let (_guard, dir) = common::scene_copy("d-grid-step");
    let out = dir.join("out.parquet");
    let args = [
        "run",
        dir.to_str().unwrap(),
        "--stop-time",
        "0.5",
        "--out",
        out.to_str().unwrap(),
    ];
    let profiled = windrive(&[&args[..], &["--profile"]].concat());
    assert!(
        profiled.status.success(),
        "{}",
        String::from_utf8_lossy(&profiled.stderr)
    );
    let text = String::from_utf8_lossy(&profiled.stderr);
    assert!(regex_like(&text, "s wall, ", " s CPU ("), "{text}");
    let profile = &text[text.find("profile ").expect("a profile")..];
    for row in ["torsional", "generator", "recorder", "master", "other threads"] {
        assert!(profile.contains(row), "{row}: {profile}");
    }
    assert_eq!(profile.matches("recorded reads").count(), 2, "{profile}");
    let plain = windrive(&args);
    assert!(!String::from_utf8_lossy(&plain.stderr).contains("profile "));
}

/// Whether `text` has `a`, then a number, then `b`.
fn regex_like(text: &str, a: &str, b: &str) -> bool {
    text.split(a).skip(1).any(|rest| {
        let digits = rest.trim_start_matches(|c: char| c.is_ascii_digit() || c == '.');
        digits.len() < rest.len() && digits.starts_with(b)
    })
}
