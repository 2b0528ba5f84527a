//! Shared helpers for tests that load the packed FMU through the FMI boundary or run its Rust face.
#![allow(dead_code)]

use std::path::PathBuf;
use windrive::fmi2::host::import::{Fmu, Instance};

/// A packed FMU of ours (scripts/test packs them before running the tests).
pub fn fmu_path(name: &str) -> PathBuf {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target"));
    let path = target.join("fmu").join(format!("{name}.fmu"));
    assert!(
        path.is_file(),
        "{} is missing: run `cargo run --release -- pack` first (scripts/test does)",
        path.display()
    );
    path
}

pub fn torsional_fmu_path() -> PathBuf {
    fmu_path("torsional")
}

/// A copy of the repository's scene folder `scenes/<name>` in a fresh temporary folder, with our
/// packed FMUs under resources/; returns (guard, scene folder).
pub fn scene_copy(name: &str) -> (windrive::fmi2::host::archive::TempDir, PathBuf) {
    let tmp = windrive::fmi2::host::archive::TempDir::new("windrive-test-scene").unwrap();
    let dir = tmp.path().join(name);
    let src = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name);
    std::fs::create_dir_all(dir.join("resources")).unwrap();
    for entry in std::fs::read_dir(&src).unwrap().flatten() {
        if entry.path().is_file() {
            std::fs::copy(entry.path(), dir.join(entry.file_name())).unwrap();
        }
    }
    for fmu in ["rotor", "torsional", "generator", "gearbox6dof"] {
        std::fs::copy(fmu_path(fmu), dir.join("resources").join(format!("{fmu}.fmu"))).unwrap();
    }
    (tmp, dir)
}

pub fn torsional() -> Fmu {
    Fmu::open(&torsional_fmu_path()).expect("the packed FMU opens")
}

/// An instance in step mode with string and real parameters applied.
pub fn initialised(fmu: &Fmu, strings: &[(&str, &str)], reals: &[(&str, f64)]) -> Instance {
    let mut inst = fmu.instantiate("test", true).unwrap();
    inst.setup_experiment(0.0, None).unwrap();
    for (name, value) in strings {
        inst.set_string(&[fmu.vr(name).unwrap()], &[value]).unwrap();
    }
    for (name, value) in reals {
        inst.set_real(&[fmu.vr(name).unwrap()], &[*value]).unwrap();
    }
    inst.enter_initialization_mode().unwrap();
    inst.exit_initialization_mode().unwrap();
    inst
}

pub fn get(fmu: &Fmu, inst: &mut Instance, name: &str) -> f64 {
    let mut v = [0.0];
    inst.get_real(&[fmu.vr(name).unwrap()], &mut v).unwrap();
    v[0]
}

pub fn set(fmu: &Fmu, inst: &mut Instance, name: &str, value: f64) {
    inst.set_real(&[fmu.vr(name).unwrap()], &[value]).unwrap();
}

/// Time and the given channels (`component.variable`) of a repository scene run through the master
/// (Gauss–Seidel, 1 ms), with parameter overrides (component, variable, value) and optionally
/// another stop time: columns [time, channel…].
pub fn run_scene(
    scene: &str,
    overrides: &[(&str, &str, &str)],
    channels: &[String],
    stop: Option<f64>,
) -> Vec<Vec<f64>> {
    let (_guard, dir) = scene_copy(scene);
    let scene = windrive::cosim::Scene::open(&dir).unwrap();
    let overrides: Vec<(String, String, String)> = overrides
        .iter()
        .map(|(c, v, x)| (c.to_string(), v.to_string(), x.to_string()))
        .collect();
    let channels: Vec<&str> = channels.iter().map(String::as_str).collect();
    windrive::cosim::master::run_columns(&scene, &overrides, &channels, stop).unwrap()
}

/// Keeps what a model's Rust face says, to check its warnings.
#[derive(Default)]
pub struct Recorder(pub Vec<String>);

impl windrive::fmi2::fmu::slave::Log for Recorder {
    fn warning(&mut self, msg: &str) {
        self.0.push(msg.to_string());
    }
    fn event(&mut self, _: &str) {}
}

/// Runs the ignored test `test` (its module path) of this binary alone under valgrind: no byte
/// definitely or indirectly lost, no invalid read or write (libm's `floor` trips definedness tracking,
/// which is off). Returns valgrind's stdout.
pub fn valgrind_clean(test: &str) -> String {
    let exe = std::env::current_exe().unwrap();
    let out = std::process::Command::new("valgrind")
        .args([
            "--leak-check=full",
            "--errors-for-leak-kinds=definite,indirect",
            "--error-exitcode=9",
            "--undef-value-errors=no",
            "--quiet",
        ])
        .arg(&exe)
        .args(["--ignored", "--exact", test, "--test-threads=1"])
        .output()
        .expect("valgrind runs (apt install valgrind)");
    let report = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "{test}: valgrind found leaks or errors:\n{report}"
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// xorshift64*: random sequences reproducible from their seed (a failure names it).
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    pub fn pick<T: Copy>(&mut self, xs: &[T]) -> T {
        xs[self.below(xs.len())]
    }

    /// Uniform in [-1, 1).
    pub fn symmetric(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// CPU time of this thread: what a call costs, not how long a busy machine (or a paused test) kept
/// it waiting, so a test run at low priority is not failed for a hang it did not have.
pub fn cpu_now() -> std::time::Duration {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: clock_gettime writes the struct it is given.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    std::time::Duration::new(ts.tv_sec as u64, ts.tv_nsec as u32)
}

/// The "measured" cell (the last) of docs/GEARBOX.md's verification-table row whose check starts with
/// `check`: the tests that measure it assert the page quotes what they measure.
pub fn gearbox_doc_measured(check: &str) -> String {
    let page = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/GEARBOX.md")).unwrap();
    let row = page
        .lines()
        .find(|l| l.starts_with(&format!("| {check}")))
        .unwrap_or_else(|| panic!("docs/GEARBOX.md has no verification row \"{check}\""));
    row.trim_end_matches('|').rsplit('|').next().unwrap().trim().to_string()
}

/// Every Real output of a slave through its Rust face, in the order its variables are declared, as bits.
pub fn real_output_bits<S: windrive::fmi2::fmu::slave::Slave>(s: &mut S) -> Vec<u64> {
    use windrive::fmi2::fmu::variables::{Causality, VarType};
    let vrs: Vec<u32> = S::VARIABLES
        .iter()
        .filter(|v| v.ty == VarType::Real && v.causality == Causality::Output)
        .map(|v| v.vr)
        .collect();
    let mut values = vec![0.0; vrs.len()];
    s.get_reals(&vrs, &mut values).unwrap();
    values.into_iter().map(f64::to_bits).collect()
}
