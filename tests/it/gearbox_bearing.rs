//! The roller–lamina bearing against closed-form bearing theory: Stribeck's and Sjövall's load
//! distribution under a radial load (with and without clearance), the equal share of an angular
//! set under a pure axial load, Hertz stresses of a roller on its race, and the tangent it hands
//! the integrators.

use windrive::physics::gearbox::bearing::{Mounting, RollerBearing, RollerLoads, SetMemory};
use windrive::physics::gearbox::description::{Contact, Rollers};
use windrive::physics::gearbox::roller_table::RollerTables;
use windrive::physics::gearbox::row::Row;

fn unit(i: usize) -> Row {
    let mut row = Row::default();
    row.add(i, 1.0);
    row
}

/// A bearing on six coordinates: the five relative ones and the cage angle.
fn bearing(r: &Rollers) -> RollerBearing {
    mounted(r, 0.0, false)
}

/// The same with a damping time and, with `tabulated`, the roller sums by table.
fn mounted(r: &Rollers, damping_time: f64, tabulated: bool) -> RollerBearing {
    let mut tables = RollerTables::default();
    RollerBearing::new(
        r,
        Mounting {
            bearing: 0,
            rows: std::array::from_fn(unit),
            cage: unit(5),
            offset: [0.0; 2],
            sign: 1.0,
        },
        damping_time,
        tabulated.then_some(&mut tables),
    )
}

fn crb(count: u32, clearance_um: f64, laminae: u32) -> Rollers {
    Rollers {
        count,
        diameter_mm: 30.0,
        length_mm: 50.0,
        pitch_diameter_mm: 400.0,
        contact_angle_deg: 0.0,
        rows: 1,
        row_spacing_mm: 0.0,
        clearance_um,
        axial_clearance_um: 0.0,
        laminae,
        contact: Contact::Line,
        roller_stiffness: None,
        profile_radius_mm: None,
        race_profile_radii_mm: None,
        crowning_um: 0.0,
    }
}

/// Loads and the 5×5 stiffness at x (no motion, cage at 0).
fn at(b: &RollerBearing, x: [f64; 5]) -> (RollerLoads, [[f64; 5]; 5]) {
    let (mut k, mut c) = ([[0.0; 5]; 5], [[0.0; 5]; 5]);
    let l = b.evaluate(&x, &[0.0; 5], 0.0, true, Some((&mut k, &mut c)));
    (l, k)
}

/// Newton on one coordinate until the bearing's force there equals `load`.
fn solve(b: &RollerBearing, dir: usize, load: f64, start: f64) -> ([f64; 5], RollerLoads) {
    let mut x = [0.0; 5];
    x[dir] = start;
    for _ in 0..200 {
        let (l, k) = at(b, x);
        let r = load - l.force[dir];
        if r.abs() < 1e-10 * load {
            return (x, l);
        }
        x[dir] += r / k[dir][dir].max(1e3);
    }
    panic!("no equilibrium for load {load}");
}

/// Sjövall's radial integral J_r(ε) for line contact: F_r = Z·Q_max·J_r(ε), by Simpson's rule
/// over the loaded zone (ε = ½(1 − P_d/(2δ_r)); ½ without clearance).
fn sjovall_jr(eps: f64) -> f64 {
    radial_integral(eps, 10.0 / 9.0)
}

