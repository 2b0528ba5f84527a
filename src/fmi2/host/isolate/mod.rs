//! Out-of-process FMU instances (`windrive run --isolate`): each FMU instance lives in a child
//! process (`windrive fmu-host`, hidden) and the master drives it through a shared-memory mailbox,
//! so an FMU that crashes ends the run with a message naming it, the signal and the time, while the
//! master keeps every recorded row.
//!
//! The master's side ([`remote::Remote`]) keeps FMI's call-by-call semantics but crosses between
//! processes as rarely as it can: calls that only return a status (setting inputs) are queued and
//! travel with the next call that returns something, and the values read right after a step are
//! computed by the host with the step and sent back in its reply. A macro step of one FMU is then one
//! round trip (docs/FMU-BOUNDARY.md measures what it costs).

use std::path::PathBuf;
use std::time::Duration;

pub mod channel;
pub mod remote;
pub mod wire;

/// How isolated instances are run.
#[derive(Debug, Clone)]
pub struct Isolation {
    /// The `windrive` executable, run as `windrive fmu-host`.
    pub host: PathBuf,
    /// A host that takes longer than this for one call (an FMU in an endless loop) is killed and the
    /// call fails saying so; None waits as long as an in-process call would.
    pub call_timeout: Option<Duration>,
}

impl Isolation {
    pub fn new(host: impl Into<PathBuf>) -> Self {
        Self {
            host: host.into(),
            call_timeout: None,
        }
    }
}

/// Request codes of the mailbox protocol. A message is `[count][request]…`; its reply is
/// `[requests done][status of the last one done]` followed by the last request's results, or on a
/// status other than OK and Warning by the FMU's log texts.
pub(super) mod op {
    pub const SETUP_EXPERIMENT: u32 = 1;
    pub const ENTER_INITIALIZATION_MODE: u32 = 2;
    pub const EXIT_INITIALIZATION_MODE: u32 = 3;
    pub const TERMINATE: u32 = 4;
    pub const RESET: u32 = 5;
    pub const SET_REAL: u32 = 6;
    pub const GET_REAL: u32 = 7;
    pub const SET_INTEGER: u32 = 8;
    pub const GET_INTEGER: u32 = 9;
    pub const SET_BOOLEAN: u32 = 10;
    pub const GET_BOOLEAN: u32 = 11;
    pub const SET_STRING: u32 = 12;
    pub const SET_REAL_INPUT_DERIVATIVES: u32 = 13;
    pub const DO_STEP: u32 = 14;
    pub const GET_STATE: u32 = 15;
    pub const UPDATE_STATE: u32 = 16;
    pub const SET_STATE: u32 = 17;
    pub const FREE_STATE: u32 = 18;
    pub const SERIALIZE_STATE: u32 = 19;
    pub const DESERIALIZE_STATE: u32 = 20;
    pub const TAKE_LOG: u32 = 21;
    pub const QUIT: u32 = 22;
    /// The host's first message: whether fmi2Instantiate worked.
    pub const HELLO: u32 = 23;

    /// The FMI function a request stands for, for messages.
    pub fn function(op: u32) -> &'static str {
        match op {
            SETUP_EXPERIMENT => "fmi2SetupExperiment",
            ENTER_INITIALIZATION_MODE => "fmi2EnterInitializationMode",
            EXIT_INITIALIZATION_MODE => "fmi2ExitInitializationMode",
            TERMINATE => "fmi2Terminate",
            RESET => "fmi2Reset",
            SET_REAL => "fmi2SetReal",
            GET_REAL => "fmi2GetReal",
            SET_INTEGER => "fmi2SetInteger",
            GET_INTEGER => "fmi2GetInteger",
            SET_BOOLEAN => "fmi2SetBoolean",
            GET_BOOLEAN => "fmi2GetBoolean",
            SET_STRING => "fmi2SetString",
            SET_REAL_INPUT_DERIVATIVES => "fmi2SetRealInputDerivatives",
            DO_STEP => "fmi2DoStep",
            GET_STATE | UPDATE_STATE => "fmi2GetFMUstate",
            SET_STATE => "fmi2SetFMUstate",
            FREE_STATE => "fmi2FreeFMUstate",
            SERIALIZE_STATE => "fmi2SerializeFMUstate",
            DESERIALIZE_STATE => "fmi2DeSerializeFMUstate",
            TAKE_LOG => "reading the FMU's log",
            QUIT => "fmi2FreeInstance",
            HELLO => "fmi2Instantiate",
            _ => "an unknown request",
        }
    }
}
