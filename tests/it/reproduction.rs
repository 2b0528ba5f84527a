//! The reproduction report (`windrive reproduce`, docs/REPRODUCTION.md): every row we claim to
//! reproduce holds within its stated tolerance, the claims cover the modes, mesh orders, operating
//! hours, rated speeds and braking frequencies, and the committed table lists every row.

use windrive::cli::reproduce::open_scene;
use windrive::studies::reproduce::rows;

#[test]
fn every_claimed_row_holds_and_the_documentation_lists_every_row() {
    let rows = rows(&open_scene).unwrap();
    let claimed: Vec<_> = rows.iter().filter(|r| r.claimed.is_some()).collect();
    for r in &claimed {
        println!(
            "{}: thesis {}, ours {:.5} ({:+.3} %)",
            r.quantity,
            r.thesis,
            r.ours,
            r.difference() * 100.0
        );
        assert!(r.reproduced(), "{}: {} vs thesis {}", r.quantity, r.ours, r.thesis);
    }
    for family in [
        "mesh order",
        "D 2-mass",
        "operating hours",
        "rated rotor speed",
        "dominant HSS-torque",
        "generator speed",
    ] {
        assert!(
            claimed.iter().any(|r| r.quantity.contains(family)),
            "no claimed row for {family}"
        );
    }
    assert!(claimed.len() >= 24, "{} claimed rows", claimed.len());
    let docs = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/REPRODUCTION.md")).unwrap();
    for r in &rows {
        assert!(
            docs.contains(&format!("| {} |", r.quantity)),
            "docs/REPRODUCTION.md lacks {}",
            r.quantity
        );
    }
}
