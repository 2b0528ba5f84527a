//! The one generic adapter that turns a [`Slave`] into every fmi2* symbol of a Co-Simulation FMU.
//!
//! It owns what every FMU must get right and no model should repeat: the FMI state machine (calls in
//! the wrong state are refused with fmi2Error and a log line), null-pointer and value-reference checks,
//! NaN/inf rejection, parameter ranges from the XML, logging through the host's callback, FMU state
//! snapshots and their serialisation, and `catch_unwind` around every entry point so no panic crosses
//! the C boundary. The `export_fmu!` macro (crate root) emits the `#[no_mangle]` symbols that call
//! these functions.
//!
//! # Safety
//! Every function here is `unsafe` because it dereferences pointers handed over by the host. Each one
//! checks for null before reading and never builds a slice from a null pointer, even of length 0.

use super::error::SlaveResult;
use super::slave::{Log, Slave};
use super::variables::{Causality, VarType, Variability, Variable};
use crate::fmi2::types::*;
use crate::fmi2::values::first_non_finite;
use std::ffi::{CStr, CString, c_int};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;

/// FMI 2.0 §4.2.4 states of a Co-Simulation slave. stepFailed and stepCanceled are never entered: a
/// step that fails answers fmi2Error (state Error), and steps never return fmi2Discard or fmi2Pending.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum ModelState {
    Instantiated,
    InitializationMode,
    StepComplete,
    Terminated,
    Error,
    Fatal,
}

use ModelState::*;

const CATEGORIES: [&str; 4] = ["logEvents", "logStatusWarning", "logStatusError", "logCalls"];
/// Categories on when logging is on and none were named: all but the per-call trace, which only a
/// host that names "logCalls" gets (libcosim turns logging on for every FMU).
const DEFAULT_CATEGORIES: [bool; 4] = [true, true, true, false];
const LOG_CALLS: usize = 3;

/// The host's logger and what it wants to hear.
pub struct LogSink {
    instance_name: CString,
    callbacks: Fmi2CallbackFunctions,
    logging_on: bool,
    enabled: [bool; CATEGORIES.len()],
    warned: bool,
}

impl LogSink {
    fn emit(&self, status: Fmi2Status, category: &str, msg: &str) {
        let Some(logger) = self.callbacks.logger else {
            return;
        };
        let always = matches!(status, Fmi2Status::Error | Fmi2Status::Fatal);
        let wanted = self.logging_on && CATEGORIES.iter().zip(self.enabled).any(|(c, on)| on && *c == category);
        if !(always || wanted) {
            return;
        }
        let category = CString::new(category).unwrap_or_default();
        let text = CString::new(msg.replace('\0', " ")).unwrap_or_default();
        // SAFETY: the host gave us this logger; "%s" with one C string is the only safe format.
        unsafe {
            logger(
                self.callbacks.component_environment,
                self.instance_name.as_ptr(),
                status as c_int,
                category.as_ptr(),
                c"%s".as_ptr(),
                text.as_ptr(),
            )
        };
    }

    fn error(&self, msg: &str) {
        self.emit(Fmi2Status::Error, "logStatusError", msg);
    }
}

impl Log for LogSink {
    fn warning(&mut self, msg: &str) {
        self.warned = true;
        self.emit(Fmi2Status::Warning, "logStatusWarning", msg);
    }
    fn event(&mut self, msg: &str) {
        self.emit(Fmi2Status::Ok, "logEvents", msg);
    }
}

/// One FMU instance: what `fmi2Component` points to.
pub struct Instance<S: Slave> {
    sink: LogSink,
    resources: Option<PathBuf>,
    state: ModelState,
    time: f64,
    start_time: f64,
    stop_time: Option<f64>,
    last_successful_time: f64,
    slave: S,
    returned_strings: Vec<CString>,
    /// The last few value-reference arrays of fmi2GetReal whose every reference was a known Real:
    /// a master asks for the same arrays every step (its coupled outputs, its recorded variables),
    /// and an equal array needs no lookups.
    known_reals: Vec<Vec<u32>>,
    /// Every FMU state this instance handed out and the host has not freed: fmi2FreeInstance frees
    /// them (FMI 2.0: the instance owns what it allocated), and a pointer not in here is refused
    /// rather than dereferenced.
    states: Vec<*mut Snapshot<S>>,
}

impl<S: Slave> Drop for Instance<S> {
    fn drop(&mut self) {
        for &p in &self.states {
            // SAFETY: every pointer here came from Box::into_raw and was not freed (freeing removes it).
            drop(unsafe { Box::from_raw(p) });
        }
    }
}

impl<S: Slave> Instance<S> {
    /// The state behind a host's pointer, if this instance handed it out and it is still alive.
    fn owned(&self, state: Fmi2FmuState) -> Result<*mut Snapshot<S>, String> {
        let p = state as *mut Snapshot<S>;
        if self.states.contains(&p) {
            Ok(p)
        } else {
            Err("FMUstate was not handed out by this instance, or was freed already".into())
        }
    }

    /// Hands a new state to the host, tracked until freed.
    fn hand_out(&mut self, snap: Snapshot<S>) -> Fmi2FmuState {
        let p = Box::into_raw(Box::new(snap));
        self.states.push(p);
        p as Fmi2FmuState
    }

    fn release(&mut self, p: *mut Snapshot<S>) {
        self.states.retain(|&q| q != p);
        // SAFETY: `p` was owned (checked by the caller) and is no longer listed.
        drop(unsafe { Box::from_raw(p) });
    }
}

/// A saved FMU state (fmi2GetFMUstate) and the unit of serialisation.
#[derive(Clone, serde::Serialize, serde::Deserialize)]
struct Snapshot<S> {
    state: ModelState,
    time: f64,
    start_time: f64,
    stop_time: Option<f64>,
    last_successful_time: f64,
    slave: S,
}

