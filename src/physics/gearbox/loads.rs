//! What a gearbox run reports: mesh loads, bearing loads, shaft torques, load sharing.

use super::bearing::{RaceStresses, RollerBearing, RollerLoads};
use super::mesh::{FlankLoad, MeshReport};
use super::model::{Gearbox, SPIN, TX, TY};
use super::system::Sets;

/// Loads of one bearing, in the frame it sits in.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BearingLoad {
    /// √(F_x² + F_y²), N.
    pub radial: f64,
    /// Along the shaft axis, N.
    pub axial: f64,
    /// √(M_x² + M_y²), N·m.
    pub tilting: f64,
    /// Roller sets only (zeros for a linear bearing): rollers carrying load, the largest roller
    /// load (N), and the contact stresses of the most loaded lamina.
    pub rollers_in_contact: usize,
    pub max_roller_load: f64,
    pub stresses: RaceStresses,
}

#[derive(Debug, Clone, Default, PartialEq)]
pub struct Loads {
    pub meshes: Vec<MeshReport>,
    pub bearings: Vec<BearingLoad>,
    /// Torsion of each shaft (lss, is1, …, hss), positive in normal operation, N·m.
    pub shafts: Vec<f64>,
    /// Per-slice loads of every mesh, one after another (drive positive).
    pub slices: Vec<f64>,
}

impl Gearbox {
    /// Every reported load at (q, v), from one evaluation of the forces with every mesh's slices and
    /// every roller set's loads.
    pub fn loads(&self, q: &[f64], v: &[f64]) -> Loads {
        let mut slices = vec![0.0; self.slice_count()];
        let mut sets = vec![RollerLoads::default(); self.rollers.len()];
        let mut flanks = Vec::with_capacity(self.meshes.len());
        // f_int itself is not reported (the FMU's steps leave it by their equation of motion)
        let mut forces = vec![0.0; self.dofs()];
        self.state_forces(q, v, &mut forces, Some(&mut slices), Sets::Reported(&mut sets), |l| {
            flanks.push(l)
        });
        Loads {
            meshes: flanks
                .iter()
                .enumerate()
                .map(|(i, l)| self.report_of(i, q, l))
                .collect(),
            bearings: (0..self.bearings.len())
                .map(|i| self.bearing_load_of(i, q, v, &sets))
                .collect(),
            shafts: (0..self.shafts.len()).map(|i| self.shaft_torque(i, q, v)).collect(),
            slices,
        }
    }

    /// Mesh `i`'s report at (q, v) on its own, its per-slice loads written to `slices` (its slice
    /// count) and its part of f_int added to `scratch` (n entries, for the caller to discard): the
    /// bits of its report in [`Self::loads`], for an owner that reports a few meshes and not the rest.
    pub fn mesh_report(&self, i: usize, q: &[f64], v: &[f64], slices: &mut [f64], scratch: &mut [f64]) -> MeshReport {
        let flanks = self.meshes[i].add_forces(q, v, scratch, Some(slices));
        self.report_of(i, q, &flanks)
    }

    /// Bearing `i`'s loads at (q, v) on its own, its roller set's part of f_int added to `scratch`
    /// (n entries, discarded): the bits of its loads in [`Self::loads`].
    pub fn bearing_load(&self, i: usize, q: &[f64], v: &[f64], scratch: &mut [f64]) -> BearingLoad {
        let set = self.bearings[i]
            .rollers
            .map(|k| (k, self.rollers[k].add_forces(q, v, true, scratch)));
        match set {
            Some((k, loads)) => self.bearing_load_with(i, q, v, Some((&self.rollers[k], loads))),
            None => self.bearing_load_with(i, q, v, None),
        }
    }

    /// The torsion of shaft `i` at (q, v), positive in normal operation, N·m.
    pub fn shaft_torque(&self, i: usize, q: &[f64], v: &[f64]) -> f64 {
        let s = &self.shafts[i];
        s.sign * self.springs[s.spring].force(q, v)
    }

    /// Mesh `i`'s report from its flank loads, with the Hertz contact of its largest slice load.
    fn report_of(&self, i: usize, q: &[f64], flanks: &[FlankLoad; 2]) -> MeshReport {
        let mut r = self.meshes[i].report(q, flanks);
        r.contact = self.contacts[i].at(r.max_slice);
        r
    }

