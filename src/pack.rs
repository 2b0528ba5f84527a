//! `windrive pack`: builds an FMU crate and writes `target/fmu/<name>.fmu` with
//! modelDescription.xml (taken from the built binary, so its GUID is the binary's),
//! binaries/linux64/<name>.so, resources/ and documentation/index.html. Also the packing around
//! scenes: our FMUs into a scene folder's resources/, and a scene folder into an .ssp archive.

use crate::fmi2::host::description::ModelDescription;
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(Debug, thiserror::Error)]
pub enum PackError {
    #[error("cannot find the windrive workspace (a folder with Cargo.toml and fmus/) above {0}")]
    NoWorkspace(PathBuf),
    #[error("no FMU crate fmus/{0}; available: {1}")]
    UnknownFmu(String, String),
    #[error("cargo build of {0} failed")]
    Build(String),
    #[error("{0}")]
    Io(String),
}

fn io<E: std::fmt::Display>(context: &Path) -> impl Fn(E) -> PackError + '_ {
    move |e| PackError::Io(format!("{}: {e}", context.display()))
}

/// The workspace root: the nearest ancestor of the current folder holding Cargo.toml and fmus/,
/// else the folder this binary was built from.
pub fn workspace_root() -> Result<PathBuf, PackError> {
    let cwd = std::env::current_dir().unwrap_or_default();
    let is_root = |p: &Path| p.join("Cargo.toml").is_file() && p.join("fmus").is_dir();
    if let Some(p) = cwd.ancestors().find(|p| is_root(p)) {
        return Ok(p.to_path_buf());
    }
    let built = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    if is_root(&built) {
        Ok(built)
    } else {
        Err(PackError::NoWorkspace(cwd))
    }
}

pub fn target_dir(root: &Path) -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target"))
}

