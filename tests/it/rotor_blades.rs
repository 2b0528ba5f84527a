//! The rotor FMU with its blades sampling a full field (wind_sampling = blades), through the C
//! boundary: in uniform steady wind it gives the rotor-averaged loads to the table's tolerance (the
//! physics tests, src/physics/blades/tests.rs, hold the element-by-element checks); every way a field
//! can be unusable is an error status naming the parameter or file, never a panic.

use crate::common::*;
use windrive::fmi2::host::archive::TempDir;
use windrive::fmi2::host::import::{Fmu, Instance};
use windrive::physics::wind_field::{WindField, bts};

/// Initialises the rotor with these settings and returns the error message it refused them with.
fn refusal(fmu: &Fmu, strings: &[(&str, &str)], reals: &[(&str, f64)]) -> String {
    let mut inst = fmu.instantiate("refused", true).unwrap();
    inst.setup_experiment(0.0, None).unwrap();
    for (name, value) in strings {
        inst.set_string(&[fmu.vr(name).unwrap()], &[value]).unwrap();
    }
    for (name, value) in reals {
        inst.set_real(&[fmu.vr(name).unwrap()], &[*value]).unwrap();
    }
    let err = inst
        .enter_initialization_mode()
        .and_then(|()| inst.exit_initialization_mode())
        .expect_err(&format!("{strings:?} {reals:?} was accepted"))
        .to_string();
    assert!(!err.contains("internal error") && !err.contains("Fatal"), "{err}");
    err
}

/// A uniform field of `ny` × `nz` points `spacing` m apart about an 80 m hub, `nt` planes 0.05 s apart.
fn uniform(ny: usize, nz: usize, spacing: f64, nt: usize, periodic: bool) -> WindField {
    let points = ny * nz * nt;
    WindField {
        ny,
        nz,
        nt,
        dy: spacing,
        dz: spacing,
        dt: 0.05,
        z_bottom: 80.0 - 0.5 * (nz - 1) as f64 * spacing,
        hub_height: 80.0,
        mean_hub: 11.0,
        periodic,
        velocity: [vec![11.0; points], vec![0.0; points], vec![0.0; points]],
        tower: Default::default(),
    }
}

fn c_blades(file: &str) -> Vec<(&'static str, String)> {
    vec![
        ("preset", "C".into()),
        ("turbulence", "none".into()),
        ("wind_sampling", "blades".into()),
        ("wind_file", file.into()),
    ]
}

