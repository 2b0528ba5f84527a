//! Modal analysis against the thesis's published 2-mass values (its §6.1, from Table 4.2) and agreement of
//! the three fidelities built from one description.

use windrive::linear::modes::{Boundary, modes};
use windrive::physics::drivetrain::{Drivetrain, PRESETS};
use windrive::physics::torsional::{Fidelity, ModelOptions, TorsionalModel};

fn model(preset: &str, fidelity: Fidelity) -> (Drivetrain, TorsionalModel) {
    let dt = Drivetrain::preset(preset).unwrap();
    let m = TorsionalModel::new(&dt, fidelity, &ModelOptions::default()).unwrap();
    (dt, m)
}

fn close(actual: f64, expected: f64, rel: f64) {
    assert!(
        (actual - expected).abs() <= rel * expected.abs(),
        "{actual} vs {expected} (tolerance {rel})"
    );
}

#[test]
fn two_mass_d_matches_the_thesis_within_0_1_percent() {
    let (dt, m) = model("D", Fidelity::Two);
    let connected = modes(&m, Boundary::Connected, dt.k_generator);
    println!("connected {:?}", connected.frequencies_hz);
    // tolerance 0.1 %: the published figures are rounded to four digits and use N1 = 5.714 etc.
    close(connected.frequencies_hz[0], 0.865, 1e-3);
    close(connected.frequencies_hz[1], 5.890, 1e-3);
    let free = modes(&m, Boundary::Disconnected, dt.k_generator);
    println!("free {:?}", free.frequencies_hz);
    assert!(free.frequencies_hz[0].abs() < 1e-6);
    close(free.frequencies_hz[1], 2.524, 1e-3);
}

#[test]
fn fidelities_agree_on_the_lowest_modes() {
    for preset in PRESETS {
        let lowest = |f, b| {
            let (dt, m) = model(preset, f);
            let fr = modes(&m, b, dt.k_generator).frequencies_hz;
            fr.into_iter().find(|x| *x > 1e-6).unwrap()
        };
        for b in [Boundary::Disconnected, Boundary::Connected] {
            let (two, five, full) = (
                lowest(Fidelity::Two, b),
                lowest(Fidelity::Five, b),
                lowest(Fidelity::Full, b),
            );
            println!("{preset} {b:?}: 2-mass {two:.4} Hz, 5-mass {five:.4} Hz, full {full:.4} Hz");
            // the reductions drop only mesh and intermediate-inertia flexibility, which sits far
            // above the lowest mode: 1 % between neighbours is the physics, not slack
            // 2 vs 5: series shafts vs discrete intermediate inertias, both with rigid meshes: 1 %.
            close(two, five, 0.01);
            // 5 vs full: the full model adds mesh compliance, which lowers the first mode by up to
            // 3.2 % (B, whose 1.43e8 N·m/rad second-stage meshes are softer than its shafts): 4 %.
            close(full, five, 0.04);
            assert!(full <= five * (1.0 + 1e-9), "added compliance cannot raise the mode");
        }
    }
}

/// The thesis's Eq. 4.9 lumps the first stage as J_pc + N1²·J_s, leaving out the planets' spin
/// inertia; our default keeps it. Drivetrain D's fourth 5-mass mode (free–free) is 8.6 % lower with
/// the planets' spin than without (476.7 → 435.8 Hz; ±0.2 %, the figure found when the difference was
/// first reported), and only the reduced models change.
#[test]
fn thesis_lumping_leaves_out_the_planet_spin() {
    use windrive::physics::torsional::Lumping;
    let dt = Drivetrain::preset("D").unwrap();
    let build = |fidelity, lumping| {
        let opt = ModelOptions {
            lumping,
            ..ModelOptions::default()
        };
        let m = TorsionalModel::new(&dt, fidelity, &opt).unwrap();
        modes(&m, Boundary::Disconnected, dt.k_generator).frequencies_hz
    };
    let physical = build(Fidelity::Five, Lumping::Physical);
    let thesis = build(Fidelity::Five, Lumping::Thesis);
    let shift = 1.0 - physical[3] / thesis[3];
    println!(
        "5-mass D free-free: physical {physical:?}, thesis {thesis:?}, 4th mode {:+.2} %",
        100.0 * shift
    );
    assert!((shift - 0.086).abs() < 0.002, "fourth mode moved by {shift}");
    assert_eq!(
        build(Fidelity::Full, Lumping::Thesis),
        build(Fidelity::Full, Lumping::Physical)
    );
}
