//! Stage description of a drivetrain and the presets A–D of the thesis (its Tables 4.1–4.3, 4.7).
//!
//! A drivetrain is a rotor, a chain of gear stages joined by shafts, and a generator. Planetary
//! stages have a fixed ring, the carrier as input and the sun as output; parallel stages take the
//! gear as input and the pinion as output. Every model fidelity is derived from this one description.

use serde::{Deserialize, Serialize};

/// Gear geometry used for line-of-action quantities (mesh force, TVMS). Only the base radii matter
/// to the dynamics' force outputs: the torsional mesh stiffness is given referred to the small wheel.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Geometry {
    /// Normal module, m.
    pub module: f64,
    /// Normal pressure angle, rad.
    pub pressure_angle: f64,
    /// Helix angle, rad.
    pub helix_angle: f64,
    /// True when the module is a documented estimate rather than published data.
    pub estimated: bool,
}

impl Geometry {
    /// Base radius of a wheel with `z` teeth (standard gearing, x = 0).
    pub fn base_radius(&self, z: u32) -> f64 {
        let transverse_module = self.module / self.helix_angle.cos();
        let transverse_pressure = (self.pressure_angle.tan() / self.helix_angle.cos()).atan();
        0.5 * transverse_module * f64::from(z) * transverse_pressure.cos()
    }
}

/// A fixed-ring planetary stage: carrier in, sun out.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Planetary {
    pub z_sun: u32,
    pub z_planet: u32,
    pub z_ring: u32,
    pub planets: usize,
    pub j_carrier: f64,
    pub j_planet: f64,
    pub j_sun: f64,
    /// Ring–planet and sun–planet torsional mesh stiffness, N·m/rad, referred to the sun base radius.
    pub k_ring_planet: f64,
    pub k_sun_planet: f64,
    /// Mesh damping, N·m·s/rad referred to the sun base radius; None = derive from ζ_mesh.
    pub c_ring_planet: Option<f64>,
    pub c_sun_planet: Option<f64>,
    pub geometry: Geometry,
}

/// A parallel stage: gear in, pinion out.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Parallel {
    pub z_gear: u32,
    pub z_pinion: u32,
    pub j_gear: f64,
    pub j_pinion: f64,
    /// Torsional mesh stiffness, N·m/rad, referred to the pinion base radius.
    pub k_mesh: f64,
    /// Mesh damping, N·m·s/rad referred to the pinion base radius; None = derive from ζ_mesh.
    pub c_mesh: Option<f64>,
    pub geometry: Geometry,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Stage {
    Planetary(Planetary),
    Parallel(Parallel),
}

impl Stage {
    /// Output speed over input speed.
    pub fn ratio(&self) -> f64 {
        match self {
            Stage::Planetary(p) => 1.0 + f64::from(p.z_ring) / f64::from(p.z_sun),
            Stage::Parallel(p) => f64::from(p.z_gear) / f64::from(p.z_pinion),
        }
    }
}

/// A torsional shaft: stiffness N·m/rad, damping N·m·s/rad (None = derive from ζ_shaft).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Shaft {
    pub stiffness: f64,
    pub damping: Option<f64>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Drivetrain {
    pub name: String,
    pub rated_power: f64,
    /// Rated rotor speed, rad/s: the generator's rated speed (thesis Table 4.6) over the gear ratio,
    /// the speed the thesis simulated; see [`TABLE_4_1_RATED_RPM`] for the rotor speeds Table 4.1 prints.
    pub rated_rotor_speed: f64,
    pub j_rotor: f64,
    pub j_generator: f64,
    pub stages: Vec<Stage>,
    /// stages.len() + 1 shafts: LSS (rotor → stage 1), the intermediate shafts, HSS (last stage → generator).
    pub shafts: Vec<Shaft>,
    /// Electrical torsional stiffness of a grid-locked generator, N·m/rad at the HSS (thesis K_gen).
    pub k_generator: f64,
    /// True when k_generator is an estimate (A–C), not a published value.
    pub k_generator_estimated: bool,
}

impl Drivetrain {
    pub fn gear_ratio(&self) -> f64 {
        self.stages.iter().map(Stage::ratio).product()
    }

    pub fn rated_rotor_torque(&self) -> f64 {
        self.rated_power / self.rated_rotor_speed
    }

