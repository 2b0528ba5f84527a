//! The sampled rotor against what it must reduce to: in a uniform steady field the rotor-averaged BEM
//! (exactly when each station is solved, within the table's interpolation error when read from it);
//! the field's interpolation exact on a field linear in y, z and t; the table against the solved
//! stations in a turbulent, sheared field; a grid that misses the blade tips refused.

use super::*;
use crate::physics::aero::AIR_DENSITY;
use crate::physics::blade::Blade;
use crate::physics::drivetrain::Drivetrain;
use crate::physics::rotor::{Aerodynamics, trim_pitch};
use crate::physics::turbulence::Variance;
use crate::physics::wind_field::{FieldSpec, Grid, generate, steady};
use std::path::Path;

/// Drivetrain C's rotor: the WindPACT blade scaled to 40 m, as the rotor FMU builds it.
fn rotor_c() -> BemRotor {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fmus/rotor/resources/blades/windpact-1.5mw");
    BemRotor::new(Blade::load(&dir).unwrap().scaled(40.0), AIR_DENSITY)
}

fn spec(mean_wind: f64, sigma: f64, shear: f64) -> FieldSpec {
    FieldSpec {
        mean_wind,
        sigma,
        hub_height: 80.0,
        shear_exponent: shear,
        grid: Grid {
            ny: 11,
            nz: 11,
            width: 88.0,
            height: 88.0,
        },
        period: 60.0,
        max_dt: 0.05,
        variance: Variance::TenMinute,
        seed: 7,
    }
}

/// Uniform steady wind: every element sees (V, ω·r), so the solved stations give the rotor-averaged
/// BEM's torque and thrust to rounding, and no tilt or yaw moment; the table gives them to within its
/// interpolation error: torque to 0.25 % of the larger of its value and its value at 11 m/s (6e-4 at
/// fine pitch, 2.0e-3 at 24 m/s pitched 26°, the worst case), thrust to 0.1 %, at fine pitch below and
/// above rated wind, trimmed, and parked and feathered.
#[test]
fn uniform_wind_gives_the_rotor_averaged_loads() {
    let bem = rotor_c();
    let c = Drivetrain::preset("C").unwrap();
    let rated = c.rated_rotor_speed;
    let aero = Aerodynamics::Bem(bem.clone());
    let (q_rated, t_rated) = bem.torque_thrust(11.0, rated, 0.0);
    for (v, omega, pitch) in [
        (6.0, 0.7 * rated, 0.0),
        (11.0, rated, 0.0),
        (16.0, rated, trim_pitch(&aero, 16.0, c.rated_power, rated, 1.5)),
        (24.0, 1.05 * rated, trim_pitch(&aero, 24.0, c.rated_power, rated, 1.5)),
        (16.0, 0.0, 1.5),
        (16.0, -0.05, 1.5),
    ] {
        let sampling = BladeSampling::new(&bem, steady(&spec(v, 0.0, 0.0)).unwrap(), 80.0, 0.0, 1.5).unwrap();
        let (q, t) = bem.torque_thrust(v, omega, pitch);
        for azimuth in [0.0, 0.3, 2.0] {
            let solved = sampling.loads_solved(&bem, 1.0, azimuth, omega, pitch, DiscMotion::default());
            assert!(
                (solved.torque - q).abs() <= 1e-12 * q.abs().max(q_rated),
                "{v} {omega} {pitch}: {solved:?} vs {q}"
            );
            assert!((solved.thrust - t).abs() <= 1e-12 * t.abs().max(t_rated));
            assert!(solved.tilt.abs() <= 1e-12 * t_rated * 40.0 && solved.yaw.abs() <= 1e-12 * t_rated * 40.0);
            assert_eq!(solved.hub_wind, v);
            let read = sampling.loads(&bem, 1.0, azimuth, omega, pitch, DiscMotion::default());
            let dq = (read.torque - q).abs() / q.abs().max(q_rated);
            let dt = (read.thrust - t).abs() / t.abs().max(t_rated);
            assert!(
                dq < 2.5e-3 && dt < 1e-3,
                "{v} m/s {omega} rad/s pitch {pitch}: torque {dq:.2e}, thrust {dt:.2e}"
            );
        }
    }
}

