//! The child process's side: loads one FMU, instantiates it and answers the master's requests
//! from the mailbox until told to quit or the master goes away.

use super::isolate::channel::Channel;
use super::isolate::op;
use super::isolate::wire::{Reader, WireError, Writer};
use crate::fmi2::host::error::ImportError;
use crate::fmi2::host::import::{Fmu, Instance};
use crate::fmi2::host::state::SavedState;
use crate::fmi2::types::Fmi2Status;
use std::os::fd::RawFd;
use std::path::Path;
use std::time::Duration;

/// What a host spins (yielding) before sleeping while it waits for the next request: the master
/// usually asks again within a macro step of the other FMUs; waking a sleeping process costs
/// tens of microseconds on a virtual machine.
const SPIN: Duration = Duration::from_micros(50);

/// Runs the host for instance `name` of the unpacked FMU in `dir`, on the mailbox `fd` the master
/// `master_pid` handed down. Returns when the master says quit or is gone.
pub fn serve(fd: RawFd, dir: &Path, name: &str, logging_on: bool, master_pid: u32) -> Result<(), String> {
    // SAFETY: asks the kernel to kill this process when its parent dies (then checks for the race
    // where the parent died before the request).
    unsafe { libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL) };
    let master_alive = || {
        // SAFETY: getppid cannot fail.
        if unsafe { libc::getppid() } as u32 == master_pid {
            Ok(())
        } else {
            Err("the master is gone".to_string())
        }
    };
    master_alive()?;
    let mut channel = Channel::open(fd).map_err(|e| e.to_string())?;
    let mut host = Host {
        instance: Fmu::open(dir).and_then(|fmu| {
            let instance = fmu.instantiate(name, logging_on);
            // the library stays loaded as long as the instance: leak the Fmu into the process
            std::mem::forget(fmu);
            instance
        }),
        vr: Vec::new(),
        reals: Vec::new(),
        ints: Vec::new(),
        bools: Vec::new(),
        out: Vec::new(),
    };
    let mut last = 0;
    loop {
        last = channel.next_request(last, SPIN, master_alive)?;
        let quit = host.answer(channel.payload());
        let payload = channel.payload();
        if host.out.len() > payload.len() {
            let mut w = Writer::at(payload, 0);
            let _ = (w.u32(0), w.i32(Fmi2Status::Error as i32), w.u32(1));
            let _ = w.str("the reply does not fit the isolation mailbox");
        } else {
            payload[..host.out.len()].copy_from_slice(&host.out);
        }
        channel.reply(last);
        if quit {
            return Ok(());
        }
    }
}

struct Host {
    /// The instance, or why there is none (every request then answers with that).
    instance: Result<Instance, ImportError>,
    vr: Vec<u32>,
    reals: Vec<f64>,
    ints: Vec<i32>,
    bools: Vec<bool>,
    /// The reply being written.
    out: Vec<u8>,
}

/// Why a request failed: the FMU's status and log, or a message the host makes itself.
struct Failure {
    status: Fmi2Status,
    log: Vec<String>,
}

impl From<ImportError> for Failure {
    fn from(e: ImportError) -> Self {
        match e {
            ImportError::Call { status, log, .. } => Self {
                status: [
                    Fmi2Status::Discard,
                    Fmi2Status::Error,
                    Fmi2Status::Fatal,
                    Fmi2Status::Pending,
                ]
                .into_iter()
                .find(|s| s.name() == status)
                .unwrap_or(Fmi2Status::Fatal),
                log,
            },
            ImportError::Instantiate { log, .. } => Self {
                status: Fmi2Status::Error,
                log,
            },
            other => Self {
                status: Fmi2Status::Error,
                log: vec![other.to_string()],
            },
        }
    }
}

impl From<WireError> for Failure {
    fn from(e: WireError) -> Self {
        Self {
            status: Fmi2Status::Error,
            log: vec![format!("fmu-host: {e}")],
        }
    }
}