    pub fn rated_generator_torque(&self) -> f64 {
        self.rated_rotor_torque() / self.gear_ratio()
    }

    /// Looks up a preset by name (case-insensitive): A, B, C, D or P.
    pub fn preset(name: &str) -> Option<Drivetrain> {
        match name.trim().to_ascii_uppercase().as_str() {
            "A" => Some(preset_a()),
            "B" => Some(preset_b()),
            "C" => Some(preset_c()),
            "D" => Some(preset_d()),
            "P" => Some(preset_p()),
            _ => None,
        }
    }
}

/// The thesis's drivetrains (Table 4.1). [`preset_p`], the paper's turbine, is not among them: the
/// thesis tables (4.1, 4.6, 3.1) and the checks against them do not apply to it.
pub const PRESETS: [&str; 4] = ["A", "B", "C", "D"];

/// Rated generator speeds of A–D, rpm (thesis Table 4.6). The presets' rated rotor speeds are these over
/// the gear ratio: C's field turbine runs at 1680 rpm (Table 3.1: 18.1 rpm rotor, ratio 92), D's
/// simulations at 1809 rpm (ch. 6: "around the 1809 RPM", LSS 22.4 rpm; the public GRC operating point is
/// 1800 rpm, 22.1 rpm rotor), so Table 4.1's 16 and 18.6 rpm would put C's and D's rated torque 13 % and
/// 19 % above what the thesis's own models carried.
pub const RATED_GENERATOR_RPM: [(&str, f64); 4] = [("A", 515.0), ("B", 1836.0), ("C", 1680.0), ("D", 1809.0)];

/// Rated rotor speeds as thesis Table 4.1 prints them, rpm (kept for the documentation's comparison).
pub const TABLE_4_1_RATED_RPM: [(&str, f64); 4] = [("A", 14.8), ("B", 16.1), ("C", 16.0), ("D", 18.6)];

/// Sets the rated rotor speed from the preset's rated generator speed and its gear ratio.
fn with_generator_rated_speed(mut dt: Drivetrain) -> Drivetrain {
    let (_, n) = RATED_GENERATOR_RPM
        .iter()
        .find(|(name, _)| *name == dt.name)
        .expect("every preset has a rated generator speed");
    dt.rated_rotor_speed = rpm(*n) / dt.gear_ratio();
    dt
}

/// Rotor speed range (min, max) of a preset in rpm (thesis Table 3.1 / 4.1; P: an estimate).
pub fn operating_speed_range_rpm(name: &str) -> Option<(f64, f64)> {
    match name.trim().to_ascii_uppercase().as_str() {
        "A" | "B" => Some((8.6, 18.4)),
        "C" => Some((10.8, 19.1)),
        "D" => Some((14.8, 22.1)),
        // the paper gives none: C's minimum and maximum over its rated speed (0.59, 1.04) at 17.5 rpm
        "P" => Some((10.3, 18.3)),
        _ => None,
    }
}

fn rpm(n: f64) -> f64 {
    n * std::f64::consts::PI / 30.0
}

fn geometry(module_mm: f64, helix_deg: f64, estimated: bool) -> Geometry {
    Geometry {
        module: module_mm * 1e-3,
        pressure_angle: 20f64.to_radians(),
        helix_angle: helix_deg.to_radians(),
        estimated,
    }
}

fn shaft(stiffness: f64) -> Shaft {
    Shaft {
        stiffness,
        damping: None,
    }
}

#[allow(clippy::too_many_arguments)]
fn planetary(z: (u32, u32, u32), j: (f64, f64, f64), k: f64, g: Geometry) -> Stage {
    Stage::Planetary(Planetary {
        z_sun: z.0,
        z_planet: z.1,
        z_ring: z.2,
        planets: 3,
        j_carrier: j.0,
        j_planet: j.1,
        j_sun: j.2,
        k_ring_planet: k,
        k_sun_planet: k,
        c_ring_planet: None,
        c_sun_planet: None,
        geometry: g,
    })
}

fn parallel(z_gear: u32, z_pinion: u32, j_gear: f64, j_pinion: f64, k: f64, g: Geometry) -> Stage {
    Stage::Parallel(Parallel {
        z_gear,
        z_pinion,
        j_gear,
        j_pinion,
        k_mesh: k,
        c_mesh: None,
        geometry: g,
    })
}

