//! The assembled 6-DOF gearbox: bodies, their DOFs and frames, and the force elements.
//!
//! Formulation (and why): every body has six DOFs, [u_x, u_y, u_z, θ_x, θ_y, φ]: small translations
//! and tilts, and its absolute spin φ about the shaft axis (large). The small motions of a planetary
//! stage's bodies (carrier, planets, sun, ring, and the rotor ahead of stage 1) are measured in the
//! frame that turns with the stage's carrier (Lin & Parker's choice), those of parallel stages and
//! the generator in the housing frame. In its carrier's frame a planet pin, a planet bearing and
//! each line of action are fixed, so every bearing and mesh row is constant and the tangent matrix
//! changes only with the contact pattern, however far the shafts turn: the step can reuse
//! factorisations. The price is the frame's inertial terms, exact for a frame whose speed Ω varies:
//! Coriolis 2mΩ J u̇, centripetal −mΩ²(p₀+u), the orbital coupling m(J p₀)·Ω̇ (in the mass matrix)
//! and the tilt gyroscopics of an axisymmetric body, I_t θ̈ + (2I_tΩ − I_pω) J θ̇ + (I_pωΩ − I_tΩ²) θ.
//! Supports to the housing of bodies in a carrier frame must be isotropic (radial, tilting), which
//! is what the description format allows; bodies in different frames are joined only by splines
//! (torque and axial force), so no row depends on the angle between two frames.

use super::beam;
use super::bearing::{Mounting, RollerBearing};
use super::contact::GearContact;
use super::description::{self as desc, BearingModel, Description, ForceLaw, MeshStiffnessModel};
use super::involute::{Pair, PairGeometry};
use super::mesh::{Law, Mesh, Phase};
use super::row::Row;
use crate::solver::system::InputLoad;
use nalgebra::DMatrix;
use std::f64::consts::{PI, TAU};

pub const UX: usize = 0;
pub const UY: usize = 1;
pub const UZ: usize = 2;
pub const TX: usize = 3;
pub const TY: usize = 4;
pub const SPIN: usize = 5;

/// Inputs, in the order `torsional` has them.
pub const INPUT_ROTOR_TORQUE: usize = 0;
pub const INPUT_GENERATOR_TORQUE: usize = 1;
pub const INPUT_BRAKE_COMMAND: usize = 2;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BodyKind {
    Rotor,
    Carrier,
    Planet,
    Sun,
    Ring,
    Gear,
    Pinion,
    Generator,
    /// A node between the elements of a flexible shaft (`beam.elements` ≥ 2): the shaft's own mass.
    ShaftNode,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    pub name: String,
    pub kind: BodyKind,
    pub stage: Option<usize>,
    /// First of its six DOFs; None = part of the housing (a rigid ring).
    pub first: Option<usize>,
    /// The carrier (body index) whose spin is this body's frame; None = the housing frame.
    pub frame: Option<usize>,
    /// Nominal transverse position of the centre in its frame, m.
    pub centre: [f64; 2],
    pub mass: f64,
    pub polar: f64,
    pub transverse: f64,
}

/// A linear spring on one deflection δ = row·q − offset: f = k·δ + c·row·v.
#[derive(Debug, Clone, PartialEq)]
pub struct Spring {
    pub row: Row,
    pub stiffness: f64,
    pub damping: f64,
    pub offset: f64,
    /// A bearing direction that a roller set carries in the dynamics (`bearings = "lamina"`): the
    /// spring stays for modal analysis, which linearises the description's stiffness.
    pub lamina: bool,
}

impl Spring {
    /// Its force at (q, v), positive stretching δ.
    pub fn force(&self, q: &[f64], v: &[f64]) -> f64 {
        self.stiffness * (self.row.dot(q) - self.offset) + self.damping * self.row.dot(v)
    }
}

/// A named bearing: springs x, y, axial, tilt x, tilt y, rotation (indices into `springs`), its
/// roller set (index into `rollers`) when the lamina model carries it, and the roller geometry the
/// description gives whichever model carries it (its ISO 281 load rating needs it).
#[derive(Debug, Clone, PartialEq)]
pub struct BearingSprings {
    pub name: String,
    pub springs: [usize; 6],
    pub rollers: Option<usize>,
    pub geometry: Option<desc::Rollers>,
}

/// A shaft's torsion spring, with the sign that makes its torque positive in normal operation.
#[derive(Debug, Clone, PartialEq)]
pub struct ShaftSpring {
    pub name: String,
    pub spring: usize,
    pub sign: f64,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Gearbox {
    pub name: String,
    pub bodies: Vec<Body>,
    pub springs: Vec<Spring>,
    pub bearings: Vec<BearingSprings>,
    /// Roller sets of the bearings the lamina model carries.
    pub rollers: Vec<RollerBearing>,
    pub shafts: Vec<ShaftSpring>,
    pub meshes: Vec<Mesh>,
    pub(super) mass: DMatrix<f64>,
    pub(super) input_loads: Vec<InputLoad>,
    /// Spin of every body when the input turns one radian (translations 0), if the chain is free.
    pub rigid: Option<Vec<f64>>,
    pub rigid_dof: usize,
    /// Gravity in the housing frame, m/s².
    pub gravity: [f64; 3],
    /// Moments about the housing's transverse axes at the rotor (or first carrier), N·m: set by the
    /// owner each communication step (held over it).
    pub external_moment: [f64; 2],
    /// Rotor thrust on the input body along the shaft, positive downwind, N (set like the moment).
    pub thrust: f64,
    pub input_body: usize,
    pub output_body: usize,
    /// Sign of the output body's spin when the input turns positive.
    pub output_sign: f64,
    pub gear_ratio: f64,
    pub rated_rotor_torque: Option<f64>,
    pub nonlinear: bool,
    /// The HSS brake on the output body (none until the owner sets one).
    pub brake: crate::physics::brake::DiskBrake,
    /// Geometry of every mesh (same order as `meshes`).
    pub geometry: Vec<PairGeometry>,
    /// Hertz contact of every mesh's slices (same order).
    pub contacts: Vec<GearContact>,
}

impl Gearbox {
    pub fn dofs(&self) -> usize {
        self.mass.nrows()
    }

    pub fn dof(&self, body: usize, k: usize) -> Option<usize> {
        self.bodies[body].first.map(|f| f + k)
    }

    pub fn body(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }

    /// Spin DOF of a body's frame, when it turns with a carrier.
    pub fn frame_spin(&self, body: usize) -> Option<usize> {
        self.bodies[body].frame.and_then(|c| self.dof(c, SPIN))
    }