type CallResult = Result<Fmi2Status, String>;

/// Runs `body` on the instance behind `c` if the call is legal in its state, with panics caught.
/// A refused or failed call logs its reason and moves the instance to the Error state (FMI 2.0:
/// after fmi2Error only get, reset, set-state and free are meaningful). Inlined into each entry
/// point, its only caller: the host's arguments stay in registers instead of being captured by
/// reference and passed on (≈ 30 instructions a call, three calls a communication step).
#[inline(always)]
unsafe fn call<S: Slave>(
    c: Fmi2Component,
    function: &str,
    allowed: &[ModelState],
    body: impl FnOnce(&mut Instance<S>) -> CallResult,
) -> Fmi2Status {
    if c.is_null() {
        return Fmi2Status::Error;
    }
    let ptr = c as *mut Instance<S>;
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: non-null component pointers come from fmi2Instantiate and stay valid until freed.
        let inst = unsafe { &mut *ptr };
        if inst.sink.logging_on && inst.sink.enabled[LOG_CALLS] {
            inst.sink.emit(Fmi2Status::Ok, "logCalls", function);
        }
        if !allowed.contains(&inst.state) {
            return Err(format!("{function} is not allowed in state {:?}", inst.state));
        }
        inst.sink.warned = false;
        let status = body(inst)?;
        Ok(if inst.sink.warned {
            status.max(Fmi2Status::Warning)
        } else {
            status
        })
    }));
    // SAFETY: as above; the closure's borrow has ended.
    let inst = unsafe { &mut *ptr };
    match outcome {
        Ok(Ok(status)) => status,
        Ok(Err(msg)) => {
            inst.sink.error(&format!("{function}: {msg}"));
            if inst.state != Fatal {
                inst.state = Error;
            }
            Fmi2Status::Error
        }
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            inst.state = Fatal;
            inst.sink.emit(
                Fmi2Status::Fatal,
                "logStatusError",
                &format!("{function}: internal error: {what}"),
            );
            Fmi2Status::Fatal
        }
    }
}

const ANY: &[ModelState] = &[Instantiated, InitializationMode, StepComplete, Terminated, Error];
const READABLE: &[ModelState] = &[InitializationMode, StepComplete, Terminated, Error];

unsafe fn c_str<'a>(p: Fmi2String) -> Option<&'a str> {
    if p.is_null() {
        return None;
    }
    // SAFETY: non-null strings from the host are NUL-terminated (FMI 2.0 §2.1.2).
    unsafe { CStr::from_ptr(p) }.to_str().ok()
}

/// `fmuResourceLocation` → directory: `file:///abs`, `file:/abs` and `file://localhost/abs`, percent-decoded.
pub fn resource_dir(uri: &str) -> Option<PathBuf> {
    let rest = uri.strip_prefix("file:")?;
    let path = if let Some(r) = rest.strip_prefix("//") {
        let slash = r.find('/')?;
        let authority = &r[..slash];
        if !(authority.is_empty() || authority.eq_ignore_ascii_case("localhost")) {
            return None;
        }
        &r[slash..]
    } else {
        rest
    };
    let bytes = path.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' && i + 2 < bytes.len() {
            let hex = std::str::from_utf8(&bytes[i + 1..i + 3]).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    Some(PathBuf::from(String::from_utf8(out).ok()?))
}

/// # Safety
/// `instance_name`, `guid` and `resource_location` must be NUL-terminated or null; `functions` a valid
/// pointer or null.
pub unsafe fn instantiate<S: Slave>(
    instance_name: Fmi2String,
    fmu_type: c_int,
    guid: Fmi2String,
    resource_location: Fmi2String,
    functions: *const Fmi2CallbackFunctions,
    _visible: Fmi2Boolean,
    logging_on: Fmi2Boolean,
) -> Fmi2Component {
    let built = catch_unwind(AssertUnwindSafe(|| {
        let callbacks = if functions.is_null() {
            Fmi2CallbackFunctions {
                logger: None,
                allocate_memory: None,
                free_memory: None,
                step_finished: None,
                component_environment: std::ptr::null_mut(),
            }
        } else {
            // SAFETY: checked non-null; copied so the host may drop its struct.
            unsafe { *functions }
        };
        let name = unsafe { c_str(instance_name) }.unwrap_or("");
        let sink = LogSink {
            instance_name: CString::new(if name.is_empty() { S::MODEL_IDENTIFIER } else { name }).unwrap_or_default(),
            callbacks,
            logging_on: logging_on != FMI2_FALSE,
            enabled: DEFAULT_CATEGORIES,
            warned: false,
        };
        let refuse = |msg: String| {
            sink.error(&format!("fmi2Instantiate: {msg}"));
            None
        };
        if instance_name.is_null() || name.is_empty() {
            return refuse("instanceName is null or empty".into());
        }
        if fmu_type != FMI2_CO_SIMULATION {
            return refuse(format!(
                "fmuType {fmu_type} requested, this FMU supports only fmi2CoSimulation (1)"
            ));
        }
        match unsafe { c_str(guid) } {
            Some(g) if g == S::GUID => {}
            Some(g) => return refuse(format!("GUID {g} does not match this binary's {}", S::GUID)),
            None => return refuse("fmuGUID is null".into()),
        }
        let resources = unsafe { c_str(resource_location) }.and_then(resource_dir);
        let slave = S::instantiate(resources.as_deref());
        Some(Box::new(Instance {
            sink,
            resources,
            state: Instantiated,
            time: 0.0,
            start_time: 0.0,
            stop_time: None,
            last_successful_time: 0.0,
            slave,
            returned_strings: Vec::new(),
            known_reals: Vec::new(),
            states: Vec::new(),
        }))
    }));
    match built {
        Ok(Some(inst)) => Box::into_raw(inst) as Fmi2Component,
        _ => std::ptr::null_mut(),
    }
}

