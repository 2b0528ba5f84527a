//! The inputs no source gives (src/studies/data/estimates.toml): each nominal value is what its scene or
//! gearbox file holds, so the table of ranges cannot drift from what the scenes run; each acts on a scene
//! the reproduction runs; and setting one reaches the scene (a parameter binding) or the gearbox (an edited
//! description the FMU loads by path).

use windrive::cosim::Scene;
use windrive::physics::gearbox::description::Description;
use windrive::studies::estimates::{self, Setting, Target, key_values, preset_table};
use windrive::studies::reproduce::scenes_run;

/// A repository scene as written, without packing its FMUs (reading and binding parameters needs none;
/// packing here would race the other tests that pack).
fn open_scene(name: &str) -> anyhow::Result<Scene> {
    Ok(Scene::open(
        &windrive::pack::workspace_root()?.join("scenes").join(name),
    )?)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs().max(1e-300)
}

#[test]
fn every_nominal_is_what_the_scenes_and_gearboxes_hold() {
    let all = estimates::all().unwrap();
    assert!(all.len() >= 15, "{} estimates", all.len());
    let run = scenes_run().unwrap();
    for e in &all {
        assert!(
            e.low < e.high && !e.reason.is_empty(),
            "{}: empty range or no reason",
            e.name
        );
        assert!(
            e.low <= e.nominal && e.nominal <= e.high,
            "{}: nominal {} outside its range {}–{}",
            e.name,
            e.nominal,
            e.low,
            e.high
        );
        let mut reached = false;
        for t in &e.targets {
            match t {
                Target::Parameter {
                    scenes,
                    component,
                    variable,
                } => {
                    for name in scenes {
                        let scene = open_scene(name).unwrap();
                        let bound = scene.real_parameter(component, variable);
                        if e.unbound {
                            assert_eq!(bound, None, "{}: scene {name} binds {component}.{variable}", e.name);
                        } else {
                            let want = e.in_scene(e.nominal).unwrap();
                            let got = bound.unwrap_or_else(|| panic!("{}: {name} binds no {variable}", e.name));
                            assert!(close(got, want), "{}: scene {name} holds {got}, nominal {want}", e.name);
                        }
                        reached |= run.contains(name);
                    }
                }
                Target::Gearbox { gearbox, key } => {
                    let values = key_values(&preset_table(gearbox).unwrap(), key);
                    assert!(!values.is_empty(), "{}: {key} matches nothing in {gearbox}", e.name);
                    for v in values {
                        assert!(
                            close(v, e.nominal),
                            "{}: {gearbox} {key} holds {v}, nominal {}",
                            e.name,
                            e.nominal
                        );
                    }
                    reached |= run
                        .iter()
                        .any(|name| estimates::gearbox_component(&open_scene(name).unwrap(), gearbox).is_some());
                }
            }
        }
        assert!(reached, "{}: no scene of the reproduction uses it", e.name);
    }
}

#[test]
fn a_set_estimate_reaches_the_scene_and_the_gearbox() {
    let folder = std::env::temp_dir().join(format!("windrive-it-estimates-{}", std::process::id()));
    let set =
        |pairs: &[&str]| Setting::parse(&pairs.iter().map(|s| s.to_string()).collect::<Vec<_>>(), &folder).unwrap();

    let mut scene = open_scene("a-shutdown").unwrap();
    let setting = set(&["a_trip_delay=0.45", "a_brake_torque=2"]);
    assert!(setting.acts_on("a-shutdown", &scene));
    setting.apply("a-shutdown", &mut scene).unwrap();
    assert_eq!(scene.real_parameter("rotor", "trip_delay"), Some(0.45));
    let a = windrive::physics::drivetrain::Drivetrain::preset("A").unwrap();
    assert_eq!(
        scene.real_parameter("torsional", "brake_torque_max"),
        Some(2.0 * a.rated_generator_torque())
    );
    // at its nominal value an estimate leaves the scene's own binding alone
    let mut c = open_scene("c-shutdown").unwrap();
    let own = c.real_parameter("rotor", "trip_delay");
    set(&["c_trip_delay=0.6118799001187182"])
        .apply("c-shutdown", &mut c)
        .unwrap();
    assert_eq!(c.real_parameter("rotor", "trip_delay"), own);

    let mut six = open_scene("c-shutdown-6dof").unwrap();
    let setting = set(&["c2mw_planet_clearance=150", "c2mw_planet_rollers=24.6"]);
    assert!(setting.acts_on("c-shutdown-6dof", &six));
    assert!(!setting.acts_on("c-shutdown", &open_scene("c-shutdown").unwrap()));
    setting.apply("c-shutdown-6dof", &mut six).unwrap();
    let path = six.string_parameter("gearbox", "gearbox").unwrap().to_string();
    let edited = Description::load(&path).unwrap();
    let table: toml::Table = std::fs::read_to_string(&path).unwrap().parse().unwrap();
    assert_eq!(
        key_values(&table, "stage.0.planetary.planet.bearings.*.rollers.clearance_um"),
        [150.0, 150.0]
    );
    // a count stays an integer, rounded
    assert_eq!(
        key_values(&table, "stage.0.planetary.planet.bearings.*.rollers.count"),
        [25.0, 25.0]
    );
    assert_eq!(edited.name, Description::load("c2mw").unwrap().name);

    let err = Setting::parse(&["no_such=1".to_string()], &folder)
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("no estimate \"no_such\""), "{err}");
    let err = Setting::parse(&["a_trip_delay=nan".to_string()], &folder)
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("not a finite number"), "{err}");
    let _ = std::fs::remove_dir_all(&folder);
}