impl Host {
    /// Carries out the message in `payload`, leaving the reply in `self.out`; true on quit.
    fn answer(&mut self, payload: &[u8]) -> bool {
        let mut out = std::mem::take(&mut self.out);
        out.clear();
        out.resize(8, 0);
        let mut r = Reader::at(payload, 0);
        let mut done = 0u32;
        let mut quit = false;
        let outcome = (|| -> Result<(), Failure> {
            let count = r.u32()?;
            for k in 0..count {
                out.truncate(8);
                let code = r.u32()?;
                quit |= code == op::QUIT;
                self.request(code, &mut r, &mut out)?;
                done = k + 1;
            }
            Ok(())
        })();
        let status = match outcome {
            Ok(()) => Fmi2Status::Ok,
            Err(failure) => {
                out.truncate(8);
                write_strings(&mut out, &failure.log);
                failure.status
            }
        };
        out[..4].copy_from_slice(&done.to_le_bytes());
        out[4..8].copy_from_slice(&(status as i32).to_le_bytes());
        self.out = out;
        quit
    }

    fn request(&mut self, code: u32, r: &mut Reader, out: &mut Vec<u8>) -> Result<(), Failure> {
        let inst = match &mut self.instance {
            Ok(i) => i,
            Err(e) => {
                return Err(Failure {
                    status: Fmi2Status::Error,
                    log: vec![e.to_string()],
                });
            }
        };
        let (vr, reals, ints, bools) = (&mut self.vr, &mut self.reals, &mut self.ints, &mut self.bools);
        match code {
            op::HELLO | op::QUIT => {}
            op::SETUP_EXPERIMENT => {
                let (start, has_stop, stop) = (r.f64()?, r.u32()?, r.f64()?);
                inst.setup_experiment(start, (has_stop != 0).then_some(stop))?;
            }
            op::ENTER_INITIALIZATION_MODE => inst.enter_initialization_mode()?,
            op::EXIT_INITIALIZATION_MODE => inst.exit_initialization_mode()?,
            op::TERMINATE => inst.terminate()?,
            op::RESET => inst.reset()?,
            op::SET_REAL => {
                r.u32s(vr)?;
                r.f64s(reals)?;
                check_lengths(vr, reals.len())?;
                inst.set_real(vr, reals)?;
            }
            op::GET_REAL | op::GET_INTEGER | op::GET_BOOLEAN => {
                r.u32s(vr)?;
                get(inst, code, vr, reals, ints, bools, out)?;
            }
            op::SET_INTEGER => {
                r.u32s(vr)?;
                r.i32s(ints)?;
                check_lengths(vr, ints.len())?;
                inst.set_integer(vr, ints)?;
            }
            op::SET_BOOLEAN => {
                r.u32s(vr)?;
                r.i32s(ints)?;
                check_lengths(vr, ints.len())?;
                bools.clear();
                bools.extend(ints.iter().map(|&b| b != 0));
                inst.set_boolean(vr, bools)?;
            }
            op::SET_STRING => {
                r.u32s(vr)?;
                let n = r.u32()? as usize;
                check_lengths(vr, n)?;
                let values = (0..n).map(|_| r.string()).collect::<Result<Vec<_>, _>>()?;
                let refs: Vec<&str> = values.iter().map(String::as_str).collect();
                inst.set_string(vr, &refs)?;
            }
            op::SET_REAL_INPUT_DERIVATIVES => {
                r.u32s(vr)?;
                let order = r.i32()?;
                r.f64s(reals)?;
                check_lengths(vr, reals.len())?;
                inst.set_real_input_derivatives(vr, order, reals)?;
            }
            op::DO_STEP => {
                let (t, h) = (r.f64()?, r.f64()?);
                inst.do_step(t, h)?;
                // the reads the master does right after a step, answered now
                let reads = r.u32()?;
                put_u32(out, reads);
                for _ in 0..reads {
                    let kind = r.u32()?;
                    r.u32s(vr)?;
                    let at = out.len();
                    put_u32(out, Fmi2Status::Ok as u32);
                    if get(inst, kind, vr, reals, ints, bools, out).is_err() {
                        // the master asks again and gets the error then
                        out.truncate(at);
                        put_u32(out, Fmi2Status::Error as u32);
                    }
                }
            }
            op::GET_STATE => {
                let s = inst.get_state()?;
                put_u64(out, s.handle());
            }
            op::UPDATE_STATE => {
                let mut s = SavedState::from_handle(r.u64()?);
                inst.update_state(&mut s)?;
                put_u64(out, s.handle());
            }
            op::SET_STATE => inst.set_state(&SavedState::from_handle(r.u64()?))?,
            op::FREE_STATE => inst.free_state(SavedState::from_handle(r.u64()?))?,
            op::SERIALIZE_STATE => {
                let bytes = inst.serialize_state(&SavedState::from_handle(r.u64()?))?;
                put_blob(out, &bytes);
            }
            op::DESERIALIZE_STATE => {
                let s = inst.deserialize_state(r.blob()?)?;
                put_u64(out, s.handle());
            }
            op::TAKE_LOG => {
                let log = inst.take_log();
                put_u32(out, log.len() as u32);
                for (status, category, text) in log {
                    put_u32(out, status as u32);
                    put_blob(out, category.as_bytes());
                    put_blob(out, text.as_bytes());
                }
            }
            other => {
                return Err(Failure {
                    status: Fmi2Status::Error,
                    log: vec![format!("fmu-host: unknown request {other}")],
                });
            }
        }
        Ok(())
    }
}