/// # Safety
/// `c` must come from [`instantiate`] of the same `S` and not be freed yet, or be null.
pub unsafe fn free_instance<S: Slave>(c: Fmi2Component) {
    if c.is_null() {
        return;
    }
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the host hands back the pointer fmi2Instantiate gave it, exactly once.
        drop(unsafe { Box::from_raw(c as *mut Instance<S>) });
    }));
}

/// # Safety
/// As [`free_instance`]; `categories` holds `n` C strings or is null when `n` is 0.
pub unsafe fn set_debug_logging<S: Slave>(
    c: Fmi2Component,
    logging_on: Fmi2Boolean,
    n: usize,
    categories: *const Fmi2String,
) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2SetDebugLogging", ANY, |inst| {
            let mut enabled = if n == 0 {
                DEFAULT_CATEGORIES
            } else {
                [false; CATEGORIES.len()]
            };
            if n > 0 {
                if categories.is_null() {
                    return Err(format!("{n} categories announced but the array is null"));
                }
                for &p in std::slice::from_raw_parts(categories, n) {
                    let name = c_str(p).ok_or("a category is null")?;
                    let i = CATEGORIES
                        .iter()
                        .position(|c| *c == name)
                        .ok_or_else(|| format!("unknown log category {name:?}; known: {}", CATEGORIES.join(", ")))?;
                    enabled[i] = true;
                }
            }
            inst.sink.logging_on = logging_on != FMI2_FALSE;
            inst.sink.enabled = enabled;
            Ok(Fmi2Status::Ok)
        })
    }
}

/// # Safety
/// As [`free_instance`].
pub unsafe fn setup_experiment<S: Slave>(
    c: Fmi2Component,
    _tolerance_defined: Fmi2Boolean,
    _tolerance: f64,
    start_time: f64,
    stop_time_defined: Fmi2Boolean,
    stop_time: f64,
) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2SetupExperiment", &[Instantiated], |inst| {
            if !start_time.is_finite() {
                return Err(format!("startTime {start_time} is not finite"));
            }
            let stop = (stop_time_defined != FMI2_FALSE).then_some(stop_time);
            if let Some(stop) = stop
                && (!stop.is_finite() || stop < start_time)
            {
                return Err(format!(
                    "stopTime {stop} is not finite or lies before startTime {start_time}"
                ));
            }
            inst.start_time = start_time;
            inst.time = start_time;
            inst.last_successful_time = start_time;
            inst.stop_time = stop;
            Ok(Fmi2Status::Ok)
        })
    }
}

/// # Safety
/// As [`free_instance`].
pub unsafe fn enter_initialization_mode<S: Slave>(c: Fmi2Component) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2EnterInitializationMode", &[Instantiated], |inst| {
            inst.state = InitializationMode;
            Ok(Fmi2Status::Ok)
        })
    }
}

/// # Safety
/// As [`free_instance`].
pub unsafe fn exit_initialization_mode<S: Slave>(c: Fmi2Component) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2ExitInitializationMode", &[InitializationMode], |inst| {
            inst.slave
                .initialize(inst.start_time, &mut inst.sink)
                .map_err(|e| e.0)?;
            inst.state = StepComplete;
            Ok(Fmi2Status::Ok)
        })
    }
}

/// # Safety
/// As [`free_instance`].
pub unsafe fn terminate<S: Slave>(c: Fmi2Component) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2Terminate", &[StepComplete, Error], |inst| {
            inst.state = Terminated;
            Ok(Fmi2Status::Ok)
        })
    }
}

/// # Safety
/// As [`free_instance`].
pub unsafe fn reset<S: Slave>(c: Fmi2Component) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2Reset", ANY, |inst| {
            inst.slave = S::instantiate(inst.resources.as_deref());
            inst.state = Instantiated;
            inst.time = 0.0;
            inst.start_time = 0.0;
            inst.stop_time = None;
            inst.last_successful_time = 0.0;
            Ok(Fmi2Status::Ok)
        })
    }
}

/// Checks a value reference: it exists with this type. The checks here run for every value a host
/// gets or sets, so they are inlined and their messages built out of line (`#[cold]`): with the
/// formatting inside them they stayed calls of 15 instructions each per value (callgrind).
#[inline]
fn known<S: Slave>(ty: VarType, vr: u32) -> Result<&'static Variable, String> {
    match S::variable(ty, vr) {
        Some(v) => Ok(v),
        None => Err(unknown(ty, vr)),
    }
}

#[cold]
fn unknown(ty: VarType, vr: u32) -> String {
    format!("unknown {ty:?} value reference {vr}")
}

/// Checks that a variable may be set now (FMI 2.0 §4.2.4).
#[inline]
fn settable(v: &Variable, state: ModelState) -> Result<(), String> {
    if settable_in(v, state) {
        Ok(())
    } else {
        Err(not_settable(v, state))
    }
}

#[inline]
fn settable_in(v: &Variable, state: ModelState) -> bool {
    match v.causality {
        Causality::Input => matches!(state, Instantiated | InitializationMode | StepComplete),
        Causality::Parameter => match v.variability {
            Variability::Tunable => {
                matches!(state, Instantiated | InitializationMode | StepComplete)
            }
            Variability::Fixed => matches!(state, Instantiated | InitializationMode),
            _ => false,
        },
        _ => false,
    }
}

#[cold]
fn not_settable(v: &Variable, state: ModelState) -> String {
    format!(
        "{} ({:?} {:?}) cannot be set in state {state:?}",
        v.name, v.variability, v.causality
    )
}