/// Electrical stiffness for A–C, which the thesis does not give: D's per-unit value
/// K_gen / T_rated,gen = 2.81e4 / 3.96e3 ≈ 7.1 per rad, applied to each rated generator torque.
fn estimated_k_generator(dt: &Drivetrain) -> f64 {
    let d = preset_d();
    d.k_generator / d.rated_generator_torque() * dt.rated_generator_torque()
}

/// Drivetrain A: 3 MW, two planetary stages, PMG (thesis Tables 4.1, 4.3, 4.7). Modules are estimates.
pub fn preset_a() -> Drivetrain {
    let mut dt = Drivetrain {
        name: "A".into(),
        rated_power: 3e6,
        rated_rotor_speed: 0.0,
        j_rotor: 2.67e6,
        j_generator: 680.0,
        stages: vec![
            planetary(
                (24, 49, 122),
                (2.32e3, 37.119, 2.187),
                1.54e9,
                geometry(20.0, 0.0, true),
            ),
            planetary((21, 39, 99), (871.4, 7.115, 0.887), 1.62e8, geometry(14.0, 0.0, true)),
        ],
        shafts: vec![shaft(9.30e9), shaft(1.06e8), shaft(1.40e7)],
        k_generator: 0.0,
        k_generator_estimated: true,
    };
    dt = with_generator_rated_speed(dt);
    dt.k_generator = estimated_k_generator(&dt);
    dt
}

/// Drivetrain B: 3 MW, two planetary stages and one parallel stage, DFIG. Modules are estimates.
pub fn preset_b() -> Drivetrain {
    let mut dt = Drivetrain {
        name: "B".into(),
        rated_power: 3e6,
        rated_rotor_speed: 0.0,
        j_rotor: 2.67e6,
        j_generator: 680.0,
        stages: vec![
            planetary((27, 50, 127), (2.32e3, 87.9, 7.9), 7.09e8, geometry(20.0, 0.0, true)),
            planetary((19, 43, 105), (871.4, 9.0, 0.4), 1.43e8, geometry(14.0, 0.0, true)),
            parallel(65, 21, 17.7, 0.3, 5.88e8, geometry(10.0, 0.0, true)),
        ],
        shafts: vec![shaft(9.30e9), shaft(1.06e8), shaft(1.40e7), shaft(1.95e6)],
        k_generator: 0.0,
        k_generator_estimated: true,
    };
    dt = with_generator_rated_speed(dt);
    dt.k_generator = estimated_k_generator(&dt);
    dt
}

/// Drivetrain C: 2 MW field turbine, one planetary and two parallel stages, DFIG. Modules are estimates.
pub fn preset_c() -> Drivetrain {
    let mut dt = Drivetrain {
        name: "C".into(),
        rated_power: 2e6,
        rated_rotor_speed: 0.0,
        j_rotor: 6.03e6,
        j_generator: 60.0,
        stages: vec![
            planetary((29, 58, 145), (173.86, 356.0, 29.0), 1.22e9, geometry(16.0, 0.0, true)),
            parallel(108, 27, 270.0, 1.5, 1.63e9, geometry(12.0, 0.0, true)),
            parallel(111, 29, 270.0, 2.0, 5.7e8, geometry(9.0, 0.0, true)),
        ],
        shafts: vec![shaft(1.6e8), shaft(3.42e8), shaft(1.85e9), shaft(3.1e8)],
        k_generator: 0.0,
        k_generator_estimated: true,
    };
    dt = with_generator_rated_speed(dt);
    dt.k_generator = estimated_k_generator(&dt);
    dt
}

