//! Reading a field where a blade element is: bilinear in the rotor plane, linear in time.
//!
//! The field is frozen (Taylor's hypothesis) and carried through the rotor at the hub's mean speed, as
//! OpenFAST's InflowWind reads a full field: the grid stored at field time τ is the plane passing the
//! rotor at simulation time τ. (InflowWind also starts a non-periodic field half a grid width upstream;
//! here time 0 is the file's first plane, so a file and its periodic copy give the same wind.) A periodic
//! field wraps round after nt·dt, interpolating between its last and first planes; a non-periodic one
//! ends at its last plane, and [`WindField::end_time`] says when, for the caller to refuse a step beyond.

use super::WindField;

/// The two planes either side of a time and the weight of the later one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    first: usize,
    second: usize,
    weight: f64,
}

/// Where a point of the rotor plane falls in the grid: the lower-left corner's index in a plane and the
/// weights of the next point across and up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cell {
    corner: usize,
    across: usize,
    up: usize,
    wy: f64,
    wz: f64,
}

/// The index below `x` (in grid spacings from the first point) and the weight of the one above, clamped
/// to the `n` points: a point just outside by rounding reads the edge.
fn bracket(x: f64, n: usize) -> (usize, usize, f64) {
    if n < 2 || !x.is_finite() {
        return (0, 0, 0.0);
    }
    let x = x.clamp(0.0, (n - 1) as f64);
    let i = (x.floor() as usize).min(n - 2);
    (i, 1, x - i as f64)
}

impl WindField {
    /// The last simulation time the field holds, s, or None when it wraps round (periodic).
    pub fn end_time(&self) -> Option<f64> {
        (!self.periodic).then(|| (self.nt - 1) as f64 * self.dt)
    }

    /// The planes read at simulation time `t`, s.
    pub fn frame(&self, t: f64) -> Frame {
        let nt = self.nt;
        if self.periodic {
            let tau = (t / self.dt).rem_euclid(nt as f64);
            let first = (tau.floor() as usize).min(nt - 1);
            Frame {
                first,
                second: (first + 1) % nt,
                weight: tau - first as f64,
            }
        } else {
            let (first, step, weight) = bracket(t / self.dt, nt);
            Frame {
                first,
                second: first + step,
                weight,
            }
        }
    }

    /// The cell holding lateral position `y` and height `z`, m (y = 0 at the grid's centre line).
    pub fn cell(&self, y: f64, z: f64) -> Cell {
        let (j, across, wy) = bracket(y / self.dy + 0.5 * (self.ny - 1) as f64, self.ny);
        let (k, up, wz) = bracket((z - self.z_bottom) / self.dz, self.nz);
        Cell {
            corner: k * self.ny + j,
            across,
            up: up * self.ny,
            wy,
            wz,
        }
    }

    /// u, v, w (m/s) at `cell` in `frame`.
    pub fn at(&self, frame: Frame, cell: Cell) -> [f64; 3] {
        let plane = self.ny * self.nz;
        let (a, b) = (frame.first * plane + cell.corner, frame.second * plane + cell.corner);
        let (wy, wz, wt) = (cell.wy, cell.wz, frame.weight);
        std::array::from_fn(|c| {
            let x = &self.velocity[c];
            let bilinear = |p: usize| {
                let low = x[p] + wy * (x[p + cell.across] - x[p]);
                let high = x[p + cell.up] + wy * (x[p + cell.up + cell.across] - x[p + cell.up]);
                low + wz * (high - low)
            };
            let (early, late) = (bilinear(a), bilinear(b));
            early + wt * (late - early)
        })
    }

    /// u, v, w (m/s) at simulation time `t`, lateral position `y` and height `z`.
    pub fn velocity_at(&self, t: f64, y: f64, z: f64) -> [f64; 3] {
        self.at(self.frame(t), self.cell(y, z))
    }

    /// Whether a disc of `radius` about (0, `hub_height`) lies inside the grid (to 1 mm: a disc the
    /// size of the grid fits).
    pub fn covers(&self, radius: f64, hub_height: f64) -> bool {
        let half_width = 0.5 * (self.ny - 1) as f64 * self.dy;
        let top = self.z(self.nz - 1);
        let slack = 1e-3;
        radius <= half_width + slack
            && hub_height - radius >= self.z_bottom - slack
            && hub_height + radius <= top + slack
    }

    /// The grid's extent as text for messages: "y ±a m, z b to c m".
    pub fn extent(&self) -> String {
        format!(
            "y ±{:.2} m, z {:.2} to {:.2} m",
            0.5 * (self.ny - 1) as f64 * self.dy,
            self.z_bottom,
            self.z(self.nz - 1)
        )
    }
}