/// Refuses NaN and infinities. The XML's min/max are the model's to check: the generated
/// `models::<name>::Parameters` setters refuse a parameter outside them, Real and Integer alike.
#[inline]
fn check_real(v: &Variable, value: f64) -> Result<(), String> {
    if !value.is_finite() {
        return Err(not_finite_input(v, value));
    }
    Ok(())
}

#[cold]
fn not_finite_input(v: &Variable, value: f64) -> String {
    format!("{} = {value} rejected: not a finite number", v.name)
}

/// Pairs the host's value-reference and value arrays, refusing null pointers when n > 0.
unsafe fn arrays<'a, T>(
    vr: *const Fmi2ValueReference,
    n: usize,
    values: *const T,
) -> Result<(&'a [u32], &'a [T]), String> {
    if n == 0 {
        return Ok((&[], &[]));
    }
    if vr.is_null() || values.is_null() {
        return Err(format!("null value-reference or value array for {n} variables"));
    }
    // SAFETY: checked non-null; the host promises n elements.
    Ok(unsafe { (std::slice::from_raw_parts(vr, n), std::slice::from_raw_parts(values, n)) })
}

unsafe fn arrays_mut<'a, T>(
    vr: *const Fmi2ValueReference,
    n: usize,
    values: *mut T,
) -> Result<(&'a [u32], &'a mut [T]), String> {
    if n == 0 {
        return Ok((&[], &mut []));
    }
    if vr.is_null() || values.is_null() {
        return Err(format!("null value-reference or value array for {n} variables"));
    }
    // SAFETY: checked non-null; the host promises n elements.
    Ok(unsafe {
        (
            std::slice::from_raw_parts(vr, n),
            std::slice::from_raw_parts_mut(values, n),
        )
    })
}

/// A computed value (output, calculated parameter, local) must be finite: a model whose outputs
/// became inf or NaN says so with an error naming the variable, rather than handing them on with OK.
trait Finite {
    fn finite(&self) -> bool;
}

impl Finite for f64 {
    fn finite(&self) -> bool {
        self.is_finite()
    }
}

impl Finite for i32 {
    fn finite(&self) -> bool {
        true
    }
}

impl Finite for bool {
    fn finite(&self) -> bool {
        true
    }
}

#[inline]
fn check_computed<T: Finite + std::fmt::Debug>(var: &Variable, v: &T) -> Result<(), String> {
    let computed = matches!(
        var.causality,
        Causality::Output | Causality::CalculatedParameter | Causality::Local
    );
    if computed && !v.finite() {
        return Err(not_finite_output(var, v));
    }
    Ok(())
}

#[cold]
fn not_finite_output<T: std::fmt::Debug>(var: &Variable, v: &T) -> String {
    format!(
        "{} = {v:?} is not finite: the model's state or inputs are out of range",
        var.name
    )
}

/// Value by value: each reference looked up, read, and checked finite when the model computes it; the
/// first variable at fault is named. Every getter's path, and fmi2GetReal's whenever its array path
/// finds something amiss.
fn read_each<S: Slave, V: Finite + std::fmt::Debug, T>(
    slave: &mut S,
    ty: VarType,
    vrs: &[u32],
    out: &mut [T],
    read: impl Fn(&mut S, u32) -> SlaveResult<V>,
    conv: impl Fn(V) -> T,
) -> CallResult {
    for (r, o) in vrs.iter().zip(out.iter_mut()) {
        let var = known::<S>(ty, *r)?;
        let v = read(slave, *r).map_err(|e| e.0)?;
        check_computed(var, &v)?;
        *o = conv(v);
    }
    Ok(Fmi2Status::Ok)
}

macro_rules! getter {
    ($name:ident, $fmi:literal, $t:ty, $ty:expr, $method:ident, $conv:expr) => {
        /// # Safety
        /// `c` as [`free_instance`]; `vr` and `value` hold `n` elements or are null when `n` is 0.
        pub unsafe fn $name<S: Slave>(
            c: Fmi2Component,
            vr: *const Fmi2ValueReference,
            n: usize,
            value: *mut $t,
        ) -> Fmi2Status {
            unsafe {
                call::<S>(c, $fmi, READABLE, |inst| {
                    let (vrs, out) = arrays_mut(vr, n, value)?;
                    read_each(&mut inst.slave, $ty, vrs, out, |s, r| s.$method(r), $conv)
                })
            }
        }
    };
}

/// How many value-reference arrays an instance remembers as checked ([`Instance::known_reals`]),
/// and the shortest it remembers: a short array is checked as fast as it is compared, and a host that
/// reads one variable at a time would otherwise have an allocation per call.
const KNOWN_ARRAYS: usize = 4;
const KNOWN_MIN_LEN: usize = 8;

/// # Safety
/// `c` as [`free_instance`]; `vr` and `value` hold `n` elements or are null when `n` is 0.
///
/// One lookup pass (none when the array equals one of the last checked), one call into the model
/// ([`Slave::get_reals`]) and one finiteness scan for the whole array: a master reading a row of
/// recorded variables pays per value only what the model computes. Anything amiss (an unknown
/// reference, a model error, a value that is not finite) is answered by the value-by-value path,
/// whose error names the first variable at fault, as it always did.
pub unsafe fn get_real<S: Slave>(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *mut f64,
) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2GetReal", READABLE, |inst| {
            let (vrs, out) = arrays_mut(vr, n, value)?;
            let all_known = inst.known_reals.iter().any(|k| k.as_slice() == vrs)
                || vrs.iter().all(|&r| S::variable(VarType::Real, r).is_some()) && {
                    if vrs.len() >= KNOWN_MIN_LEN {
                        if inst.known_reals.len() == KNOWN_ARRAYS {
                            inst.known_reals.remove(0);
                        }
                        inst.known_reals.push(vrs.to_vec());
                    }
                    true
                };
            if all_known && inst.slave.get_reals(vrs, out).is_ok() && first_non_finite(out).is_none() {
                return Ok(Fmi2Status::Ok);
            }
            read_each(&mut inst.slave, VarType::Real, vrs, out, |s, r| s.get_real(r), |v| v)
        })
    }
}

