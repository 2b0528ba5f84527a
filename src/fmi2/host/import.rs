//! Host side of FMI 2.0 Co-Simulation: open an `.fmu` (or an unpacked folder), resolve all 34
//! symbols up front, and drive instances through a safe [`Instance`] whose every call returns a
//! `Result` the caller must handle. Messages an FMU logs are collected per instance.

use super::archive::{TempDir, unzip};
use super::description::ModelDescription;
use super::error::{ImportError, LogRecord};
use super::state::SavedState;
use crate::fmi2::types::*;
use libloading::Library;
use std::ffi::{CStr, CString, c_char, c_int, c_void};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// dlopen of an FMU binary; the error text carries dlerror's (missing library, undefined symbol).
fn open_library(path: &Path) -> Result<Library, String> {
    // SAFETY: loading runs the library's initialisers; an FMU binary is trusted code by design.
    unsafe { Library::new(path) }.map_err(|e| {
        let why = std::error::Error::source(&e).map(|w| w.to_string()).unwrap_or_default();
        format!("{e}: {why}")
    })
}

/// Whether a dlopen failure is the Python C API missing from the process.
fn needs_python(dlerror: &str) -> bool {
    dlerror.contains("undefined symbol: Py") || dlerror.contains("undefined symbol: _Py")
}

/// The Python interpreter whose runtime PythonFMU binaries get: the active virtual environment's
/// (`VIRTUAL_ENV`), else `python3` on PATH.
fn python_interpreter() -> PathBuf {
    std::env::var_os("VIRTUAL_ENV")
        .map(|venv| PathBuf::from(venv).join("bin").join("python3"))
        .filter(|p| p.is_file())
        .unwrap_or_else(|| PathBuf::from("python3"))
}

/// What the interpreter reports: its shared libpython candidates and its module search path.
const PYTHON_QUERY: &str = "import os, sys, sysconfig\n\
    v = sysconfig.get_config_var\n\
    print(v('LIBDIR') or '')\n\
    print(v('INSTSONAME') or '')\n\
    print(v('LDLIBRARY') or '')\n\
    print(os.pathsep.join(p for p in sys.path if p))";

/// Loads the Python runtime into the process once, with its symbols global so that a PythonFMU
/// binary loaded afterwards binds to them, and puts the interpreter's module path (its standard
/// library and site-packages, the virtual environment's included) on PYTHONPATH so the runtime the
/// binary starts finds pythonfmu. Returns what it did, for the log; the outcome is kept for later
/// FMUs. The manual way (LD_PRELOAD and PYTHONPATH set by the user) still works: a preloaded runtime
/// never reaches here.
fn python_runtime() -> Result<String, String> {
    static RUNTIME: std::sync::OnceLock<Result<String, String>> = std::sync::OnceLock::new();
    RUNTIME.get_or_init(load_python_runtime).clone()
}

