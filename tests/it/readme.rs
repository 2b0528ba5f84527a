//! The README's main-job output is what the main job prints today: both of its blocks (the calibrated
//! BEM scenes, then `--spring`), line by line, from `windrive shutdown --preset C` run as a user runs it;
//! and its sentence on what `windrive life` makes of those CSVs is what that command prints.

use std::process::Command;

/// The README's code blocks that begin as the main job's table does, in order.
fn readme_blocks() -> Vec<Vec<String>> {
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
    let mut blocks = vec![];
    let mut current: Option<Vec<String>> = None;
    for line in readme.lines() {
        match (&mut current, line.starts_with("```")) {
            (None, true) => current = Some(vec![]),
            (Some(_), true) => {
                let block = current.take().expect("open block");
                if block.first().is_some_and(|l| l.starts_with("shaft ")) {
                    blocks.push(block);
                }
            }
            (Some(block), false) => block.push(line.to_string()),
            (None, false) => {}
        }
    }
    blocks
}

/// The main job's table and findings (its output from the table's heading to the mesh-force line), and
/// what `windrive life` prints for sun–planet mesh 1 from its CSVs as the README's sentence says.
fn main_job(extra: &[&str]) -> (Vec<String>, String) {
    let dir = std::env::temp_dir().join(format!("windrive-readme-{}-{}", std::process::id(), extra.len()));
    let out = Command::new(env!("CARGO_BIN_EXE_windrive"))
        .args(["shutdown", "--preset", "C", "--out-dir"])
        .arg(&dir)
        .args(extra)
        .output()
        .unwrap();
    let life = Command::new(env!("CARGO_BIN_EXE_windrive"))
        .arg("life")
        .arg("--normal")
        .arg(dir.join("normal.csv"))
        .arg("--shutdown")
        .arg(dir.join("shutdown.csv"))
        .args(["--channel", "torsional.mesh_force_sun_planet_1", "--mean-wind", "10"])
        .args(["--shutdowns-per-year", "1100", "--m", "3,6,9"])
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(life.status.success(), "{}", String::from_utf8_lossy(&life.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    let lines = text
        .lines()
        .skip_while(|l| !l.starts_with("shaft "))
        .scan(false, |done, l| {
            if *done {
                return None;
            }
            *done = l.starts_with("mesh-force reversal");
            Some(l.to_string())
        })
        .collect();
    (lines, String::from_utf8(life.stdout).unwrap())
}

/// The shutdowns' share of the lifetime DEL damage at m = 3, 6, 9 as `windrive life` prints them ("10.4%").
fn shutdown_shares(life: &str) -> Vec<String> {
    life.lines()
        .filter_map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (f.len() == 3 && ["3", "6", "9"].contains(&f[0]) && f[2].ends_with('%'))
                .then(|| f[2].trim_end_matches('%').to_string())
        })
        .collect()
}

#[test]
fn the_readme_shows_what_the_main_job_prints() {
    let blocks = readme_blocks();
    assert_eq!(blocks.len(), 2, "README: the main job's block and the --spring one");
    for (block, extra) in blocks.iter().zip([&[][..], &["--spring"][..]]) {
        let (printed, life) = main_job(extra);
        if extra.is_empty() {
            let s = shutdown_shares(&life);
            assert_eq!(s.len(), 3, "windrive life printed no m = 3, 6, 9 rows:\n{life}");
            let sentence = format!(
                "shutdowns cause {} % of the lifetime DEL damage at m = 3, {} % at m = 6 and\n{} % at m = 9",
                s[0], s[1], s[2]
            );
            let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
            assert!(
                readme.contains(&sentence),
                "README.md should say: {sentence}\n(windrive life printed:\n{life})"
            );
        }
        assert_eq!(
            &printed,
            block,
            "README.md: the block of `windrive shutdown --preset C {}` differs from what it prints; paste its output",
            extra.join(" ")
        );
    }
}
