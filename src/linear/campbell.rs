//! Campbell analysis of a drivetrain: excitation orders of the rotor speed (1P, 3P and every stage's
//! gear-mesh frequency with harmonics) against its natural frequencies, and where they cross inside
//! the operating speed range. Torsional natural frequencies do not change with speed here (no
//! gyroscopic or centrifugal terms), so crossings sit at n = 60·f_mode/order rpm.
//!
//! Mesh orders are the physical ones: z_ring·(carrier speed) for a fixed-ring planetary stage and
//! z_gear·(gear speed) for a parallel stage. The thesis's Table 4.8 prints z_sun·(sun speed) for
//! planetary stages (C stage I: 174× where the mesh frequency is 145×); that value is kept beside.

use crate::physics::drivetrain::{Drivetrain, Stage};

#[derive(Debug, Clone, PartialEq)]
pub struct Order {
    pub name: String,
    /// Excitation frequency / rotor speed (Hz per rev/s).
    pub order: f64,
    /// The thesis's convention for the same excitation when it differs.
    pub thesis_order: Option<f64>,
}

/// 1P, 3P, and each stage's mesh order times 1..=harmonics.
pub fn excitation_orders(dt: &Drivetrain, harmonics: u32) -> Vec<Order> {
    let mut out = vec![
        Order {
            name: "1P".into(),
            order: 1.0,
            thesis_order: None,
        },
        Order {
            name: "3P".into(),
            order: 3.0,
            thesis_order: None,
        },
    ];
    let mut input = 1.0; // stage input speed / rotor speed
    for (k, stage) in dt.stages.iter().enumerate() {
        let (physical, thesis) = match stage {
            Stage::Planetary(p) => (f64::from(p.z_ring) * input, f64::from(p.z_sun) * input * stage.ratio()),
            Stage::Parallel(p) => (f64::from(p.z_gear) * input, f64::from(p.z_gear) * input),
        };
        for h in 1..=harmonics {
            let h_f = f64::from(h);
            out.push(Order {
                name: format!(
                    "stage {} GMF{}",
                    k + 1,
                    if h == 1 { String::new() } else { format!(" ×{h}") }
                ),
                order: h_f * physical,
                thesis_order: ((thesis - physical).abs() > 1e-9).then_some(h_f * thesis),
            });
        }
        input *= stage.ratio();
    }
    out
}

#[derive(Debug, Clone, PartialEq)]
pub struct Crossing {
    pub order: String,
    pub mode_hz: f64,
    pub rotor_rpm: f64,
}

/// Every (order, mode) pair that meets at a rotor speed within [rpm_min, rpm_max].
pub fn crossings(orders: &[Order], modes_hz: &[f64], rpm_min: f64, rpm_max: f64) -> Vec<Crossing> {
    let mut out = Vec::new();
    for o in orders {
        for &f in modes_hz.iter().filter(|f| **f > 1e-6) {
            let rpm = 60.0 * f / o.order;
            if (rpm_min..=rpm_max).contains(&rpm) {
                out.push(Crossing {
                    order: o.name.clone(),
                    mode_hz: f,
                    rotor_rpm: rpm,
                });
            }
        }
    }
    out.sort_by(|a, b| a.rotor_rpm.total_cmp(&b.rotor_rpm));
    out
}

/// The natural frequencies a Campbell diagram draws: non-zero, up to `f_max`, repeated modes (the
/// planet modes of a symmetric stage) as one line with their multiplicity. `frequencies_hz` ascending.
pub fn distinct_modes(frequencies_hz: &[f64], f_max: f64) -> Vec<(f64, usize)> {
    let mut out: Vec<(f64, usize)> = Vec::new();
    for f in frequencies_hz.iter().cloned().filter(|f| *f > 1e-6 && *f <= f_max) {
        match out.last_mut() {
            Some((last, k)) if (f / *last - 1.0).abs() < 1e-6 => *k += 1,
            _ => out.push((f, 1)),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rigid-body and out-of-range modes drop out; a repeated pair becomes one line of multiplicity 2.
    #[test]
    fn repeated_modes_are_one_line() {
        let m = distinct_modes(&[0.0, 2.5, 40.0, 40.0 * (1.0 + 1e-9), 70.0, 900.0], 100.0);
        assert_eq!(m, vec![(2.5, 1), (40.0, 2), (70.0, 1)]);
    }

    /// Table 4.8 of the thesis: C 174×, 648×, 2664× (thesis convention) with the
    /// physical first stage 145×; A 146× and 730× (thesis) for the two planetary stages.
    #[test]
    fn mesh_orders_of_c_and_a() {
        let c = excitation_orders(&Drivetrain::preset("C").unwrap(), 1);
        let gmf: Vec<&Order> = c.iter().filter(|o| o.name.contains("GMF")).collect();
        assert!((gmf[0].order - 145.0).abs() < 1e-9 && (gmf[0].thesis_order.unwrap() - 174.0).abs() < 1e-9);
        assert!((gmf[1].order - 648.0).abs() < 1e-9 && gmf[1].thesis_order.is_none());
        assert!((gmf[2].order - 2664.0).abs() < 1e-9);
        let a = excitation_orders(&Drivetrain::preset("A").unwrap(), 1);
        let thesis: Vec<f64> = a.iter().filter_map(|o| o.thesis_order).collect();
        assert!((thesis[0] - 146.0).abs() < 1e-9, "{thesis:?}");
        // 21 × 34.762: the thesis prints 730×
        assert!((thesis[1] - 730.0).abs() < 0.01, "{thesis:?}");
    }

    #[test]
    fn crossing_speed() {
        let o = [Order {
            name: "x".into(),
            order: 100.0,
            thesis_order: None,
        }];
        let c = crossings(&o, &[0.0, 25.0, 60.0], 10.0, 20.0);
        // 25 Hz / 100 = 0.25 rev/s = 15 rpm; 60 Hz would need 36 rpm
        assert_eq!(c.len(), 1);
        assert!((c[0].rotor_rpm - 15.0).abs() < 1e-12);
    }
}
