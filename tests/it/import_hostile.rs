//! The importer and the SSP reader on archives and XML a hostile or careless tool made (issue 16):
//! every one refused with a message naming the user's file and the entry, nothing written outside
//! the private folder, the bytes unpacked bounded, nothing left behind, and no panic from the
//! parsers on ten thousand mutated documents.

use std::io::Write;
use std::path::{Path, PathBuf};
use windrive::cosim::Scene;
use windrive::fmi2::host::archive::{Limits, TempDir, remove_orphans, unzip, unzip_within};
use windrive::fmi2::host::import::Fmu;
use zip::write::SimpleFileOptions;

/// A zip archive at `path` with `(name, bytes)` entries, deflated.
fn write_zip(path: &Path, entries: &[(&str, &[u8])]) {
    let mut w = zip::ZipWriter::new(std::fs::File::create(path).unwrap());
    let opts = SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    for (name, bytes) in entries {
        w.start_file(*name, opts).unwrap();
        w.write_all(bytes).unwrap();
    }
    w.finish().unwrap();
}

fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        if e.path().is_dir() {
            out.extend(files_under(&e.path()));
        } else {
            out.push(e.path());
        }
    }
    out
}

fn error_of<T>(r: Result<T, impl std::fmt::Display>) -> String {
    match r {
        Ok(_) => panic!("accepted"),
        Err(e) => e.to_string(),
    }
}

const MINIMAL_XML: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="m" guid="{0}">
  <CoSimulation modelIdentifier="m"/>
  <ModelVariables/>
  <ModelStructure/>
</fmiModelDescription>"#;

#[test]
fn zip_slip_absolute_and_empty_names_are_refused_by_name_and_nothing_escapes() {
    let tmp = TempDir::new("windrive-test-hostile").unwrap();
    let cases: [(&str, &str); 3] = [
        ("../../evil.txt", "leaves the archive's folder"),
        ("/tmp/windrive-evil-absolute.txt", "is an absolute path"),
        ("resources/../../evil.txt", "leaves the archive's folder"),
    ];
    for (i, (name, why)) in cases.iter().enumerate() {
        let archive = tmp.path().join(format!("slip{i}.fmu"));
        write_zip(
            &archive,
            &[("modelDescription.xml", MINIMAL_XML.as_bytes()), (name, b"x")],
        );
        let dest = tmp.path().join(format!("out{i}"));
        std::fs::create_dir_all(&dest).unwrap();
        let msg = error_of(unzip(&archive, &dest));
        assert!(msg.contains(&format!("entry \"{name}\" {why}")), "{msg}");
        assert!(msg.contains(&format!("slip{i}.fmu")), "{msg}");
        assert!(
            !msg.contains("Ok(") && !msg.contains("Err("),
            "Rust debug text in {msg:?}"
        );
        // refused before anything was written
        assert!(files_under(&dest).is_empty(), "{:?}", files_under(&dest));
    }
    assert!(!tmp.path().parent().unwrap().join("evil.txt").exists());
    assert!(!Path::new("/tmp/windrive-evil-absolute.txt").exists());
}

#[test]
fn a_symbolic_link_entry_is_refused() {
    let tmp = TempDir::new("windrive-test-hostile").unwrap();
    let archive = tmp.path().join("link.fmu");
    let mut w = zip::ZipWriter::new(std::fs::File::create(&archive).unwrap());
    w.add_symlink("resources/passwd", "/etc/passwd", SimpleFileOptions::default())
        .unwrap();
    w.finish().unwrap();
    let msg = error_of(Fmu::open(&archive));
    assert!(
        msg.contains("link.fmu") && msg.contains("\"resources/passwd\" is a symbolic link"),
        "{msg}"
    );
}