getter!(
    get_integer,
    "fmi2GetInteger",
    c_int,
    VarType::Integer,
    get_integer,
    |v| v
);
getter!(
    get_boolean,
    "fmi2GetBoolean",
    Fmi2Boolean,
    VarType::Boolean,
    get_boolean,
    |v: bool| v as Fmi2Boolean
);

/// # Safety
/// As [`get_real`]. The returned strings stay valid until the next fmi2GetString on this instance.
pub unsafe fn get_string<S: Slave>(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *mut Fmi2String,
) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2GetString", READABLE, |inst| {
            let (vrs, out) = arrays_mut(vr, n, value)?;
            let mut strings = Vec::with_capacity(n);
            for r in vrs {
                known::<S>(VarType::String, *r)?;
                let s = inst.slave.get_string(*r).map_err(|e| e.0)?;
                strings.push(CString::new(s).map_err(|_| "string contains NUL")?);
            }
            for (o, s) in out.iter_mut().zip(&strings) {
                *o = s.as_ptr();
            }
            // kept by the instance until its next fmi2GetString (FMI 2.0 §2.1.7)
            inst.returned_strings = strings;
            Ok(Fmi2Status::Ok)
        })
    }
}

const SETTABLE: &[ModelState] = &[Instantiated, InitializationMode, StepComplete];

/// # Safety
/// `c` as [`free_instance`]; `vr` and `value` hold `n` elements or are null when `n` is 0.
pub unsafe fn set_real<S: Slave>(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *const f64,
) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2SetReal", SETTABLE, |inst| {
            let (vrs, vals) = arrays(vr, n, value)?;
            for (r, v) in vrs.iter().zip(vals) {
                let var = known::<S>(VarType::Real, *r)?;
                settable(var, inst.state)?;
                check_real(var, *v)?;
                inst.slave.set_real(*r, *v, &mut inst.sink).map_err(|e| e.0)?;
            }
            Ok(Fmi2Status::Ok)
        })
    }
}

/// # Safety
/// As [`set_real`].
pub unsafe fn set_integer<S: Slave>(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *const c_int,
) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2SetInteger", SETTABLE, |inst| {
            let (vrs, vals) = arrays(vr, n, value)?;
            for (r, v) in vrs.iter().zip(vals) {
                let var = known::<S>(VarType::Integer, *r)?;
                settable(var, inst.state)?;
                inst.slave.set_integer(*r, *v, &mut inst.sink).map_err(|e| e.0)?;
            }
            Ok(Fmi2Status::Ok)
        })
    }
}

/// # Safety
/// As [`set_real`].
pub unsafe fn set_boolean<S: Slave>(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *const Fmi2Boolean,
) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2SetBoolean", SETTABLE, |inst| {
            let (vrs, vals) = arrays(vr, n, value)?;
            for (r, v) in vrs.iter().zip(vals) {
                let var = known::<S>(VarType::Boolean, *r)?;
                settable(var, inst.state)?;
                inst.slave
                    .set_boolean(*r, *v != FMI2_FALSE, &mut inst.sink)
                    .map_err(|e| e.0)?;
            }
            Ok(Fmi2Status::Ok)
        })
    }
}

/// # Safety
/// As [`set_real`]; every string is NUL-terminated.
pub unsafe fn set_string<S: Slave>(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *const Fmi2String,
) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2SetString", SETTABLE, |inst| {
            let (vrs, vals) = arrays(vr, n, value)?;
            for (r, v) in vrs.iter().zip(vals) {
                let var = known::<S>(VarType::String, *r)?;
                settable(var, inst.state)?;
                let s = c_str(*v).ok_or_else(|| format!("{}: null or non-UTF-8 string", var.name))?;
                inst.slave.set_string(*r, s, &mut inst.sink).map_err(|e| e.0)?;
            }
            Ok(Fmi2Status::Ok)
        })
    }
}

fn snapshot<S: Slave>(inst: &Instance<S>) -> Snapshot<S> {
    Snapshot {
        state: inst.state,
        time: inst.time,
        start_time: inst.start_time,
        stop_time: inst.stop_time,
        last_successful_time: inst.last_successful_time,
        slave: inst.slave.snapshot(),
    }
}

fn restore<S: Slave>(inst: &mut Instance<S>, snap: &Snapshot<S>) -> Result<(), String> {
    inst.state = snap.state;
    inst.time = snap.time;
    inst.start_time = snap.start_time;
    inst.stop_time = snap.stop_time;
    inst.last_successful_time = snap.last_successful_time;
    inst.slave.restore(&snap.slave);
    Ok(())
}

/// # Safety
/// `c` as [`free_instance`]; `state` points to null or to a state from this function.
pub unsafe fn get_fmu_state<S: Slave>(c: Fmi2Component, state: *mut Fmi2FmuState) -> Fmi2Status {
    unsafe {
        call::<S>(
            c,
            "fmi2GetFMUstate",
            &[Instantiated, InitializationMode, StepComplete, Terminated],
            |inst| {
                if state.is_null() {
                    return Err("FMUstate pointer is null".into());
                }
                if (*state).is_null() {
                    let snap = snapshot(inst);
                    *state = inst.hand_out(snap);
                } else {
                    // FMI 2.0: a non-null *FMUstate is updated in place (reusing its allocations).
                    let into = &mut *inst.owned(*state)?;
                    into.state = inst.state;
                    into.time = inst.time;
                    into.start_time = inst.start_time;
                    into.stop_time = inst.stop_time;
                    into.last_successful_time = inst.last_successful_time;
                    inst.slave.snapshot_into(&mut into.slave);
                }
                inst.slave.state_taken();
                Ok(Fmi2Status::Ok)
            },
        )
    }
}

