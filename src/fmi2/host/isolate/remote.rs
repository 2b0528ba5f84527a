//! The master's side of an isolated instance: the same calls as an in-process instance, carried to
//! the host process through the mailbox.

use super::channel::{CAPACITY, Channel, POLL};
use super::wire::{Reader, WireError, Writer};
use super::{Isolation, op};
use crate::fmi2::host::error::{ImportError, LogRecord};
use crate::fmi2::host::state::SavedState;
use crate::fmi2::types::Fmi2Status;
use std::os::fd::AsRawFd;
use std::os::unix::process::{CommandExt, ExitStatusExt};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// What the master spins (yielding) before sleeping while a host works, at least: a short FMU call
/// (a macro step of the torsional FMU takes a microsecond) comes back faster than a sleeping
/// process is woken (tens of microseconds on a virtual machine). For an FMU whose calls take longer
/// (the 6-DOF gearbox: hundreds of microseconds) it spins twice its last call, up to [`MAX_SPIN`].
const MIN_SPIN: Duration = Duration::from_micros(200);
const MAX_SPIN: Duration = Duration::from_millis(5);
/// Reads remembered per instance and answered with the next step (the coupled outputs, the
/// recorded ones, and a Boolean or Integer group of each).
const MAX_READS_AFTER_STEP: usize = 4;
/// How long a host may take to quit before it is killed.
const QUIT_GRACE: Duration = Duration::from_secs(2);

/// One FMU instance in its own process.
pub struct Remote {
    name: String,
    channel: Channel,
    child: Child,
    seq: u32,
    /// Requests written but not yet sent (they only return a status), in order.
    queued: Vec<u32>,
    /// Where the next request goes in the payload (after the request count).
    write_pos: usize,
    /// Reads (request code, value references) the master made right after a step: the host answers
    /// them with the next step.
    reads: Vec<(u32, Vec<u32>)>,
    /// Answers to `reads` since the last step, as reply bytes, per read (None: the host's read
    /// failed, ask again); valid until a call that may change the FMU.
    answers: Vec<Option<std::ops::Range<usize>>>,
    answer_bytes: Vec<u8>,
    answers_valid: bool,
    /// Whether no call but reads came since the last step (reads made then are learned).
    after_step: bool,
    /// How the host process ended, once it has.
    ended: Option<String>,
    /// How long the last call took.
    last_call: Duration,
    /// Longest a call may take before the host is killed.
    timeout: Option<Duration>,
}

/// The message for a host that ended: the signal (with its name) or the exit code.
fn describe_exit(status: std::process::ExitStatus) -> String {
    match (status.signal(), status.code()) {
        (Some(sig), _) => {
            // SAFETY: strsignal returns a static or thread-local string for any number.
            let text = unsafe { std::ffi::CStr::from_ptr(libc::strsignal(sig)) };
            format!("killed by signal {sig} ({})", text.to_string_lossy())
        }
        (None, Some(code)) => format!("exited with code {code}"),
        _ => format!("ended ({status})"),
    }
}