/// Names of the FMU crates under fmus/.
pub fn fmu_names(root: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(root.join("fmus"))
        .map(|d| {
            d.flatten()
                .filter(|e| e.path().join("Cargo.toml").is_file())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    names
}

/// Builds the FMU crate in release mode (a no-op when it is up to date) and returns the library path.
/// Built beside the `windrive` package, so the library's features are the workspace build's: the FMU
/// links the very library `cargo build --release --workspace` made (no second compile of it without
/// the command line, which cost minutes on a fresh clone, nor relinks back and forth). No command-line
/// crate is in the FMU binary (nothing it exports reaches them); the binaries are 0.1–0.35 MB larger,
/// shared dependencies being compiled with the workspace's features.
pub fn build(root: &Path, name: &str) -> Result<PathBuf, PackError> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let status = std::process::Command::new(cargo)
        .current_dir(root)
        .args(["build", "--quiet", "--release", "-p", "windrive", "-p", name])
        .status()
        .map_err(|e| PackError::Io(format!("cannot run cargo: {e}")))?;
    if !status.success() {
        return Err(PackError::Build(name.into()));
    }
    Ok(target_dir(root).join("release").join(format!("lib{name}.so")))
}

/// The modelDescription.xml compiled into a built FMU binary.
pub fn embedded_description(lib: &Path) -> Result<String, PackError> {
    // SAFETY: our own FMU binary; the symbol returns a static NUL-terminated string.
    unsafe {
        let library = libloading::Library::new(lib).map_err(io(lib))?;
        let f = library
            .get::<unsafe extern "C" fn() -> *const std::ffi::c_char>(b"windrive_model_description\0")
            .map_err(io(lib))?;
        let xml = std::ffi::CStr::from_ptr(f()).to_string_lossy().into_owned();
        Ok(xml)
    }
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// documentation/index.html: the FMU's notes (fmus/<name>/documentation.html) and a table of every variable.
fn documentation(root: &Path, name: &str, md: &ModelDescription) -> String {
    let notes = std::fs::read_to_string(root.join("fmus").join(name).join("documentation.html")).unwrap_or_default();
    let mut rows = String::new();
    for v in &md.model_variables.variables {
        let a = v.attributes();
        rows.push_str(&format!(
            "<tr><td><code>{}</code></td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            escape(&v.name),
            v.value_reference,
            v.type_name(),
            escape(&v.causality),
            escape(a.and_then(|a| a.unit.as_deref()).unwrap_or("")),
            escape(a.and_then(|a| a.start.as_deref()).unwrap_or("")),
            escape(v.description.as_deref().unwrap_or(""))
        ));
    }
    format!(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{name} FMU</title>\
         <style>body{{font-family:sans-serif;max-width:70em;margin:auto}}td,th{{border-bottom:1px solid #ccc;padding:2px 6px;text-align:left}}</style>\
         </head><body>\n<h1>{name}: {}</h1>\n<p>GUID <code>{}</code>, FMI {} Co-Simulation.</p>\n{notes}\n\
         <h2>Variables</h2>\n<table><tr><th>name</th><th>vr</th><th>type</th><th>causality</th><th>unit</th><th>start</th><th>description</th></tr>\n{rows}</table>\n</body></html>\n",
        escape(&md.model_name),
        escape(&md.guid),
        escape(&md.fmi_version)
    )
}

/// Builds (if needed) and packs one FMU; returns the path of the written `.fmu`.
pub fn pack(root: &Path, name: &str) -> Result<PathBuf, PackError> {
    let names = fmu_names(root);
    if !names.iter().any(|n| n == name) {
        return Err(PackError::UnknownFmu(name.into(), names.join(", ")));
    }
    let lib = build(root, name)?;
    let xml = embedded_description(&lib)?;
    let md = ModelDescription::parse(&xml).map_err(|e| PackError::Io(format!("embedded modelDescription: {e}")))?;
    let out_dir = target_dir(root).join("fmu");
    std::fs::create_dir_all(&out_dir).map_err(io(&out_dir))?;
    let out = out_dir.join(format!("{name}.fmu"));
    // written to a file private to this call and renamed, so concurrent packers (other processes, or
    // tests opening scenes on several threads of one) never leave a torn archive or rename another's file
    let tmp = out_dir.join(format!(".{name}.fmu.{}", private_suffix()));
    {
        let file = std::fs::File::create(&tmp).map_err(io(&tmp))?;
        let mut zip = zip::ZipWriter::new(file);
        let opts = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
        let binary = std::fs::read(&lib).map_err(io(&lib))?;
        let doc = documentation(root, name, &md);
        let entries: [(String, &[u8]); 3] = [
            ("modelDescription.xml".into(), xml.as_bytes()),
            (format!("binaries/linux64/{name}.so"), &binary),
            ("documentation/index.html".into(), doc.as_bytes()),
        ];
        for (path, bytes) in entries {
            zip.start_file(path, opts).map_err(io(&tmp))?;
            zip.write_all(bytes).map_err(io(&tmp))?;
        }
        zip.add_directory("resources/", opts).map_err(io(&tmp))?;
        let resources = root.join("fmus").join(name).join("resources");
        // sub-folders too: the rotor keeps one folder per blade (resources/blades/<name>/)
        for f in files_under(&resources) {
            let rel = f.strip_prefix(&resources).unwrap_or(&f);
            let rel = format!("resources/{}", rel.to_string_lossy().replace('\\', "/"));
            zip.start_file(rel, opts).map_err(io(&f))?;
            zip.write_all(&std::fs::read(&f).map_err(io(&f))?).map_err(io(&tmp))?;
        }
        zip.finish().map_err(io(&tmp))?;
    }
    std::fs::rename(&tmp, &out).map_err(io(&out))?;
    Ok(out)
}

/// Every file below `dir`, sorted so that a package's bytes do not depend on the directory order.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else { continue };
        for p in entries.flatten().map(|e| e.path()) {
            if p.is_dir() {
                stack.push(p);
            } else if p.is_file() {
                files.push(p);
            }
        }
    }
    files.sort();
    files
}

/// Our own FMUs among `fmus` (a scene's component files, resources/<name>.fmu) are packed from the
/// workspace when the file is missing (or always, with `refresh`), and replaced by
/// target/fmu/<name>.fmu when that is newer, so a scene folder runs on a fresh clone and never with a
/// stale copy. Outside a workspace, and for other tools' FMUs, nothing is done.
pub fn provide_own_fmus<'a>(fmus: impl IntoIterator<Item = &'a Path>, refresh: bool) -> Result<(), PackError> {
    let Ok(root) = workspace_root() else {
        return Ok(());
    };
    let ours = fmu_names(&root);
    let modified = |p: &Path| std::fs::metadata(p).and_then(|m| m.modified()).ok();
    for path in fmus {
        let Some(stem) = path.file_stem().map(|s| s.to_string_lossy().into_owned()) else {
            continue;
        };
        if !ours.contains(&stem) || path.extension().is_none_or(|e| e != "fmu") {
            continue;
        }
        let packed = target_dir(&root).join("fmu").join(format!("{stem}.fmu"));
        let source = if refresh || !path.exists() {
            pack(&root, &stem)?
        } else if modified(&packed) > modified(path) {
            packed
        } else {
            continue;
        };
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(io(dir))?;
        }
        copy_atomically(&source, path)?;
    }
    Ok(())
}