    pub fn mass_matrix(&self) -> &DMatrix<f64> {
        &self.mass
    }
}

/// Builder state: bodies and elements as they are added.
struct Builder<'a> {
    d: &'a Description,
    bodies: Vec<Body>,
    springs: Vec<Spring>,
    bearings: Vec<BearingSprings>,
    rollers: Vec<RollerBearing>,
    meshes: Vec<Mesh>,
    geometry: Vec<PairGeometry>,
    /// (upstream body, downstream body, shaft spec, name)
    shafts: Vec<(usize, usize, desc::Shaft, String)>,
    /// (carrier, its downwind plate) while a planetary stage with carrier webs is built: bearings
    /// downwind of the centre of the carrier or a planet sit in the plate.
    downwind_plate: Option<(usize, usize)>,
    /// Entries of `shafts` that are carrier webs: springs like a shaft's, not reported as one.
    webs: Vec<usize>,
    /// Per entry of `shafts`, the nodes of its beam from upstream to downstream (none for springs
    /// or a beam of one element); filled once every shaft is listed.
    beam_nodes: Vec<Vec<usize>>,
    dofs: usize,
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

impl Builder<'_> {
    #[allow(clippy::too_many_arguments)]
    fn add_body(
        &mut self,
        name: String,
        kind: BodyKind,
        stage: Option<usize>,
        frame: Option<usize>,
        centre: [f64; 2],
        inertia: (f64, f64, f64),
        ground: bool,
    ) -> usize {
        let first = if ground {
            None
        } else {
            self.dofs += 6;
            Some(self.dofs - 6)
        };
        self.bodies.push(Body {
            name,
            kind,
            stage,
            first,
            frame,
            centre,
            mass: inertia.0,
            polar: inertia.1,
            transverse: inertia.2,
        });
        self.bodies.len() - 1
    }

    fn frame_spin(&self, b: usize) -> Option<usize> {
        self.bodies[b]
            .frame
            .and_then(|c| self.bodies[c].first.map(|f| f + SPIN))
    }

    /// Adds sign·n·d(P) to `row`: the displacement of body b's point at r (from its centre, in its
    /// frame) along n, with its spin measured relative to its frame.
    fn point(&self, row: &mut Row, b: usize, r: [f64; 3], n: [f64; 3], sign: f64) {
        let c = cross(r, n);
        if let Some(f) = self.bodies[b].first {
            for (k, v) in [n[0], n[1], n[2], c[0], c[1], c[2]].into_iter().enumerate() {
                row.add(f + k, sign * v);
            }
        }
        if let Some(fs) = self.frame_spin(b) {
            row.add(fs, -sign * c[2]);
        }
    }

    /// The change of `point` per metre along the axis (the tilt lever of a slice).
    fn lever(&self, row: &mut Row, b: usize, n: [f64; 3], sign: f64) {
        if let Some(f) = self.bodies[b].first {
            row.add(f + TX, -sign * n[1]);
            row.add(f + TY, sign * n[0]);
        }
    }

    fn spring(&mut self, row: Row, k: f64, c: f64, offset: f64) -> usize {
        self.springs.push(Spring {
            row,
            stiffness: k,
            damping: c,
            offset,
            lamina: false,
        });
        self.springs.len() - 1
    }

    /// A bearing of body b at axial position e to `other` (a body in the same frame, at `pin` from
    /// the other body's centre) or to the housing (None). `error` displaces the pin (m, frame axes).
    /// `rollers` is the described roller set; with the lamina model it carries the radial and tilt
    /// directions (and the axial one at a contact angle), the linear springs of those directions
    /// staying for modal analysis only.
    #[allow(clippy::too_many_arguments)]
    fn bearing(
        &mut self,
        name: String,
        b: usize,
        other: Option<(usize, [f64; 2])>,
        e: f64,
        s: &desc::Support,
        error: [f64; 2],
        rollers: Option<&desc::Rollers>,
    ) {
        let tau = self.d.model.bearing_damping_time;
        let k = [s.radial, s.radial, s.axial, s.tilting, s.tilting, s.rotational];
        let c = match s.damping {
            Some(dm) => [dm[0], dm[0], dm[1], dm[2], dm[2], dm[3]],
            None => k.map(|x| x * tau),
        };
        let mut idx = [0; 6];
        for dir in 0..6 {
            let mut row = Row::default();
            match dir {
                0..=2 => {
                    let mut n = [0.0; 3];
                    n[dir] = 1.0;
                    self.point(&mut row, b, [0.0, 0.0, e], n, 1.0);
                    if let Some((o, pin)) = other {
                        self.point(&mut row, o, [pin[0], pin[1], e], n, -1.0);
                    }
                }
                3 | 4 => {
                    if let Some(f) = self.bodies[b].first {
                        row.add(f + dir, 1.0);
                    }
                    if let Some((o, _)) = other
                        && let Some(f) = self.bodies[o].first
                    {
                        row.add(f + dir, -1.0);
                    }
                }
                _ => {
                    // rotation about the axis, absolute spins (frame-independent)
                    if let Some(f) = self.bodies[b].first {
                        row.add(f + SPIN, 1.0);
                    }
                    if let Some((o, _)) = other
                        && let Some(f) = self.bodies[o].first
                    {
                        row.add(f + SPIN, -1.0);
                    }
                }
            }
            row.compact();
            let offset = if dir < 2 { error[dir] } else { 0.0 };
            idx[dir] = self.spring(row, k[dir], c[dir], offset);
        }
        let geometry = rollers.copied();
        let lamina = self.d.model.bearings == BearingModel::Lamina;
        let rollers = rollers.filter(|_| lamina).map(|r| {
            let angled = r.contact_angle_deg != 0.0;
            for dir in [UX, UY, UZ, TX, TY] {
                if dir != UZ || angled {
                    self.springs[idx[dir]].lamina = true;
                }
            }
            let mounting = self.mounting(b, other, idx, r, error);
            self.rollers
                .push(RollerBearing::new(r, mounting, self.d.model.bearing_damping_time));
            self.rollers.len() - 1
        });
        self.bearings.push(BearingSprings {
            name,
            springs: idx,
            rollers,
            geometry,
        });
    }