fn load_python_runtime() -> Result<String, String> {
    use libloading::os::unix::{Library as UnixLibrary, RTLD_GLOBAL, RTLD_NOW};
    let python = python_interpreter();
    let out = std::process::Command::new(&python)
        .args(["-c", PYTHON_QUERY])
        .output()
        .map_err(|e| format!("cannot run {}: {e}", python.display()))?;
    if !out.status.success() {
        return Err(format!(
            "{} failed: {}",
            python.display(),
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let lines: Vec<&str> = text.lines().collect();
    let [libdir, instsoname, ldlibrary, module_path] = lines[..] else {
        return Err(format!("{} answered {text:?}", python.display()));
    };
    let lib = [instsoname, ldlibrary]
        .iter()
        .filter(|name| name.contains(".so"))
        .map(|name| Path::new(libdir).join(name))
        .find(|p| p.is_file())
        .ok_or_else(|| format!("{} has no shared libpython in {libdir:?}", python.display()))?;
    // SAFETY: libpython's initialisers only set up its own statics. It stays loaded for the life of
    // the process (forgotten below): FMU binaries bind to its symbols.
    let runtime = unsafe { UnixLibrary::open(Some(&lib), RTLD_NOW | RTLD_GLOBAL) }
        .map_err(|e| format!("{}: {e}", lib.display()))?;
    std::mem::forget(runtime);
    let joined = match std::env::var_os("PYTHONPATH").filter(|p| !p.is_empty()) {
        Some(user) => format!("{}:{module_path}", user.to_string_lossy()),
        None => module_path.to_string(),
    };
    // SAFETY: FMUs are loaded while the system is built, before the master starts worker threads;
    // nothing else in the process reads or writes the environment concurrently then.
    unsafe { std::env::set_var("PYTHONPATH", &joined) };
    Ok(format!(
        "{} of {} with RTLD_GLOBAL, PYTHONPATH={joined}",
        lib.display(),
        python.display()
    ))
}

macro_rules! api {
    ($($field:ident : $sym:literal : $ty:ty,)*) => {
        /// Every FMI 2.0 Co-Simulation function, resolved when the library is loaded.
        pub struct Api { $(pub $field: $ty,)* _lib: Library }
        impl Api {
            /// # Safety
            /// `lib` must be an FMI 2.0 FMU binary whose symbols have the standard signatures.
            unsafe fn resolve(lib: Library, path: &Path) -> Result<Self, ImportError> {
                $(
                    let $field: $ty = *unsafe { lib.get::<$ty>(concat!($sym, "\0").as_bytes()) }
                        .map_err(|_| ImportError::MissingSymbol { path: path.to_path_buf(), symbol: $sym.into() })?;
                )*
                Ok(Self { $($field,)* _lib: lib })
            }
        }
    };
}

type C = Fmi2Component;
type Vr = *const Fmi2ValueReference;
api! {
    get_types_platform: "fmi2GetTypesPlatform": unsafe extern "C" fn() -> *const c_char,
    get_version: "fmi2GetVersion": unsafe extern "C" fn() -> *const c_char,
    set_debug_logging: "fmi2SetDebugLogging": unsafe extern "C" fn(C, Fmi2Boolean, usize, *const Fmi2String) -> Fmi2Status,
    instantiate: "fmi2Instantiate": unsafe extern "C" fn(Fmi2String, c_int, Fmi2String, Fmi2String, *const Fmi2CallbackFunctions, Fmi2Boolean, Fmi2Boolean) -> C,
    free_instance: "fmi2FreeInstance": unsafe extern "C" fn(C),
    setup_experiment: "fmi2SetupExperiment": unsafe extern "C" fn(C, Fmi2Boolean, f64, f64, Fmi2Boolean, f64) -> Fmi2Status,
    enter_initialization_mode: "fmi2EnterInitializationMode": unsafe extern "C" fn(C) -> Fmi2Status,
    exit_initialization_mode: "fmi2ExitInitializationMode": unsafe extern "C" fn(C) -> Fmi2Status,
    terminate: "fmi2Terminate": unsafe extern "C" fn(C) -> Fmi2Status,
    reset: "fmi2Reset": unsafe extern "C" fn(C) -> Fmi2Status,
    get_real: "fmi2GetReal": unsafe extern "C" fn(C, Vr, usize, *mut f64) -> Fmi2Status,
    get_integer: "fmi2GetInteger": unsafe extern "C" fn(C, Vr, usize, *mut c_int) -> Fmi2Status,
    get_boolean: "fmi2GetBoolean": unsafe extern "C" fn(C, Vr, usize, *mut Fmi2Boolean) -> Fmi2Status,
    get_string: "fmi2GetString": unsafe extern "C" fn(C, Vr, usize, *mut Fmi2String) -> Fmi2Status,
    set_real: "fmi2SetReal": unsafe extern "C" fn(C, Vr, usize, *const f64) -> Fmi2Status,
    set_integer: "fmi2SetInteger": unsafe extern "C" fn(C, Vr, usize, *const c_int) -> Fmi2Status,
    set_boolean: "fmi2SetBoolean": unsafe extern "C" fn(C, Vr, usize, *const Fmi2Boolean) -> Fmi2Status,
    set_string: "fmi2SetString": unsafe extern "C" fn(C, Vr, usize, *const Fmi2String) -> Fmi2Status,
    get_fmu_state: "fmi2GetFMUstate": unsafe extern "C" fn(C, *mut Fmi2FmuState) -> Fmi2Status,
    set_fmu_state: "fmi2SetFMUstate": unsafe extern "C" fn(C, Fmi2FmuState) -> Fmi2Status,
    free_fmu_state: "fmi2FreeFMUstate": unsafe extern "C" fn(C, *mut Fmi2FmuState) -> Fmi2Status,
    serialized_fmu_state_size: "fmi2SerializedFMUstateSize": unsafe extern "C" fn(C, Fmi2FmuState, *mut usize) -> Fmi2Status,
    serialize_fmu_state: "fmi2SerializeFMUstate": unsafe extern "C" fn(C, Fmi2FmuState, *mut Fmi2Byte, usize) -> Fmi2Status,
    deserialize_fmu_state: "fmi2DeSerializeFMUstate": unsafe extern "C" fn(C, *const Fmi2Byte, usize, *mut Fmi2FmuState) -> Fmi2Status,
    get_directional_derivative: "fmi2GetDirectionalDerivative": unsafe extern "C" fn(C, Vr, usize, Vr, usize, *const f64, *mut f64) -> Fmi2Status,
    set_real_input_derivatives: "fmi2SetRealInputDerivatives": unsafe extern "C" fn(C, Vr, usize, *const Fmi2Integer, *const f64) -> Fmi2Status,
    get_real_output_derivatives: "fmi2GetRealOutputDerivatives": unsafe extern "C" fn(C, Vr, usize, *const Fmi2Integer, *mut f64) -> Fmi2Status,
    do_step: "fmi2DoStep": unsafe extern "C" fn(C, f64, f64, Fmi2Boolean) -> Fmi2Status,
    cancel_step: "fmi2CancelStep": unsafe extern "C" fn(C) -> Fmi2Status,
    get_status: "fmi2GetStatus": unsafe extern "C" fn(C, c_int, *mut c_int) -> Fmi2Status,
    get_real_status: "fmi2GetRealStatus": unsafe extern "C" fn(C, c_int, *mut f64) -> Fmi2Status,
    get_integer_status: "fmi2GetIntegerStatus": unsafe extern "C" fn(C, c_int, *mut c_int) -> Fmi2Status,
    get_boolean_status: "fmi2GetBooleanStatus": unsafe extern "C" fn(C, c_int, *mut Fmi2Boolean) -> Fmi2Status,
    get_string_status: "fmi2GetStringStatus": unsafe extern "C" fn(C, c_int, *mut Fmi2String) -> Fmi2Status,
}

/// An FMU ready to instantiate: its description, unpacked folder and loaded binary.
pub struct Fmu {
    pub description: ModelDescription,
    pub dir: PathBuf,
    /// None when opened for a host process: the binary is then only loaded there.
    api: Option<Arc<Api>>,
    _unpacked: Option<TempDir>,
}

impl Fmu {
    /// Opens a `.fmu` archive (unpacked into a private temporary folder, removed on drop) or an
    /// already unpacked folder. Errors name `path`, never the temporary folder.
    pub fn open(path: &Path) -> Result<Self, ImportError> {
        Self::open_with(path, true)
    }

    /// Like [`Fmu::open`], but leaves the binary unloaded (checking it is there): its instances are
    /// made by [`Fmu::instantiate_isolated`], so none of the FMU's code runs in this process.
    pub fn open_for_host(path: &Path) -> Result<Self, ImportError> {
        Self::open_with(path, false)
    }

    fn open_with(path: &Path, load_binary: bool) -> Result<Self, ImportError> {
        if path.is_dir() {
            return Self::load(path.to_path_buf(), None, path, load_binary);
        }
        let tmp = TempDir::new("windrive-fmu").map_err(|e| ImportError::Archive {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        unzip(path, tmp.path())?;
        Self::load(tmp.path().to_path_buf(), Some(tmp), path, load_binary)
    }

    /// Reads the description and loads the binary of the unpacked FMU in `dir`; `origin` (the
    /// `.fmu` or folder the user named) is what messages name.
    fn load(dir: PathBuf, unpacked: Option<TempDir>, origin: &Path, load_binary: bool) -> Result<Self, ImportError> {
        let describe = |message: String| ImportError::Description {
            path: origin.to_path_buf(),
            message,
        };
        let md_path = dir.join("modelDescription.xml");
        let xml = std::fs::read_to_string(&md_path).map_err(|e| describe(e.to_string()))?;
        let description = ModelDescription::parse(&xml).map_err(|e| describe(e.to_string()))?;
        let cs = description
            .co_simulation
            .as_ref()
            .ok_or_else(|| describe("no <CoSimulation> element: only Co-Simulation FMUs are supported".into()))?;
        let binary = Path::new("binaries")
            .join("linux64")
            .join(format!("{}.so", cs.model_identifier));
        let lib_path = dir.join(&binary);
        if !lib_path.is_file() {
            return Err(ImportError::Library {
                path: origin.to_path_buf(),
                message: format!("no {} in the FMU ({})", binary.display(), platforms(&dir)),
            });
        }
        let api = if load_binary {
            Some(Arc::new(Self::load_library(&lib_path)?))
        } else {
            None
        };
        Ok(Self {
            description,
            dir,
            api,
            _unpacked: unpacked,
        })
    }

    /// Loads a binary and resolves the 34 functions. A binary that needs the Python runtime in the
    /// host (PythonFMU's: not linked to libpython on Linux) gets it: see [`python_runtime`].
    pub fn load_library(path: &Path) -> Result<Api, ImportError> {
        let lib = match open_library(path) {
            Err(why) if needs_python(&why) => match python_runtime() {
                Ok(runtime) => {
                    eprintln!("note: {} needs the Python runtime: loaded {}", path.display(), runtime);
                    open_library(path)
                }
                Err(no_runtime) => Err(format!(
                    "{why} (an FMU made by PythonFMU expects the Python runtime in the host process, and \
                     loading it failed: {no_runtime}; run with LD_PRELOAD=<path>/libpython3.X.so and \
                     PYTHONPATH=<site-packages holding pythonfmu>)"
                )),
            },
            other => other,
        }
        .map_err(|message| ImportError::Library {
            path: path.to_path_buf(),
            message,
        })?;
        // SAFETY: the symbols of an FMI 2.0 binary have the standard signatures.
        unsafe { Api::resolve(lib, path) }
    }

    pub fn resource_uri(&self) -> String {
        let path = self.dir.join("resources");
        let mut uri = String::from("file://");
        for b in path.to_string_lossy().bytes() {
            if b.is_ascii_alphanumeric() || b"/-_.~".contains(&b) {
                uri.push(b as char);
            } else {
                uri.push_str(&format!("%{b:02X}"));
            }
        }
        uri
    }

    /// Value reference of a variable by name.
    pub fn vr(&self, name: &str) -> Result<u32, ImportError> {
        self.description
            .variable(name)
            .map(|v| v.value_reference)
            .ok_or_else(|| ImportError::UnknownVariable {
                model: self.description.model_name.clone(),
                name: name.into(),
            })
    }

    /// An instance in this process.
    pub fn instantiate(&self, name: &str, logging_on: bool) -> Result<Instance, ImportError> {
        let Some(api) = &self.api else {
            return Err(ImportError::Isolation {
                instance: name.into(),
                message: "the FMU was opened for a host process (Fmu::open_for_host): instantiate it isolated".into(),
            });
        };
        InProcess::new(
            Arc::clone(api),
            name,
            &self.description.guid,
            &self.resource_uri(),
            logging_on,
        )
        .map(|i| Instance(Backend::InProcess(i)))
    }

    /// An instance in a process of its own, run by `how.host` (the `windrive` executable): a crash
    /// of the FMU ends that process, and every later call on the instance says so.
    pub fn instantiate_isolated(
        &self,
        name: &str,
        logging_on: bool,
        how: &super::isolate::Isolation,
    ) -> Result<Instance, ImportError> {
        super::isolate::remote::Remote::spawn(&self.dir, name, logging_on, how).map(|r| Instance(Backend::Isolated(r)))
    }

    /// The loaded binary's functions, for tests that call them directly.
    ///
    /// # Panics
    /// When the FMU was opened with [`Fmu::open_for_host`] (its binary is not loaded here).
    pub fn api(&self) -> &Api {
        self.api
            .as_deref()
            .expect("the FMU was opened without loading its binary")
    }
}

/// What an unpacked FMU has instead of the binary this host needs, as a phrase for a message: the
/// files of its linux64 folder, or the platforms it has binaries for.
fn platforms(dir: &Path) -> String {
    let names = |d: PathBuf, dirs: bool| -> Vec<String> {
        let mut found: Vec<String> = std::fs::read_dir(d)
            .into_iter()
            .flatten()
            .flatten()
            .filter(|e| e.file_type().is_ok_and(|t| t.is_dir() == dirs))
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        found.sort();
        found
    };
    let platforms = names(dir.join("binaries"), true);
    if platforms.iter().any(|p| p == "linux64") {
        let files = names(dir.join("binaries").join("linux64"), false);
        return format!(
            "binaries/linux64 holds {}",
            if files.is_empty() {
                "nothing".into()
            } else {
                files.join(", ")
            }
        );
    }
    if platforms.is_empty() {
        "it has no binaries: a source-only or Model Exchange-only FMU?".into()
    } else {
        format!(
            "it has binaries for {} only; this host needs linux64",
            platforms.join(", ")
        )
    }
}

/// The newest messages kept per instance until drained; older ones are dropped and counted (a chatty
/// or flooding FMU must not grow memory without bound over a long run, and the newest messages are
/// the ones that explain an error).
const MAX_KEPT_LOG_RECORDS: usize = 1_000;
/// Longer messages are cut here (with their length said): 1 000 of them bound a log to 4 MB.
const MAX_LOG_MESSAGE_BYTES: usize = 4_096;

#[derive(Default)]
struct LogRecords {
    newest: std::collections::VecDeque<LogRecord>,
    dropped: usize,
}

struct LogTarget {
    records: Mutex<LogRecords>,
    echo: bool,
}

/// `text` cut to at most [`MAX_LOG_MESSAGE_BYTES`] at a character boundary, saying so.
fn bounded(mut text: String) -> String {
    if text.len() > MAX_LOG_MESSAGE_BYTES {
        let total = text.len();
        let mut cut = MAX_LOG_MESSAGE_BYTES;
        while !text.is_char_boundary(cut) {
            cut -= 1;
        }
        text.truncate(cut);
        text.push_str(&format!("… (message of {total} bytes cut)"));
    }
    text
}

unsafe extern "C" {
    fn windrive_fmi2_logger(
        env: *mut c_void,
        instance: *const c_char,
        status: c_int,
        category: *const c_char,
        format: *const c_char,
        ...
    );
    fn windrive_set_log_sink(sink: LogSink);
}

type LogSink = unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char);

/// Hands the C shim its sink, once per process, before the first instance can log.
fn register_log_sink() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    // SAFETY: the shim stores the pointer; windrive_log_sink has the signature it calls.
    ONCE.call_once(|| unsafe { windrive_set_log_sink(windrive_log_sink) });
}

/// Called by the C shim with the formatted message.
///
/// # Safety
/// `env` is the `LogTarget` an [`Instance`] registered; strings are NUL-terminated or null.
unsafe extern "C" fn windrive_log_sink(
    env: *mut c_void,
    instance: *const c_char,
    status: c_int,
    category: *const c_char,
    message: *const c_char,
) {
    let _ = std::panic::catch_unwind(|| {
        if env.is_null() {
            return;
        }
        let text = |p: *const c_char| {
            if p.is_null() {
                String::new()
            } else {
                unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
            }
        };
        // SAFETY: env is the boxed LogTarget owned by the instance that is calling.
        let target = unsafe { &*(env as *const LogTarget) };
        let status = Fmi2Status::from_raw(status);
        let (instance, category, message) = (text(instance), bounded(text(category)), bounded(text(message)));
        if target.echo {
            eprintln!("[{instance}] {} {category}: {message}", status.name());
        }
        if let Ok(mut r) = target.records.lock() {
            if r.newest.len() == MAX_KEPT_LOG_RECORDS {
                r.newest.pop_front();
                r.dropped += 1;
            }
            r.newest.push_back((status, category, message));
        }
    });
}

/// Runs `f` on `n` copies of `fill`, on the stack when `n` is small: the per-call arrays of FMI's
/// Boolean and derivative functions cost no allocation at every step.
fn with_buffer<T: Copy, R>(n: usize, fill: T, f: impl FnOnce(&mut [T]) -> R) -> R {
    const ON_STACK: usize = 32;
    if n <= ON_STACK {
        let mut small = [fill; ON_STACK];
        f(&mut small[..n])
    } else {
        f(&mut vec![fill; n])
    }
}

/// The kept messages, oldest first, after a note of how many were dropped before them.
fn drain(target: &LogTarget) -> Vec<LogRecord> {
    let Ok(mut r) = target.records.lock() else {
        return Vec::new();
    };
    let r = std::mem::take(&mut *r);
    let note = (r.dropped > 0).then(|| {
        let text = format!(
            "({} earlier messages dropped; the newest {} kept)",
            r.dropped,
            r.newest.len()
        );
        (Fmi2Status::Warning, "windrive".to_string(), text)
    });
    note.into_iter().chain(r.newest).collect()
}

/// A live FMU instance, in this process or in a host process of its own
/// ([`Fmu::instantiate_isolated`]): the same calls either way. Freed on drop.
pub struct Instance(Backend);

enum Backend {
    InProcess(InProcess),
    Isolated(super::isolate::remote::Remote),
}

/// Forwards each call to the backend that holds the instance.
macro_rules! forward {
    ($(fn $m:ident(&mut self $(, $a:ident: $t:ty)*) -> $r:ty;)*) => {
        impl Instance {
            $(pub fn $m(&mut self $(, $a: $t)*) -> $r {
                match &mut self.0 {
                    Backend::InProcess(i) => i.$m($($a),*),
                    Backend::Isolated(i) => i.$m($($a),*),
                }
            })*
        }
    };
}

forward! {
    fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), ImportError>;
    fn enter_initialization_mode(&mut self) -> Result<(), ImportError>;
    fn exit_initialization_mode(&mut self) -> Result<(), ImportError>;
    fn terminate(&mut self) -> Result<(), ImportError>;
    fn reset(&mut self) -> Result<(), ImportError>;
    fn set_real(&mut self, vr: &[u32], values: &[f64]) -> Result<(), ImportError>;
    fn get_real(&mut self, vr: &[u32], values: &mut [f64]) -> Result<(), ImportError>;
    fn set_integer(&mut self, vr: &[u32], values: &[i32]) -> Result<(), ImportError>;
    fn get_integer(&mut self, vr: &[u32], values: &mut [i32]) -> Result<(), ImportError>;
    fn set_boolean(&mut self, vr: &[u32], values: &[bool]) -> Result<(), ImportError>;
    fn get_boolean(&mut self, vr: &[u32], values: &mut [bool]) -> Result<(), ImportError>;
    fn set_string(&mut self, vr: &[u32], values: &[&str]) -> Result<(), ImportError>;
    fn set_real_input_derivatives(&mut self, vr: &[u32], order: i32, values: &[f64]) -> Result<(), ImportError>;
    fn do_step(&mut self, t: f64, h: f64) -> Result<(), ImportError>;
    fn get_state(&mut self) -> Result<SavedState, ImportError>;
    fn update_state(&mut self, st: &mut SavedState) -> Result<(), ImportError>;
    fn set_state(&mut self, st: &SavedState) -> Result<(), ImportError>;
    fn free_state(&mut self, st: SavedState) -> Result<(), ImportError>;
    fn serialize_state(&mut self, st: &SavedState) -> Result<Vec<u8>, ImportError>;
    fn deserialize_state(&mut self, bytes: &[u8]) -> Result<SavedState, ImportError>;
    fn take_log(&mut self) -> Vec<LogRecord>;
}

impl Instance {
    pub fn name(&self) -> &str {
        match &self.0 {
            Backend::InProcess(i) => i.name(),
            Backend::Isolated(i) => i.name(),
        }
    }

    /// The process the FMU runs in: this one, or its host's.
    pub fn pid(&self) -> u32 {
        match &self.0 {
            Backend::InProcess(_) => std::process::id(),
            Backend::Isolated(i) => i.pid(),
        }
    }

    fn in_process(&self) -> &InProcess {
        match &self.0 {
            Backend::InProcess(i) => i,
            Backend::Isolated(_) => panic!("{}: an isolated instance has no component pointer here", self.name()),
        }
    }

    /// The component pointer, for tests that call the FMU's functions directly.
    ///
    /// # Panics
    /// For an isolated instance (its component lives in the host process).
    pub fn raw(&self) -> Fmi2Component {
        self.in_process().c
    }

    /// The binary's functions, for tests that call them directly.
    ///
    /// # Panics
    /// For an isolated instance.
    pub fn api(&self) -> &Api {
        &self.in_process().api
    }
}

/// An FMU instance in this process. Freed on drop.
pub struct InProcess {
    api: Arc<Api>,
    c: Fmi2Component,
    name: String,
    log: Box<LogTarget>,
    _callbacks: Box<Fmi2CallbackFunctions>,
}

// SAFETY: an FMI instance may be used from any one thread at a time (FMI 2.0 §2.1.5); Instance is
// not Sync, so it is never used from two threads at once.
unsafe impl Send for InProcess {}

impl InProcess {
    fn new(api: Arc<Api>, name: &str, guid: &str, resources: &str, logging_on: bool) -> Result<Self, ImportError> {
        let log = Box::new(LogTarget {
            records: Mutex::new(LogRecords::default()),
            echo: std::env::var_os("WINDRIVE_FMU_LOG").is_some(),
        });
        register_log_sink();
        let callbacks = Box::new(Fmi2CallbackFunctions {
            // the C shim has exactly the fmi2CallbackLogger signature
            logger: Some(windrive_fmi2_logger),
            allocate_memory: Some(calloc_shim),
            free_memory: Some(free_shim),
            step_finished: None,
            component_environment: &*log as *const LogTarget as *mut c_void,
        });
        let cname = CString::new(name).unwrap_or_default();
        let cguid = CString::new(guid).unwrap_or_default();
        let cres = CString::new(resources).unwrap_or_default();
        // SAFETY: all pointers are valid for the call; callbacks and log outlive the instance.
        let c = unsafe {
            (api.instantiate)(
                cname.as_ptr(),
                FMI2_CO_SIMULATION,
                cguid.as_ptr(),
                cres.as_ptr(),
                &*callbacks,
                FMI2_FALSE,
                logging_on as c_int,
            )
        };
        if c.is_null() {
            return Err(ImportError::Instantiate {
                instance: name.into(),
                log: drain(&log).into_iter().map(|r| r.2).collect(),
            });
        }
        Ok(Self {
            api,
            c,
            name: name.into(),
            log,
            _callbacks: callbacks,
        })
    }

    /// Messages the FMU logged so far (drained); when older ones were dropped, the first record
    /// says how many.
    pub fn take_log(&self) -> Vec<LogRecord> {
        drain(&self.log)
    }

    /// Ok and Warning are results (the warning's text stays in the log for the caller to drain);
    /// Discard, Error, Fatal and Pending are errors carrying the FMU's log.
    fn check(&self, function: &'static str, status: Fmi2Status) -> Result<Fmi2Status, ImportError> {
        match status {
            Fmi2Status::Ok | Fmi2Status::Warning => Ok(status),
            _ => Err(ImportError::Call {
                instance: self.name.clone(),
                function,
                status: status.name(),
                log: self.take_log().into_iter().map(|r| r.2).collect(),
            }),
        }
    }

    pub fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), ImportError> {
        let s = unsafe {
            (self.api.setup_experiment)(
                self.c,
                FMI2_FALSE,
                0.0,
                start,
                stop.is_some() as c_int,
                stop.unwrap_or(0.0),
            )
        };
        self.check("fmi2SetupExperiment", s).map(|_| ())
    }
    pub fn enter_initialization_mode(&mut self) -> Result<(), ImportError> {
        let s = unsafe { (self.api.enter_initialization_mode)(self.c) };
        self.check("fmi2EnterInitializationMode", s).map(|_| ())
    }
    pub fn exit_initialization_mode(&mut self) -> Result<(), ImportError> {
        let s = unsafe { (self.api.exit_initialization_mode)(self.c) };
        self.check("fmi2ExitInitializationMode", s).map(|_| ())
    }
    pub fn terminate(&mut self) -> Result<(), ImportError> {
        let s = unsafe { (self.api.terminate)(self.c) };
        self.check("fmi2Terminate", s).map(|_| ())
    }
    pub fn reset(&mut self) -> Result<(), ImportError> {
        let s = unsafe { (self.api.reset)(self.c) };
        self.check("fmi2Reset", s).map(|_| ())
    }
    pub fn set_real(&mut self, vr: &[u32], values: &[f64]) -> Result<(), ImportError> {
        assert_eq!(vr.len(), values.len());
        let s = unsafe { (self.api.set_real)(self.c, vr.as_ptr(), vr.len(), values.as_ptr()) };
        self.check("fmi2SetReal", s).map(|_| ())
    }
    pub fn get_real(&mut self, vr: &[u32], values: &mut [f64]) -> Result<(), ImportError> {
        assert_eq!(vr.len(), values.len());
        let s = unsafe { (self.api.get_real)(self.c, vr.as_ptr(), vr.len(), values.as_mut_ptr()) };
        self.check("fmi2GetReal", s).map(|_| ())
    }
    pub fn set_integer(&mut self, vr: &[u32], values: &[i32]) -> Result<(), ImportError> {
        assert_eq!(vr.len(), values.len());
        let s = unsafe { (self.api.set_integer)(self.c, vr.as_ptr(), vr.len(), values.as_ptr()) };
        self.check("fmi2SetInteger", s).map(|_| ())
    }
    pub fn set_boolean(&mut self, vr: &[u32], values: &[bool]) -> Result<(), ImportError> {
        assert_eq!(vr.len(), values.len());
        let s = with_buffer(vr.len(), 0, |raw: &mut [Fmi2Boolean]| {
            raw.iter_mut().zip(values).for_each(|(r, &b)| *r = b as Fmi2Boolean);
            unsafe { (self.api.set_boolean)(self.c, vr.as_ptr(), vr.len(), raw.as_ptr()) }
        });
        self.check("fmi2SetBoolean", s).map(|_| ())
    }
    /// Sets the `order`-th time derivative of real inputs for the next fmi2DoStep (the FMU must
    /// declare canInterpolateInputs).
    pub fn set_real_input_derivatives(&mut self, vr: &[u32], order: i32, values: &[f64]) -> Result<(), ImportError> {
        assert_eq!(vr.len(), values.len());
        let s = with_buffer(vr.len(), order, |orders| unsafe {
            (self.api.set_real_input_derivatives)(self.c, vr.as_ptr(), vr.len(), orders.as_ptr(), values.as_ptr())
        });
        self.check("fmi2SetRealInputDerivatives", s).map(|_| ())
    }
    pub fn name(&self) -> &str {
        &self.name
    }
    pub fn get_integer(&mut self, vr: &[u32], values: &mut [i32]) -> Result<(), ImportError> {
        let s = unsafe { (self.api.get_integer)(self.c, vr.as_ptr(), vr.len(), values.as_mut_ptr()) };
        self.check("fmi2GetInteger", s).map(|_| ())
    }
    pub fn get_boolean(&mut self, vr: &[u32], values: &mut [bool]) -> Result<(), ImportError> {
        assert_eq!(vr.len(), values.len());
        let s = with_buffer(vr.len(), 0, |raw: &mut [Fmi2Boolean]| {
            let s = unsafe { (self.api.get_boolean)(self.c, vr.as_ptr(), vr.len(), raw.as_mut_ptr()) };
            values.iter_mut().zip(raw.iter()).for_each(|(v, r)| *v = *r != 0);
            s
        });
        self.check("fmi2GetBoolean", s).map(|_| ())
    }
    pub fn set_string(&mut self, vr: &[u32], values: &[&str]) -> Result<(), ImportError> {
        let owned: Vec<CString> = values.iter().map(|v| CString::new(*v).unwrap_or_default()).collect();
        let ptrs: Vec<Fmi2String> = owned.iter().map(|c| c.as_ptr()).collect();
        let s = unsafe { (self.api.set_string)(self.c, vr.as_ptr(), vr.len(), ptrs.as_ptr()) };
        self.check("fmi2SetString", s).map(|_| ())
    }
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<(), ImportError> {
        let s = unsafe { (self.api.do_step)(self.c, t, h, FMI2_TRUE) };
        self.check("fmi2DoStep", s).map(|_| ())
    }
    /// Saves the FMU state; free it with [`Instance::free_state`].
    pub fn get_state(&mut self) -> Result<SavedState, ImportError> {
        let mut st: Fmi2FmuState = std::ptr::null_mut();
        let s = unsafe { (self.api.get_fmu_state)(self.c, &mut st) };
        self.check("fmi2GetFMUstate", s).map(|_| SavedState(st))
    }
    /// Saves the FMU state into an existing snapshot (FMI 2.0: a non-null state is overwritten).
    pub fn update_state(&mut self, st: &mut SavedState) -> Result<(), ImportError> {
        let s = unsafe { (self.api.get_fmu_state)(self.c, &mut st.0) };
        self.check("fmi2GetFMUstate", s).map(|_| ())
    }
    pub fn set_state(&mut self, st: &SavedState) -> Result<(), ImportError> {
        let s = unsafe { (self.api.set_fmu_state)(self.c, st.0) };
        self.check("fmi2SetFMUstate", s).map(|_| ())
    }
    pub fn free_state(&mut self, st: SavedState) -> Result<(), ImportError> {
        let mut raw = st.0;
        let s = unsafe { (self.api.free_fmu_state)(self.c, &mut raw) };
        self.check("fmi2FreeFMUstate", s).map(|_| ())
    }
    pub fn serialize_state(&mut self, st: &SavedState) -> Result<Vec<u8>, ImportError> {
        let st = st.0;
        let mut size = 0usize;
        let s = unsafe { (self.api.serialized_fmu_state_size)(self.c, st, &mut size) };
        self.check("fmi2SerializedFMUstateSize", s)?;
        let mut bytes = vec![0u8; size];
        let s = unsafe { (self.api.serialize_fmu_state)(self.c, st, bytes.as_mut_ptr() as *mut Fmi2Byte, size) };
        self.check("fmi2SerializeFMUstate", s)?;
        Ok(bytes)
    }
    pub fn deserialize_state(&mut self, bytes: &[u8]) -> Result<SavedState, ImportError> {
        let mut st: Fmi2FmuState = std::ptr::null_mut();
        let s = unsafe {
            (self.api.deserialize_fmu_state)(self.c, bytes.as_ptr() as *const Fmi2Byte, bytes.len(), &mut st)
        };
        self.check("fmi2DeSerializeFMUstate", s).map(|_| SavedState(st))
    }
}

impl Drop for InProcess {
    fn drop(&mut self) {
        // SAFETY: c came from fmi2Instantiate and is freed exactly once.
        unsafe { (self.api.free_instance)(self.c) };
    }
}

unsafe extern "C" fn calloc_shim(n: usize, size: usize) -> *mut c_void {
    unsafe extern "C" {
        fn calloc(n: usize, size: usize) -> *mut c_void;
    }
    unsafe { calloc(n, size) }
}

unsafe extern "C" fn free_shim(p: *mut c_void) {
    unsafe extern "C" {
        fn free(p: *mut c_void);
    }
    unsafe { free(p) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_log_flood_keeps_the_newest_thousand_messages_cut_to_4_kb() {
        let target = LogTarget {
            records: Mutex::new(LogRecords::default()),
            echo: false,
        };
        let env = &target as *const LogTarget as *mut c_void;
        let long = CString::new("x".repeat(100_000)).unwrap();
        let name = CString::new("flood").unwrap();
        for k in 0..5_000 {
            let text = if k == 4_999 {
                CString::new("the last one").unwrap()
            } else {
                long.clone()
            };
            // SAFETY: env is the LogTarget above; the strings are NUL-terminated.
            unsafe { windrive_log_sink(env, name.as_ptr(), 3, name.as_ptr(), text.as_ptr()) };
        }
        let log = drain(&target);
        assert_eq!(log.len(), MAX_KEPT_LOG_RECORDS + 1);
        assert_eq!(log[0].2, "(4000 earlier messages dropped; the newest 1000 kept)");
        assert!(log[1].2.ends_with("… (message of 100000 bytes cut)") && log[1].2.len() < 4_200);
        assert_eq!(log[MAX_KEPT_LOG_RECORDS].2, "the last one");
        assert!(drain(&target).is_empty());
    }
}
