//! Natural frequencies of the gearbox about its unloaded state with every mesh engaged, each mode
//! classified as planetary-gear dynamics names them (Lin & Parker 1999): rotational (central members
//! turn, planets move alike), translational (central members translate), planet (only planets
//! move), axial/tilting (out of the plane), with its torsional projection.

use crate::linear::modes::eigenpairs_of;
use crate::physics::gearbox::model::{BodyKind, Gearbox, SPIN, TX, TY, UX, UY, UZ};
use serde::Serialize;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Family {
    /// Zero frequency: the free chain turning (or an unheld DOF).
    Rigid,
    Rotational,
    Translational,
    Planet,
    AxialTilting,
}

impl Family {
    /// Its name, as it serialises.
    pub fn name(self) -> &'static str {
        match self {
            Family::Rigid => "rigid",
            Family::Rotational => "rotational",
            Family::Translational => "translational",
            Family::Planet => "planet",
            Family::AxialTilting => "axial-tilting",
        }
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct GearMode {
    pub frequency_hz: f64,
    pub family: Family,
    /// Share of the mode's kinetic energy in the spin DOFs (1 = purely torsional).
    pub torsional_projection: f64,
    /// Body holding the largest share of the kinetic energy.
    pub dominant_body: String,
}

/// The modes as `windrive modes --gearbox` lists them: number, frequency, family, torsional share and
/// dominant body, a row each.
pub fn table(m: &[GearMode]) -> String {
    let mut s = format!(
        "{:>4}  {:>12}  {:<14} {:>10}  dominant body\n",
        "mode", "f / Hz", "family", "torsional"
    );
    for (i, x) in m.iter().enumerate() {
        s += &format!(
            "{:>4}  {:>12.4}  {:<14} {:>10.3}  {}\n",
            i + 1,
            x.frequency_hz,
            x.family.name(),
            x.torsional_projection,
            x.dominant_body
        );
    }
    s
}

/// Every mode, lowest first.
pub fn modes(g: &Gearbox) -> Vec<GearMode> {
    let lin = g.engaged_linearisation();
    let n = g.dofs();
    let keep: Vec<usize> = (0..n).collect();
    let (lambda, x) = eigenpairs_of(&lin.mass, &lin.stiffness, &keep);
    let largest = lambda.iter().fold(0.0f64, |m, &l| m.max(l.abs()));
    let mut out: Vec<GearMode> = (0..n)
        .map(|k| {
            let col = x.column(k);
            // kinetic energy per DOF: x_i (M x)_i (the orbit coupling shares it between planet and carrier)
            let mx = &lin.mass * col;
            let e: Vec<f64> = (0..n).map(|i| (col[i] * mx[i]).max(0.0)).collect();
            let total: f64 = e.iter().sum::<f64>().max(1e-300);
            let (mut spin, mut out_of_plane, mut central_spin, mut central_trans) = (0.0, 0.0, 0.0, 0.0);
            let mut per_body = vec![0.0; g.bodies.len()];
            for (bi, b) in g.bodies.iter().enumerate() {
                let Some(f) = b.first else { continue };
                let central = b.kind != BodyKind::Planet;
                for d in 0..6 {
                    let ei = e[f + d] / total;
                    per_body[bi] += ei;
                    match d {
                        SPIN => {
                            spin += ei;
                            if central {
                                central_spin += ei;
                            }
                        }
                        UZ | TX | TY => out_of_plane += ei,
                        UX | UY if central => central_trans += ei,
                        _ => {}
                    }
                }
            }
            let dominant = per_body
                .iter()
                .enumerate()
                .fold((0, 0.0), |(bi, be), (i, &v)| if v > be { (i, v) } else { (bi, be) })
                .0;
            let zero = lambda[k] <= 1e-10 * largest;
            let family = if zero {
                Family::Rigid
            } else if out_of_plane > 0.5 {
                Family::AxialTilting
            } else if central_spin + central_trans < 1e-6 {
                Family::Planet
            } else if central_trans > central_spin {
                Family::Translational
            } else {
                Family::Rotational
            };
            GearMode {
                frequency_hz: lambda[k].max(0.0).sqrt() / std::f64::consts::TAU,
                family,
                torsional_projection: spin,
                dominant_body: g.bodies[dominant].name.clone(),
            }
        })
        .collect();
    out.sort_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz));
    out
}