/// # Safety
/// `c` as [`free_instance`]; `state` from [`get_fmu_state`] or [`deserialize_fmu_state`] of this FMU.
pub unsafe fn set_fmu_state<S: Slave>(c: Fmi2Component, state: Fmi2FmuState) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2SetFMUstate", ANY, |inst| {
            if state.is_null() {
                return Err("FMUstate is null".into());
            }
            let snap = &*inst.owned(state)?;
            restore(inst, snap)?;
            Ok(Fmi2Status::Ok)
        })
    }
}

/// # Safety
/// As [`set_fmu_state`]; `*state` is set to null.
pub unsafe fn free_fmu_state<S: Slave>(c: Fmi2Component, state: *mut Fmi2FmuState) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2FreeFMUstate", ANY, |inst| {
            if state.is_null() {
                return Err("FMUstate pointer is null".into());
            }
            if !(*state).is_null() {
                let p = inst.owned(*state)?;
                inst.release(p);
                *state = std::ptr::null_mut();
            }
            Ok(Fmi2Status::Ok)
        })
    }
}

/// A serialised state: "WDST", the format version, the payload's length and its CRC-32, then the
/// payload (postcard). A flipped bit, a truncated or padded buffer, another version: all refused.
const STATE_MAGIC: &[u8; 4] = b"WDST";
const STATE_FORMAT: u32 = 1;
const STATE_HEADER: usize = 16;

fn encode<S: Slave>(snap: &Snapshot<S>) -> Result<Vec<u8>, String> {
    let payload = postcard::to_allocvec(&(S::GUID, snap)).map_err(|e| format!("cannot serialise state: {e}"))?;
    let mut out = Vec::with_capacity(STATE_HEADER + payload.len());
    out.extend_from_slice(STATE_MAGIC);
    out.extend_from_slice(&STATE_FORMAT.to_le_bytes());
    out.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    out.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
    out.extend_from_slice(&payload);
    Ok(out)
}

fn decode<S: Slave>(data: &[u8]) -> Result<Snapshot<S>, String> {
    let word = |k: usize| u32::from_le_bytes(data[4 * k..4 * k + 4].try_into().expect("4 bytes"));
    if data.len() < STATE_HEADER || &data[..4] != STATE_MAGIC {
        return Err(format!(
            "corrupt serialised state: {} bytes without the WDST header",
            data.len()
        ));
    }
    if word(1) != STATE_FORMAT {
        return Err(format!(
            "serialised state has format {}, this FMU reads {STATE_FORMAT}",
            word(1)
        ));
    }
    let payload = &data[STATE_HEADER..];
    if payload.len() != word(2) as usize {
        return Err(format!(
            "corrupt serialised state: {} payload bytes where the header says {}",
            payload.len(),
            word(2)
        ));
    }
    if crc32fast::hash(payload) != word(3) {
        return Err("corrupt serialised state: checksum mismatch".into());
    }
    let ((guid, snap), rest): ((String, Snapshot<S>), _) =
        postcard::take_from_bytes(payload).map_err(|e| format!("corrupt serialised state: {e}"))?;
    if !rest.is_empty() {
        return Err(format!(
            "corrupt serialised state: {} bytes after the state",
            rest.len()
        ));
    }
    if guid != S::GUID {
        return Err(format!(
            "serialised state belongs to GUID {guid}, this FMU is {}",
            S::GUID
        ));
    }
    Ok(snap)
}

/// # Safety
/// As [`set_fmu_state`]; `size` is writable.
pub unsafe fn serialized_fmu_state_size<S: Slave>(
    c: Fmi2Component,
    state: Fmi2FmuState,
    size: *mut usize,
) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2SerializedFMUstateSize", ANY, |inst| {
            if state.is_null() || size.is_null() {
                return Err("FMUstate or size pointer is null".into());
            }
            *size = encode(&*inst.owned(state)?)?.len();
            Ok(Fmi2Status::Ok)
        })
    }
}

/// # Safety
/// As [`set_fmu_state`]; `bytes` has room for `size` bytes.
pub unsafe fn serialize_fmu_state<S: Slave>(
    c: Fmi2Component,
    state: Fmi2FmuState,
    bytes: *mut Fmi2Byte,
    size: usize,
) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2SerializeFMUstate", ANY, |inst| {
            if state.is_null() || bytes.is_null() {
                return Err("FMUstate or byte buffer is null".into());
            }
            let encoded = encode(&*inst.owned(state)?)?;
            if encoded.len() > size {
                return Err(format!(
                    "buffer of {size} bytes is smaller than the state ({} bytes)",
                    encoded.len()
                ));
            }
            std::ptr::copy_nonoverlapping(encoded.as_ptr(), bytes as *mut u8, encoded.len());
            Ok(Fmi2Status::Ok)
        })
    }
}

/// # Safety
/// `c` as [`free_instance`]; `bytes` holds `size` bytes; `state` is writable.
pub unsafe fn deserialize_fmu_state<S: Slave>(
    c: Fmi2Component,
    bytes: *const Fmi2Byte,
    size: usize,
    state: *mut Fmi2FmuState,
) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2DeSerializeFMUstate", ANY, |inst| {
            if bytes.is_null() || state.is_null() {
                return Err("byte buffer or FMUstate pointer is null".into());
            }
            let data = std::slice::from_raw_parts(bytes as *const u8, size);
            let snap: Snapshot<S> = decode(data)?;
            if !(*state).is_null() {
                let p = inst.owned(*state)?;
                inst.release(p);
            }
            *state = inst.hand_out(snap);
            Ok(Fmi2Status::Ok)
        })
    }
}