fn strs<'a>(v: &'a [(&'static str, String)]) -> Vec<(&'static str, &'a str)> {
    v.iter().map(|(k, s)| (*k, s.as_str())).collect()
}

#[test]
fn unusable_fields_are_refused_by_name() {
    let fmu = Fmu::open(&fmu_path("rotor")).unwrap();
    let dir = TempDir::new("windrive-test-blades").unwrap();
    let path = |name: &str| dir.path().join(name).to_string_lossy().into_owned();

    let missing = path("missing.bts");
    let err = refusal(&fmu, &strs(&c_blades(&missing)), &[]);
    assert!(err.contains("wind_file") && err.contains(&missing), "{err}");

    let garbage = path("garbage.bts");
    std::fs::write(&garbage, vec![0x55u8; 300]).unwrap();
    let err = refusal(&fmu, &strs(&c_blades(&garbage)), &[]);
    assert!(
        err.contains("wind_file") && err.contains(&garbage) && err.contains("format ID"),
        "{err}"
    );

    let truncated = path("truncated.bts");
    bts::write(std::path::Path::new(&truncated), &uniform(9, 9, 11.0, 4, true), "test").unwrap();
    let bytes = std::fs::read(&truncated).unwrap();
    std::fs::write(&truncated, &bytes[..bytes.len() - 7]).unwrap();
    let err = refusal(&fmu, &strs(&c_blades(&truncated)), &[]);
    assert!(err.contains(&truncated) && err.contains("bytes where"), "{err}");

    // 3 × 3 points 15 m apart: ±15 m about the hub against C's 40 m blades
    let small = path("small.bts");
    bts::write(std::path::Path::new(&small), &uniform(3, 3, 15.0, 4, true), "test").unwrap();
    let err = refusal(&fmu, &strs(&c_blades(&small)), &[]);
    assert!(
        err.contains(&small) && err.contains("too small for the rotor") && err.contains("radius 40 m"),
        "{err}"
    );

    // a NaN never reaches the field: the setter refuses it by name
    let mut inst = fmu.instantiate("nan", true).unwrap();
    let err = inst
        .set_real(&[fmu.vr("shear_exponent").unwrap()], &[f64::NAN])
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("shear_exponent") && err.contains("not a finite number"),
        "{err}"
    );
    let mut analytic = c_blades("");
    analytic.push(("aerodynamics", "analytic".into()));
    assert!(refusal(&fmu, &strs(&analytic), &[]).contains("aerodynamics = bem"));
    let low = refusal(&fmu, &strs(&c_blades("")), &[("hub_height", 30.0)]);
    assert!(low.contains("hub_height = 30 m"), "{low}");
    // a file the rotor-averaged series would not read
    let err = refusal(&fmu, &[("wind_file", &small)], &[]);
    assert!(
        err.contains("wind_file") && err.contains("wind_sampling = blades"),
        "{err}"
    );

    // a non-periodic file ends: a step beyond its last plane is an error naming it, not a held value
    let short = path("short.bts");
    bts::write(std::path::Path::new(&short), &uniform(9, 9, 11.0, 5, false), "test").unwrap();
    let mut inst: Instance = initialised(&fmu, &strs(&c_blades(&short)), &[]);
    inst.do_step(0.0, 0.1).unwrap();
    let err = inst.do_step(0.1, 0.2).unwrap_err().to_string();
    assert!(
        err.contains("holds wind until t = 0.2 s") && err.contains("short.bts"),
        "{err}"
    );
}

/// Uniform steady wind through the FMU: the blades' torque and thrust are the rotor-averaged ones to
/// the table's tolerance (0.25 %), with no yaw moment and no tilt beyond it.
#[test]
fn uniform_wind_through_fmi_matches_the_rotor_average() {
    let fmu = Fmu::open(&fmu_path("rotor")).unwrap();
    let dir = TempDir::new("windrive-test-blades").unwrap();
    let file = dir.path().join("uniform.bts").to_string_lossy().into_owned();
    bts::write(std::path::Path::new(&file), &uniform(9, 9, 11.0, 4, true), "test").unwrap();
    let mut averaged = initialised(
        &fmu,
        &[("preset", "C"), ("turbulence", "none")],
        &[("wind_speed", 11.0), ("shear_exponent", 0.0)],
    );
    let mut bladed = initialised(&fmu, &strs(&c_blades(&file)), &[]);
    let omega = get(&fmu, &mut averaged, "rated_tip_speed_ratio") * 11.0 / 40.0;
    for inst in [&mut averaged, &mut bladed] {
        set(&fmu, inst, "rotor_speed", omega);
        inst.do_step(0.0, 0.37).unwrap();
    }
    let (q, t) = (
        get(&fmu, &mut averaged, "rotor_torque"),
        get(&fmu, &mut averaged, "thrust"),
    );
    let (qb, tb) = (get(&fmu, &mut bladed, "rotor_torque"), get(&fmu, &mut bladed, "thrust"));
    assert!(
        (qb / q - 1.0).abs() < 2.5e-3 && (tb / t - 1.0).abs() < 1e-3,
        "{qb} vs {q}, {tb} vs {t}"
    );
    assert!(get(&fmu, &mut bladed, "yaw_moment").abs() < 1e-3 * t * 40.0);
    assert!(get(&fmu, &mut bladed, "tilt_moment").abs() < 1e-3 * t * 40.0);
    assert_eq!(
        get(&fmu, &mut bladed, "wind_speed_hub"),
        get(&fmu, &mut averaged, "wind_speed_hub")
    );
}