/// J_r(ε) for a load–approach exponent e (10/9 line, 3/2 point contact).
fn radial_integral(eps: f64, exponent: f64) -> f64 {
    let limit = (1.0 - 2.0 * eps).clamp(-1.0, 1.0).acos();
    let f = |psi: f64| (1.0 - (1.0 - psi.cos()) / (2.0 * eps)).max(0.0).powf(exponent) * psi.cos();
    let n = 20_000;
    let h = 2.0 * limit / n as f64;
    let mut s = f(-limit) + f(limit);
    for i in 1..n {
        s += f(-limit + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    s * h / 3.0 / std::f64::consts::TAU
}

/// Without clearance Q_max = F_r/(Z·J_r(½)) = 4.08·F_r/Z (Stribeck's line-contact number). 60
/// rollers make the sum over rollers the integral within 0.1 %; tolerance 0.5 %.
#[test]
fn radial_load_without_clearance_follows_stribeck() {
    let z = 60;
    let b = bearing(&crb(z, 0.0, 1));
    let f_r = 200e3;
    let (_, l) = solve(&b, 0, f_r, 1e-5);
    let ratio = l.max_roller_load * z as f64 / f_r;
    let theory = 1.0 / sjovall_jr(0.5);
    assert!((theory - 4.08).abs() < 0.01, "J_r(0.5) gives {theory}");
    assert!(
        (ratio / theory - 1.0).abs() < 5e-3,
        "Q_max·Z/F_r = {ratio}, theory {theory}"
    );
    // half the rollers (those facing the load) carry it
    assert!((29..=31).contains(&l.rollers_in_contact), "{}", l.rollers_in_contact);
}

/// A set of balls given by their profile radii (point contact: Ø20 mm balls on a 150 mm pitch
/// circle in grooves of 0.53·D) needs no stiffness: the Hertz ellipses give it. Without clearance
/// Q_max = F_r/(Z·J_r(½)) = 4.37·F_r/Z, Stribeck's number for point contact (60 balls, 0.5 %). At
/// Q_max the inner race's pressure and the balls' approach agree with Hamrock and Dowson's fits
/// for the two contacts (their own error is under 0.5 % on the pressure and 1.3 % on the approach
/// at these curvature ratios, 15 and 20: tolerances 1 % and 1.5 %).
#[test]
fn a_ball_set_carries_a_radial_load_as_stribeck_and_hertz_say() {
    use std::f64::consts::PI;
    let z = 60;
    let (d, dm, groove) = (20.0, 150.0, 0.53 * 20.0);
    let balls = Rollers {
        diameter_mm: d,
        length_mm: d,
        pitch_diameter_mm: dm,
        contact: Contact::Point,
        profile_radius_mm: Some(0.5 * d),
        race_profile_radii_mm: Some([groove, groove]),
        ..crb(z, 0.0, 1)
    };
    let b = bearing(&balls);
    let f_r = 100e3;
    let (x, l) = solve(&b, 0, f_r, 1e-5);
    let theory = 1.0 / radial_integral(0.5, 1.5);
    assert!((theory - 4.37).abs() < 0.01, "J_r(0.5) gives {theory}");
    let ratio = l.max_roller_load * z as f64 / f_r;
    assert!(
        (ratio / theory - 1.0).abs() < 5e-3,
        "Q_max·Z/F_r = {ratio}, theory {theory}"
    );
    // Hamrock–Dowson for each race at Q_max (mm → m)
    let q = l.max_roller_load;
    let e_prime = 2.0 / (2.0 * (1.0 - 0.09) / 210e9);
    let fit = |rx: f64, ry: f64| {
        let alpha = ry / rx;
        let k = 1.0339 * alpha.powf(0.636);
        let e = 1.0003 + 0.5968 / alpha;
        let f = 1.5277 + 0.6023 * alpha.ln();
        let r = 1.0 / (1.0 / rx + 1.0 / ry);
        let a = (6.0 * k * k * e * q * r / (PI * e_prime)).cbrt();
        let bb = (6.0 * e * q * r / (PI * k * e_prime)).cbrt();
        let delta = f * ((9.0 / (2.0 * e * r)) * (q / (PI * k * e_prime)).powi(2)).cbrt();
        (3.0 * q / (2.0 * PI * a * bb), delta)
    };
    let mm = 1e-3;
    let ry = 1.0 / (1.0 / (0.5 * d * mm) - 1.0 / (groove * mm));
    let inner = fit(1.0 / (2.0 / (d * mm) + 2.0 / ((dm - d) * mm)), ry);
    let outer = fit(1.0 / (2.0 / (d * mm) - 2.0 / ((dm + d) * mm)), ry);
    let stresses = b.stresses(&l);
    assert!(
        (stresses.inner_pressure / inner.0 - 1.0).abs() < 0.01,
        "inner p_max {} vs {}",
        stresses.inner_pressure,
        inner.0
    );
    assert!(
        (stresses.outer_pressure / outer.0 - 1.0).abs() < 0.01,
        "outer p_max {} vs {}",
        stresses.outer_pressure,
        outer.0
    );
    assert!(stresses.inner_pressure > stresses.outer_pressure);
    // the most loaded ball, straight under the load, approaches by x[0]
    assert!(
        ((inner.1 + outer.1) / x[0] - 1.0).abs() < 0.015,
        "approach {} vs {}",
        x[0],
        inner.1 + outer.1
    );
    // its shear lies under the inner race at the depth of its ellipse's shape
    assert!(stresses.max_shear > 0.29 * stresses.inner_pressure && stresses.max_shear < 0.33 * stresses.inner_pressure);
}

/// With clearance the load zone shrinks: Q_max·Z/F_r = 1/J_r(ε) with ε from the solved approach;
/// a clearance of the order of the elastic approach gives ≈ 4.6 (ISO/TS 16281's and Harris's
/// range 4.08–4.6 and beyond). Tolerance 1 % (the discrete rollers near the zone's edge).
#[test]
fn radial_load_with_clearance_follows_sjovall() {
    let z = 60;
    for clearance_um in [20.0, 50.0] {
        let b = bearing(&crb(z, clearance_um, 1));
        let f_r = 200e3;
        let (x, l) = solve(&b, 0, f_r, 1e-4);
        let eps = 0.5 * (1.0 - clearance_um * 1e-6 / (2.0 * x[0]));
        let theory = 1.0 / sjovall_jr(eps);
        let ratio = l.max_roller_load * z as f64 / f_r;
        assert!(
            (ratio / theory - 1.0).abs() < 1e-2,
            "clearance {clearance_um} µm: ε = {eps:.3}, Q_max·Z/F_r = {ratio:.3}, theory {theory:.3}"
        );
        assert!(
            ratio > 4.2 && eps < 0.5,
            "clearance {clearance_um} µm: {ratio}, ε {eps}"
        );
    }
}

/// An angular set under a pure axial load shares it equally: Q = F_a/(Z·sin α), exact.
#[test]
fn axial_load_on_an_angular_set_is_shared_equally() {
    let mut r = crb(24, 0.0, 5);
    r.contact_angle_deg = 15.0;
    let b = bearing(&r);
    let f_a = 50e3;
    let (_, l) = solve(&b, 2, f_a, 1e-5);
    let expected = f_a / (24.0 * 15f64.to_radians().sin());
    assert!(
        (l.max_roller_load / expected - 1.0).abs() < 1e-9,
        "{} vs {expected}",
        l.max_roller_load
    );
    assert_eq!(l.rollers_in_contact, 24);
    // radial components cancel
    assert!(l.force[0].abs() < 1e-6 * f_a && l.force[1].abs() < 1e-6 * f_a);
}

/// The tangent is the derivative of the force (central differences, 1e-4 of the largest term: a
/// lamina just touching has a stiffness ∝ δ^(1/9), steep for differences), in a state
/// with clearance, tilt and the load zone at an angle, so every lamina term is exercised.
#[test]
fn tangent_is_the_derivative_of_the_force() {
    let mut r = crb(17, 30.0, 8);
    r.contact_angle_deg = 10.0;
    r.crowning_um = 5.0;
    let b = bearing(&r);
    let x = [60e-6, -25e-6, 20e-6, 1e-4, -2e-4];
    let (_, k) = at(&b, x);
    let scale = k.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    for j in 0..5 {
        let h = 1e-11;
        let (mut xp, mut xm) = (x, x);
        xp[j] += h;
        xm[j] -= h;
        let (fp, fm) = (at(&b, xp).0.force, at(&b, xm).0.force);
        for i in 0..5 {
            let fd = (fp[i] - fm[i]) / (2.0 * h);
            assert!((fd - k[i][j]).abs() < 1e-4 * scale, "K[{i}][{j}] = {} vs {fd}", k[i][j]);
        }
    }
}

/// A tilt loads one end of the rollers: the bearing pushes back against it (restoring moment),
/// and the most loaded lamina carries more than under the same radial load without tilt.
#[test]
fn tilt_loads_the_laminae_unevenly() {
    let b = bearing(&crb(22, -10.0, 10));
    let straight = at(&b, [30e-6, 0.0, 0.0, 0.0, 0.0]).0;
    let tilted = at(&b, [30e-6, 0.0, 0.0, 0.0, 1e-3]).0;
    assert!(tilted.force[4] > 0.0, "moment {} must resist the tilt", tilted.force[4]);
    assert!(tilted.max_lamina_load > 1.5 * straight.max_lamina_load);
    assert!(straight.force[4].abs() < 1e-6 * straight.force[0]);
}

/// Worked by hand from Johnson's formulas: a Ø40 roller on a Ø200 inner race (R' = 16.67 mm), steel,
/// 1000 N/mm: p_max = 1484 MPa, b = 0.429 mm; the shear peaks at 0.300 p_max, 0.786 b deep
/// (Johnson §4.2). Tolerances 0.2 % (the printed digits).
#[test]
fn race_stresses_match_the_hertz_example() {
    let mut r = crb(20, 0.0, 1);
    (r.diameter_mm, r.pitch_diameter_mm, r.length_mm) = (40.0, 240.0, 10.0);
    let b = bearing(&r);
    let loads = RollerLoads {
        max_lamina_load: 10e3,
        ..Default::default()
    };
    let s = b.stresses(&loads);
    assert!((s.inner_pressure / 1484e6 - 1.0).abs() < 2e-3, "{}", s.inner_pressure);
    assert!(
        s.outer_pressure < s.inner_pressure,
        "the concave outer race is the gentler contact"
    );
    assert!((s.max_shear / s.inner_pressure - 0.300).abs() < 1e-3);
    assert!(
        (s.max_shear_depth / 0.429e-3 / 0.786 - 1.0).abs() < 4e-3,
        "{}",
        s.max_shear_depth
    );
}

/// `lamina-table` against `lamina` on the GRC's roller sets (a CRB with clearance, a tapered row,
/// damping at the GRC's 0.1 ms): forces, moments, the tangents' stiffness and damping within 1e-9 of
/// their scale over poses from a touch to edge loading with tilts either way, rates that unload
/// laminae by damping (where the table hands the roller to the loop) and every cage angle; the peaks
/// a host reads (rollers in contact, the largest lamina's load) the loop's to the bit, the largest
/// lamina's load from the more loaded end's lamina or, where a tilting rate's damping loads the other
/// end more, from the loop (a table that always took the end fails here). The table's rounding is
/// not the loop's, so most poses must differ in their last bits: the table is what is tested.
#[test]
fn a_tabulated_set_gives_the_lamina_loops_loads_and_tangents() {
    let crb = crb(20, 60.0, 10);
    let mut tapered = crb;
    (tapered.count, tapered.contact_angle_deg, tapered.axial_clearance_um) = (22, 13.0, 30.0);
    let mut random = windrive::xorshift::Xorshift::new(0x9e37_79b9_7f4a_7c15);
    let mut uniform = move || random.unit();
    for r in [crb, tapered] {
        let (exact, table) = (mounted(&r, 1e-4, false), mounted(&r, 1e-4, true));
        assert!(table.tabulated() && !exact.tabulated());
        let (mut poses, mut different) = (0, 0);
        for _ in 0..4000 {
            let radial = 10e-6 + 60e-6 * uniform();
            let angle = std::f64::consts::TAU * uniform();
            let tilt = 10f64.powf(-7.0 + 4.0 * uniform());
            let x = [
                radial * angle.cos(),
                radial * angle.sin(),
                20e-6 * (uniform() - 0.5),
                tilt * (uniform() - 0.5),
                tilt * (uniform() - 0.5),
            ];
            let rate = 10f64.powf(-4.0 + 3.0 * uniform());
            let xd: [f64; 5] = std::array::from_fn(|i| rate * (uniform() - 0.5) * if i > 2 { 10.0 } else { 1.0 });
            let cage = std::f64::consts::TAU * uniform();
            let eval = |b: &RollerBearing| {
                let (mut k, mut c) = ([[0.0; 5]; 5], [[0.0; 5]; 5]);
                let l = b.evaluate(&x, &xd, cage, true, Some((&mut k, &mut c)));
                (l, k, c)
            };
            let ((le, ke, ce), (lt, kt, ct)) = (eval(&exact), eval(&table));
            if le.rollers_in_contact == 0 {
                assert_eq!(lt, le);
                continue;
            }
            poses += 1;
            let largest = |m: &[[f64; 5]; 5]| m.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
            let force = le.force.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for i in 0..5 {
                assert!(
                    (lt.force[i] - le.force[i]).abs() <= 1e-9 * force,
                    "force {i}: {lt:?} vs {le:?}"
                );
                for j in 0..5 {
                    assert!(
                        (kt[i][j] - ke[i][j]).abs() <= 1e-9 * largest(&ke),
                        "K[{i}][{j}] at {x:?}"
                    );
                    assert!(
                        (ct[i][j] - ce[i][j]).abs() <= 1e-9 * largest(&ce),
                        "C[{i}][{j}] at {x:?}"
                    );
                }
            }
            assert!((lt.max_roller_load - le.max_roller_load).abs() <= 1e-9 * le.max_roller_load);
            assert_eq!(lt.max_lamina_load, le.max_lamina_load, "at {x:?}, {xd:?}");
            assert_eq!(lt.rollers_in_contact, le.rollers_in_contact, "at {x:?}, {xd:?}");
            different += usize::from(lt.force != le.force);
        }
        assert!(
            poses > 1000 && 2 * different > poses,
            "{different} of {poses} poses differ from the loop"
        );
    }
}

/// Roller sets the table cannot sum keep the lamina loop: crowned rollers and point contact.
#[test]
fn crowned_and_point_contact_sets_keep_the_lamina_loop() {
    let mut crowned = crb(20, 60.0, 10);
    crowned.crowning_um = 5.0;
    assert!(!mounted(&crowned, 1e-4, true).tabulated());
    let mut point = crb(20, 60.0, 10);
    (point.contact, point.roller_stiffness) = (Contact::Point, Some(1e9));
    assert!(!mounted(&point, 1e-4, true).tabulated());
    assert!(mounted(&crb(20, 60.0, 1), 1e-4, true).tabulated());
}

/// A damped, tilted, angular, crowned set with clearance at (x, ẋ) and the cage at ψ_c: q and v on
/// the six coordinates of [`mounted`].
fn near_case() -> (RollerBearing, [f64; 6], [f64; 6]) {
    let mut r = crb(17, 30.0, 8);
    r.contact_angle_deg = 10.0;
    r.crowning_um = 5.0;
    let b = mounted(&r, 2e-4, false);
    let q = [60e-6, -25e-6, 20e-6, 1e-4, -2e-4, 0.3];
    let v = [1e-3, -2e-3, 5e-4, 0.02, -0.01, 40.0];
    (b, q, v)
}

/// The force `add_forces_near` adds at (q, v) with `distance`, from `near`.
fn near_force(b: &RollerBearing, q: &[f64; 6], v: &[f64; 6], distance: f64, near: &mut SetMemory) -> [f64; 6] {
    let mut out = [0.0; 6];
    b.add_forces_near(q, v, distance, near, &mut out);
    out
}

fn exact_force(b: &RollerBearing, q: &[f64; 6], v: &[f64; 6]) -> [f64; 6] {
    let mut out = [0.0; 6];
    b.add_forces(q, v, false, &mut out);
    out
}

/// Between exact evaluations a roller set's force is its last exact evaluation's force plus its
/// stiffness and damping times the change (so at the same point, the exact force to the bit); once
/// a lamina can have moved further than the distance (a translation, a tilt at the farthest lamina
/// or the load zone's turn with the cage), the set is evaluated exactly and that evaluation kept; after
/// a tangent never used, eight evaluations are exact without one.
#[test]
fn a_set_near_its_last_evaluation_takes_its_tangent() {
    let (b, q0, v0) = near_case();
    let distance = 3e-7;
    let mut near = SetMemory::Empty;
    assert_eq!(
        near_force(&b, &q0, &v0, distance, &mut near),
        exact_force(&b, &q0, &v0),
        "first: exact"
    );
    assert_eq!(
        near_force(&b, &q0, &v0, distance, &mut near),
        exact_force(&b, &q0, &v0),
        "same point"
    );

    // within the distance: f0 + K·Δx + C·Δẋ, within the linearisation's remainder of the exact force
    let (dq, dv) = (
        [1e-7, -5e-8, 4e-8, 2e-7, -1e-7, 0.0],
        [1e-4, 0.0, -2e-4, 1e-3, 0.0, 0.0],
    );
    let (q1, v1): ([f64; 6], [f64; 6]) = (
        std::array::from_fn(|i| q0[i] + dq[i]),
        std::array::from_fn(|i| v0[i] + dv[i]),
    );
    let x0: [f64; 5] = std::array::from_fn(|i| q0[i]);
    let xd0: [f64; 5] = std::array::from_fn(|i| v0[i]);
    let (mut k, mut c) = ([[0.0; 5]; 5], [[0.0; 5]; 5]);
    let f0 = b.evaluate(&x0, &xd0, q0[5], false, Some((&mut k, &mut c))).force;
    let linear: [f64; 5] =
        std::array::from_fn(|a| f0[a] + (0..5).map(|j| k[a][j] * dq[j] + c[a][j] * dv[j]).sum::<f64>());
    let got = near_force(&b, &q1, &v1, distance, &mut near);
    let exact = exact_force(&b, &q1, &v1);
    let scale = exact.iter().take(3).fold(0.0f64, |m, f| m.max(f.abs()));
    for i in 0..5 {
        assert!(
            (got[i] - linear[i]).abs() <= 1e-12 * scale,
            "f[{i}] = {} against f0 + KΔx + CΔẋ = {}",
            got[i],
            linear[i]
        );
        assert!(
            (got[i] - exact[i]).abs() <= 1e-3 * scale,
            "f[{i}] = {} against the exact {}",
            got[i],
            exact[i]
        );
        assert_ne!(got[i], exact[i], "f[{i}] must come from the tangent");
    }

    // a translation beyond the distance: exact, and kept (the same point again is exact to the bit)
    let mut q2 = q0;
    q2[0] += 4e-7;
    assert_eq!(near_force(&b, &q2, &v0, distance, &mut near), exact_force(&b, &q2, &v0));
    assert_eq!(near_force(&b, &q2, &v0, distance, &mut near), exact_force(&b, &q2, &v0));

    // the cage's turn moves the load zone: 1e-2 rad at a radial displacement of 65 µm (plus the
    // tilt's part at the farthest lamina, 13 µm) is beyond 3e-7 m, 1e-3 rad within it (the force
    // then held where the cage was)
    let turned = |dpsi: f64| {
        let mut q = q2;
        q[5] += dpsi;
        q
    };
    let held = near_force(&b, &turned(1e-3), &v0, distance, &mut near);
    assert_eq!(
        held[..5],
        exact_force(&b, &q2, &v0)[..5],
        "the cage within the distance: the kept force"
    );
    let q3 = turned(1e-2);
    assert_eq!(near_force(&b, &q3, &v0, distance, &mut near), exact_force(&b, &q3, &v0));

    // a tilt: 1e-5 rad moves the farthest lamina by 0.59 µm, beyond 3e-7 m (the contact angle's arm
    // at the 200 mm pitch radius, 35 mm, and half the roller's 50 mm along the axis)
    let mut q4 = q3;
    q4[4] += 1e-5;
    assert_eq!(near_force(&b, &q4, &v0, distance, &mut near), exact_force(&b, &q4, &v0));
    // q3's tangent was left unused: the next eight evaluations are exact even within the distance, and
    // keep no tangent (the ninth evaluates one, the tenth takes a force from it)
    let mut q5 = q4;
    for k in 0..8 {
        q5[0] += 1e-9;
        assert_eq!(
            near_force(&b, &q5, &v0, distance, &mut near),
            exact_force(&b, &q5, &v0),
            "after an unused tangent {k}"
        );
    }
    assert!(matches!(near, SetMemory::Exact { left: 0, backoff: 16 }), "{near:?}");
    near_force(&b, &q5, &v0, distance, &mut near);
    assert!(matches!(near, SetMemory::Tangent { used: false, .. }), "{near:?}");
    q5[0] += 1e-9;
    assert_ne!(
        near_force(&b, &q5, &v0, distance, &mut near),
        exact_force(&b, &q5, &v0),
        "from the new tangent"
    );

    // no distance: always exact
    let mut none = SetMemory::Empty;
    near_force(&b, &q0, &v0, 0.0, &mut none);
    assert_eq!(near_force(&b, &q1, &v1, 0.0, &mut none), exact, "distance 0");
}

/// A lamina near a kink of its law is not crossed on a tangent: with a roller 10 nm from touching
/// its races, a move of 50 nm (within the distance, 300 nm) is evaluated exactly; 5 nm is not.
#[test]
fn a_set_near_a_kink_is_evaluated_exactly() {
    let b = bearing(&crb(20, 30.0, 8));
    let distance = 3e-7;
    // the roller at the cage's zero is 10 nm from touching: half the clearance away
    let q0 = [15e-6 - 10e-9, 0.0, 0.0, 0.0, 0.0, 0.0];
    let v0 = [0.0; 6];
    let mut near = SetMemory::Empty;
    near_force(&b, &q0, &v0, distance, &mut near);
    let mut q1 = q0;
    q1[0] += 5e-9;
    assert_eq!(
        near_force(&b, &q1, &v0, distance, &mut near),
        exact_force(&b, &q1, &v0),
        "clear, and no load"
    );
    assert!(
        matches!(near, SetMemory::Tangent { used: true, .. }),
        "5 nm short of the kink: {near:?}"
    );
    let mut q2 = q0;
    q2[0] += 50e-9;
    let exact = exact_force(&b, &q2, &v0);
    assert!(exact[0] > 0.0, "the roller touches at 40 nm");
    assert_eq!(
        near_force(&b, &q2, &v0, distance, &mut near),
        exact,
        "across the kink: exact"
    );
}
