//! Frequency response of any linearised model ([`dynamic_response`]) and the Bode plots of the
//! linear drivetrain: a torque at the rotor or the generator in,
//! a speed or a shaft torque out, from the dynamic stiffness K − ω²M + jωC (every mesh at its mean
//! stiffness, no backlash) with the generator boundary of the modal analysis (locked = DOF removed).

use crate::linear::modes::{Boundary, linearised};
use crate::physics::torsional::TorsionalModel;
use crate::solver::system::Linearisation;
use nalgebra::{DMatrix, DVector};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Input {
    /// Aerodynamic torque on the rotor.
    RotorTorque,
    /// Electromagnetic torque on the generator rotor, positive opposing rotation.
    GeneratorTorque,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Output {
    RotorSpeed,
    GeneratorSpeed,
    /// Torque in a shaft: index into the model's shafts (0 = LSS, last = HSS).
    Shaft(usize),
}

impl Input {
    /// "rotor" or "generator", as `windrive bode --input` names them.
    pub fn named(name: &str) -> Option<Self> {
        match name {
            "rotor" => Some(Self::RotorTorque),
            "generator" => Some(Self::GeneratorTorque),
            _ => None,
        }
    }
}

impl Output {
    /// generator-speed, rotor-speed, lss-torque or hss-torque (the model's last shaft), as
    /// `windrive bode --output` names them.
    pub fn named(name: &str, model: &TorsionalModel) -> Option<Self> {
        Some(match name {
            "generator-speed" => Self::GeneratorSpeed,
            "rotor-speed" => Self::RotorSpeed,
            "lss-torque" => Self::Shaft(0),
            "hss-torque" => Self::Shaft(model.shafts.iter().rposition(|s| s.is_some()).unwrap_or(0)),
            _ => return None,
        })
    }
}

/// (DOF, weight) pairs whose sum of angles is the output's deflection.
pub type Weights = Vec<(usize, f64)>;

/// What a response reads: Σ w_d·x_d over (DOF, weight) pairs, as a speed (jω·x) or as the force of
/// an element with stiffness and damping (k + jωc)·δ.
#[derive(Debug, Clone, PartialEq)]
pub enum Observation {
    Speed(Weights),
    ElementForce {
        deflection: Weights,
        stiffness: f64,
        damping: f64,
    },
}

/// Complex response (re, im) of an observation per unit force vector `load` at each frequency (Hz)
/// of any linearised model restricted to the DOFs `keep`: solves (K − ω²M + jωC)·x = load in real
/// arithmetic.
pub fn dynamic_response(
    lin: &Linearisation,
    keep: &[usize],
    load: &[f64],
    observation: &Observation,
    frequencies_hz: &[f64],
) -> Result<Vec<(f64, f64)>, String> {
    let n = keep.len();
    let pos = |d: usize| keep.iter().position(|&x| x == d);
    let weights = match observation {
        Observation::Speed(w) => w,
        Observation::ElementForce { deflection, .. } => deflection,
    };
    let mut out = Vec::with_capacity(frequencies_hz.len());
    for &f in frequencies_hz {
        let w = std::f64::consts::TAU * f;
        // [K − ω²M, −ωC; ωC, K − ω²M] [x_re; x_im] = [F; 0]
        let mut a = DMatrix::zeros(2 * n, 2 * n);
        for (i, &di) in keep.iter().enumerate() {
            for (j, &dj) in keep.iter().enumerate() {
                let kr = lin.stiffness[(di, dj)] - w * w * lin.mass[(di, dj)];
                a[(i, j)] = kr;
                a[(n + i, n + j)] = kr;
                a[(i, n + j)] = -w * lin.damping[(di, dj)];
                a[(n + i, j)] = w * lin.damping[(di, dj)];
            }
        }
        let b = DVector::from_fn(2 * n, |i, _| if i < n { load[keep[i]] } else { 0.0 });
        let x = a
            .lu()
            .solve(&b)
            .ok_or(format!("the dynamic stiffness is singular at {f} Hz"))?;
        let (mut re, mut im) = (0.0, 0.0);
        for &(d, wt) in weights {
            if let Some(p) = pos(d) {
                re += wt * x[p];
                im += wt * x[n + p];
            }
        }
        out.push(match observation {
            // (k + jωc)(re + j im)
            Observation::ElementForce { stiffness, damping, .. } => {
                (stiffness * re - w * damping * im, stiffness * im + w * damping * re)
            }
            // jω(re + j im)
            Observation::Speed(_) => (-w * im, w * re),
        });
    }
    Ok(out)
}

/// Complex response (re, im) of `output` per unit `input` at each frequency (Hz).
pub fn frequency_response(
    model: &TorsionalModel,
    boundary: Boundary,
    k_generator: f64,
    input: Input,
    output: Output,
    frequencies_hz: &[f64],
) -> Result<Vec<(f64, f64)>, String> {
    let (lin, keep) = linearised(model, boundary, k_generator);
    let g = model.generator;
    let (load_dof, sign) = match input {
        Input::RotorTorque => (model.rotor, 1.0),
        Input::GeneratorTorque => (g, -1.0),
    };
    if !keep.contains(&load_dof) {
        return Err("the generator is locked: it takes no torque input".into());
    }
    let mut load = vec![0.0; model.dofs()];
    load[load_dof] = sign;
    let observation = match output {
        Output::RotorSpeed => Observation::Speed(vec![(model.rotor, 1.0)]),
        Output::GeneratorSpeed => Observation::Speed(vec![(g, 1.0)]),
        Output::Shaft(i) => {
            let o = model
                .shafts
                .get(i)
                .copied()
                .flatten()
                .ok_or(format!("this model has no shaft {i}"))?;
            let e = &model.elements[o.element];
            Observation::ElementForce {
                deflection: e.coeffs.iter().map(|&(d, w)| (d, w * o.factor)).collect(),
                stiffness: e.stiffness,
                damping: e.damping,
            }
        }
    };
    dynamic_response(&lin, &keep, &load, &observation, frequencies_hz)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linear::modes::modes;
    use crate::physics::drivetrain::Drivetrain;
    use crate::physics::torsional::{Fidelity, ModelOptions};

    /// Drivetrain D free–free, rotor torque → generator speed: at low frequency the drivetrain turns
    /// as one body, |G|·ω → r_gen/J_eq with J_eq = Σ J_d r_d² (rigid rotation); the magnitude peaks
    /// at the lowest non-zero free–free mode of the modal analysis (light damping).
    #[test]
    fn rigid_asymptote_and_resonance_of_drivetrain_d() {
        let dt = Drivetrain::preset("D").unwrap();
        let model = TorsionalModel::new(&dt, Fidelity::Full, &ModelOptions::default()).unwrap();
        let j_eq: f64 = model.mass.iter().zip(&model.speed_ratio).map(|(m, r)| m * r * r).sum();
        let r_gen = model.speed_ratio[model.generator];
        let f = 1e-3;
        let g = frequency_response(
            &model,
            Boundary::Disconnected,
            0.0,
            Input::RotorTorque,
            Output::GeneratorSpeed,
            &[f],
        )
        .unwrap()[0];
        let w = std::f64::consts::TAU * f;
        assert!((g.0.hypot(g.1) * w / (r_gen / j_eq) - 1.0).abs() < 1e-4, "{g:?}");
        let f1 = modes(&model, Boundary::Disconnected, dt.k_generator)
            .frequencies_hz
            .into_iter()
            .find(|f| *f > 1e-6)
            .unwrap();
        let grid: Vec<f64> = (0..2001).map(|i| f1 * (0.9 + 0.2 * i as f64 / 2000.0)).collect();
        let r = frequency_response(
            &model,
            Boundary::Disconnected,
            0.0,
            Input::RotorTorque,
            Output::GeneratorSpeed,
            &grid,
        )
        .unwrap();
        // past the rigid-body roll-off the first resonance is the largest local maximum in ±10 %
        let peak = (1..grid.len() - 1)
            .filter(|&i| {
                r[i].0.hypot(r[i].1) > r[i - 1].0.hypot(r[i - 1].1)
                    && r[i].0.hypot(r[i].1) >= r[i + 1].0.hypot(r[i + 1].1)
            })
            .max_by(|&i, &j| r[i].0.hypot(r[i].1).total_cmp(&r[j].0.hypot(r[j].1)))
            .map(|i| grid[i])
            .expect("a resonance");
        assert!((peak / f1 - 1.0).abs() < 2e-3, "{peak} vs {f1}");
    }

    /// Quasi-static LSS torque with the generator connected: a rotor torque is carried by the LSS in
    /// full (the only load path to the generator spring).
    #[test]
    fn static_lss_torque_carries_the_rotor_torque() {
        let dt = Drivetrain::preset("C").unwrap();
        let model = TorsionalModel::new(&dt, Fidelity::Full, &ModelOptions::default()).unwrap();
        let g = frequency_response(
            &model,
            Boundary::Connected,
            dt.k_generator,
            Input::RotorTorque,
            Output::Shaft(0),
            &[1e-4],
        )
        .unwrap()[0];
        assert!((g.0.abs() - 1.0).abs() < 1e-3 && g.1.abs() < 1e-3, "{g:?}");
    }
}