/// Copies to a file private to this call and renames it into place: runs of the same scene started
/// together (a campaign's workers, or tests opening one scene on several threads of one process) each
/// open a whole FMU, the old or the new, never one half written, and no copy renames another's file.
fn copy_atomically(source: &Path, dest: &Path) -> Result<(), PackError> {
    let name = dest
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dest.with_file_name(format!(".{name}.{}.tmp", private_suffix()));
    let context = |e: std::io::Error| PackError::Io(format!("copying {} to {}: {e}", source.display(), dest.display()));
    std::fs::copy(source, &tmp).map_err(context)?;
    std::fs::rename(&tmp, dest)
        .inspect_err(|_| drop(std::fs::remove_file(&tmp)))
        .map_err(context)
}

/// A suffix no other call, in this process or another, uses: the process id and a count of calls.
fn private_suffix() -> String {
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    format!("{}-{call}", std::process::id())
}

/// Writes every file below the scene folder `folder` into the SSP archive `out`, deflated, in the
/// order of their paths within the folder.
pub fn write_ssp(folder: &Path, out: &Path) -> Result<(), PackError> {
    let mut files = Vec::new();
    scene_files(folder, folder, &mut files)?;
    files.sort();
    let file = std::fs::File::create(out).map_err(io(out))?;
    let mut zip = zip::ZipWriter::new(file);
    let opts = zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    let plain = |e: &dyn std::fmt::Display| PackError::Io(e.to_string());
    for (rel, path) in files {
        zip.start_file(rel, opts).map_err(|e| plain(&e))?;
        zip.write_all(&std::fs::read(&path).map_err(io(&path))?)
            .map_err(|e| plain(&e))?;
    }
    zip.finish().map_err(|e| plain(&e))?;
    Ok(())
}

/// (path within `root` with / separators, path) of every file below `dir`.
fn scene_files(root: &Path, dir: &Path, out: &mut Vec<(String, PathBuf)>) -> Result<(), PackError> {
    for entry in std::fs::read_dir(dir).map_err(io(dir))? {
        let path = entry.map_err(|e| PackError::Io(e.to_string()))?.path();
        if path.is_dir() {
            scene_files(root, &path, out)?;
        } else {
            let rel = path
                .strip_prefix(root)
                .map_err(|e| PackError::Io(e.to_string()))?
                .to_string_lossy()
                .replace('\\', "/");
            out.push((rel, path));
        }
    }
    Ok(())
}
