//! One shared-memory mailbox between the master and the process hosting one FMU instance: a memfd
//! both map, two counters that say whose turn it is, and a payload area the side whose turn it is
//! owns. The waiting side spins for a few microseconds (a reply to a short FMU call comes back
//! faster than a sleeping process can be woken) and then sleeps on a futex, waking every
//! [`POLL`] to ask whether the other side is still alive.

use std::io;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd, RawFd};
use std::ptr::NonNull;
use std::sync::atomic::{AtomicU32, Ordering::SeqCst};
use std::time::{Duration, Instant};

/// Bytes of the mapping: requests and replies (a serialised FMU state included) must fit in it. Pages
/// are only backed when written, so a mailbox that carries a few hundred bytes per call costs that.
pub const CAPACITY: usize = 64 << 20;
/// The counters sit in the first page; the payload starts after it.
const PAYLOAD_OFFSET: usize = 4096;
/// How often a sleeping side checks that the other is alive.
pub const POLL: Duration = Duration::from_millis(20);

/// The first page of the mapping. Each counter on its own cache line: the two processes write
/// different ones and must not slow each other down.
#[repr(C, align(64))]
struct Line(AtomicU32);

#[repr(C)]
struct Header {
    /// Bumped by the master when a request is in the payload.
    request: Line,
    /// Set to the request's number by the host when the reply is in the payload.
    reply: Line,
    /// Whether the host / the master sleeps on its futex (the other side then has to wake it).
    host_sleeps: Line,
    master_sleeps: Line,
}

/// A mapping of a mailbox. The memfd behind it lives as long as some process maps it.
pub struct Channel {
    base: NonNull<u8>,
    len: usize,
}

// SAFETY: the mapping is plain shared memory; which side may touch the payload is decided by the
// counters, and a Channel is used by one thread at a time (it is not Sync).
unsafe impl Send for Channel {}

fn last_os_error<T>(what: &str) -> io::Result<T> {
    let e = io::Error::last_os_error();
    Err(io::Error::new(e.kind(), format!("{what}: {e}")))
}

impl Channel {
    /// A new mailbox and its memfd (close-on-exec: hand it to a child explicitly).
    pub fn create() -> io::Result<(Self, OwnedFd)> {
        // SAFETY: plain syscalls on a name and a fresh descriptor.
        let raw = unsafe { libc::memfd_create(c"windrive-fmu-mailbox".as_ptr(), libc::MFD_CLOEXEC) };
        if raw < 0 {
            return last_os_error("memfd_create");
        }
        // SAFETY: raw is a descriptor we own from here on.
        let fd = unsafe { OwnedFd::from_raw_fd(raw) };
        if unsafe { libc::ftruncate(fd.as_raw_fd(), (PAYLOAD_OFFSET + CAPACITY) as libc::off_t) } != 0 {
            return last_os_error("ftruncate of the mailbox");
        }
        let channel = Self::map(fd.as_raw_fd(), PAYLOAD_OFFSET + CAPACITY)?;
        Ok((channel, fd))
    }

    /// Maps the mailbox whose descriptor a host process inherited.
    pub fn open(fd: RawFd) -> io::Result<Self> {
        // SAFETY: fstat writes into the zeroed struct.
        let mut st: libc::stat = unsafe { std::mem::zeroed() };
        if unsafe { libc::fstat(fd, &mut st) } != 0 {
            return last_os_error("fstat of the mailbox");
        }
        let len = st.st_size as usize;
        if len <= PAYLOAD_OFFSET {
            return Err(io::Error::other(format!(
                "descriptor {fd} is not a mailbox ({len} bytes)"
            )));
        }
        Self::map(fd, len)
    }

    fn map(fd: RawFd, len: usize) -> io::Result<Self> {
        // SAFETY: a shared mapping of a descriptor we hold; unmapped on drop.
        let p = unsafe {
            libc::mmap(
                std::ptr::null_mut(),
                len,
                libc::PROT_READ | libc::PROT_WRITE,
                libc::MAP_SHARED,
                fd,
                0,
            )
        };
        if p == libc::MAP_FAILED {
            return last_os_error("mmap of the mailbox");
        }
        Ok(Self {
            base: NonNull::new(p as *mut u8).expect("mmap never maps page 0"),
            len,
        })
    }

    fn header(&self) -> &Header {
        // SAFETY: the first page is the header; its fields are atomics, valid for any bit pattern.
        unsafe { &*(self.base.as_ptr() as *const Header) }
    }

    /// The payload: the caller must hold the turn (the master before `call`, the host between
    /// `next_request` and `reply`).
    pub fn payload(&mut self) -> &mut [u8] {
        // SAFETY: within the mapping; the other process does not touch it while we hold the turn.
        unsafe { std::slice::from_raw_parts_mut(self.base.as_ptr().add(PAYLOAD_OFFSET), self.len - PAYLOAD_OFFSET) }
    }

    /// Master: hands request number `seq` (the payload holds it) to the host and waits for its
    /// reply. `alive` is asked every [`POLL`] while waiting; its error ends the wait.
    pub fn call<E>(&mut self, seq: u32, spin: Duration, alive: impl FnMut() -> Result<(), E>) -> Result<(), E> {
        let h = self.header();
        h.request.0.store(seq, SeqCst);
        if h.host_sleeps.0.load(SeqCst) != 0 {
            futex_wake(&h.request.0);
        }
        wait_while(&h.reply.0, seq.wrapping_sub(1), &h.master_sleeps.0, spin, alive)
    }

