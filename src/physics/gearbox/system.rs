//! The gearbox as a [`SecondOrderSystem`]: forces, tangent and contact pattern for the integrators,
//! and the engaged-mesh linearisation for modal analysis.

use super::bearing::{RollerLoads, SetMemory};
use super::mesh::{FlankLoad, KeyBits};
use super::model::{Gearbox, INPUT_BRAKE_COMMAND, SPIN, TX, TY, UX, UY, UZ};
use super::row::add_outer;
use crate::solver::system::{Friction, InputLoad, Linearisation, Linearity, Mass, SecondOrderSystem};
use nalgebra::DMatrix;

/// How an evaluation of f_int takes the roller sets' forces.
pub(super) enum Sets<'a> {
    /// Each set evaluated exactly.
    Exact,
    /// Exactly, each set's loads (its largest lamina load included) written to its entry.
    Reported(&'a mut [RollerLoads]),
    /// From each set's own tangent while its laminae are within the distance (m) of its last exact
    /// evaluation, which each entry keeps ([`super::bearing::RollerBearing::add_forces_near`]).
    Near(&'a mut [SetMemory], f64),
}

impl Gearbox {
    /// Springs' forces (bearings, shafts) and the roller sets' into `out` (added), the roller sets'
    /// as `sets` asks.
    #[inline(always)]
    fn add_spring_forces(&self, q: &[f64], v: &[f64], out: &mut [f64], sets: Sets<'_>) {
        for s in self.springs.iter().filter(|s| !s.lamina) {
            let f = s.force(q, v);
            if f != 0.0 {
                s.row.axpy(f, out);
            }
        }
        match sets {
            Sets::Exact => {
                for r in &self.rollers {
                    r.add_forces(q, v, false, out);
                }
            }
            Sets::Reported(loads) => {
                for (r, l) in self.rollers.iter().zip(loads) {
                    *l = r.add_forces(q, v, true, out);
                }
            }
            Sets::Near(tangents, distance) => {
                for (r, near) in self.rollers.iter().zip(tangents) {
                    r.add_forces_near(q, v, distance, near, out);
                }
            }
        }
    }

    /// The rotating frames' inertial forces, gyroscopic moments and gravity, added to f_int (they sit
    /// on the left-hand side: loads enter negated).
    #[inline(always)]
    fn add_frame_forces(&self, q: &[f64], v: &[f64], out: &mut [f64]) {
        for (i, b) in self.bodies.iter().enumerate() {
            let Some(f) = b.first else { continue };
            let (omega_f, angle) = match self.frame_spin(i) {
                Some(fs) => (v[fs], q[fs]),
                None => (0.0, 0.0),
            };
            let spin = v[f + SPIN];
            if omega_f != 0.0 {
                let (m, p) = (b.mass, [b.centre[0] + q[f + UX], b.centre[1] + q[f + UY]]);
                let (ux, uy) = (v[f + UX], v[f + UY]);
                // m(2Ω J u̇ − Ω² p); J u̇ = (−u̇_y, u̇_x)
                out[f + UX] += m * (-2.0 * omega_f * uy - omega_f * omega_f * p[0]);
                out[f + UY] += m * (2.0 * omega_f * ux - omega_f * omega_f * p[1]);
                // the frame's spin equation: d/dt of the orbit's angular momentum, 2mΩ p·u̇
                if let Some(fs) = self.frame_spin(i) {
                    out[fs] += 2.0 * m * omega_f * (p[0] * ux + p[1] * uy);
                }
            }
            // tilt: (2 I_t Ω − I_p ω) J θ̇ + (I_p ω Ω − I_t Ω²) θ
            let (it, ip) = (b.transverse, b.polar);
            let gyro = 2.0 * it * omega_f - ip * spin;
            let stiff = ip * spin * omega_f - it * omega_f * omega_f;
            out[f + TX] += -gyro * v[f + TY] + stiff * q[f + TX];
            out[f + TY] += gyro * v[f + TX] + stiff * q[f + TY];
            // gravity, turned into the body's frame
            let (s, c) = angle.sin_cos();
            let g = self.gravity;
            if g != [0.0; 3] {
                out[f + UX] -= b.mass * (c * g[0] + s * g[1]);
                out[f + UY] -= b.mass * (-s * g[0] + c * g[1]);
                out[f + UZ] -= b.mass * g[2];
            }
        }
    }

    /// The rotor's moment and thrust on the input body, turned into its frame, added to f_int
    /// (negated): the only part of f_int that follows the inputs the owner sets each communication
    /// step rather than the state. [`Self::forces`] adds it last, so the state's part
    /// ([`Self::state_forces`]) plus this is f_int to the bit; the gearbox FMU takes it off the forces a
    /// step leaves for the next and adds that step's own. (It used to be added with
    /// the input body's frame forces; no mesh acts on the presets' input bodies, so the move changed
    /// no output.)
    pub fn add_rotor_loads(&self, q: &[f64], out: &mut [f64]) {
        let Some(f) = self.bodies[self.input_body].first else {
            return;
        };
        let angle = self.frame_spin(self.input_body).map_or(0.0, |fs| q[fs]);
        let (s, c) = angle.sin_cos();
        let mo = self.external_moment;
        out[f + TX] -= c * mo[0] + s * mo[1];
        out[f + TY] -= -s * mo[0] + c * mo[1];
        out[f + UZ] -= self.thrust;
    }

    /// f_int less the rotor's loads ([`Self::add_rotor_loads`]) into `out`, the roller sets' as `sets`
    /// asks, handing each mesh's flank loads to `each_mesh` and, when given,
    /// writing the per-slice loads of every mesh to `slices` (mesh after mesh).
    pub(super) fn state_forces(
        &self,
        q: &[f64],
        v: &[f64],
        out: &mut [f64],
        slices: Option<&mut [f64]>,
        sets: Sets<'_>,
        each_mesh: impl FnMut([FlankLoad; 2]),
    ) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx") {
            // SAFETY: the CPU has AVX.
            return unsafe { self.state_forces_avx(q, v, out, slices, sets, each_mesh) };
        }
        self.state_forces_by(q, v, out, slices, sets, each_mesh)
    }

    /// [`Self::state_forces`] compiled for AVX: the roller sets' and meshes' loops on four values a
    /// register where the compiler vectorises them, with the same operations on each value (no fused
    /// multiply–adds), so the same bits as the baseline build.
    ///
    /// # Safety
    /// The CPU has AVX.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn state_forces_avx(
        &self,
        q: &[f64],
        v: &[f64],
        out: &mut [f64],
        slices: Option<&mut [f64]>,
        sets: Sets<'_>,
        each_mesh: impl FnMut([FlankLoad; 2]),
    ) {
        self.state_forces_by(q, v, out, slices, sets, each_mesh)
    }

    #[inline(always)]
    fn state_forces_by(
        &self,
        q: &[f64],
        v: &[f64],
        out: &mut [f64],
        slices: Option<&mut [f64]>,
        sets: Sets<'_>,
        each_mesh: impl FnMut([FlankLoad; 2]),
    ) {
        out.iter_mut().for_each(|x| *x = 0.0);
        self.add_spring_forces(q, v, out, sets);
        self.add_frame_forces(q, v, out);
        self.add_mesh_forces(q, v, out, slices, each_mesh);
    }

    /// f_int into `out`, handing each mesh's flank loads to `each` and, when given, writing the
    /// per-slice loads of every mesh to `slices` (mesh after mesh).
    fn forces(
        &self,
        q: &[f64],
        v: &[f64],
        out: &mut [f64],
        slices: Option<&mut [f64]>,
        each: impl FnMut([FlankLoad; 2]),
    ) {
        self.state_forces(q, v, out, slices, Sets::Exact, each);
        self.add_rotor_loads(q, out);
    }

    /// The meshes' part of f_int added to `out`, each mesh's flank loads handed to `each` and,
    /// when given, the per-slice loads written to `slices` (mesh after mesh).
    #[inline(always)]
    fn add_mesh_forces(
        &self,
        q: &[f64],
        v: &[f64],
        out: &mut [f64],
        mut slices: Option<&mut [f64]>,
        mut each: impl FnMut([FlankLoad; 2]),
    ) {
        let mut at = 0;
        for m in &self.meshes {
            let n = m.slices();
            each(m.add_forces(q, v, out, slices.as_deref_mut().map(|s| &mut s[at..at + n])));
            at += n;
        }
    }

    /// Internal forces with the per-slice loads of every mesh written to `slices` (mesh after mesh).
    pub fn forces_with_slices(&self, q: &[f64], v: &[f64], out: &mut [f64], slices: &mut [f64]) -> Vec<[FlankLoad; 2]> {
        let mut loads = Vec::with_capacity(self.meshes.len());
        self.forces(q, v, out, Some(slices), |l| loads.push(l));
        loads
    }

    /// Every mesh's flank loads, its per-slice loads written to `slices`, without the springs',
    /// roller sets' and frames' forces: what a study of the meshes alone needs.
    pub fn mesh_loads(&self, q: &[f64], v: &[f64], slices: &mut [f64]) -> Vec<[FlankLoad; 2]> {
        let mut loads = Vec::with_capacity(self.meshes.len());
        self.add_mesh_forces(q, v, &mut vec![0.0; self.dofs()], Some(slices), |l| loads.push(l));
        loads
    }

    pub fn slice_count(&self) -> usize {
        self.meshes.iter().map(|m| m.slices()).sum()
    }

    /// c_c·C + c_k·K of the springs (constant); `modal` keeps the linear springs of the directions
    /// roller sets carry in the dynamics.
    fn add_spring_tangent(&self, c_c: f64, c_k: f64, modal: bool, j: &mut DMatrix<f64>) {
        for s in self.springs.iter().filter(|s| modal || !s.lamina) {
            add_outer(j, c_k * s.stiffness + c_c * s.damping, &s.row, &s.row);
        }
    }

    /// The linearisation with every mesh engaged on its drive flank at mean stiffness (no errors,
    /// no backlash) and every bearing at its description's linear stiffness (roller sets in
    /// clearance have none at rest): what modal analysis of a gearbox means. Speeds are zero (no
    /// gyroscopics).
    pub fn engaged_linearisation(&self) -> Linearisation {
        let n = self.dofs();
        let mut k = DMatrix::zeros(n, n);
        let mut c = DMatrix::zeros(n, n);
        self.add_spring_tangent(0.0, 1.0, true, &mut k);
        self.add_spring_tangent(1.0, 0.0, true, &mut c);
        for m in &self.meshes {
            let (s0, s1, s2) = m
                .zeta
                .iter()
                .fold((0.0, 0.0, 0.0), |(a, b, cc), &z| (a + 1.0, b + z, cc + z * z));
            for (mat, per) in [(&mut k, m.k_slice), (&mut c, m.c_slice)] {
                add_outer(mat, per * s0, &m.drive[0], &m.drive[0]);
                add_outer(mat, per * s1, &m.drive[0], &m.drive[1]);
                add_outer(mat, per * s1, &m.drive[1], &m.drive[0]);
                add_outer(mat, per * s2, &m.drive[1], &m.drive[1]);
            }
        }
        Linearisation {
            mass: self.mass.clone(),
            damping: c,
            stiffness: k,
        }
    }
}