impl Remote {
    /// Starts `host` (`windrive`'s executable) as `fmu-host` for instance `name` of the FMU unpacked
    /// in `dir` and waits until it has instantiated the FMU.
    pub fn spawn(dir: &Path, name: &str, logging_on: bool, how: &Isolation) -> Result<Self, ImportError> {
        let host = &how.host;
        let failed = |message: String| ImportError::Isolation {
            instance: name.into(),
            message,
        };
        let (channel, fd) = Channel::create().map_err(|e| failed(e.to_string()))?;
        let raw = fd.as_raw_fd();
        let mut cmd = Command::new(host);
        cmd.arg("fmu-host")
            .arg("--fd")
            .arg(raw.to_string())
            .arg("--dir")
            .arg(dir)
            .arg("--name")
            .arg(name)
            .arg("--master")
            .arg(std::process::id().to_string())
            .stdin(Stdio::null())
            .stdout(Stdio::null());
        if logging_on {
            cmd.arg("--logging");
        }
        // SAFETY: fcntl is async-signal-safe; it lets this one descriptor survive the exec.
        unsafe {
            cmd.pre_exec(move || {
                let flags = libc::fcntl(raw, libc::F_GETFD);
                if flags < 0 || libc::fcntl(raw, libc::F_SETFD, flags & !libc::FD_CLOEXEC) < 0 {
                    return Err(std::io::Error::last_os_error());
                }
                Ok(())
            })
        };
        let child = cmd
            .spawn()
            .map_err(|e| failed(format!("cannot start {} fmu-host: {e}", host.display())))?;
        drop(fd);
        let mut remote = Self {
            name: name.into(),
            channel,
            child,
            seq: 0,
            queued: Vec::new(),
            write_pos: 4,
            reads: Vec::new(),
            answers: Vec::new(),
            answer_bytes: Vec::new(),
            answers_valid: false,
            after_step: false,
            ended: None,
            last_call: Duration::ZERO,
            timeout: how.call_timeout,
        };
        match remote.call(op::HELLO, |_| Ok(())) {
            Err(ImportError::Call { log, .. }) => Err(ImportError::Instantiate {
                instance: name.into(),
                log,
            }),
            other => other.map(|_| remote),
        }
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// Writes a request after those queued. Any request but a read may change the FMU.
    fn push(&mut self, code: u32, args: impl FnOnce(&mut Writer) -> Result<(), WireError>) -> Result<(), ImportError> {
        if let Some(how) = &self.ended {
            return Err(ImportError::Crashed {
                instance: self.name.clone(),
                calls: op::function(code).into(),
                how: how.clone(),
            });
        }
        if !matches!(code, op::GET_REAL | op::GET_INTEGER | op::GET_BOOLEAN | op::TAKE_LOG) {
            self.answers_valid = false;
            self.after_step = false;
        }
        if self.queued.is_empty() {
            self.write_pos = 4;
        }
        let mut w = Writer::at(self.channel.payload(), self.write_pos);
        let written = w.u32(code).and_then(|()| args(&mut w));
        let end = w.pos;
        written.map_err(|e| ImportError::Isolation {
            instance: self.name.clone(),
            message: format!("{}: {e}", op::function(code)),
        })?;
        self.write_pos = end;
        self.queued.push(code);
        Ok(())
    }

    /// Queues a request that only returns a status: it travels with the next call that waits for
    /// an answer, and its failure is reported by that call (naming the queued function).
    fn queue(&mut self, code: u32, args: impl FnOnce(&mut Writer) -> Result<(), WireError>) -> Result<(), ImportError> {
        self.push(code, args)?;
        if self.write_pos > CAPACITY / 2 {
            self.call(op::HELLO, |_| Ok(()))?;
        }
        Ok(())
    }

    /// Sends the queued requests and this one, waits for the host and returns where the last
    /// request's results start in the payload.
    fn call(
        &mut self,
        code: u32,
        args: impl FnOnce(&mut Writer) -> Result<(), WireError>,
    ) -> Result<usize, ImportError> {
        if let Err(e) = self.push(code, args) {
            self.queued.clear();
            return Err(e);
        }
        let sent = std::mem::take(&mut self.queued);
        self.channel.payload()[..4].copy_from_slice(&(sent.len() as u32).to_le_bytes());
        self.seq = self.seq.wrapping_add(1);
        if self.seq == 0 {
            self.seq = 1; // 0 is the counters' initial value: never a request's number
        }
        let Self {
            channel,
            child,
            timeout,
            ..
        } = self;
        let spin = (2 * self.last_call).clamp(MIN_SPIN, MAX_SPIN);
        let started = Instant::now();
        let waited = channel.call(self.seq, spin, || match child.try_wait() {
            Ok(None) => match timeout {
                Some(limit) if started.elapsed() > *limit => {
                    let _ = child.kill();
                    let _ = child.wait();
                    Err(format!("no answer within {} s, killed", limit.as_secs_f64()))
                }
                _ => Ok(()),
            },
            Ok(Some(status)) => Err(describe_exit(status)),
            Err(e) => Err(format!("cannot watch it: {e}")),
        });
        self.last_call = started.elapsed();
        if let Err(how) = waited {
            self.ended = Some(how.clone());
            let mut calls: Vec<&str> = sent.iter().map(|&c| op::function(c)).collect();
            calls.dedup();
            return Err(ImportError::Crashed {
                instance: self.name.clone(),
                calls: calls.join(", "),
                how,
            });
        }
        let mut r = Reader::at(self.channel.payload(), 0);
        let malformed = |e: WireError| ImportError::Isolation {
            instance: self.name.clone(),
            message: format!("reply to {}: {e}", op::function(code)),
        };
        let done = r.u32().map_err(malformed)? as usize;
        let status = Fmi2Status::from_raw(r.i32().map_err(malformed)?);
        if done == sent.len() && matches!(status, Fmi2Status::Ok | Fmi2Status::Warning) {
            return Ok(8);
        }
        let n = r.u32().map_err(malformed)? as usize;
        let log = (0..n.min(1000))
            .map(|_| r.string())
            .collect::<Result<Vec<_>, _>>()
            .map_err(malformed)?;
        Err(ImportError::Call {
            instance: self.name.clone(),
            function: op::function(sent.get(done).copied().unwrap_or(code)),
            status: status.name(),
            log,
        })
    }

    fn reader(&mut self, at: usize) -> Reader<'_> {
        Reader::at(self.channel.payload(), at)
    }