#[test]
fn a_zip_bomb_is_refused_from_its_declared_size_before_anything_is_written() {
    let tmp = TempDir::new("windrive-test-hostile").unwrap();
    let archive = tmp.path().join("bomb.fmu");
    let zeros = vec![0u8; 8 << 20];
    write_zip(&archive, &[("a.bin", &zeros), ("b.bin", &zeros), ("c.bin", &zeros)]);
    let size = std::fs::metadata(&archive).unwrap().len();
    assert!(size < 200_000, "{size} bytes: not a bomb-like ratio");
    let dest = tmp.path().join("out");
    std::fs::create_dir_all(&dest).unwrap();
    let limits = Limits {
        max_bytes: 16 << 20,
        max_entries: 100,
    };
    let msg = error_of(unzip_within(&archive, &dest, limits));
    assert!(
        msg.contains("declares 25165824 bytes unpacked") && msg.contains("zip bomb"),
        "{msg}"
    );
    assert!(msg.contains("WINDRIVE_MAX_UNPACKED_BYTES"), "{msg}");
    assert!(files_under(&dest).is_empty());
    // within the limit it unpacks whole
    let roomy = Limits {
        max_bytes: 32 << 20,
        ..limits
    };
    unzip_within(&archive, &dest, roomy).unwrap();
    assert_eq!(files_under(&dest).len(), 3);
    // the default for a 100 kB archive is the 1 GiB floor
    assert_eq!(Limits::for_archive(100_000).max_bytes, 1 << 30);
    assert_eq!(Limits::for_archive(100 << 20).max_bytes, 20_000 << 20);
}

#[test]
fn a_header_that_understates_the_size_cannot_inflate_past_the_limit() {
    let tmp = TempDir::new("windrive-test-hostile").unwrap();
    let archive = tmp.path().join("liar.fmu");
    let zeros = vec![0u8; 8 << 20];
    write_zip(&archive, &[("a.bin", &zeros)]);
    // rewrite the central directory's uncompressed size (offset 24 of its header) to 1 kB
    let mut bytes = std::fs::read(&archive).unwrap();
    let cd = bytes.windows(4).rposition(|w| w == [0x50, 0x4b, 0x01, 0x02]).unwrap();
    bytes[cd + 24..cd + 28].copy_from_slice(&1024u32.to_le_bytes());
    let lo = bytes.windows(4).position(|w| w == [0x50, 0x4b, 0x03, 0x04]).unwrap();
    bytes[lo + 22..lo + 26].copy_from_slice(&1024u32.to_le_bytes());
    std::fs::write(&archive, &bytes).unwrap();
    let dest = tmp.path().join("out");
    std::fs::create_dir_all(&dest).unwrap();
    let limits = Limits {
        max_bytes: 1 << 20,
        max_entries: 100,
    };
    // refused (by the byte count or by the zip reader's own size/CRC check); never 8 MB on disk
    let msg = error_of(unzip_within(&archive, &dest, limits));
    assert!(msg.contains("liar.fmu") && msg.contains("entry \"a.bin\""), "{msg}");
    let written: u64 = files_under(&dest)
        .iter()
        .map(|f| std::fs::metadata(f).unwrap().len())
        .sum();
    assert!(written <= (1 << 20) + 1, "{written} bytes written");
}

#[test]
fn a_truncated_archive_and_an_archive_that_is_no_zip_are_refused() {
    let tmp = TempDir::new("windrive-test-hostile").unwrap();
    let archive = tmp.path().join("cut.fmu");
    write_zip(&archive, &[("modelDescription.xml", MINIMAL_XML.as_bytes())]);
    let bytes = std::fs::read(&archive).unwrap();
    std::fs::write(&archive, &bytes[..bytes.len() / 2]).unwrap();
    let msg = error_of(Fmu::open(&archive));
    assert!(
        msg.contains("cut.fmu") && msg.contains("not a valid zip archive"),
        "{msg}"
    );
}

#[test]
fn a_malformed_description_names_the_fmu_not_the_temporary_folder() {
    let tmp = TempDir::new("windrive-test-hostile").unwrap();
    let archive = tmp.path().join("broken-xml.fmu");
    write_zip(
        &archive,
        &[("modelDescription.xml", b"<fmiModelDescription fmiVersion=\"2.0\" <oops")],
    );
    let msg = error_of(Fmu::open(&archive));
    assert!(msg.contains("broken-xml.fmu: modelDescription.xml:"), "{msg}");
    assert!(!msg.contains("windrive-fmu-"), "{msg}");
}