    /// The rows a roller set reads: its races' relative motion (inner minus outer; a planet rides
    /// on the outer race, every shaft on an inner race) and its cage angle, which turns at the
    /// kinematic cage speed ((1 − γ)·ω_inner + (1 + γ)·ω_outer)/2, γ = D·cos α / d_m, relative to the
    /// bearing's frame. A pin error offsets the approach as it offsets the linear springs.
    fn mounting(
        &self,
        b: usize,
        other: Option<(usize, [f64; 2])>,
        springs: [usize; 6],
        r: &desc::Rollers,
        error: [f64; 2],
    ) -> Mounting {
        let body_is_outer = self.bodies[b].kind == BodyKind::Planet;
        let sign = if body_is_outer { -1.0 } else { 1.0 };
        let rows = [UX, UY, UZ, TX, TY].map(|dir| {
            let mut row = self.springs[springs[dir]].row.clone();
            row.val.iter_mut().for_each(|v| *v *= sign);
            row
        });
        let gamma = r.diameter_mm * r.contact_angle_deg.to_radians().cos() / r.pitch_diameter_mm;
        let (w_body, w_other) = if body_is_outer {
            (0.5 * (1.0 + gamma), 0.5 * (1.0 - gamma))
        } else {
            (0.5 * (1.0 - gamma), 0.5 * (1.0 + gamma))
        };
        let mut cage = Row::default();
        if let Some(f) = self.bodies[b].first {
            cage.add(f + SPIN, w_body);
        }
        if let Some((o, _)) = other
            && let Some(f) = self.bodies[o].first
        {
            cage.add(f + SPIN, w_other);
        }
        if let Some(fs) = self.frame_spin(b) {
            cage.add(fs, -1.0);
        }
        cage.compact();
        Mounting {
            bearing: self.bearings.len(),
            rows,
            cage,
            offset: [sign * error[0], sign * error[1]],
            sign,
        }
    }

    /// Supports of a body as its description gives them (bearings or one support at the centre),
    /// named by the description (`hss_a`), a planet's prefixed with it (`planet_1_uw`), a support
    /// after its body (`sun_1_support`).
    fn supports(
        &mut self,
        prefix: &str,
        b: usize,
        body: &desc::Body,
        other: Option<(usize, [f64; 2])>,
        error: [f64; 2],
    ) {
        if let Some(s) = &body.support {
            let name = format!("{}_support", self.bodies[b].name);
            self.bearing(name, b, other, 0.0, s, error, None);
        }
        for br in &body.bearings {
            let name = if prefix.is_empty() {
                br.name.clone()
            } else {
                format!("{prefix}_{}", br.name)
            };
            let (b, other) = match self.downwind_plate {
                Some((carrier, plate)) if br.position > 0.0 && b == carrier => (plate, other),
                Some((carrier, plate)) if br.position > 0.0 && other.is_some_and(|o| o.0 == carrier) => {
                    (b, other.map(|(_, pin)| (plate, pin)))
                }
                _ => (b, other),
            };
            self.bearing(name, b, other, br.position, &br.stiffness(), error, br.rollers.as_ref());
        }
    }
}

/// Mass, polar and transverse inertia of a body: given, or estimated (documented in the description
/// format): gears as solid cylinders of their reference radius and face width.
fn inertia(b: &desc::Body, gear: Option<(f64, f64)>, density: f64, at: &str) -> Result<(f64, f64, f64), String> {
    let (m, jp) = match (b.mass, b.polar_inertia, gear) {
        (Some(m), Some(j), _) => (m, j),
        (None, Some(j), Some((r, _))) => (2.0 * j / (r * r), j),
        (Some(m), None, Some((r, _))) => (m, 0.5 * m * r * r),
        (None, None, Some((r, w))) => {
            let m = density * PI * r * r * w;
            (m, 0.5 * m * r * r)
        }
        _ => return Err(format!("{at}: give mass and polar_inertia")),
    };
    let jt = b.transverse_inertia.unwrap_or(match gear {
        Some((r, w)) => m * (3.0 * r * r + w * w) / 12.0,
        None => 0.5 * jp,
    });
    Ok((m, jp, jt))
}

/// Unit vector at `deg` degrees from the upward transverse axis (y), turning towards +x.
fn direction(deg: f64) -> [f64; 2] {
    let a = deg.to_radians();
    [a.sin(), a.cos()]
}

/// The toothing of a stage as an involute pair (wheel 1, wheel 2).
fn pair(t: &desc::Toothing, teeth: [u32; 2], shift: [f64; 2], internal: bool, centre: Option<f64>) -> Pair {
    Pair {
        teeth,
        shift,
        module: t.module_mm * 1e-3,
        pressure_angle: t.pressure_angle_deg.to_radians(),
        helix_angle: t.helix_angle_deg.abs().to_radians(),
        face_width: t.face_width_mm * 1e-3,
        addendum: t.addendum,
        dedendum: t.dedendum,
        internal,
        centre_distance: centre,
    }
}

/// What one mesh needs from its stage.
struct MeshSpec<'a> {
    name: String,
    driver: usize,
    driven: usize,
    internal: bool,
    geometry: PairGeometry,
    pair: Pair,
    toothing: &'a desc::Toothing,
    data: desc::MeshData,
    /// Base radius the torsional stiffness is referred to.
    torsional_radius: f64,
    /// Teeth of the wheel whose relative spin gives the roll position, and that wheel.
    roll_body: usize,
    roll_teeth: u32,
    phase: f64,
    hand: f64,
}