impl SecondOrderSystem for Gearbox {
    fn dofs(&self) -> usize {
        self.mass.nrows()
    }

    fn linearity(&self) -> Linearity {
        if self.nonlinear {
            Linearity::Nonlinear
        } else {
            Linearity::NearlyPiecewiseLinear
        }
    }

    fn mass(&self) -> Mass<'_> {
        Mass::Sparse(&self.mass, &self.mass_entries)
    }

    fn input_loads(&self) -> &[InputLoad] {
        &self.input_loads
    }

    fn internal_forces(&self, _t: f64, q: &[f64], v: &[f64], out: &mut [f64]) {
        self.forces(q, v, out, None, |_| {});
    }

    fn add_tangent(&self, _t: f64, q: &[f64], v: &[f64], c_c: f64, c_k: f64, j: &mut DMatrix<f64>) {
        self.add_spring_tangent(c_c, c_k, false, j);
        for r in &self.rollers {
            r.add_tangent(q, v, c_c, c_k, j);
        }
        for m in &self.meshes {
            m.add_tangent(q, v, c_c, c_k, j);
        }
    }

    fn factor_key(&self, _t: f64, q: &[f64], key: &mut Vec<u64>) {
        let mut bits = KeyBits::new(key);
        for m in &self.meshes {
            m.key(q, &mut bits);
        }
        for r in &self.rollers {
            r.key(q, &mut bits);
        }
        bits.finish();
    }

    fn friction(&self, u: &[f64]) -> Option<Friction> {
        let dof = self.dof(self.output_body, SPIN)?;
        self.brake.friction(dof, u[INPUT_BRAKE_COMMAND])
    }

    fn rigid_mode(&self) -> Option<(&[f64], usize)> {
        self.rigid.as_deref().map(|r| (r, self.rigid_dof))
    }
}