#[test]
fn missing_binaries_and_a_wrong_platform_are_named() {
    let tmp = TempDir::new("windrive-test-hostile").unwrap();
    let win = tmp.path().join("windows-only.fmu");
    write_zip(
        &win,
        &[
            ("modelDescription.xml", MINIMAL_XML.as_bytes()),
            ("binaries/win64/m.dll", b"MZ"),
        ],
    );
    let msg = error_of(Fmu::open(&win));
    assert!(
        msg.contains("windows-only.fmu") && msg.contains("no binaries/linux64/m.so"),
        "{msg}"
    );
    assert!(msg.contains("binaries for win64 only"), "{msg}");
    let none = tmp.path().join("no-binaries.fmu");
    write_zip(&none, &[("modelDescription.xml", MINIMAL_XML.as_bytes())]);
    let msg = error_of(Fmu::open(&none));
    assert!(
        msg.contains("no-binaries.fmu") && msg.contains("it has no binaries"),
        "{msg}"
    );
}

#[test]
fn a_refused_archive_leaves_no_folder_and_a_killed_runs_folder_is_removed_by_the_next() {
    let base = std::env::temp_dir();
    let prefix = format!("windrive-test-orphan{}", std::process::id());
    // a process that has ended: its pid names no /proc entry (pids are not reused this soon)
    let mut child = std::process::Command::new("true").spawn().unwrap();
    let dead = child.id();
    child.wait().unwrap();
    let orphan = base.join(format!("{prefix}-{dead}-0-1"));
    std::fs::create_dir_all(orphan.join("binaries")).unwrap();
    std::fs::write(orphan.join("binaries/x.so"), b"x").unwrap();
    let ours = TempDir::new(&prefix).unwrap();
    assert!(!orphan.exists(), "the dead process's folder is still there");
    assert!(ours.path().is_dir());
    // a live process's folder stays
    let live = base.join(format!("{prefix}-{}-9-9", std::process::id()));
    std::fs::create_dir_all(&live).unwrap();
    remove_orphans(&base, &prefix);
    assert!(live.is_dir());
    std::fs::remove_dir_all(&live).unwrap();
    drop(ours);

    // an FMU refused after unpacking leaves no windrive-fmu folder of this process behind
    let tmp = TempDir::new("windrive-test-hostile").unwrap();
    let archive = tmp.path().join("refused.fmu");
    write_zip(&archive, &[("modelDescription.xml", MINIMAL_XML.as_bytes())]);
    let mine = |p: &std::fs::DirEntry| {
        let n = p.file_name().to_string_lossy().into_owned();
        n.starts_with(&format!("windrive-fmu-{}-", std::process::id()))
    };
    let before = std::fs::read_dir(&base).unwrap().flatten().filter(mine).count();
    let _ = error_of(Fmu::open(&archive));
    let after = std::fs::read_dir(&base).unwrap().flatten().filter(mine).count();
    assert!(after <= before, "{before} -> {after} extraction folders");
}

const SSD_HEAD: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" version="1.0" name="x">
  <ssd:System name="s"><ssd:Elements>"#;