/// Answers a read of Reals, Integers or Booleans (Booleans travel as 0/1 Integers).
fn get(
    inst: &mut Instance,
    code: u32,
    vr: &[u32],
    reals: &mut Vec<f64>,
    ints: &mut Vec<i32>,
    bools: &mut Vec<bool>,
    out: &mut Vec<u8>,
) -> Result<(), Failure> {
    match code {
        op::GET_REAL => {
            reals.resize(vr.len(), 0.0);
            inst.get_real(vr, reals)?;
            put_u32(out, reals.len() as u32);
            reals.iter().for_each(|x| out.extend_from_slice(&x.to_le_bytes()));
        }
        op::GET_INTEGER => {
            ints.resize(vr.len(), 0);
            inst.get_integer(vr, ints)?;
            put_u32(out, ints.len() as u32);
            ints.iter().for_each(|x| out.extend_from_slice(&x.to_le_bytes()));
        }
        op::GET_BOOLEAN => {
            bools.resize(vr.len(), false);
            inst.get_boolean(vr, bools)?;
            put_u32(out, bools.len() as u32);
            bools
                .iter()
                .for_each(|&b| out.extend_from_slice(&i32::from(b).to_le_bytes()));
        }
        _ => return Err(WireError::Malformed(0).into()),
    }
    Ok(())
}

fn check_lengths(vr: &[u32], n: usize) -> Result<(), Failure> {
    if vr.len() == n {
        Ok(())
    } else {
        Err(Failure {
            status: Fmi2Status::Error,
            log: vec![format!("fmu-host: {} value references but {n} values", vr.len())],
        })
    }
}

fn put_u32(out: &mut Vec<u8>, x: u32) {
    out.extend_from_slice(&x.to_le_bytes());
}

fn put_u64(out: &mut Vec<u8>, x: u64) {
    out.extend_from_slice(&x.to_le_bytes());
}

fn put_blob(out: &mut Vec<u8>, b: &[u8]) {
    put_u32(out, b.len() as u32);
    out.extend_from_slice(b);
}

fn write_strings(out: &mut Vec<u8>, texts: &[String]) {
    put_u32(out, texts.len() as u32);
    texts.iter().for_each(|t| put_blob(out, t.as_bytes()));
}
