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

use super::bearing::RollerBearing;
use super::contact::GearContact;
use super::description::{self as desc};
use super::involute::PairGeometry;
use super::mesh::Mesh;
use super::row::Row;
use crate::solver::system::{InputLoad, SparseColumns};
use nalgebra::DMatrix;

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
        let (deflection, rate) = self.row.dot2(q, v);
        self.stiffness * (deflection - self.offset) + self.damping * rate
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
    /// Its nonzero entries (six a body and the planets' orbit couplings), which the integrators'
    /// products and solves visit instead of all of it.
    pub(super) mass_entries: SparseColumns,
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
