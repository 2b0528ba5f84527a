//! Unpacking `.fmu` and `.ssp` archives, which may come from anyone: every entry must land inside
//! the folder (no `../`, no absolute path, no symbolic link), the bytes written are bounded (a zip
//! bomb is refused, not extracted), and the private folder is removed when its owner is dropped,
//! or, when a run was killed before that, by the next run that unpacks anything.

use super::error::ImportError;
use std::io::Read;
use std::path::{Path, PathBuf};

/// The environment variable that overrides [`Limits::for_archive`]'s byte bound.
pub const MAX_BYTES_VAR: &str = "WINDRIVE_MAX_UNPACKED_BYTES";

/// What one archive may unpack to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Bytes written over all entries.
    pub max_bytes: u64,
    pub max_entries: usize,
}

impl Limits {
    /// 1 GiB or 200 times the archive's size, whichever is larger, unless `WINDRIVE_MAX_UNPACKED_BYTES`
    /// says otherwise. Why: real FMUs compress their binaries and tables 2–20×; a zip bomb
    /// compresses zeros 1000×. The floor keeps FMUs with large compressible resources working.
    pub fn for_archive(archive_bytes: u64) -> Self {
        let default = (1u64 << 30).max(archive_bytes.saturating_mul(200));
        let max_bytes = std::env::var(MAX_BYTES_VAR)
            .ok()
            .and_then(|v| v.trim().parse().ok())
            .unwrap_or(default);
        Self {
            max_bytes,
            max_entries: 100_000,
        }
    }
}

/// Unpacks the zip archive `archive` into the empty folder `dest` within [`Limits::for_archive`].
/// On an error, whatever was written stays in `dest` for its owner (a [`TempDir`]) to remove.
pub fn unzip(archive: &Path, dest: &Path) -> Result<(), ImportError> {
    let size = std::fs::metadata(archive).map(|m| m.len()).unwrap_or(0);
    unzip_within(archive, dest, Limits::for_archive(size))
}

/// [`unzip`] with explicit limits.
pub fn unzip_within(archive: &Path, dest: &Path, limits: Limits) -> Result<(), ImportError> {
    let fail = |message: String| ImportError::Archive {
        path: archive.to_path_buf(),
        message,
    };
    let file = std::fs::File::open(archive).map_err(|e| fail(e.to_string()))?;
    let mut zip = zip::ZipArchive::new(file)
        .map_err(|e| fail(format!("not a valid zip archive (truncated or not a zip file?): {e}")))?;
    if zip.len() > limits.max_entries {
        return Err(fail(format!(
            "{} entries, more than the {} an FMU or SSP may hold",
            zip.len(),
            limits.max_entries
        )));
    }
    // First pass, before anything is written: names, kinds and the sizes the archive declares.
    let mut plan = Vec::with_capacity(zip.len());
    let mut declared: u64 = 0;
    for i in 0..zip.len() {
        let entry = zip.by_index_raw(i).map_err(|e| fail(format!("entry {i}: {e}")))?;
        let name = String::from_utf8_lossy(entry.name_raw()).into_owned();
        let rel = safe_path(&name, entry.enclosed_name()).map_err(|why| fail(format!("entry \"{name}\" {why}")))?;
        if entry.is_symlink() {
            return Err(fail(format!(
                "entry \"{name}\" is a symbolic link (refused: it could point outside the archive's folder)"
            )));
        }
        if entry.encrypted() {
            return Err(fail(format!("entry \"{name}\" is encrypted")));
        }
        declared = declared.saturating_add(entry.size());
        plan.push((rel, entry.is_dir()));
    }
    if declared > limits.max_bytes {
        return Err(too_big(archive, declared, limits, "declares"));
    }
    // Second pass: the bytes actually inflated are counted too, since a header may lie.
    let mut written: u64 = 0;
    for (i, (rel, is_dir)) in plan.into_iter().enumerate() {
        let out = dest.join(&rel);
        if is_dir {
            std::fs::create_dir_all(&out).map_err(|e| fail(format!("{}: {e}", out.display())))?;
            continue;
        }
        if let Some(parent) = out.parent() {
            std::fs::create_dir_all(parent).map_err(|e| fail(format!("{}: {e}", parent.display())))?;
        }
        let entry = zip
            .by_index(i)
            .map_err(|e| fail(format!("entry \"{}\": {e}", rel.display())))?;
        let mut w = std::fs::File::create(&out).map_err(|e| fail(format!("{}: {e}", out.display())))?;
        let allowed = limits.max_bytes - written;
        let n = std::io::copy(&mut entry.take(allowed + 1), &mut w)
            .map_err(|e| fail(format!("entry \"{}\": {e}", rel.display())))?;
        written += n;
        if n > allowed {
            return Err(too_big(archive, written, limits, "inflates to at least"));
        }
    }
    Ok(())
}

/// Why an entry's name is refused, or the relative path it unpacks to.
fn safe_path(name: &str, enclosed: Option<PathBuf>) -> Result<PathBuf, &'static str> {
    if name.contains('\0') {
        return Err("has a NUL byte in its name");
    }
    if name.starts_with('/') || name.starts_with('\\') || name.get(1..3) == Some(":\\") || name.get(1..3) == Some(":/")
    {
        return Err("is an absolute path");
    }
    match enclosed {
        Some(p) if !p.as_os_str().is_empty() => Ok(p),
        Some(_) => Err("has an empty name"),
        None => Err("leaves the archive's folder (a zip-slip path)"),
    }
}

fn too_big(archive: &Path, bytes: u64, limits: Limits, verb: &str) -> ImportError {
    ImportError::Archive {
        path: archive.to_path_buf(),
        message: format!(
            "{verb} {bytes} bytes unpacked, more than the limit of {} bytes (a zip bomb?); nothing of it is kept. \
             Set {MAX_BYTES_VAR} to a larger number of bytes if the archive is genuine",
            limits.max_bytes
        ),
    }
}

/// A private temporary folder, removed on drop. Its name holds the process id, so folders that a
/// killed process left behind are recognised and removed when the next one is made.
#[derive(Debug)]
pub struct TempDir(PathBuf);

impl TempDir {
    pub fn new(prefix: &str) -> std::io::Result<Self> {
        use std::sync::atomic::{AtomicU64, Ordering};
        static COUNTER: AtomicU64 = AtomicU64::new(0);
        let base = std::env::temp_dir();
        remove_orphans(&base, prefix);
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        let path = base.join(format!(
            "{prefix}-{}-{}-{nanos}",
            std::process::id(),
            COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::create_dir_all(&path)?;
        Ok(Self(path))
    }

    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Removes `<base>/<prefix>-<pid>-…` folders whose process is gone (Linux: no `/proc/<pid>`).
/// Where there is no `/proc`, nothing is removed: a live process's folder must never go.
pub fn remove_orphans(base: &Path, prefix: &str) {
    if !Path::new("/proc/self").exists() {
        return;
    }
    let Ok(entries) = std::fs::read_dir(base) else {
        return;
    };
    let head = format!("{prefix}-");
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(rest) = name.to_str().and_then(|n| n.strip_prefix(&head)) else {
            continue;
        };
        let Some(pid) = rest.split('-').next().and_then(|p| p.parse::<u32>().ok()) else {
            continue;
        };
        let alive = Path::new("/proc").join(pid.to_string()).exists();
        if !alive && entry.file_type().is_ok_and(|t| t.is_dir()) {
            let _ = std::fs::remove_dir_all(entry.path());
        }
    }
}
