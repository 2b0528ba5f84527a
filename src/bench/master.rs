//! `windrive bench master`: what our master costs beyond the FMUs it drives. The same scene runs
//! (a) through the master (Jacobi, one thread, every connection and recording as in a real run)
//! and (b) through the floor any FMI master pays: per FMU and step one fmi2SetReal of its inputs,
//! one fmi2DoStep, one fmi2GetReal of the coupled outputs, nothing else. (a − b) per FMU-step is
//! the master's own overhead. Best of 5 after a warm-up.

use crate::cosim::{Algorithm, Master, Options, Record, Scene, System};
use std::time::Instant;

fn prepared(scene: &Scene, stop: f64) -> anyhow::Result<System> {
    let record = Record::Only(vec![format!("{}.{}", scene.components[0].name, "generator_speed")]);
    let mut system = System::build(scene, &[], &record)?;
    system.initialize(Some(stop))?;
    Ok(system)
}

/// The master, recording one variable every step into memory.
fn through_master(scene: &Scene, step: f64, stop: f64) -> anyhow::Result<f64> {
    let mut system = prepared(scene, stop)?;
    let mut kept = Vec::with_capacity((stop / step) as usize + 2);
    let started = Instant::now();
    let mut master = Master::new(&mut system, Options::new(Algorithm::Jacobi, step, stop))?;
    master.run(|_, sys| {
        let (_, u, i) = sys.recorded[0];
        kept.push(sys.units[u].values[i]);
        Ok(())
    })?;
    let wall = started.elapsed().as_secs_f64();
    std::hint::black_box(&kept);
    Ok(wall)
}

/// The floor: the FMI calls alone, with the connections precomputed.
fn bare_loop(scene: &Scene, step: f64, stop: f64) -> anyhow::Result<f64> {
    let mut system = prepared(scene, stop)?;
    let n = (stop / step).round() as u64;
    let mut inputs = vec![0.0; system.units.iter().map(|u| u.real_in.vr.len()).max().unwrap_or(0)];
    let started = Instant::now();
    for k in 0..n {
        let t = k as f64 * step;
        for u in 0..system.units.len() {
            let count = system.units[u].real_in.vr.len();
            for (slot, l) in inputs.iter_mut().zip(&system.units[u].real_in.links) {
                *slot = l.factor * system.units[l.src_unit].values[l.src] + l.offset;
            }
            let unit = &mut system.units[u];
            unit.instance.set_real(&unit.real_in.vr, &inputs[..count])?;
        }
        for unit in &mut system.units {
            unit.instance.do_step(t, step)?;
            let nr = unit.coupled.real.len();
            unit.instance.get_real(&unit.coupled.real, &mut unit.values[..nr])?;
        }
    }
    Ok(started.elapsed().as_secs_f64())
}

/// The two ways' best wall times over `steps` macro steps of the scene's own step.
pub struct Overhead {
    pub fmus: f64,
    pub macro_steps: u64,
    pub step_s: f64,
    pub master_s: f64,
    pub bare_fmi_loop_s: f64,
}

impl Overhead {
    /// Wall time per FMU-step, µs.
    pub fn per_fmu_step_us(&self, seconds: f64) -> f64 {
        seconds / (self.macro_steps as f64 * self.fmus) * 1e6
    }

    /// The line `windrive bench master` prints for the scene named `scene`.
    pub fn to_json(&self, scene: &str) -> serde_json::Value {
        let per = |s: f64| self.per_fmu_step_us(s);
        serde_json::json!({
            "scene": scene, "fmus": self.fmus, "macro_steps": self.macro_steps, "step_s": self.step_s,
            "master_s": self.master_s, "bare_fmi_loop_s": self.bare_fmi_loop_s,
            "master_us_per_fmu_step": per(self.master_s), "bare_us_per_fmu_step": per(self.bare_fmi_loop_s),
            "overhead_us_per_fmu_step": per(self.master_s - self.bare_fmi_loop_s),
        })
    }
}

pub fn run(scene: &Scene, steps: u64) -> anyhow::Result<Overhead> {
    let step = scene.experiment.step_size.unwrap_or(1e-3);
    let stop = steps as f64 * step;
    // warm-up: page in the FMUs, settle the CPU clock
    through_master(scene, step, stop / 10.0)?;
    let (mut master, mut floor) = (f64::MAX, f64::MAX);
    for _ in 0..5 {
        master = master.min(through_master(scene, step, stop)?);
        floor = floor.min(bare_loop(scene, step, stop)?);
    }
    Ok(Overhead {
        fmus: scene.components.len() as f64,
        macro_steps: steps,
        step_s: step,
        master_s: master,
        bare_fmi_loop_s: floor,
    })
}