/// # Safety
/// As [`free_instance`].
pub unsafe fn get_directional_derivative<S: Slave>(c: Fmi2Component) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2GetDirectionalDerivative", ANY, |_| {
            Err("not provided (providesDirectionalDerivative=\"false\" in modelDescription.xml)".into())
        })
    }
}

/// # Safety
/// `c` as [`free_instance`]; the three arrays hold `n` elements or are null when `n` is 0.
pub unsafe fn set_real_input_derivatives<S: Slave>(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    order: *const Fmi2Integer,
    value: *const f64,
) -> Fmi2Status {
    unsafe {
        call::<S>(
            c,
            "fmi2SetRealInputDerivatives",
            &[InitializationMode, StepComplete],
            |inst| {
                let (vrs, vals) = arrays(vr, n, value)?;
                let (_, orders) = arrays(vr, n, order)?;
                for ((r, v), o) in vrs.iter().zip(vals).zip(orders) {
                    let var = known::<S>(VarType::Real, *r)?;
                    if var.causality != Causality::Input {
                        return Err(format!("{} is not an input", var.name));
                    }
                    if !v.is_finite() {
                        return Err(format!("derivative of {} = {v} rejected: not finite", var.name));
                    }
                    inst.slave
                        .set_input_derivative(*r, *o, *v)
                        .map_err(|e| format!("{}: {e}", var.name))?;
                }
                Ok(Fmi2Status::Ok)
            },
        )
    }
}

/// # Safety
/// As [`free_instance`].
pub unsafe fn get_real_output_derivatives<S: Slave>(c: Fmi2Component) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2GetRealOutputDerivatives", ANY, |_| {
            Err("not provided (maxOutputDerivativeOrder=\"0\" in modelDescription.xml)".into())
        })
    }
}

/// # Safety
/// As [`free_instance`].
pub unsafe fn do_step<S: Slave>(c: Fmi2Component, t: f64, h: f64, _no_set_prior: Fmi2Boolean) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2DoStep", &[StepComplete], |inst| {
            if !t.is_finite() || !h.is_finite() {
                return Err(format!(
                    "currentCommunicationPoint {t} or communicationStepSize {h} is not finite"
                ));
            }
            if h <= 0.0 {
                return Err(format!("communicationStepSize {h} must be positive"));
            }
            let tolerance = 1e-9 * (1.0 + t.abs());
            if (t - inst.time).abs() > tolerance {
                return Err(format!(
                    "currentCommunicationPoint {t} does not match the FMU's time {}; steps must be contiguous \
                     (roll back with fmi2SetFMUstate to repeat a step)",
                    inst.time
                ));
            }
            if let Some(stop) = inst.stop_time
                && t + h > stop + 1e-9 * (1.0 + stop.abs())
            {
                return Err(format!(
                    "step to {} passes the stopTime {stop} given in fmi2SetupExperiment",
                    t + h
                ));
            }
            match inst.slave.do_step(t, h, &mut inst.sink) {
                Ok(()) => {
                    inst.time = t + h;
                    inst.last_successful_time = inst.time;
                    Ok(Fmi2Status::Ok)
                }
                Err(e) => Err(format!("step from t = {t} s by {h} s failed: {e}")),
            }
        })
    }
}

/// # Safety
/// As [`free_instance`].
pub unsafe fn cancel_step<S: Slave>(c: Fmi2Component) -> Fmi2Status {
    unsafe {
        call::<S>(c, "fmi2CancelStep", ANY, |_| {
            Err("no step in progress: fmi2DoStep always completes before returning (never fmi2Pending)".into())
        })
    }
}

/// The five status queries share one shape: a null check, then either an answer for the kinds this
/// FMU knows (fmi2OK) or fmi2Discard, as FMI 2.0 prescribes for unsupported kinds.
unsafe fn status_query<S: Slave, T>(
    c: Fmi2Component,
    function: &str,
    value: *mut T,
    answer: impl FnOnce(&Instance<S>) -> Option<T>,
) -> Fmi2Status {
    unsafe {
        call::<S>(c, function, ANY, |inst| {
            if value.is_null() {
                return Err("status pointer is null".into());
            }
            Ok(match answer(inst) {
                Some(v) => {
                    *value = v;
                    Fmi2Status::Ok
                }
                None => Fmi2Status::Discard,
            })
        })
    }
}

/// # Safety
/// `c` as [`free_instance`]; `value` writable.
pub unsafe fn get_status<S: Slave>(c: Fmi2Component, _kind: c_int, value: *mut c_int) -> Fmi2Status {
    // Only fmi2DoStepStatus exists here, and only after fmi2Pending, which this FMU never returns.
    unsafe { status_query::<S, c_int>(c, "fmi2GetStatus", value, |_| None) }
}

/// # Safety
/// `c` as [`free_instance`]; `value` writable.
pub unsafe fn get_real_status<S: Slave>(c: Fmi2Component, kind: c_int, value: *mut f64) -> Fmi2Status {
    unsafe {
        status_query::<S, f64>(c, "fmi2GetRealStatus", value, |inst| {
            (kind == FMI2_LAST_SUCCESSFUL_TIME).then_some(inst.last_successful_time)
        })
    }
}

/// # Safety
/// `c` as [`free_instance`]; `value` writable.
pub unsafe fn get_integer_status<S: Slave>(c: Fmi2Component, _kind: c_int, value: *mut c_int) -> Fmi2Status {
    unsafe { status_query::<S, c_int>(c, "fmi2GetIntegerStatus", value, |_| None) }
}