    fn malformed(&self, code: u32, e: WireError) -> ImportError {
        ImportError::Isolation {
            instance: self.name.clone(),
            message: format!("reply to {}: {e}", op::function(code)),
        }
    }

    pub fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Result<(), ImportError> {
        self.call(op::SETUP_EXPERIMENT, |w| {
            w.f64(start)?;
            w.u32(u32::from(stop.is_some()))?;
            w.f64(stop.unwrap_or(0.0))
        })
        .map(drop)
    }
    pub fn enter_initialization_mode(&mut self) -> Result<(), ImportError> {
        self.call(op::ENTER_INITIALIZATION_MODE, |_| Ok(())).map(drop)
    }
    pub fn exit_initialization_mode(&mut self) -> Result<(), ImportError> {
        self.call(op::EXIT_INITIALIZATION_MODE, |_| Ok(())).map(drop)
    }
    pub fn terminate(&mut self) -> Result<(), ImportError> {
        self.call(op::TERMINATE, |_| Ok(())).map(drop)
    }
    pub fn reset(&mut self) -> Result<(), ImportError> {
        self.call(op::RESET, |_| Ok(())).map(drop)
    }
    pub fn set_real(&mut self, vr: &[u32], values: &[f64]) -> Result<(), ImportError> {
        self.queue(op::SET_REAL, |w| {
            w.u32s(vr)?;
            w.f64s(values)
        })
    }
    pub fn set_integer(&mut self, vr: &[u32], values: &[i32]) -> Result<(), ImportError> {
        self.queue(op::SET_INTEGER, |w| {
            w.u32s(vr)?;
            w.i32s(values)
        })
    }
    pub fn set_boolean(&mut self, vr: &[u32], values: &[bool]) -> Result<(), ImportError> {
        self.queue(op::SET_BOOLEAN, |w| {
            w.u32s(vr)?;
            w.u32(values.len() as u32)?;
            values.iter().try_for_each(|&b| w.i32(i32::from(b)))
        })
    }
    pub fn set_string(&mut self, vr: &[u32], values: &[&str]) -> Result<(), ImportError> {
        self.queue(op::SET_STRING, |w| {
            w.u32s(vr)?;
            w.u32(values.len() as u32)?;
            values.iter().try_for_each(|s| w.str(s))
        })
    }
    pub fn set_real_input_derivatives(&mut self, vr: &[u32], order: i32, values: &[f64]) -> Result<(), ImportError> {
        self.queue(op::SET_REAL_INPUT_DERIVATIVES, |w| {
            w.u32s(vr)?;
            w.i32(order)?;
            w.f64s(values)
        })
    }

    /// Steps the FMU; the host also answers the reads the master made after the previous step.
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<(), ImportError> {
        let reads = std::mem::take(&mut self.reads);
        let sent = self.call(op::DO_STEP, |w| {
            w.f64(t)?;
            w.f64(h)?;
            w.u32(reads.len() as u32)?;
            reads.iter().try_for_each(|(code, vr)| {
                w.u32(*code)?;
                w.u32s(vr)
            })
        });
        self.reads = reads;
        let at = sent?;
        let Self {
            channel,
            reads,
            answers,
            answer_bytes,
            ..
        } = self;
        answers.clear();
        answer_bytes.clear();
        let mut r = Reader::at(channel.payload(), at);
        let kept = (|| -> Result<(), WireError> {
            let n = r.u32()? as usize;
            for (code, _) in reads.iter().take(n) {
                if r.u32()? != Fmi2Status::Ok as u32 {
                    answers.push(None);
                    continue;
                }
                let start = r.pos;
                let count = r.u32()? as usize;
                let size = if *code == op::GET_REAL { 8 } else { 4 };
                r.bytes(count.checked_mul(size).ok_or(WireError::Malformed(start))?)?;
                let from = answer_bytes.len();
                answer_bytes.extend_from_slice(r.slice(start));
                answers.push(Some(from..answer_bytes.len()));
            }
            Ok(())
        })();
        kept.map_err(|e| self.malformed(op::DO_STEP, e))?;
        self.answers_valid = true;
        self.after_step = true;
        Ok(())
    }

