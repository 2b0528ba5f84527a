//! FMU faces of the physics: each maps one modelDescription's variables onto a model and implements
//! [`crate::fmi2::fmu::slave::Slave`]. The `fmus/<name>` crates only export them. Parameters and
//! inputs come from the generated `crate::models::<name>::{Parameters, Inputs, get_*, set_*}`
//! (build.rs, from the XML); a face writes its outputs, what to drop when a parameter changes,
//! how to build its model and how to step it.

pub mod gearbox6dof;
pub mod generator;
pub mod rotor;
pub mod torsional;

/// The brake's lock and release events of the last step, through the host's logger (logEvents).
pub fn log_brake_events(events: &[crate::solver::Event], log: &mut dyn crate::fmi2::fmu::slave::Log) {
    for e in events {
        let what = if e.locked {
            "locked (stiction)"
        } else {
            "released (slipping)"
        };
        log.event(&format!("t = {:.6} s: HSS brake {what}", e.time));
    }
}

/// Whether two slaves share one build of their model (a state taken since the last parameter
/// change): then the instance's integrator workspace serves the restored state too.
/// Makes `into` share `from`'s build, touching the reference count only when it is another build
/// (a state updated at every macro step then costs no atomic operation here).
pub(crate) fn share_build<B>(into: &mut Option<std::sync::Arc<B>>, from: &Option<std::sync::Arc<B>>) {
    if !same_build(into, from) {
        into.clone_from(from);
    }
}

pub(crate) fn same_build<B>(a: &Option<std::sync::Arc<B>>, b: &Option<std::sync::Arc<B>>) -> bool {
    matches!((a, b), (Some(a), Some(b)) if std::sync::Arc::ptr_eq(a, b))
}