/// Drivetrain D: NREL GRC 750 kW, the thesis's 11-mass model (Table 4.2) with its damping values.
/// Modules and helix angles from the GRC description (NREL/TP-5000-47773 via gfsReboucas/Drivetrain;
/// unconfirmed against the report).
pub fn preset_d() -> Drivetrain {
    let planetary = Stage::Planetary(Planetary {
        z_sun: 21,
        z_planet: 39,
        z_ring: 99,
        planets: 3,
        j_carrier: 65.2,
        j_planet: 3.2,
        j_sun: 1.02,
        k_ring_planet: 5.86e7,
        k_sun_planet: 5.86e7,
        c_ring_planet: Some(3.13e3),
        c_sun_planet: Some(0.812e3),
        geometry: geometry(10.0, 7.5, false),
    });
    let p1 = Stage::Parallel(Parallel {
        z_gear: 82,
        z_pinion: 23,
        j_gear: 31.72,
        j_pinion: 0.4,
        k_mesh: 5.23e7,
        c_mesh: Some(3.974e3),
        geometry: geometry(8.25, 14.0, false),
    });
    let p2 = Stage::Parallel(Parallel {
        z_gear: 88,
        z_pinion: 22,
        j_gear: 3.42,
        j_pinion: 0.08,
        k_mesh: 1.72e7,
        c_mesh: Some(0.354e3),
        geometry: geometry(5.0, 14.0, false),
    });
    let damped = |stiffness, damping| Shaft {
        stiffness,
        damping: Some(damping),
    };
    with_generator_rated_speed(Drivetrain {
        name: "D".into(),
        rated_power: 750e3,
        rated_rotor_speed: 0.0,
        j_rotor: 998_138.0,
        j_generator: 24.0,
        stages: vec![planetary, p1, p2],
        shafts: vec![
            damped(3.69e7, 2.396),
            damped(2.45e7, 0.476),
            damped(2.70e8, 5.561),
            damped(2.08e6, 5.753),
        ],
        k_generator: 2.81e4,
        k_generator_estimated: false,
    })
}

/// Density of gear steel, kg/m³ (the gearbox6dof presets' value).
const STEEL_DENSITY: f64 = 7850.0;

/// Estimated inertia and mass of a gear as a solid steel cylinder of its reference diameter and face
/// width: (J = ρπb d⁴/32, m = ρπb d²/4). The paper's gearbox6dof preset estimates its bodies the same way.
fn solid_gear(z: u32, module: f64, helix_deg: f64, face_width: f64) -> (f64, f64) {
    let d = f64::from(z) * module / helix_deg.to_radians().cos();
    let area = std::f64::consts::PI * d * d / 4.0;
    (
        STEEL_DENSITY * area * face_width * d * d / 8.0,
        STEEL_DENSITY * area * face_width,
    )
}

/// Linear mesh stiffness, N/m, of an impact contact F = k·δ^e at force F: dF/dδ = e·k^(1/e)·F^(1−1/e).
fn impact_tangent_stiffness(k: f64, exponent: f64, force: f64) -> f64 {
    exponent * k.powf(1.0 / exponent) * force.powf(1.0 - 1.0 / exponent)
}