    /// Host: waits for the request after number `last` and returns its number.
    pub fn next_request<E>(
        &mut self,
        last: u32,
        spin: Duration,
        alive: impl FnMut() -> Result<(), E>,
    ) -> Result<u32, E> {
        let h = self.header();
        wait_while(&h.request.0, last, &h.host_sleeps.0, spin, alive)?;
        Ok(h.request.0.load(SeqCst))
    }

    /// Host: the reply to request `seq` is in the payload.
    pub fn reply(&mut self, seq: u32) {
        let h = self.header();
        h.reply.0.store(seq, SeqCst);
        if h.master_sleeps.0.load(SeqCst) != 0 {
            futex_wake(&h.reply.0);
        }
    }
}

impl Drop for Channel {
    fn drop(&mut self) {
        // SAFETY: the mapping made in `map`, unmapped once.
        unsafe { libc::munmap(self.base.as_ptr() as *mut libc::c_void, self.len) };
    }
}

/// Waits until `word` is no longer `old`: spinning for `spin`, then sleeping on the futex with
/// `sleeping` raised (so the writer knows to wake us), asking `alive` every [`POLL`].
fn wait_while<E>(
    word: &AtomicU32,
    old: u32,
    sleeping: &AtomicU32,
    spin: Duration,
    mut alive: impl FnMut() -> Result<(), E>,
) -> Result<(), E> {
    // Spinning yields the core each time round: on a machine with fewer cores than busy processes
    // (two, here: the master, the host that steps, hosts that wait) a plain spin keeps the process
    // that would answer from running (measured: a pure spin of 10 µs before yielding makes a
    // run 2.7x slower, sleeping at once 7x).
    let start = Instant::now();
    while word.load(SeqCst) == old && start.elapsed() < spin {
        // SAFETY: sched_yield has no arguments and cannot fail.
        unsafe { libc::sched_yield() };
    }
    loop {
        if word.load(SeqCst) != old {
            return Ok(());
        }
        sleeping.store(1, SeqCst);
        // raised before the second look: a writer that changed the word after it saw the flag
        let woken = word.load(SeqCst) != old || futex_wait(word, old, POLL);
        sleeping.store(0, SeqCst);
        if !woken && word.load(SeqCst) == old {
            alive()?;
        }
    }
}

/// Sleeps while `*word == old`, at most `timeout`; false when the timeout passed.
fn futex_wait(word: &AtomicU32, old: u32, timeout: Duration) -> bool {
    let ts = libc::timespec {
        tv_sec: timeout.as_secs() as libc::time_t,
        tv_nsec: timeout.subsec_nanos() as libc::c_long,
    };
    // SAFETY: futex on a word of a shared mapping (not FUTEX_PRIVATE: two processes use it).
    let r = unsafe {
        libc::syscall(
            libc::SYS_futex,
            word.as_ptr(),
            libc::FUTEX_WAIT,
            old,
            &ts as *const libc::timespec,
            std::ptr::null::<u32>(),
            0,
        )
    };
    !(r != 0 && io::Error::last_os_error().raw_os_error() == Some(libc::ETIMEDOUT))
}

fn futex_wake(word: &AtomicU32) {
    // SAFETY: wakes the waiters of a word of a shared mapping.
    unsafe {
        libc::syscall(
            libc::SYS_futex,
            word.as_ptr(),
            libc::FUTEX_WAKE,
            i32::MAX,
            std::ptr::null::<libc::timespec>(),
            std::ptr::null::<u32>(),
            0,
        )
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_mappings_of_one_mailbox_take_turns() {
        let (mut master, fd) = Channel::create().unwrap();
        let mut host = Channel::open(fd.as_raw_fd()).unwrap();
        let server = std::thread::spawn(move || {
            let mut last = 0;
            for _ in 0..1000 {
                last = host
                    .next_request(last, Duration::from_micros(5), || Ok::<(), ()>(()))
                    .unwrap();
                let p = host.payload();
                let x = u64::from_le_bytes(p[..8].try_into().unwrap());
                p[..8].copy_from_slice(&(x * 2).to_le_bytes());
                host.reply(last);
            }
        });
        for seq in 1..=1000u32 {
            master.payload()[..8].copy_from_slice(&u64::from(seq).to_le_bytes());
            // short spin: most waits end asleep, exercising the futex path
            master
                .call(seq, Duration::from_micros(if seq % 2 == 0 { 0 } else { 50 }), || {
                    Ok::<(), ()>(())
                })
                .unwrap();
            assert_eq!(
                u64::from_le_bytes(master.payload()[..8].try_into().unwrap()),
                2 * u64::from(seq)
            );
        }
        server.join().unwrap();
    }

    #[test]
    fn a_silent_host_is_noticed_by_the_liveness_check() {
        let (mut master, _fd) = Channel::create().unwrap();
        let mut asked = 0;
        let r = master.call(1, Duration::ZERO, || {
            asked += 1;
            if asked == 3 { Err("gone") } else { Ok(()) }
        });
        assert_eq!(r, Err("gone"));
    }
}