    /// Bearing `i`'s loads with its roller set's evaluated loads taken from `sets`.
    fn bearing_load_of(&self, i: usize, q: &[f64], v: &[f64], sets: &[RollerLoads]) -> BearingLoad {
        let set = self.bearings[i].rollers.map(|k| (&self.rollers[k], sets[k]));
        self.bearing_load_with(i, q, v, set)
    }

    /// Bearing `i`'s loads: its linear springs' forces at (q, v) and its roller set's evaluated loads.
    fn bearing_load_with(
        &self,
        i: usize,
        q: &[f64],
        v: &[f64],
        set: Option<(&RollerBearing, RollerLoads)>,
    ) -> BearingLoad {
        let mut s = self.bearings[i].springs.map(|k| {
            let spring = &self.springs[k];
            if spring.lamina { 0.0 } else { spring.force(q, v) }
        });
        let mut load = BearingLoad::default();
        if let Some((r, rl)) = set {
            for (si, f) in s.iter_mut().zip(rl.force) {
                *si += r.sign * f;
            }
            load.rollers_in_contact = rl.rollers_in_contact;
            load.max_roller_load = rl.max_roller_load;
            load.stresses = r.stresses(&rl);
        }
        load.radial = s[0].hypot(s[1]);
        load.axial = s[2];
        load.tilting = s[3].hypot(s[4]);
        load
    }

    /// Load sharing factor K_γ of a planetary stage's sun–planet meshes: N·max F / ΣF (1 = equal).
    pub fn load_sharing(&self, loads: &Loads, stage_suffix: &str) -> Option<f64> {
        self.load_sharing_by(stage_suffix, |i| loads.meshes[i].force)
    }

    /// [`Self::load_sharing`] with mesh `i`'s force from `force(i)`, asked of the stage's sun–planet
    /// meshes only.
    pub fn load_sharing_by(&self, stage_suffix: &str, mut force: impl FnMut(usize) -> f64) -> Option<f64> {
        let prefix = format!("sun_planet{stage_suffix}_");
        let forces: Vec<f64> = self
            .meshes
            .iter()
            .enumerate()
            .filter(|(_, m)| m.name.starts_with(&prefix))
            .map(|(i, _)| force(i))
            .collect();
        let total: f64 = forces.iter().sum();
        (total > 0.0).then(|| forces.len() as f64 * forces.iter().fold(0.0f64, |m, &x| m.max(x)) / total)
    }

    /// How fast each bearing's races turn against each other per unit input speed, |ω_body − ω_other|
    /// / ω_input, from the rigid-body kinematics (a planet bearing's is the planet's spin relative to its
    /// carrier); None when the chain is not free to turn.
    pub fn bearing_speed_ratios(&self) -> Option<Vec<f64>> {
        let rigid = self.rigid.as_ref()?;
        Some(
            self.bearings
                .iter()
                .map(|b| self.springs[b.springs[5]].row.dot(rigid).abs())
                .collect(),
        )
    }

    /// The input body's (the rotor's) angular velocity about the housing's x and y axes, rad/s: the
    /// rates its disc tilts and yaws with (the rotor FMU's tilt_rate and yaw_rate), turned out of the
    /// body's frame as the external moment is turned into it.
    pub fn input_tilt_rates(&self, q: &[f64], v: &[f64]) -> [f64; 2] {
        let body = self.input_body;
        let Some(f) = self.bodies[body].first else {
            return [0.0; 2];
        };
        let angle = self.frame_spin(body).map_or(0.0, |fs| q[fs]);
        let (s, c) = angle.sin_cos();
        let (x, y) = (v[f + TX], v[f + TY]);
        [c * x - s * y, s * x + c * y]
    }

    /// Speed of a body's spin, signed so the input turns positive (rad/s).
    pub fn speed(&self, body: usize, v: &[f64]) -> f64 {
        let sign = match (&self.rigid, self.bodies[body].first) {
            (Some(r), Some(f)) => r[f + SPIN].signum(),
            _ => 1.0,
        };
        self.bodies[body].first.map_or(0.0, |f| sign * v[f + SPIN])
    }
}