/// # Safety
/// `c` as [`free_instance`]; `value` writable.
pub unsafe fn get_boolean_status<S: Slave>(c: Fmi2Component, kind: c_int, value: *mut Fmi2Boolean) -> Fmi2Status {
    unsafe {
        status_query::<S, Fmi2Boolean>(c, "fmi2GetBooleanStatus", value, |inst| {
            // a failed step cannot be continued: the master should terminate (or roll back)
            (kind == FMI2_TERMINATED).then_some((inst.state == Error) as Fmi2Boolean)
        })
    }
}

/// # Safety
/// `c` as [`free_instance`]; `value` writable.
pub unsafe fn get_string_status<S: Slave>(c: Fmi2Component, _kind: c_int, value: *mut Fmi2String) -> Fmi2Status {
    unsafe { status_query::<S, Fmi2String>(c, "fmi2GetStringStatus", value, |_| None) }
}

#[cfg(test)]
mod tests {
    //! The adapter's own guarantees, checked on a deliberately misbehaving model.
    use super::*;
    use crate::fmi2::fmu::error::{SlaveError, SlaveResult};
    use crate::fmi2::fmu::variables::Start;

    static VARS: [Variable; 1] = [Variable {
        name: "x",
        vr: 0,
        ty: VarType::Real,
        causality: Causality::Output,
        variability: Variability::Continuous,
        start: Start::None,
        min: None,
        max: None,
    }];

    #[derive(Clone, serde::Serialize, serde::Deserialize)]
    struct Panicky;

    impl Slave for Panicky {
        const MODEL_IDENTIFIER: &'static str = "panicky";
        const GUID: &'static str = "{panicky}";
        const MODEL_DESCRIPTION_XML: &'static str = "";
        const VARIABLES: &'static [Variable] = &VARS;
        fn variable(ty: VarType, vr: u32) -> Option<&'static Variable> {
            super::super::variables::lookup(&VARS, ty, vr)
        }
        fn instantiate(_: Option<&std::path::Path>) -> Self {
            Panicky
        }
        fn get_real(&mut self, _: u32) -> SlaveResult<f64> {
            panic!("model bug in get_real")
        }
        fn set_real(&mut self, _: u32, _: f64, _: &mut dyn Log) -> SlaveResult<()> {
            Ok(())
        }
        fn get_integer(&mut self, _: u32) -> SlaveResult<i32> {
            Err(SlaveError::new("none"))
        }
        fn set_integer(&mut self, _: u32, _: i32, _: &mut dyn Log) -> SlaveResult<()> {
            Ok(())
        }
        fn get_boolean(&mut self, _: u32) -> SlaveResult<bool> {
            Err(SlaveError::new("none"))
        }
        fn set_boolean(&mut self, _: u32, _: bool, _: &mut dyn Log) -> SlaveResult<()> {
            Ok(())
        }
        fn get_string(&mut self, _: u32) -> SlaveResult<String> {
            Err(SlaveError::new("none"))
        }
        fn set_string(&mut self, _: u32, _: &str, _: &mut dyn Log) -> SlaveResult<()> {
            Ok(())
        }
        fn initialize(&mut self, _: f64, _: &mut dyn Log) -> SlaveResult<()> {
            Ok(())
        }
        fn do_step(&mut self, _: f64, _: f64, _: &mut dyn Log) -> SlaveResult<()> {
            let v: Vec<f64> = Vec::new();
            let _ = v[3]; // index out of bounds: a panic
            Ok(())
        }
    }

    fn instance() -> Fmi2Component {
        let name = CString::new("p").unwrap();
        let guid = CString::new("{panicky}").unwrap();
        unsafe {
            instantiate::<Panicky>(
                name.as_ptr(),
                FMI2_CO_SIMULATION,
                guid.as_ptr(),
                std::ptr::null(),
                std::ptr::null(),
                0,
                0,
            )
        }
    }

    #[test]
    fn a_panicking_model_answers_fatal_and_the_instance_stays_freeable() {
        let c = instance();
        assert!(!c.is_null());
        unsafe {
            assert_eq!(setup_experiment::<Panicky>(c, 0, 0.0, 0.0, 0, 0.0), Fmi2Status::Ok);
            assert_eq!(enter_initialization_mode::<Panicky>(c), Fmi2Status::Ok);
            assert_eq!(exit_initialization_mode::<Panicky>(c), Fmi2Status::Ok);
            assert_eq!(do_step::<Panicky>(c, 0.0, 0.1, 1), Fmi2Status::Fatal);
            // fatal: nothing but free is allowed any more
            assert_eq!(do_step::<Panicky>(c, 0.0, 0.1, 1), Fmi2Status::Error);
            assert_eq!(reset::<Panicky>(c), Fmi2Status::Error);
            free_instance::<Panicky>(c);
        }
        let c = instance();
        unsafe {
            enter_initialization_mode::<Panicky>(c);
            let mut x = [0.0];
            assert_eq!(
                get_real::<Panicky>(c, [0].as_ptr(), 1, x.as_mut_ptr()),
                Fmi2Status::Fatal
            );
            free_instance::<Panicky>(c);
        }
    }

    #[test]
    fn resource_locations_in_every_form_importers_use() {
        let p = |s: &str| resource_dir(s).map(|p| p.to_string_lossy().into_owned());
        assert_eq!(p("file:///tmp/a/resources").as_deref(), Some("/tmp/a/resources"));
        assert_eq!(p("file:/tmp/a/resources").as_deref(), Some("/tmp/a/resources"));
        assert_eq!(p("file://localhost/tmp/a").as_deref(), Some("/tmp/a"));
        assert_eq!(
            p("file:///tmp/my%20dir/%C3%BC/resources").as_deref(),
            Some("/tmp/my dir/\u{fc}/resources")
        );
        assert_eq!(p("file://otherhost/tmp"), None);
        assert_eq!(p("http://x/y"), None);
        assert_eq!(p("file:///bad%zz"), None);
    }
}