#[test]
fn an_ssp_archive_may_only_name_its_own_files_and_its_errors_name_the_archive() {
    let tmp = TempDir::new("windrive-test-hostile").unwrap();
    for (i, source) in ["../../outside.fmu", "/usr/lib/evil.fmu", "file:/etc/x.fmu"]
        .iter()
        .enumerate()
    {
        let ssd = format!(
            "{SSD_HEAD}<ssd:Component name=\"c\" source=\"{source}\" type=\"application/x-fmu-sharedlibrary\"/>\
             </ssd:Elements></ssd:System></ssd:SystemStructureDescription>"
        );
        let archive = tmp.path().join(format!("escape{i}.ssp"));
        write_zip(&archive, &[("SystemStructure.ssd", ssd.as_bytes())]);
        let msg = error_of(Scene::open(&archive));
        assert!(msg.contains("lies outside the .ssp archive"), "{msg}");
        assert!(msg.contains(&format!("escape{i}.ssp/SystemStructure.ssd:3")), "{msg}");
        assert!(!msg.contains("windrive-ssp-"), "{msg}");
    }
    // a malformed .ssd inside an archive: the archive is named, not the temporary folder
    let archive = tmp.path().join("malformed.ssp");
    write_zip(
        &archive,
        &[("SystemStructure.ssd", b"<ssd:SystemStructureDescription><a></b>")],
    );
    let msg = error_of(Scene::open(&archive));
    assert!(
        msg.contains("malformed.ssp/SystemStructure.ssd") && !msg.contains("windrive-ssp-"),
        "{msg}"
    );
}

#[test]
fn deeply_nested_xml_is_refused_without_exhausting_the_stack() {
    let depth = 1_000_000;
    let deep = format!("{}{}", "<a>".repeat(depth), "</a>".repeat(depth));
    let msg = windrive::cosim::xml::parse(&deep).unwrap_err();
    assert!(msg.contains("nested deeper than 200"), "{msg}");
    let md = MINIMAL_XML.replace(
        "<ModelStructure/>",
        &format!("<ModelStructure/><VendorAnnotations>{deep}</VendorAnnotations>"),
    );
    // refused or accepted, but answered: no stack overflow, no panic
    let _ = windrive::fmi2::host::description::ModelDescription::parse(&md);
}

use crate::common::Rng;

/// `text` with a few bytes flipped, deleted, duplicated or replaced by XML-ish fragments.
fn mutate(text: &[u8], rng: &mut Rng) -> Vec<u8> {
    const FRAGMENTS: [&[u8]; 8] = [b"<", b">", b"\"", b"</", b"/>", b"&amp;", b"&#xFFFF;", b"\xff\xfe"];
    let mut out = text.to_vec();
    for _ in 0..1 + rng.below(4) {
        let at = rng.below(out.len());
        match rng.below(4) {
            0 => out[at] ^= 1 << rng.below(8),
            1 => {
                let end = (at + rng.below(64)).min(out.len());
                out.drain(at..end);
            }
            2 => {
                let end = (at + rng.below(256)).min(out.len());
                let copy = out[at..end].to_vec();
                out.splice(at..at, copy);
            }
            _ => {
                let f = FRAGMENTS[rng.below(FRAGMENTS.len())];
                out.splice(at..at, f.iter().copied());
            }
        }
    }
    out
}

#[test]
fn ten_thousand_mutated_descriptions_and_scenes_never_panic_the_parsers() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut docs: Vec<(PathBuf, Vec<u8>)> = Vec::new();
    for dir in ["modelDescription", "scenes/c-shutdown", "scenes/d-shutdown-6dof"] {
        // files only: a run of the scene leaves its FMUs in a resources/ folder beside them
        for e in std::fs::read_dir(root.join(dir))
            .unwrap()
            .flatten()
            .filter(|e| e.path().is_file())
        {
            docs.push((e.path(), std::fs::read(e.path()).unwrap()));
        }
    }
    let count = std::env::var("WINDRIVE_PARSER_FUZZ")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(10_000usize);
    let mut rng = Rng(0x5eed_2026_1124);
    for k in 0..count {
        let (path, text) = &docs[k % docs.len()];
        let seed = rng.0;
        let bad = mutate(text, &mut rng);
        let s = String::from_utf8_lossy(&bad);
        let outcome = std::panic::catch_unwind(|| {
            if path.extension().is_some_and(|e| e == "xml") {
                let _ = windrive::fmi2::host::description::ModelDescription::parse(&s);
            } else {
                let _ = windrive::cosim::xml::parse(&s);
            }
        });
        assert!(
            outcome.is_ok(),
            "{} mutated with seed {seed:#x} panicked the parser",
            path.display()
        );
    }
}