/// A field linear in y, z and t is read back exactly between its points (bilinear in space, linear in
/// time), and a periodic field interpolates from its last plane to its first.
#[test]
fn interpolation_is_exact_on_linear_fields_and_wraps() {
    let (ny, nz, nt) = (5, 4, 6);
    let (dy, dz, dt, z_bottom) = (10.0, 8.0, 0.5, 50.0);
    let value = |y: f64, z: f64, t: f64| 3.0 + 0.1 * y - 0.05 * z + 2.0 * t;
    let mut field = WindField {
        ny,
        nz,
        nt,
        dy,
        dz,
        dt,
        z_bottom,
        hub_height: 62.0,
        mean_hub: 8.0,
        periodic: false,
        velocity: std::array::from_fn(|_| Vec::new()),
        tower: Default::default(),
    };
    for c in 0..3 {
        field.velocity[c] = (0..nt)
            .flat_map(|t| (0..nz).flat_map(move |k| (0..ny).map(move |j| (j, k, t))))
            .map(|(j, k, t)| (c + 1) as f64 * value(field_y(j, ny, dy), z_bottom + k as f64 * dz, t as f64 * dt))
            .collect();
    }
    for (y, z, t) in [
        (0.0, 62.0, 0.3),
        (-17.3, 50.0, 2.4),
        (19.9, 73.9, 1.75),
        (20.0, 74.0, 2.5),
    ] {
        let got = field.velocity_at(t, y, z);
        for (c, g) in got.iter().enumerate() {
            let want = (c + 1) as f64 * value(y, z, t);
            assert!((g - want).abs() < 1e-12, "({y}, {z}, {t}) component {c}: {g} vs {want}");
        }
    }
    assert_eq!(field.end_time(), Some(2.5));
    // periodic: 2.75 s is halfway from the last plane (2.5 s) back to the first (0 s = 3 s)
    field.periodic = true;
    let (last, first) = (
        field.velocity_at(2.5, 0.0, 62.0)[0],
        field.velocity_at(0.0, 0.0, 62.0)[0],
    );
    assert!((field.velocity_at(2.75, 0.0, 62.0)[0] - 0.5 * (last + first)).abs() < 1e-12);
    let (again, once) = (
        field.velocity_at(3.0 + 0.3, 0.0, 62.0),
        field.velocity_at(0.3, 0.0, 62.0),
    );
    assert!((0..3).all(|c| (again[c] - once[c]).abs() < 1e-12), "{again:?} {once:?}");
    assert_eq!(field.end_time(), None);
}

fn field_y(j: usize, ny: usize, dy: f64) -> f64 {
    (j as f64 - 0.5 * (ny - 1) as f64) * dy
}

/// In a turbulent, sheared field (IEC class A at 11 m/s, α = 0.2) the table stays within 0.2 % of the
/// rated torque and thrust of the solved stations at every azimuth and time tried, also pitched.
#[test]
fn table_follows_the_solved_stations_in_turbulence() {
    let bem = rotor_c();
    let rated = Drivetrain::preset("C").unwrap().rated_rotor_speed;
    let field = generate(&spec(11.0, 0.18 * 11.0, 0.2)).unwrap();
    let sampling = BladeSampling::new(&bem, field, 80.0, 0.0, 1.5).unwrap();
    let (q_rated, t_rated) = bem.torque_thrust(11.0, rated, 0.0);
    let mut worst: f64 = 0.0;
    for n in 0..40 {
        let (t, azimuth, pitch) = (1.37 * n as f64, 0.61 * n as f64, [0.0, 0.05, 0.2][n % 3]);
        let solved = sampling.loads_solved(&bem, t, azimuth, rated, pitch, DiscMotion::default());
        let read = sampling.loads(&bem, t, azimuth, rated, pitch, DiscMotion::default());
        for (a, b, scale) in [
            (read.torque, solved.torque, q_rated),
            (read.thrust, solved.thrust, t_rated),
            (read.tilt, solved.tilt, t_rated * 40.0),
            (read.yaw, solved.yaw, t_rated * 40.0),
        ] {
            worst = worst.max((a - b).abs() / scale);
        }
    }
    assert!(worst < 2e-3, "largest difference {worst:.2e} of the rated value");
}

/// A grid narrower than the rotor, or below its lower tip, is refused with the extent and the disc.
#[test]
fn a_grid_that_misses_the_tips_is_refused() {
    let bem = rotor_c();
    let mut narrow = spec(11.0, 0.0, 0.2);
    narrow.grid.width = 70.0;
    let err = BladeSampling::new(&bem, steady(&narrow).unwrap(), 80.0, 0.0, 1.5).unwrap_err();
    assert!(
        err.to_string().contains("y ±35.00 m") && err.to_string().contains("radius 40 m"),
        "{err}"
    );
    let low = steady(&spec(11.0, 0.0, 0.2)).unwrap();
    assert!(
        BladeSampling::new(&bem, low, 90.0, 0.0, 1.5).is_err(),
        "the disc reaches above the grid"
    );
}

