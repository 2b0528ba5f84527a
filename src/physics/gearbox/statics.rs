//! Static equilibrium of the gearbox under steady torques (and a steady spin): the starting state of
//! a run and the load-sharing and face-load checks.

use super::model::Gearbox;
use crate::solver::system::{SecondOrderSystem, external_forces};
use nalgebra::DMatrix;

/// Equilibrium under inputs `u` while the chain spins rigidly at `speed` (rad/s at the input; the
/// frames' centripetal loads then act): f_int(q, v) = B·u with v the rigid spin. Newton on the
/// contact pattern's tangent, the input's angle held at 0 (the rigid rotation is free). Returns q, v.
pub fn equilibrium(g: &Gearbox, u: &[f64], speed: f64) -> Result<(Vec<f64>, Vec<f64>), String> {
    let n = g.dofs();
    let v: Vec<f64> = match &g.rigid {
        Some(r) => r.iter().map(|x| x * speed).collect(),
        None => vec![0.0; n],
    };
    let mut f_ext = vec![0.0; n];
    external_forces(g, u, &mut f_ext);
    let mut q = vec![0.0; n];
    let mut fi = vec![0.0; n];
    let mut key = Vec::new();
    let mut key_new = Vec::new();
    let held = g.rigid.as_ref().map(|_| g.rigid_dof);
    for iteration in 0..200 {
        let mut j = if iteration == 0 {
            // open contacts at q = 0: start from every mesh engaged
            g.engaged_linearisation().stiffness
        } else {
            let mut j = DMatrix::zeros(n, n);
            g.add_tangent(0.0, &q, &v, 0.0, 1.0, &mut j);
            j
        };
        g.internal_forces(0.0, &q, &v, &mut fi);
        let mut r = nalgebra::DVector::from_fn(n, |i, _| f_ext[i] - fi[i]);
        // a DOF no element holds (a spur gear's axial float) would make J singular: a stiffness a
        // trillion times below the largest holds it without moving anything that is held
        let scale = (0..n).map(|i| j[(i, i)]).fold(0.0f64, f64::max);
        for i in 0..n {
            j[(i, i)] += 1e-12 * scale;
        }
        if let Some(h) = held {
            j.row_mut(h).fill(0.0);
            j.column_mut(h).fill(0.0);
            j[(h, h)] = 1.0;
            r[h] = 0.0;
        }
        let dq = j
            .lu()
            .solve(&r)
            .ok_or("the stiffness matrix is singular: a body is not held")?;
        let size = q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let step = dq.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for i in 0..n {
            q[i] += dq[i];
        }
        std::mem::swap(&mut key, &mut key_new);
        g.factor_key(0.0, &q, &mut key_new);
        if iteration > 0 && key == key_new && step <= 1e-10 * size.max(1e-12) {
            return Ok((q, v));
        }
    }
    Err("the static contact iteration did not settle in 200 iterations".into())
}