impl Gearbox {
    /// Builds the model. Errors name the description field at fault.
    pub fn new(d: &Description) -> Result<Gearbox, String> {
        let mut b = Builder {
            d,
            bodies: Vec::new(),
            springs: Vec::new(),
            bearings: Vec::new(),
            rollers: Vec::new(),
            downwind_plate: None,
            webs: Vec::new(),
            beam_nodes: Vec::new(),
            meshes: Vec::new(),
            geometry: Vec::new(),
            shafts: Vec::new(),
            dofs: 0,
        };
        let density = d.model.density;
        let first_planetary = matches!(d.stages.first(), Some(desc::Stage::Planetary(_)));
        // the rotor turns with the first carrier's frame when that stage is planetary: its index is
        // known before the carrier is added (rotor first, carrier next)
        let mut upstream: Option<(usize, desc::Shaft, String)> = None;
        let mut mesh_specs: Vec<MeshSpec> = Vec::new();
        if let Some(r) = &d.rotor {
            let frame = if first_planetary { Some(1) } else { None };
            let i = b.add_body(
                "rotor".into(),
                BodyKind::Rotor,
                None,
                frame,
                [0.0; 2],
                inertia(r, None, density, "rotor")?,
                false,
            );
            let shaft = r.shaft.ok_or("rotor: give its shaft (the LSS) to the first stage")?;
            upstream = Some((i, shaft, "lss".into()));
        }
        let stages = d.stages.len();
        let mut last_output = 0;
        let mut planetary_count = 0;
        let mut parallel_count = 0;
        for (s, stage) in d.stages.iter().enumerate() {
            let at = |f: &str| format!("stage[{}].{f}", s + 1);
            let (input, output, out_body) = match stage {
                desc::Stage::Planetary(p) => {
                    planetary_count += 1;
                    let suffix = if planetary_count == 1 {
                        String::new()
                    } else {
                        planetary_count.to_string()
                    };
                    let t = &p.toothing;
                    let sp = pair(
                        t,
                        [p.teeth.sun, p.teeth.planet],
                        [p.profile_shift.sun, p.profile_shift.planet],
                        false,
                        p.centre_distance_mm.map(|a| a * 1e-3),
                    );
                    let gsp = sp.geometry().map_err(|e| format!("{}: sun–planet {e}", at("teeth")))?;
                    let a = gsp.centre_distance;
                    let rp = pair(
                        t,
                        [p.teeth.planet, p.teeth.ring],
                        [p.profile_shift.planet, p.profile_shift.ring],
                        true,
                        Some(a),
                    );
                    let grp = rp.geometry().map_err(|e| format!("{}: ring–planet {e}", at("teeth")))?;
                    let w = t.face_width_mm * 1e-3;
                    let carrier_index = b.bodies.len();
                    let carrier_inertia = inertia(&p.carrier, None, density, &at("carrier"))?;
                    let upwind_share = p.carrier_webs.map_or(1.0, |w| 1.0 - w.downwind_share);
                    let share = |s: f64| (carrier_inertia.0 * s, carrier_inertia.1 * s, carrier_inertia.2 * s);
                    let carrier = b.add_body(
                        format!("carrier_{planetary_count}"),
                        BodyKind::Carrier,
                        Some(s),
                        Some(carrier_index),
                        [0.0; 2],
                        share(upwind_share),
                        false,
                    );
                    let plate = p.carrier_webs.map(|w| {
                        let plate = b.add_body(
                            format!("carrier_{planetary_count}_downwind"),
                            BodyKind::Carrier,
                            Some(s),
                            Some(carrier),
                            [0.0; 2],
                            share(w.downwind_share),
                            false,
                        );
                        // the webs' damping from the shaft damping ratio and the plate's own inertia
                        let c = 2.0
                            * b.d.model.shaft_damping_ratio
                            * (w.torsional * carrier_inertia.1 * w.downwind_share).sqrt();
                        let webs = desc::Shaft {
                            torsional: w.torsional,
                            torsional_damping: Some(c),
                            radial: w.radial,
                            axial: w.radial,
                            tilting: w.tilting,
                            beam: None,
                        };
                        b.webs.push(b.shafts.len());
                        b.shafts.push((carrier, plate, webs, format!("carrier_webs{suffix}")));
                        plate
                    });
                    b.downwind_plate = plate.map(|pl| (carrier, pl));
                    b.supports("", carrier, &p.carrier, None, [0.0; 2]);
                    let sun_r = sp.reference_radius(0);
                    let planet_r = sp.reference_radius(1);
                    let planet_inertia = inertia(&p.planet, Some((planet_r, w)), density, &at("planet"))?;
                    let sun_inertia = inertia(&p.sun, Some((sun_r, w)), density, &at("sun"))?;
                    let mut planets = Vec::new();
                    for n in 0..p.planets {
                        let psi = p.first_planet_deg + 360.0 * n as f64 / p.planets as f64;
                        let e = direction(psi);
                        let centre = [a * e[0], a * e[1]];
                        let i = b.add_body(
                            format!("planet_{planetary_count}_{}", n + 1),
                            BodyKind::Planet,
                            Some(s),
                            Some(carrier),
                            centre,
                            planet_inertia,
                            false,
                        );
                        // pin error: tangential, positive ahead in the +spin sense (e_z × e)
                        let err = p.pin_errors_um.get(n).copied().unwrap_or(0.0) * 1e-6;
                        let tangent = [-e[1], e[0]];
                        b.supports(
                            &format!("planet{suffix}_{}", n + 1),
                            i,
                            &p.planet,
                            Some((carrier, centre)),
                            [err * tangent[0], err * tangent[1]],
                        );
                        planets.push((i, psi.to_radians(), e));
                    }
                    b.downwind_plate = None;
                    let sun = b.add_body(
                        format!("sun_{planetary_count}"),
                        BodyKind::Sun,
                        Some(s),
                        Some(carrier),
                        [0.0; 2],
                        sun_inertia,
                        false,
                    );
                    b.supports("", sun, &p.sun, None, [0.0; 2]);
                    let ring = match &p.ring {
                        None => b.add_body(
                            format!("ring_{planetary_count}"),
                            BodyKind::Ring,
                            Some(s),
                            Some(carrier),
                            [0.0; 2],
                            (0.0, 0.0, 0.0),
                            true,
                        ),
                        Some(r) => {
                            let i = b.add_body(
                                format!("ring_{planetary_count}"),
                                BodyKind::Ring,
                                Some(s),
                                Some(carrier),
                                [0.0; 2],
                                inertia(r, None, density, &at("ring"))?,
                                false,
                            );
                            b.supports("", i, r, None, [0.0; 2]);
                            i
                        }
                    };
                    let hand = if t.helix_angle_deg < 0.0 { -1.0 } else { 1.0 };
                    for (n, &(planet, psi, _)) in planets.iter().enumerate() {
                        // in the carrier's frame the ring drives the planets and the planets drive the sun
                        mesh_specs.push(MeshSpec {
                            name: format!("ring_planet{suffix}_{}", n + 1),
                            driver: ring,
                            driven: planet,
                            internal: true,
                            geometry: grp,
                            pair: rp,
                            toothing: t,
                            data: p.ring_planet,
                            torsional_radius: sp.base_radius(0),
                            roll_body: ring,
                            roll_teeth: p.teeth.ring,
                            phase: (-f64::from(p.teeth.ring) * psi / TAU).rem_euclid(1.0),
                            hand,
                        });
                        mesh_specs.push(MeshSpec {
                            name: format!("sun_planet{suffix}_{}", n + 1),
                            driver: planet,
                            driven: sun,
                            internal: false,
                            geometry: gsp,
                            pair: sp,
                            toothing: t,
                            data: p.sun_planet,
                            torsional_radius: sp.base_radius(0),
                            roll_body: sun,
                            roll_teeth: p.teeth.sun,
                            phase: (f64::from(p.teeth.sun) * psi / TAU).rem_euclid(1.0),
                            // the planet meshes the sun and the ring on opposite sides, so the same
                            // planet tooth hand tilts the normal the other way against the carrier's
                            // tangent t (built from driver to driven, which flips between the two
                            // meshes): with `hand` as for the ring, the axial components on a planet
                            // cancel and form the overturning couple of a helical planet
                            hand,
                        });
                    }
                    (carrier, sun, &p.sun)
                }
                desc::Stage::Parallel(p) => {
                    parallel_count += 1;
                    let t = &p.toothing;
                    let gp = pair(
                        t,
                        [p.teeth.pinion, p.teeth.gear],
                        [p.profile_shift.pinion, p.profile_shift.gear],
                        false,
                        p.centre_distance_mm.map(|a| a * 1e-3),
                    );
                    let g = gp.geometry().map_err(|e| format!("{}: {e}", at("teeth")))?;
                    let w = t.face_width_mm * 1e-3;
                    // the gear sits on the axis of the body upstream; the pinion off it
                    let base = match &upstream {
                        Some((u, _, _)) if b.bodies[*u].frame.is_none() => b.bodies[*u].centre,
                        _ => [0.0; 2],
                    };
                    let dir = direction(p.pinion_direction_deg);
                    let gear = b.add_body(
                        format!("gear_{parallel_count}"),
                        BodyKind::Gear,
                        Some(s),
                        None,
                        base,
                        inertia(&p.gear, Some((gp.reference_radius(1), w)), density, &at("gear"))?,
                        false,
                    );
                    b.supports("", gear, &p.gear, None, [0.0; 2]);
                    let centre = [
                        base[0] + g.centre_distance * dir[0],
                        base[1] + g.centre_distance * dir[1],
                    ];
                    let pinion = b.add_body(
                        format!("pinion_{parallel_count}"),
                        BodyKind::Pinion,
                        Some(s),
                        None,
                        centre,
                        inertia(&p.pinion, Some((gp.reference_radius(0), w)), density, &at("pinion"))?,
                        false,
                    );
                    b.supports("", pinion, &p.pinion, None, [0.0; 2]);
                    mesh_specs.push(MeshSpec {
                        name: format!("gear_pinion_{parallel_count}"),
                        driver: gear,
                        driven: pinion,
                        internal: false,
                        geometry: g,
                        pair: gp,
                        toothing: t,
                        data: p.mesh,
                        torsional_radius: gp.base_radius(0),
                        roll_body: pinion,
                        roll_teeth: p.teeth.pinion,
                        phase: 0.0,
                        hand: if t.helix_angle_deg < 0.0 { -1.0 } else { 1.0 },
                    });
                    (gear, pinion, &p.pinion)
                }
            };
            if let Some((u, shaft, name)) = upstream.take() {
                b.shafts.push((u, input, shaft, name));
            }
            last_output = output;
            let name = if s + 1 == stages {
                "hss".to_string()
            } else {
                format!("is{}", s + 1)
            };
            upstream = match out_body.shaft {
                Some(sh) => Some((output, sh, name)),
                None if s + 1 < stages || d.generator.is_some() => {
                    return Err(format!(
                        "{}: give the shaft to the next body",
                        at(if matches!(stage, desc::Stage::Planetary(_)) {
                            "sun"
                        } else {
                            "pinion"
                        })
                    ));
                }
                None => None,
            };
        }
        // the rotor's bearings once the carrier whose frame it turns in exists
        if let Some(r) = &d.rotor {
            b.supports("", 0, r, None, [0.0; 2]);
        }
        if let Some(g) = &d.generator {
            let (u, shaft, name) = upstream.take().ok_or("generator: the last stage has no shaft to it")?;
            let centre = b.bodies[u].centre;
            let frame = b.bodies[u].frame;
            let i = b.add_body(
                "generator".into(),
                BodyKind::Generator,
                None,
                frame,
                centre,
                inertia(g, None, density, "generator")?,
                false,
            );
            b.supports("", i, g, None, [0.0; 2]);
            b.shafts.push((u, i, shaft, name));
            last_output = i;
        }
        add_beam_nodes(&mut b);
        let mut names: Vec<&str> = b.bearings.iter().map(|x| x.name.as_str()).collect();
        names.sort_unstable();
        if let Some(w) = names.windows(2).find(|w| w[0] == w[1]) {
            return Err(format!(
                "two bearings are named {:?}: bearing names must be unique",
                w[0]
            ));
        }
        // The drive flank of each mesh is the one loaded when the input turns forwards under a
        // driving torque: build the rows once, read the kinematics off them (a rigid rotation does
        // not compress a mesh, whichever flank), then orient each line of action so the driver's
        // point moves along it.
        for spec in &mesh_specs {
            add_mesh(&mut b, spec, 1.0)?;
        }
        // the chain's first body (rotor, or the first stage's input) takes the rotor torque
        let input_body = 0;
        let output_body = last_output;
        let rigid = rigid_mode(&b, input_body);
        if let Some(r) = &rigid {
            let meshes = std::mem::take(&mut b.meshes);
            b.geometry.clear();
            for (spec, mesh) in mesh_specs.iter().zip(&meshes) {
                let spin_rel = |body: usize| -> f64 {
                    let own = b.bodies[body].first.map_or(0.0, |f| r[f + SPIN]);
                    own - b.frame_spin(body).map_or(0.0, |f| r[f])
                };
                // the driver's lever (r_A × n)_z times its relative speed is the power it delivers along n
                let coefficient = mesh.driver_arm;
                let sigma = if coefficient * spin_rel(spec.driver) >= 0.0 {
                    1.0
                } else {
                    -1.0
                };
                add_mesh(&mut b, spec, sigma)?;
            }
        }
        let (shafts, mass) = finish(&mut b, &rigid)?;
        let out_spin = b.bodies[output_body].first.map_or(0, |f| f + SPIN);
        let in_spin = b.bodies[input_body].first.map_or(0, |f| f + SPIN);
        let output_sign = rigid.as_ref().map_or(1.0, |r| r[out_spin].signum());
        let gear_ratio = rigid.as_ref().map_or(1.0, |r| r[out_spin].abs());
        let input_loads = vec![
            InputLoad {
                input: INPUT_ROTOR_TORQUE,
                dof: in_spin,
                gain: 1.0,
            },
            InputLoad {
                input: INPUT_GENERATOR_TORQUE,
                dof: out_spin,
                gain: -output_sign,
            },
            // the brake acts through `friction`; listed so the input count is three
            InputLoad {
                input: INPUT_BRAKE_COMMAND,
                dof: out_spin,
                gain: 0.0,
            },
        ];
        let tilt = d.model.shaft_tilt_deg.to_radians();
        let g = d.model.gravity;
        let rated = match (d.rated_power, d.rated_rotor_speed_rpm) {
            (Some(p), Some(rpm)) if rpm > 0.0 => Some(p / (rpm * TAU / 60.0)),
            _ => None,
        };
        // roller sets are nearly linear between contact patterns (their key): not a reason to
        // rebuild the Jacobian at every iterate
        let nonlinear = matches!(d.model.force_law, ForceLaw::Impact { .. });
        let contacts = b
            .geometry
            .iter()
            .zip(&b.meshes)
            .map(|(g, m)| GearContact::new(g, m.face_width, m.slices()))
            .collect();
        Ok(Gearbox {
            name: d.name.clone(),
            bodies: b.bodies,
            springs: b.springs,
            bearings: b.bearings,
            rollers: b.rollers,
            shafts,
            meshes: b.meshes,
            mass,
            input_loads,
            rigid,
            rigid_dof: in_spin,
            gravity: [0.0, -g * tilt.cos(), g * tilt.sin()],
            external_moment: [0.0; 2],
            thrust: 0.0,
            input_body,
            output_body,
            output_sign,
            gear_ratio,
            rated_rotor_torque: rated,
            nonlinear,
            brake: Default::default(),
            contacts,
            geometry: b.geometry,
        })
    }
}

