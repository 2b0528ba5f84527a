//! The gearbox under assembly: bodies and their DOFs, force rows, springs, bearings and supports as
//! they are added, and the helpers the stages share (inertia of a body, a direction, a gear pair).

use crate::physics::gearbox::bearing::{Mounting, RollerBearing};
use crate::physics::gearbox::description::{self as desc, BearingModel, Description};
use crate::physics::gearbox::involute::{Pair, PairGeometry};
use crate::physics::gearbox::mesh::Mesh;
use crate::physics::gearbox::model::{BearingSprings, Body, BodyKind, SPIN, Spring, TX, TY, UX, UY, UZ};
use crate::physics::gearbox::roller_table::RollerTables;
use crate::physics::gearbox::row::Row;
use std::f64::consts::PI;

/// Builder state: bodies and elements as they are added.
pub(super) struct Builder<'a> {
    pub(super) d: &'a Description,
    pub(super) bodies: Vec<Body>,
    pub(super) springs: Vec<Spring>,
    pub(super) bearings: Vec<BearingSprings>,
    pub(super) rollers: Vec<RollerBearing>,
    /// The lamina law's tables (`bearings = "lamina-table"`), shared by the roller sets.
    pub(super) tables: RollerTables,
    pub(super) meshes: Vec<Mesh>,
    pub(super) geometry: Vec<PairGeometry>,
    /// (upstream body, downstream body, shaft spec, name)
    pub(super) shafts: Vec<(usize, usize, desc::Shaft, String)>,
    /// (carrier, its downwind plate) while a planetary stage with carrier webs is built: bearings
    /// downwind of the centre of the carrier or a planet sit in the plate.
    pub(super) downwind_plate: Option<(usize, usize)>,
    /// Entries of `shafts` that are carrier webs: springs like a shaft's, not reported as one.
    pub(super) webs: Vec<usize>,
    /// Per entry of `shafts`, the nodes of its beam from upstream to downstream (none for springs
    /// or a beam of one element); filled once every shaft is listed.
    pub(super) beam_nodes: Vec<Vec<usize>>,
    pub(super) dofs: usize,
}

pub(super) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

impl Builder<'_> {
    #[allow(clippy::too_many_arguments)]
    pub(super) fn add_body(
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

    pub(super) fn frame_spin(&self, b: usize) -> Option<usize> {
        self.bodies[b]
            .frame
            .and_then(|c| self.bodies[c].first.map(|f| f + SPIN))
    }

    /// Adds sign·n·d(P) to `row`: the displacement of body b's point at r (from its centre, in its
    /// frame) along n, with its spin measured relative to its frame.
    pub(super) fn point(&self, row: &mut Row, b: usize, r: [f64; 3], n: [f64; 3], sign: f64) {
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
    pub(super) fn lever(&self, row: &mut Row, b: usize, n: [f64; 3], sign: f64) {
        if let Some(f) = self.bodies[b].first {
            row.add(f + TX, -sign * n[1]);
            row.add(f + TY, sign * n[0]);
        }
    }

    pub(super) fn spring(&mut self, row: Row, k: f64, c: f64, offset: f64) -> usize {
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
    pub(super) fn bearing(
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
        let lamina = self.d.model.bearings != BearingModel::Linear;
        let tabulated = self.d.model.bearings == BearingModel::LaminaTable;
        let rollers = rollers.filter(|_| lamina).map(|r| {
            let angled = r.contact_angle_deg != 0.0;
            for dir in [UX, UY, UZ, TX, TY] {
                if dir != UZ || angled {
                    self.springs[idx[dir]].lamina = true;
                }
            }
            let mounting = self.mounting(b, other, idx, r, error);
            self.rollers.push(RollerBearing::new(
                r,
                mounting,
                self.d.model.bearing_damping_time,
                tabulated.then_some(&mut self.tables),
            ));
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
    pub(super) fn mounting(
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
            row.scale(sign);
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
    pub(super) fn supports(
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
pub(super) fn inertia(
    b: &desc::Body,
    gear: Option<(f64, f64)>,
    density: f64,
    at: &str,
) -> Result<(f64, f64, f64), String> {
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
pub(super) fn direction(deg: f64) -> [f64; 2] {
    let a = deg.to_radians();
    [a.sin(), a.cos()]
}

/// The toothing of a stage as an involute pair (wheel 1, wheel 2).
pub(super) fn pair(t: &desc::Toothing, teeth: [u32; 2], shift: [f64; 2], internal: bool, centre: Option<f64>) -> Pair {
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
pub(super) struct MeshSpec<'a> {
    pub(super) name: String,
    pub(super) driver: usize,
    pub(super) driven: usize,
    pub(super) internal: bool,
    pub(super) geometry: PairGeometry,
    pub(super) pair: Pair,
    pub(super) toothing: &'a desc::Toothing,
    pub(super) data: desc::MeshData,
    /// Base radius the torsional stiffness is referred to.
    pub(super) torsional_radius: f64,
    /// Teeth of the wheel whose relative spin gives the roll position, and that wheel.
    pub(super) roll_body: usize,
    pub(super) roll_teeth: u32,
    pub(super) phase: f64,
    pub(super) hand: f64,
}