/// Drivetrain P: the paper's 1.5 MW turbine (docs/SOURCES.md §Paper): Table 2's rotor and
/// generator inertias and main shaft (5e9 N·m/rad, 1e7 N·m·s/rad), Table 4's gears, 17.5 rpm rated.
///
/// Rated power is the rotor's 1.65 MW: the paper's mean power "stays constant (almost 1650 kW)" above
/// rated wind (its Fig. 3), the 1.5 MW nameplate being the grid's side of the generator's and
/// converter's losses, which our lossless models do not have. The WindPACT 1.5 MW blade at 35 m then
/// reaches it at 11.65 m/s, where the paper places its rated wind ("slightly higher than 11.5 m/s
/// (possibly 11.6 m/s)"); with 1.5 MW it would at 11.18 m/s.
///
/// Estimates, because the paper's ADAMS model is of rigid bodies joined by contact elements:
/// - gear inertias: solid steel cylinders of reference diameter and face width; each carrier 250 / 60
///   kg·m² (the gearbox6dof preset's estimates) plus its planets' orbiting mass m·a²;
/// - mesh stiffness: Table 5's impact law F = k·δ^1.5 (k in N/mm^1.5, as the gearbox6dof preset reads
///   it) linearised at rated torque; damping from the mesh damping ratio, as for A–C;
/// - the shafts between stages (3e8, 5e7 N·m/rad) and the HSS with its coupling (2e6 N·m/rad): the
///   gearbox6dof preset's estimates;
/// - the ratio from the teeth is 100.84, the paper's Table 2 says 100.75 (0.09 % apart).
pub fn preset_p() -> Drivetrain {
    let rated_power = 1.65e6;
    let rated_rotor_speed = rpm(17.5);
    let rated_torque = rated_power / rated_rotor_speed;
    // k of Table 5 in N/mm^1.5 → N/m^1.5
    let k_si = |k: f64| k * 1000f64.powf(1.5);
    let stage1 = geometry(14.0, 0.0, false);
    let stage2 = geometry(9.0, 0.0, false);
    let stage3 = geometry(6.0, 12.0, false);
    let planetary_stage =
        |z: (u32, u32, u32), g: Geometry, faces: (f64, f64), carrier: f64, k_sp: f64, k_rp: f64, torque: f64| {
            let (j_sun, _) = solid_gear(z.0, g.module, 0.0, faces.0);
            let (j_planet, m_planet) = solid_gear(z.1, g.module, 0.0, faces.1);
            let orbit = 0.5 * f64::from(z.0 + z.1) * g.module;
            let (r_s, r_r) = (g.base_radius(z.0), g.base_radius(z.2));
            // per mesh along the line of action: carrier torque T = 3 · F · ((r_s + r_p) + (r_r − r_p))
            let force = torque / (3.0 * (r_s + r_r));
            Stage::Planetary(Planetary {
                z_sun: z.0,
                z_planet: z.1,
                z_ring: z.2,
                planets: 3,
                j_carrier: carrier + 3.0 * m_planet * orbit * orbit,
                j_planet,
                j_sun,
                // torsional stiffness referred to the sun base radius
                k_ring_planet: impact_tangent_stiffness(k_si(k_rp), 1.5, force) * r_s * r_s,
                k_sun_planet: impact_tangent_stiffness(k_si(k_sp), 1.5, force) * r_s * r_s,
                c_ring_planet: None,
                c_sun_planet: None,
                geometry: g,
            })
        };
    let s1 = planetary_stage((23, 34, 91), stage1, (0.38, 0.38), 250.0, 9.6e5, 1.3e6, rated_torque);
    let t2 = rated_torque / s1.ratio();
    let s2 = planetary_stage((25, 45, 116), stage2, (0.18, 0.18), 60.0, 8e5, 1.1e6, t2);
    let t3 = t2 / s2.ratio();
    let (j_gear, _) = solid_gear(101, stage3.module, 12.0, 0.18);
    let (j_pinion, _) = solid_gear(28, stage3.module, 12.0, 0.19);
    let (r_g, r_pin) = (stage3.base_radius(101), stage3.base_radius(28));
    let k3 = impact_tangent_stiffness(k_si(8e5), 1.5, t3 / r_g) * r_pin * r_pin;
    let s3 = parallel(101, 28, j_gear, j_pinion, k3, stage3);
    let mut dt = Drivetrain {
        name: "P".into(),
        rated_power,
        rated_rotor_speed,
        j_rotor: 3.0854e6,
        j_generator: 53.036,
        stages: vec![s1, s2, s3],
        shafts: vec![
            Shaft {
                stiffness: 5e9,
                damping: Some(1e7),
            },
            shaft(3e8),
            shaft(5e7),
            shaft(2e6),
        ],
        k_generator: 0.0,
        k_generator_estimated: true,
    };
    dt.k_generator = estimated_k_generator(&dt);
    dt
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Preset P from the paper's Tables 2 and 4: the ratio from the teeth within 0.1 % of the printed
    /// 100.75, the rated torque of 1650 kW at 17.5 rpm, and the linearised impact contact: the tangent
    /// of F = k·δ^1.5 at rated force equals a finite difference of the law.
    #[test]
    fn paper_preset() {
        let p = Drivetrain::preset("p").unwrap();
        assert!((p.gear_ratio() / 100.75 - 1.0).abs() < 1e-3, "{}", p.gear_ratio());
        assert!((p.rated_rotor_torque() - 1.65e6 / rpm(17.5)).abs() < 1e-6);
        assert_eq!((p.j_rotor, p.j_generator), (3.0854e6, 53.036));
        let (k, e, f): (f64, f64, f64) = (3.04e10, 1.5, 3.7e5);
        let delta = (f / k).powf(1.0 / e);
        let h = delta * 1e-6;
        let fd = (k * (delta + h).powf(e) - k * (delta - h).powf(e)) / (2.0 * h);
        assert!((impact_tangent_stiffness(k, e, f) / fd - 1.0).abs() < 1e-8);
        // a solid cylinder: J = m d²/8
        let (j, m) = solid_gear(34, 0.014, 0.0, 0.38);
        assert!((j / (m * 0.476f64.powi(2) / 8.0) - 1.0).abs() < 1e-12);
        assert!(!PRESETS.contains(&"P") && operating_speed_range_rpm("P").is_some());
    }
}