/// A column is solved when first read: a table read in one order, one read in the reverse order and one
/// that went through an FMU state's serialisation (which keeps no column) give the same bits.
#[test]
fn columns_solved_on_demand_do_not_depend_on_the_order() {
    let bem = rotor_c();
    let rated = Drivetrain::preset("C").unwrap().rated_rotor_speed;
    let field = generate(&spec(11.0, 0.18 * 11.0, 0.2)).unwrap();
    let forward = BladeSampling::new(&bem, field, 80.0, 0.0, 1.5).unwrap();
    let backward = forward.clone();
    let bytes = postcard::to_allocvec(&forward).unwrap();
    let restored: BladeSampling = postcard::from_bytes(&bytes).unwrap();
    let points: Vec<(f64, f64, f64)> = (0..30)
        .map(|n| (0.91 * n as f64, 0.37 * n as f64, 0.045 * n as f64))
        .collect();
    let read = |s: &BladeSampling, &(t, azimuth, pitch): &(f64, f64, f64)| {
        let l = s.loads(&bem, t, azimuth, rated, pitch, DiscMotion::default());
        [l.torque, l.thrust, l.tilt, l.yaw].map(f64::to_bits)
    };
    let a: Vec<_> = points.iter().map(|p| read(&forward, p)).collect();
    let mut b: Vec<_> = points.iter().rev().map(|p| read(&backward, p)).collect();
    b.reverse();
    let c: Vec<_> = points.iter().map(|p| read(&restored, p)).collect();
    assert_eq!(a, b);
    assert_eq!(a, c);
}

/// A disc tilting and yawing in uniform wind is, element by element, a fixed disc in a field whose u
/// falls by Ω_tilt·(z − z_hub) and rises by Ω_yaw·y (y to the left: the right half moves downwind): the two
/// give the same loads to rounding, from the solved stations and from the table. And the motion is
/// damped: a positive tilt (yaw) rate gives a negative tilt (yaw) moment, as large for either on the
/// three-bladed disc.
#[test]
fn a_moving_disc_sees_the_wind_less_its_own_speed() {
    let bem = rotor_c();
    let c = Drivetrain::preset("C").unwrap();
    let (v, omega) = (11.0, c.rated_rotor_speed);
    let disc = DiscMotion {
        tilt_rate: 0.03,
        yaw_rate: -0.02,
    };
    let uniform = steady(&spec(v, 0.0, 0.0)).unwrap();
    let mut equivalent = uniform.clone();
    let (ny, nz, nt) = (uniform.ny, uniform.nz, uniform.nt);
    for t in 0..nt {
        for k in 0..nz {
            for j in 0..ny {
                let i = uniform.index(t, k, j);
                equivalent.velocity[0][i] += -disc.tilt_rate * (uniform.z(k) - 80.0) + disc.yaw_rate * uniform.y(j);
            }
        }
    }
    let moving = BladeSampling::new(&bem, uniform, 80.0, 0.0, 0.2).unwrap();
    let fixed = BladeSampling::new(&bem, equivalent, 80.0, 0.0, 0.2).unwrap();
    let close = |a: BladeLoads, b: BladeLoads, scale: f64| {
        let d = [a.torque - b.torque, a.thrust - b.thrust, a.tilt - b.tilt, a.yaw - b.yaw];
        d.iter().all(|x| x.abs() < 1e-9 * scale)
    };
    for azimuth in [0.0, 0.4, 1.3, 2.9] {
        let solved = moving.loads_solved(&bem, 1.0, azimuth, omega, 0.0, disc);
        let scale = solved.thrust * 40.0;
        assert!(close(
            solved,
            fixed.loads_solved(&bem, 1.0, azimuth, omega, 0.0, DiscMotion::default()),
            scale
        ));
        let read = moving.loads(&bem, 1.0, azimuth, omega, 0.0, disc);
        assert!(close(
            read,
            fixed.loads(&bem, 1.0, azimuth, omega, 0.0, DiscMotion::default()),
            scale
        ));
    }
    // damping: each rate alone against the fixed disc, averaged over a third of a turn
    let mean = |d: DiscMotion| {
        let n = 24;
        (0..n).fold([0.0; 2], |acc, k| {
            let l = moving.loads(
                &bem,
                1.0,
                k as f64 * std::f64::consts::TAU / (3 * n) as f64,
                omega,
                0.0,
                d,
            );
            [acc[0] + l.tilt / n as f64, acc[1] + l.yaw / n as f64]
        })
    };
    let still = mean(DiscMotion::default());
    let tilting = mean(DiscMotion {
        tilt_rate: 0.01,
        yaw_rate: 0.0,
    });
    let yawing = mean(DiscMotion {
        tilt_rate: 0.0,
        yaw_rate: 0.01,
    });
    let (c_tilt, c_yaw) = ((still[0] - tilting[0]) / 0.01, (still[1] - yawing[1]) / 0.01);
    assert!(c_tilt > 0.0 && c_yaw > 0.0, "{c_tilt} {c_yaw}");
    assert!(
        (c_tilt / c_yaw - 1.0).abs() < 1e-3,
        "tilt {c_tilt:e}, yaw {c_yaw:e} N·m·s"
    );
    assert!(tilting[1].abs() < 1e-3 * c_tilt * 0.01 && yawing[0].abs() < 1e-3 * c_yaw * 0.01);
}
