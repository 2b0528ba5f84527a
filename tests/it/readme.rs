//! The README's main-job output is what the main job prints today: both of its blocks (the calibrated
//! BEM scenes, then `--spring`), line by line, from `windrive shutdown --preset C` run as a user runs it.

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

/// The main job's table and findings: its output from the table's heading to the mesh-force line.
fn main_job(extra: &[&str]) -> Vec<String> {
    let dir = std::env::temp_dir().join(format!("windrive-readme-{}-{}", std::process::id(), extra.len()));
    let out = Command::new(env!("CARGO_BIN_EXE_windrive"))
        .args(["shutdown", "--preset", "C", "--out-dir"])
        .arg(&dir)
        .args(extra)
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    text.lines()
        .skip_while(|l| !l.starts_with("shaft "))
        .scan(false, |done, l| {
            if *done {
                return None;
            }
            *done = l.starts_with("mesh-force reversal");
            Some(l.to_string())
        })
        .collect()
}

#[test]
fn the_readme_shows_what_the_main_job_prints() {
    let blocks = readme_blocks();
    assert_eq!(blocks.len(), 2, "README: the main job's block and the --spring one");
    for (block, extra) in blocks.iter().zip([&[][..], &["--spring"][..]]) {
        let printed = main_job(extra);
        assert_eq!(
            &printed,
            block,
            "README.md: the block of `windrive shutdown --preset C {}` differs from what it prints; paste its output",
            extra.join(" ")
        );
    }
}