/// The line-of-action rows of a mesh (drive flank oriented by σ), its slices, stiffness and damping.
fn add_mesh(b: &mut Builder, m: &MeshSpec, sigma: f64) -> Result<(), String> {
    let g = &m.geometry;
    let (ca, cb) = (b.bodies[m.driver].centre, b.bodies[m.driven].centre);
    // e: unit vector from the driver's centre to the driven wheel's (for a ring, from the axis out
    // to the planet); t = e_z × e
    let (dx, dy) = (cb[0] - ca[0], cb[1] - ca[1]);
    let len = (dx * dx + dy * dy).sqrt();
    if len <= 0.0 {
        return Err(format!("mesh {}: the wheels' centres coincide", m.name));
    }
    let e = [dx / len, dy / len];
    let t = [-e[1], e[0]];
    // the pitch point from each centre, and the sense in which the contact force pushes the driven
    // wheel off the driver: an external pair's pitch point lies between the centres (wheel 2 of the
    // pair is the driver: the planet of sun–planet, the gear of gear–pinion) and the force separates
    // them; a ring's lies beyond the planet, and it pushes the planet towards the axis
    let (p_driver, p_driven, radial) = if m.internal {
        let (rw_planet, rw_ring) = (g.pitch_radius[0], g.pitch_radius[1]);
        (
            [rw_ring * e[0], rw_ring * e[1]],
            [rw_planet * e[0], rw_planet * e[1]],
            -1.0,
        )
    } else {
        let (rw_driven, rw_driver) = (g.pitch_radius[0], g.pitch_radius[1]);
        (
            [rw_driver * e[0], rw_driver * e[1]],
            [-rw_driven * e[0], -rw_driven * e[1]],
            1.0,
        )
    };
    let (sa, ca_) = g.pressure_angle.sin_cos();
    let (sb, cbb) = g.base_helix.sin_cos();
    // the 3-D normal in the plane of action: transverse line of action (tangential part oriented by
    // σ and the flank, radial part separating) inclined by the base helix angle; the axial thrust
    // turns with the tangential force
    let build = |flank: f64| -> [f64; 3] {
        let nt = [
            flank * sigma * ca_ * t[0] + radial * sa * e[0],
            flank * sigma * ca_ * t[1] + radial * sa * e[1],
        ];
        [cbb * nt[0], cbb * nt[1], flank * sigma * m.hand * sb]
    };
    let driver_arm = cross([p_driver[0], p_driver[1], 0.0], build(1.0))[2];
    let mut drive = [Row::default(), Row::default()];
    let mut back = [Row::default(), Row::default()];
    for (rows, flank) in [(&mut drive, 1.0), (&mut back, -1.0)] {
        let n = build(flank);
        b.point(&mut rows[0], m.driver, [p_driver[0], p_driver[1], 0.0], n, 1.0);
        b.point(&mut rows[0], m.driven, [p_driven[0], p_driven[1], 0.0], n, -1.0);
        b.lever(&mut rows[1], m.driver, n, 1.0);
        b.lever(&mut rows[1], m.driven, n, -1.0);
        rows[0].compact();
        rows[1].compact();
    }
    let settings = &b.d.model;
    let w = m.toothing.face_width_mm * 1e-3;
    let slices = settings.slices;
    let zeta: Vec<f64> = (0..slices)
        .map(|j| -0.5 * w + (j as f64 + 0.5) * w / slices as f64)
        .collect();
    let crown = m.toothing.crowning_um * 1e-6;
    let slope = m.toothing.lead_slope_um * 1e-6;
    let relief = |z: f64| -crown * (2.0 * z / w).powi(2);
    let error: Vec<f64> = zeta.iter().map(|&z| relief(z) + slope * z / w).collect();
    let error_back: Vec<f64> = zeta.iter().map(|&z| relief(z) - slope * z / w).collect();
    // mean normal stiffness of the whole mesh
    let arm = m.torsional_radius * cbb;
    let k_total = match (m.data.stiffness, m.data.torsional_stiffness) {
        (Some(k), _) => k,
        (None, Some(kt)) => kt / (arm * arm),
        (None, None) => m.pair.iso_stiffness(g.contact_ratio).1 * w,
    };
    // equivalent masses along the line of action for the damping ratio
    let along = |i: usize, r_point: [f64; 2]| -> f64 {
        let body = &b.bodies[i];
        if body.first.is_none() {
            return f64::INFINITY;
        }
        let r = (r_point[0] * r_point[0] + r_point[1] * r_point[1]).sqrt();
        let rb = r * ca_ * cbb;
        body.polar / (rb * rb).max(1e-300)
    };
    let m_eq = 1.0 / (1.0 / along(m.driver, p_driver) + 1.0 / along(m.driven, p_driven));
    let c_total = match (m.data.damping, m.data.torsional_damping) {
        (Some(c), _) => c,
        (None, Some(ct)) => ct / (arm * arm),
        (None, None) => 2.0 * settings.mesh_damping_ratio * (k_total * m_eq).sqrt(),
    };
    let law = match settings.force_law {
        ForceLaw::Linear => Law::Linear,
        ForceLaw::Impact { exponent, penetration } => Law::Impact { exponent, penetration },
    };
    let phase = match settings.mesh_stiffness {
        MeshStiffnessModel::Mean => None,
        MeshStiffnessModel::Varying => {
            let mut roll = Row::default();
            if let Some(f) = b.bodies[m.roll_body].first {
                roll.add(f + SPIN, 1.0);
            }
            if let Some(fs) = b.frame_spin(m.roll_body) {
                roll.add(fs, -1.0);
            }
            roll.compact();
            Some(Phase {
                roll,
                teeth: f64::from(m.roll_teeth),
                offset: m.phase,
                stagger: g.base_helix.tan() / g.base_pitch,
                contact_ratio: g.contact_ratio,
            })
        }
    };
    b.meshes.push(Mesh {
        name: m.name.clone(),
        drive,
        back,
        zeta,
        error,
        error_back,
        k_slice: k_total / slices as f64,
        c_slice: c_total / slices as f64,
        backlash: m.toothing.backlash_um * 1e-6,
        law,
        phase,
        face_width: w,
        driver_arm,
    });
    b.geometry.push(*g);
    Ok(())
}

