//! What a gearbox run reports: mesh loads, bearing loads, shaft torques, load sharing.

use super::mesh::MeshReport;
use super::model::{Gearbox, SPIN};

/// Loads of one bearing, in the frame it sits in.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BearingLoad {
    /// √(F_x² + F_y²), N.
    pub radial: f64,
    /// Along the shaft axis, N.
    pub axial: f64,
    /// √(M_x² + M_y²), N·m.
    pub tilting: f64,
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
    /// Every reported load at (q, v).
    pub fn loads(&self, q: &[f64], v: &[f64]) -> Loads {
        let mut f = vec![0.0; self.dofs()];
        let mut slices = vec![0.0; self.slice_count()];
        let flank = self.forces_with_slices(q, v, &mut f, &mut slices);
        let mut at = 0;
        let meshes = self
            .meshes
            .iter()
            .zip(&flank)
            .map(|(m, l)| {
                let r = m.report(q, l, &slices[at..at + m.slices()]);
                at += m.slices();
                r
            })
            .collect();
        let bearings = self
            .bearings
            .iter()
            .map(|b| {
                let s = b.springs.map(|i| self.springs[i].force(q, v));
                BearingLoad {
                    radial: s[0].hypot(s[1]),
                    axial: s[2],
                    tilting: s[3].hypot(s[4]),
                }
            })
            .collect();
        let shafts = self
            .shafts
            .iter()
            .map(|s| s.sign * self.springs[s.spring].force(q, v))
            .collect();
        Loads {
            meshes,
            bearings,
            shafts,
            slices,
        }
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

    /// Speed of a body's spin, signed so the input turns positive (rad/s).
    pub fn speed(&self, body: usize, v: &[f64]) -> f64 {
        let sign = match (&self.rigid, self.bodies[body].first) {
            (Some(r), Some(f)) => r[f + SPIN].signum(),
            _ => 1.0,
        };
        self.bodies[body].first.map_or(0.0, |f| sign * v[f + SPIN])
    }
}
