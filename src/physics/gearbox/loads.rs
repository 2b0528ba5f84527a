//! What a gearbox run reports: mesh loads, bearing loads, shaft torques, load sharing.

use super::bearing::{RaceStresses, RollerLoads};
use super::mesh::{FlankLoad, MeshReport};
use super::model::{Gearbox, SPIN, TX, TY};

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
    /// Each mesh's flank sums and each roller set's loads, as the forces' evaluation gave them (the
    /// reports above are made from them).
    pub flanks: Vec<[FlankLoad; 2]>,
    pub roller_sets: Vec<RollerLoads>,
}

impl Gearbox {
    /// Every reported load at (q, v).
    pub fn loads(&self, q: &[f64], v: &[f64]) -> Loads {
        self.loads_and_state_forces(q, v, &mut vec![0.0; self.dofs()])
    }

    /// Every reported load at (q, v), and f_int there less the rotor's loads into `forces`, to the bit
    /// what f_int is before [`Gearbox::add_rotor_loads`] adds them: the loads are taken from the forces'
    /// own evaluation, so an owner that reports loads at a communication point can hand f_int to the
    /// next step instead of evaluating it again.
    pub fn loads_and_state_forces(&self, q: &[f64], v: &[f64], forces: &mut [f64]) -> Loads {
        let mut loads = Loads::default();
        self.loads_and_state_forces_into(q, v, forces, &mut loads);
        loads
    }

    /// [`Self::loads_and_state_forces`] into `out`, its vectors reused: an owner that reports loads
    /// at every step allocates them once (six vectors and the slices' zeroing were a fifth of a
    /// report's instructions besides the forces with linear bearings, callgrind).
    pub fn loads_and_state_forces_into(&self, q: &[f64], v: &[f64], forces: &mut [f64], out: &mut Loads) {
        // every slice and every set is written by the evaluation (each mesh zeroes its slices first)
        out.slices.resize(self.slice_count(), 0.0);
        out.roller_sets.resize(self.rollers.len(), RollerLoads::default());
        out.flanks.clear();
        let Loads {
            meshes,
            bearings,
            shafts,
            slices,
            flanks,
            roller_sets: sets,
        } = out;
        self.state_forces(q, v, forces, Some(slices), Some(sets), |l| flanks.push(l));
        meshes.clear();
        meshes.extend(
            self.meshes
                .iter()
                .zip(&*flanks)
                .zip(&self.contacts)
                .map(|((m, l), contact)| {
                    let mut r = m.report(q, l);
                    r.contact = contact.at(r.max_slice);
                    r
                }),
        );
        bearings.clear();
        bearings.extend(self.bearings.iter().map(|b| {
            let mut s = b.springs.map(|i| {
                let spring = &self.springs[i];
                if spring.lamina { 0.0 } else { spring.force(q, v) }
            });
            let mut load = BearingLoad::default();
            if let Some(i) = b.rollers {
                let (r, rl) = (&self.rollers[i], sets[i]);
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
        }));
        shafts.clear();
        shafts.extend(self.shafts.iter().map(|s| s.sign * self.springs[s.spring].force(q, v)));
    }

    /// Load sharing factor K_γ of a planetary stage's sun–planet meshes: N·max F / ΣF (1 = equal).
    pub fn load_sharing(&self, loads: &Loads, stage_suffix: &str) -> Option<f64> {
        let prefix = format!("sun_planet{stage_suffix}_");
        let forces: Vec<f64> = self
            .meshes
            .iter()
            .zip(&loads.meshes)
            .filter(|(m, _)| m.name.starts_with(&prefix))
            .map(|(_, r)| r.force)
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
