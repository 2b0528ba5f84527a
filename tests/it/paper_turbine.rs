//! The paper's 1.5 MW turbine (preset P, scenes/p-normal; docs/SOURCES.md §Paper) as its global model behaves:
//!
//! - steady wind above rated: rotor speed at 17.5 rpm within 0.5 % and rotor power at the 1650 kW the
//!   paper reports above rated within 1 % (the pitch PI holds speed; the torque law holds torque);
//!   below rated (steady 9 m/s) the power is under 60 % of it and the pitch stays at fine pitch;
//! - steady 11.5 m/s lies just under the rated wind (11.65 m/s for this rotor): less power than at
//!   14 m/s, as the paper explains its own 11.5 m/s results;
//! - the gear ratings of `windrive gears` over those series: the sun's flank and the ring's root carry
//!   more damage at 14 than at 11.5 m/s, and next to nothing at 9 m/s.

use crate::common;
use windrive::analysis::rating::gear::MeshForce;
use windrive::analysis::rating::gear_set::{self, paper_1p5mw};
use windrive::physics::drivetrain::Drivetrain;

const CHANNELS: [&str; 3] = ["torsional.rotor_speed", "rotor.aerodynamic_power", "rotor.pitch"];

struct Steady {
    speed_rpm: f64,
    power: f64,
    pitch_deg: f64,
    flank_s1: f64,
    root_r1: f64,
}

/// 30 s of steady wind; the means and the gear damage over the last 15 s.
fn steady(wind: f64) -> Steady {
    let teeth = paper_1p5mw("torsional", MeshForce::Transverse);
    let mut channels: Vec<String> = CHANNELS.iter().map(|c| c.to_string()).collect();
    channels.extend(gear_set::channels(&teeth).into_iter().map(String::from));
    let wind = wind.to_string();
    let c = common::run_scene(
        "p-normal",
        &[("rotor", "wind_speed", &wind), ("rotor", "turbulence", "none")],
        &channels,
        Some(30.0),
    );
    let first = c[0].iter().position(|&t| t >= 15.0).unwrap();
    let mean = |i: usize| c[i][first..].iter().sum::<f64>() / (c[i].len() - first) as f64;
    let column = |name: &str| &c[1 + channels.iter().position(|n| n == name).unwrap()][first..];
    let rate = |name: &str| {
        let tooth = teeth.iter().find(|t| t.name == name).unwrap();
        tooth
            .rate(&c[0][first..], column(&tooth.force), column(&tooth.cycles.speed))
            .unwrap()
    };
    Steady {
        speed_rpm: mean(1) * 30.0 / std::f64::consts::PI,
        power: mean(2),
        pitch_deg: mean(3).to_degrees(),
        flank_s1: rate("s1").flank_damage,
        root_r1: rate("r1").root_damage,
    }
}

#[test]
fn the_paper_turbine_in_steady_wind() {
    let rated = Drivetrain::preset("P").unwrap().rated_power;
    let (low, near, above) = (steady(9.0), steady(11.5), steady(14.0));
    for (v, s) in [(9.0, &low), (11.5, &near), (14.0, &above)] {
        println!(
            "{v} m/s: {:.2} rpm, {:.0} kW, pitch {:.2}°, D_flank(s1) {:.3e}, D_root(r1) {:.3e}",
            s.speed_rpm,
            s.power / 1e3,
            s.pitch_deg,
            s.flank_s1,
            s.root_r1
        );
    }
    assert!((above.speed_rpm / 17.5 - 1.0).abs() < 5e-3, "{}", above.speed_rpm);
    assert!((above.power / rated - 1.0).abs() < 0.01, "{}", above.power);
    assert!(above.pitch_deg > 1.0);
    assert!(low.power < 0.6 * rated && low.pitch_deg.abs() < 1e-9);
    assert!(near.power < above.power && near.power > 0.9 * rated, "{}", near.power);
    assert!(above.flank_s1 > near.flank_s1 && above.root_r1 > near.root_r1);
    assert!(low.flank_s1 < 1e-3 * near.flank_s1 && low.root_r1 < 1e-3 * near.root_r1);
}

/// The paper's gearbox as the 6-DOF model of its Tables 4–5 (scenes/p-normal-6dof: sliced meshes with
/// its impact contact law, bearings, gravity) and as the torsional preset P rate every tooth alike in
/// steady wind at 14 m/s (10–16 s, after the start): peak stresses within 0.5 %, damage within 3 % (at
/// slopes of 11–25 a stress difference of 0.1 % is 1–2.5 % of damage; over 80 s the campaign
/// campaigns/paper-6dof.toml finds 0.1 % in damage, docs/PAPER.md). The 6-DOF model reports normal mesh forces, the torsional
/// transverse ones; the rating reads each as what it is.
#[test]
fn six_dof_and_torsional_gearboxes_rate_alike() {
    let steady = [("rotor", "wind_speed", "14"), ("rotor", "turbulence", "none")];
    let rate = |scene: &str, component: &str, kind: MeshForce, extra: &[(&str, &str, &str)]| {
        let teeth = paper_1p5mw(component, kind);
        let channels: Vec<String> = gear_set::channels(&teeth).into_iter().map(String::from).collect();
        let overrides: Vec<(&str, &str, &str)> = steady.iter().chain(extra).copied().collect();
        let c = common::run_scene(scene, &overrides, &channels, Some(16.0));
        let first = c[0].iter().position(|&t| t >= 10.0).unwrap();
        let column = |name: &str| &c[1 + channels.iter().position(|n| n == name).unwrap()][first..];
        teeth
            .iter()
            .map(|t| {
                t.rate(&c[0][first..], column(&t.force), column(&t.cycles.speed))
                    .unwrap()
            })
            .collect::<Vec<_>>()
    };
    let torsional = rate("p-normal", "torsional", MeshForce::Transverse, &[]);
    let six_dof = rate(
        "p-normal-6dof",
        "gearbox",
        MeshForce::Normal,
        &[("gearbox", "slices", "5")],
    );
    for (a, b) in torsional.iter().zip(&six_dof) {
        let close = |x: f64, y: f64, tol: f64| x.is_nan() && y.is_nan() || (x / y - 1.0).abs() < tol;
        println!(
            "{:>4}: σ_H {:.1}/{:.1} MPa, σ_F {:.1}/{:.1} MPa, D_flank {:.4e}/{:.4e}, D_root {:.4e}/{:.4e}",
            a.name,
            a.max_contact_stress / 1e6,
            b.max_contact_stress / 1e6,
            a.max_root_stress / 1e6,
            b.max_root_stress / 1e6,
            a.flank_damage,
            b.flank_damage,
            a.root_damage,
            b.root_damage
        );
        assert!(close(a.max_contact_stress, b.max_contact_stress, 5e-3) || a.max_contact_stress == 0.0);
        assert!(close(a.max_root_stress, b.max_root_stress, 5e-3) || a.max_root_stress == 0.0);
        assert!(close(a.flank_damage, b.flank_damage, 0.03), "{}", a.name);
        assert!(close(a.root_damage, b.root_damage, 0.03), "{}", a.name);
    }
}