/// Spins of the free chain when the input turns one radian: the kinematic ratios read off the mesh
/// rows (a rigid rotation compresses no mesh) and shafts; a spin held to the housing by a rotational
/// support (an elastically mounted ring) stays at 0. None when the chain is not free (the input is
/// held, or a held spin contradicts the kinematics).
fn rigid_mode(b: &Builder, input: usize) -> Option<Vec<f64>> {
    let n = b.dofs;
    let mut r = vec![f64::NAN; n];
    for body in &b.bodies {
        if let Some(f) = body.first {
            r[f..f + SPIN].iter_mut().for_each(|x| *x = 0.0);
        }
    }
    let held: Vec<usize> = b
        .springs
        .iter()
        .filter(|s| {
            s.stiffness > 0.0
                && s.row.idx.len() == 1
                && b.bodies.iter().any(|x| x.first.map(|f| f + SPIN) == Some(s.row.idx[0]))
        })
        .map(|s| s.row.idx[0])
        .collect();
    for &h in &held {
        r[h] = 0.0;
    }
    let start = b.bodies[input].first? + SPIN;
    if held.contains(&start) {
        return None;
    }
    r[start] = 1.0;
    // a shaft's nodes turn with its upstream end
    let links: Vec<(usize, usize)> = b
        .shafts
        .iter()
        .map(|&(u, d, _, _)| (u, d))
        .chain(
            b.shafts
                .iter()
                .zip(&b.beam_nodes)
                .flat_map(|(&(u, _, _, _), nodes)| nodes.iter().map(move |&k| (u, k))),
        )
        .collect();
    for _ in 0..4 * b.bodies.len() + 4 {
        let mut changed = false;
        for &(u, d) in &links {
            let (fu, fd) = (b.bodies[u].first? + SPIN, b.bodies[d].first? + SPIN);
            if r[fu].is_nan() != r[fd].is_nan() {
                let v = if r[fu].is_nan() { r[fd] } else { r[fu] };
                r[fu] = v;
                r[fd] = v;
                changed = true;
            }
        }
        for m in &b.meshes {
            let row = &m.drive[0];
            let unknown: Vec<usize> = (0..row.idx.len()).filter(|&k| r[row.idx[k]].is_nan()).collect();
            if let [k] = unknown[..] {
                let known: f64 = (0..row.idx.len())
                    .filter(|&i| i != k)
                    .map(|i| row.val[i] * r[row.idx[i]])
                    .sum();
                r[row.idx[k]] = -known / row.val[k];
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    if r.iter().any(|x| x.is_nan()) {
        return None;
    }
    // every mesh and shaft must be blind to it
    let scale = r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let consistent = b.meshes.iter().all(|m| {
        let g = m.drive[0].dot(&r);
        let size: f64 = m.drive[0].val.iter().map(|v| v.abs()).sum::<f64>() * scale;
        g.abs() <= 1e-9 * size
    });
    consistent.then_some(r)
}

/// Area, second moment of area and shear coefficient of a beam's section; Poisson's ratio from E and G.
fn section(beam: &desc::Beam) -> (f64, f64, f64) {
    beam::hollow_section(
        beam.outer_diameter_mm * 1e-3,
        beam.inner_diameter_mm * 1e-3,
        beam.youngs_modulus / (2.0 * beam.shear_modulus) - 1.0,
    )
}

/// Nodes between the elements of every beam of two or more elements, evenly along its free length,
/// on the axis of the body upstream and in its frame. A lumped-mass beam: each node carries one
/// element's mass ρAL/n and its section's rotary inertia, ρIL/n about a diameter and 2ρIL/n about
/// the axis; the half-elements at the two ends belong to the bodies the shaft joins (their described
/// masses).
fn add_beam_nodes(b: &mut Builder) {
    let density = b.d.model.density;
    for index in 0..b.shafts.len() {
        let (u, _, spec, name) = b.shafts[index].clone();
        let Some(beam) = spec.beam.filter(|beam| beam.elements > 1) else {
            b.beam_nodes.push(Vec::new());
            continue;
        };
        let (area, second_moment, _) = section(&beam);
        let element = beam.length_m / f64::from(beam.elements);
        let inertia = (
            density * area * element,
            2.0 * density * second_moment * element,
            density * second_moment * element,
        );
        let (frame, centre) = (b.bodies[u].frame, b.bodies[u].centre);
        let nodes = (1..beam.elements)
            .map(|k| {
                b.add_body(
                    format!("{name}_node_{k}"),
                    BodyKind::ShaftNode,
                    None,
                    frame,
                    centre,
                    inertia,
                    false,
                )
            })
            .collect();
        b.beam_nodes.push(nodes);
    }
}

/// One Timoshenko element of a flexible shaft, `length` long, from body `ends[0].0` (leaving it at
/// `ends[0].1` along the axis from its centre) to body `ends[1].0` (entering at `ends[1].1`): its
/// bending in the x–z plane (w = u_x, φ = θ_y) and the y–z plane (w = u_y, φ = −θ_x, as
/// du_y/dz = −θ_x), and its axial stretch, as springs on the ends' rows.
fn beam_springs(b: &mut Builder, ends: [(usize, f64); 2], beam: &desc::Beam, length: f64, tau: f64) {
    let (e, g) = (beam.youngs_modulus, beam.shear_modulus);
    let (area, second_moment, kappa) = section(beam);
    let k = beam::bending_stiffness(e * second_moment, kappa * g * area, length);
    let translation = |b: &Builder, (body, z): (usize, f64), n: [f64; 3]| {
        let mut row = Row::default();
        b.point(&mut row, body, [0.0, 0.0, z], n, 1.0);
        row
    };
    let tilt = |b: &Builder, body: usize, dof: usize, sign: f64| {
        let mut row = Row::default();
        if let Some(f) = b.bodies[body].first {
            row.add(f + dof, sign);
        }
        row
    };
    for (n, dof, sign) in [([1.0, 0.0, 0.0], TY, 1.0), ([0.0, 1.0, 0.0], TX, -1.0)] {
        let rows = [
            translation(b, ends[0], n),
            tilt(b, ends[0].0, dof, sign),
            translation(b, ends[1], n),
            tilt(b, ends[1].0, dof, sign),
        ];
        for (stiffness, v) in beam::springs(&k) {
            let mut row = Row::default();
            for (r, c) in rows.iter().zip(v) {
                for (&i, x) in r.idx.iter().zip(&r.val) {
                    row.add(i, c * x);
                }
            }
            row.compact();
            b.spring(row, stiffness, stiffness * tau, 0.0);
        }
    }
    let axial = e * area / length;
    let mut row = translation(b, ends[0], [0.0, 0.0, 1.0]);
    let downstream = translation(b, ends[1], [0.0, 0.0, 1.0]);
    for (&i, x) in downstream.idx.iter().zip(&downstream.val) {
        row.add(i, -x);
    }
    row.compact();
    b.spring(row, axial, axial * tau, 0.0);
}

/// Shaft springs (with damping from the shaft ratio and the inertia on either side) and the mass matrix.
fn finish(b: &mut Builder, rigid: &Option<Vec<f64>>) -> Result<(Vec<ShaftSpring>, DMatrix<f64>), String> {
    let n = b.dofs;
    let mut shafts = Vec::new();
    let spin_ratio = |b: &Builder, i: usize| -> f64 {
        match (rigid, b.bodies[i].first) {
            (Some(r), Some(f)) => r[f + SPIN],
            _ => 1.0,
        }
    };
    let shaft_list = b.shafts.clone();
    for (index, (u, d, spec, name)) in shaft_list.into_iter().enumerate() {
        let same_frame = b.bodies[u].frame == b.bodies[d].frame;
        if !same_frame && (spec.radial > 0.0 || spec.tilting > 0.0 || spec.beam.is_some()) {
            return Err(format!(
                "shaft {name} ({} → {}): radial or tilting stiffness joins bodies in different rotating frames; \
                 only a spline (torsional, axial) can join them",
                b.bodies[u].name, b.bodies[d].name
            ));
        }
        let ratio = spin_ratio(b, d);
        let inertia_side = |up: bool| -> f64 {
            b.bodies
                .iter()
                .enumerate()
                .filter(|(i, body)| {
                    body.first.is_some() && body.kind != BodyKind::ShaftNode && if up { *i <= u } else { *i >= d }
                })
                .map(|(i, body)| body.polar * (spin_ratio(b, i) / ratio).powi(2))
                .sum()
        };
        let (ju, jd) = (inertia_side(true), inertia_side(false));
        let j_eq = ju * jd / (ju + jd);
        let c = spec
            .torsional_damping
            .unwrap_or(2.0 * b.d.model.shaft_damping_ratio * (spec.torsional * j_eq).sqrt());
        let (fu, fd) = (
            b.bodies[u].first.ok_or("shaft from the housing")?,
            b.bodies[d].first.ok_or("shaft to the housing")?,
        );
        // a beam of n elements: n torsion springs in series, each n times as stiff and as damped as
        // the shaft, the first (at the upstream end) reporting the shaft's torque
        let nodes = b.beam_nodes[index].clone();
        // spin DOFs along the chain: the ends' checked above, a node's always its own
        let spins: Vec<usize> = std::iter::once(fu)
            .chain(nodes.iter().filter_map(|&k| b.bodies[k].first))
            .chain(std::iter::once(fd))
            .map(|f| f + SPIN)
            .collect();
        let elements = (spins.len() - 1) as f64;
        let first_torsion = b.springs.len();
        for pair in spins.windows(2) {
            let mut torsion = Row::default();
            torsion.add(pair[0], 1.0);
            torsion.add(pair[1], -1.0);
            b.spring(torsion, elements * spec.torsional, elements * c, 0.0);
        }
        if !b.webs.contains(&index) {
            shafts.push(ShaftSpring {
                name: name.clone(),
                spring: first_torsion,
                sign: ratio.signum(),
            });
        }
        let tau = b.d.model.bearing_damping_time;
        if let Some(beam) = &spec.beam {
            let chain: Vec<usize> = std::iter::once(u).chain(nodes).chain(std::iter::once(d)).collect();
            let length = beam.length_m / elements;
            let last = chain.len() - 2;
            for (k, pair) in chain.windows(2).enumerate() {
                let from = if k == 0 { beam.from_m } else { 0.0 };
                let to = if k == last { beam.to_m } else { 0.0 };
                beam_springs(b, [(pair[0], from), (pair[1], to)], beam, length, tau);
            }
        }
        for (k, stiffness) in [
            (UX, spec.radial),
            (UY, spec.radial),
            (UZ, spec.axial),
            (TX, spec.tilting),
            (TY, spec.tilting),
        ] {
            if stiffness > 0.0 {
                let mut row = Row::default();
                row.add(fu + k, 1.0);
                row.add(fd + k, -1.0);
                b.spring(row, stiffness, stiffness * tau, 0.0);
            }
        }
    }
    // mass: six diagonal terms per body plus a planet's orbit coupled to its carrier's spin
    let mut m = DMatrix::zeros(n, n);
    for body in &b.bodies {
        let Some(f) = body.first else { continue };
        for k in 0..3 {
            m[(f + k, f + k)] = body.mass;
        }
        m[(f + TX, f + TX)] = body.transverse;
        m[(f + TY, f + TY)] = body.transverse;
        m[(f + SPIN, f + SPIN)] = body.polar;
        if let Some(c) = body.frame
            && let Some(fc) = b.bodies[c].first
        {
            let p = body.centre;
            let jp = [-p[1], p[0]];
            for (k, v) in [(UX, jp[0]), (UY, jp[1])] {
                m[(f + k, fc + SPIN)] += body.mass * v;
                m[(fc + SPIN, f + k)] += body.mass * v;
            }
            m[(fc + SPIN, fc + SPIN)] += body.mass * (p[0] * p[0] + p[1] * p[1]);
        }
    }
    Ok((shafts, m))
}