    /// A read: answered from the last step's reply when the host made it then, else sent (and,
    /// right after a step, remembered for the next ones).
    fn read<T>(
        &mut self,
        code: u32,
        vr: &[u32],
        out: &mut [T],
        decode: impl Fn(&mut Reader, &mut [T]) -> Result<(), WireError>,
    ) -> Result<(), ImportError> {
        if self.answers_valid
            && let Some(i) = self.reads.iter().position(|(c, v)| *c == code && v == vr)
            && let Some(Some(range)) = self.answers.get(i)
        {
            let mut r = Reader::at(&self.answer_bytes[range.clone()], 0);
            return decode(&mut r, out).map_err(|e| self.malformed(code, e));
        }
        if self.after_step
            && self.reads.len() < MAX_READS_AFTER_STEP
            && !self.reads.iter().any(|(c, v)| *c == code && v == vr)
        {
            self.reads.push((code, vr.to_vec()));
        }
        let at = self.call(code, |w| w.u32s(vr))?;
        let mut r = self.reader(at);
        decode(&mut r, out).map_err(|e| self.malformed(code, e))
    }

    pub fn get_real(&mut self, vr: &[u32], values: &mut [f64]) -> Result<(), ImportError> {
        self.read(op::GET_REAL, vr, values, |r, out| r.f64s_into(out))
    }
    pub fn get_integer(&mut self, vr: &[u32], values: &mut [i32]) -> Result<(), ImportError> {
        self.read(op::GET_INTEGER, vr, values, |r, out| r.i32s_into(out))
    }
    pub fn get_boolean(&mut self, vr: &[u32], values: &mut [bool]) -> Result<(), ImportError> {
        self.read(op::GET_BOOLEAN, vr, values, |r, out| r.bools_into(out))
    }

    fn state_call(&mut self, code: u32, handle: Option<u64>) -> Result<u64, ImportError> {
        let at = self.call(code, |w| handle.map_or(Ok(()), |h| w.u64(h)))?;
        self.reader(at).u64().map_err(|e| self.malformed(code, e))
    }
    pub fn get_state(&mut self) -> Result<SavedState, ImportError> {
        self.state_call(op::GET_STATE, None).map(SavedState::from_handle)
    }
    pub fn update_state(&mut self, st: &mut SavedState) -> Result<(), ImportError> {
        *st = SavedState::from_handle(self.state_call(op::UPDATE_STATE, Some(st.handle()))?);
        Ok(())
    }
    pub fn set_state(&mut self, st: &SavedState) -> Result<(), ImportError> {
        self.call(op::SET_STATE, |w| w.u64(st.handle())).map(drop)
    }
    pub fn free_state(&mut self, st: SavedState) -> Result<(), ImportError> {
        self.call(op::FREE_STATE, |w| w.u64(st.handle())).map(drop)
    }
    pub fn serialize_state(&mut self, st: &SavedState) -> Result<Vec<u8>, ImportError> {
        let at = self.call(op::SERIALIZE_STATE, |w| w.u64(st.handle()))?;
        let bytes = self.reader(at).blob().map(<[u8]>::to_vec);
        bytes.map_err(|e| self.malformed(op::SERIALIZE_STATE, e))
    }
    pub fn deserialize_state(&mut self, bytes: &[u8]) -> Result<SavedState, ImportError> {
        let at = self.call(op::DESERIALIZE_STATE, |w| w.blob(bytes))?;
        let handle = self.reader(at).u64();
        handle
            .map(SavedState::from_handle)
            .map_err(|e| self.malformed(op::DESERIALIZE_STATE, e))
    }

    /// The host's kept messages (drained there); empty when the host cannot answer.
    pub fn take_log(&mut self) -> Vec<LogRecord> {
        let Ok(at) = self.call(op::TAKE_LOG, |_| Ok(())) else {
            return Vec::new();
        };
        let mut r = self.reader(at);
        let mut log = Vec::new();
        let _ = (|| -> Result<(), WireError> {
            for _ in 0..r.u32()? {
                let status = Fmi2Status::from_raw(r.u32()? as i32);
                log.push((status, r.string()?, r.string()?));
            }
            Ok(())
        })();
        log
    }
}

impl Drop for Remote {
    /// Frees the instance in the host and lets the host end; kills a host that does not.
    fn drop(&mut self) {
        if self.ended.is_none() {
            let _ = self.call(op::QUIT, |_| Ok(()));
        }
        let deadline = Instant::now() + QUIT_GRACE;
        while Instant::now() < deadline {
            match self.child.try_wait() {
                Ok(None) => std::thread::sleep(POLL / 20),
                _ => return,
            }
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
