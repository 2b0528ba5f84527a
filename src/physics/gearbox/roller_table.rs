//! The lamina law's sums over one roller by table: what a roller of n laminae without crowning needs
//! for its force, moment and tangent, with two ninth roots and a degree-7 polynomial instead of a ninth
//! root per loaded lamina (the roller sets' forces and tangents were 40 % of the gearbox FMU's step).
//!
//! A roller's laminae k = 0 … n−1 sit at s_k along its axis and approach their races by δ_k = c + p·s_k
//! (c the approach at its centre, p the tilt). Counted from the more loaded end, lamina j approaches by
//! m·(1 − j·v), m the most loaded lamina's approach and v = |p|·w/m (w a lamina's width), and carries load
//! while j < u = 1/v. The five sums the law needs, Σδ^(10/9)·{1, s} and Σδ^(1/9)·{1, s, s²}, are
//! therefore m^(10/9) or m^(1/9) times a function of u alone, which kinks where a lamina unloads (at
//! u = 1 … n−1) and, near each kink, follows the last loaded lamina's (1 − J/u)^(1/9), which no polynomial
//! follows to zero. So the last loaded lamina is evaluated exactly and the smooth rest is tabulated in
//! cells whose ends are the kinks (two cells per unit of u on [1, U), two cells in v on [0, 1/U], U ≥ 16
//! and ≥ 2n), each a degree-7 polynomial interpolating the sums at its Chebyshev nodes. Over poses from
//! a uniform roller to single-lamina edge loading, within 1e-14 of every kink, the sums are within 2e-10
//! of the lamina loop's (tests below; benches/roller_table/study.py derived the layout).

use std::sync::Arc;

/// The polynomial degree per cell.
const DEGREE: usize = 7;
/// Cells per unit of u on [1, U) (so every kink u = 1 … n−1 is a cell boundary).
const CELLS_PER_UNIT: usize = 2;
/// Cells in v on [0, 1/U], where every lamina is loaded.
const V_CELLS: usize = 2;
/// The laminae a roller may have (the description's check allows 1 to 50).
pub const MAX_LAMINAE: usize = 50;

/// Normalised sums over the laminae j counted from the loaded end, x_j = δ_j/m, σ_j = s_j/(L/2) signed
/// towards the loaded end: [Σx^(10/9), Σx^(10/9)·σ, Σx^(1/9), Σx^(1/9)·σ, Σx^(1/9)·σ²].
pub type Sums = [f64; 5];

/// One cell's polynomials in t ∈ [−1, 1], coefficient of t^k at [k].
#[derive(Debug, Clone, Copy, PartialEq)]
struct Cell {
    coef: [Sums; DEGREE + 1],
}

impl Cell {
    #[inline(always)]
    fn at(&self, t: f64) -> Sums {
        let mut acc = self.coef[DEGREE];
        for c in self.coef[..DEGREE].iter().rev() {
            for (a, c) in acc.iter_mut().zip(c) {
                *a = *a * t + c;
            }
        }
        acc
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct RollerTable {
    laminae: usize,
    /// u from which every cell is in v.
    u_end: f64,
    /// (u − 1)·CELLS_PER_UNIT cells on [1, U), then V_CELLS cells on [0, 1/U].
    cells: Vec<Cell>,
}

/// The sums over laminae j < `upto` loaded at v (x_j = 1 − j·v > 0), as the lamina loop adds them.
fn loop_sums(n: usize, v: f64, upto: usize) -> Sums {
    let mut s = [0.0; 5];
    for j in 0..upto.min(n) {
        let x = 1.0 - j as f64 * v;
        if x <= 0.0 {
            break;
        }
        let sigma = (n as f64 - 1.0 - 2.0 * j as f64) / n as f64;
        let (b, e) = (x.powf(1.0 / 9.0), x.powf(10.0 / 9.0));
        for (a, t) in s.iter_mut().zip([e, e * sigma, b, b * sigma, b * sigma * sigma]) {
            *a += t;
        }
    }
    s
}

/// Interpolates `f` at the Chebyshev nodes of [−1, 1] by a degree-`DEGREE` polynomial in monomial form.
fn interpolate(f: impl Fn(f64) -> Sums) -> Cell {
    let nodes = DEGREE + 1;
    let theta = |i: usize| std::f64::consts::PI * (i as f64 + 0.5) / nodes as f64;
    let values: Vec<Sums> = (0..nodes).map(|i| f(theta(i).cos())).collect();
    // Chebyshev coefficients by the discrete cosine transform, then T_k expanded into powers of t
    let mut cheb = [[0.0; 5]; DEGREE + 1];
    for (k, c) in cheb.iter_mut().enumerate() {
        let scale = if k == 0 { 1.0 } else { 2.0 } / nodes as f64;
        for (i, v) in values.iter().enumerate() {
            let tk = (k as f64 * theta(i)).cos();
            for (a, x) in c.iter_mut().zip(v) {
                *a += scale * tk * x;
            }
        }
    }
    let mut coef = [[0.0; 5]; DEGREE + 1];
    let (mut before, mut now) = ([0.0; DEGREE + 1], [0.0; DEGREE + 1]);
    now[0] = 1.0; // T_0
    for (k, c) in cheb.iter().enumerate() {
        if k == 1 {
            (before, now) = (now, [0.0; DEGREE + 1]);
            now[1] = 1.0;
        } else if k > 1 {
            // T_k = 2t·T_{k−1} − T_{k−2}
            let mut next = [0.0; DEGREE + 1];
            for p in 0..=DEGREE {
                next[p] = -before[p] + if p > 0 { 2.0 * now[p - 1] } else { 0.0 };
            }
            (before, now) = (now, next);
        }
        for (p, power) in now.iter().enumerate() {
            for (a, x) in coef[p].iter_mut().zip(c) {
                *a += power * x;
            }
        }
    }
    Cell { coef }
}

/// The tables of one model, one per lamina count, shared by its roller sets. The model owns them (a
/// build takes microseconds): tables held by a process-wide static were lost at every unloading of
/// the FMU's library, which a host that loads and frees it per case repeats.
#[derive(Debug, Default)]
pub struct RollerTables {
    built: Vec<Option<Arc<RollerTable>>>,
}

impl RollerTables {
    /// The table for rollers of `n` laminae (None outside the lamina counts a description allows).
    pub fn for_laminae(&mut self, n: usize) -> Option<Arc<RollerTable>> {
        if !(1..=MAX_LAMINAE).contains(&n) {
            return None;
        }
        if self.built.len() <= n {
            self.built.resize(n + 1, None);
        }
        Some(Arc::clone(
            self.built[n].get_or_insert_with(|| Arc::new(RollerTable::new(n))),
        ))
    }
}

impl RollerTable {
    fn new(n: usize) -> RollerTable {
        let u_end = (2 * n).max(16) as f64;
        let per = CELLS_PER_UNIT as f64;
        let u_cells = (u_end as usize - 1) * CELLS_PER_UNIT;
        let mut cells = Vec::with_capacity(u_cells + V_CELLS);
        for i in 0..u_cells {
            let lo = 1.0 + i as f64 / per;
            let (mid, half) = (lo + 0.5 / per, 0.5 / per);
            // the last loaded lamina on the cell, which the evaluation adds exactly
            let last = (lo.floor() as usize).min(n - 1);
            cells.push(interpolate(|t| loop_sums(n, 1.0 / (mid + half * t), last)));
        }
        let width = 1.0 / (u_end * V_CELLS as f64);
        for i in 0..V_CELLS {
            let mid = (i as f64 + 0.5) * width;
            cells.push(interpolate(|t| loop_sums(n, mid + 0.5 * width * t, n - 1)));
        }
        RollerTable {
            laminae: n,
            u_end,
            cells,
        }
    }

    /// The normalised sums over laminae 0 … `last` − 1 (counted from the loaded end) of a roller whose
    /// loaded laminae are 0 … `last`, at u = m/(|p|·w) (∞ for an untilted roller); the caller adds lamina
    /// `last` exactly. u is taken into the cells of `last` (the laminae's own signs decide which are
    /// loaded, so u may lie a rounding outside them).
    #[inline(always)]
    pub fn rest(&self, last: usize, u: f64) -> Sums {
        if last == 0 {
            return [0.0; 5];
        }
        let per = CELLS_PER_UNIT as f64;
        let u_cells = self.cells.len() - V_CELLS;
        if last + 1 == self.laminae && u >= self.u_end {
            let y = (1.0 / u) * self.u_end * V_CELLS as f64;
            // y ≥ 0, so the saturating cast is its floor (no libm call on baseline x86_64)
            let i = (y as usize).min(V_CELLS - 1);
            let t = (2.0 * (y - i as f64) - 1.0).clamp(-1.0, 1.0);
            return self.cells[u_cells + i].at(t);
        }
        // the cells where `last` is the last loaded lamina: u in [last, last + 1), or [n − 1, U) for all n
        let first = (last - 1) * CELLS_PER_UNIT;
        let end = if last + 1 == self.laminae {
            u_cells
        } else {
            first + CELLS_PER_UNIT
        };
        let x = (u - 1.0) * per;
        // the floor of x ≥ 0 by the saturating cast (a rounding below 0 goes to 0, then into the cells)
        let i = (x as usize).clamp(first, end - 1);
        let t = (2.0 * (x - i as f64) - 1.0).clamp(-1.0, 1.0);
        self.cells[i].at(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sums over a roller's laminae in physical units, as the lamina loop adds them: the reference.
    fn physical_loop(c: f64, p: f64, s: &[f64]) -> Sums {
        let mut out = [0.0; 5];
        for &sk in s {
            let d = c + p * sk;
            if d <= 0.0 {
                continue;
            }
            let (b, e) = (d.powf(1.0 / 9.0), d.powf(10.0 / 9.0));
            for (a, t) in out.iter_mut().zip([e, e * sk, b, b * sk, b * sk * sk]) {
                *a += t;
            }
        }
        out
    }

    /// The same sums from the table: the most loaded lamina's approach m, u = m/(|p|·w), the loaded
    /// count from the laminae's signs, lamina `last` exact.
    fn physical_table(table: &RollerTable, c: f64, p: f64, s: &[f64], length: f64) -> Option<Sums> {
        let n = s.len();
        let w = length / n as f64;
        let from_loaded = |j: usize| if p >= 0.0 { s[n - 1 - j] } else { s[j] };
        let m = c + p * from_loaded(0);
        if m <= 0.0 {
            return None;
        }
        let u = m / (p.abs() * w);
        let loaded = |j: usize| c + p * from_loaded(j) > 0.0;
        let mut count = if u >= n as f64 {
            n
        } else {
            (u.ceil() as usize).clamp(1, n)
        };
        while count < n && loaded(count) {
            count += 1;
        }
        while count > 1 && !loaded(count - 1) {
            count -= 1;
        }
        let last = count - 1;
        let rest = table.rest(last, u);
        let (sign, h) = (if p >= 0.0 { 1.0 } else { -1.0 }, 0.5 * length);
        let mb = m.powf(1.0 / 9.0);
        let me = mb * m;
        let sj = from_loaded(last);
        let dj = c + p * sj;
        let (b, e) = (dj.powf(1.0 / 9.0), dj.powf(10.0 / 9.0));
        Some([
            me * rest[0] + e,
            sign * h * me * rest[1] + e * sj,
            mb * rest[2] + b,
            sign * h * mb * rest[3] + b * sj,
            h * h * mb * rest[4] + b * sj * sj,
        ])
    }

    fn laminae(n: usize, length: f64) -> Vec<f64> {
        let w = length / n as f64;
        (0..n).map(|k| -0.5 * length + (k as f64 + 0.5) * w).collect()
    }

    /// Worst error of each sum over poses from a uniform roller to single-lamina edge loading and
    /// within 1e-14 of every kink, relative to the sum (the odd moments to the sum times L/2).
    fn worst_errors(n: usize, poses: usize) -> Sums {
        let table = &*RollerTables::default().for_laminae(n).unwrap();
        let mut worst = [0.0f64; 5];
        let mut random = crate::xorshift::Xorshift::new(0x2545_f491_4f6c_dd1d);
        let mut uniform = || random.unit();
        for i in 0..poses {
            let length = 0.02 + 0.18 * uniform();
            let s = laminae(n, length);
            let w = length / n as f64;
            let m = 10f64.powf(-9.0 + 6.0 * uniform());
            // v = |p|·w/m: from untilted through every kink to one loaded lamina
            let v = match i % 4 {
                0 => 0.0,
                1 => {
                    let kink = 1.0 + (uniform() * (n.max(2) - 1) as f64).floor();
                    let side = if uniform() < 0.5 { -1.0 } else { 1.0 };
                    1.0 / (kink * (1.0 + side * 10f64.powf(-15.0 + 14.0 * uniform())))
                }
                _ => 10f64.powf(-8.0 + 11.0 * uniform()),
            };
            let p = if uniform() < 0.5 { -1.0 } else { 1.0 } * v * m / w;
            let half = s[n - 1];
            let c = m - p.abs() * half;
            let exact = physical_loop(c, p, &s);
            let Some(table) = physical_table(table, c, p, &s, length) else {
                assert!(exact[0] == 0.0, "the table skips a loaded roller at c = {c}, p = {p}");
                continue;
            };
            let h = 0.5 * length;
            let scale = [exact[0], exact[0] * h, exact[2], exact[2] * h, exact[4]];
            for k in 0..5 {
                let scale = if k == 4 && scale[4] == 0.0 {
                    exact[2] * h * h
                } else {
                    scale[k]
                };
                worst[k] = worst[k].max((table[k] - exact[k]).abs() / scale);
            }
        }
        worst
    }

    #[test]
    fn sums_by_table_are_within_2e10_of_the_lamina_loop() {
        for n in [1, 2, 5, 10, 20, 50] {
            let worst = worst_errors(n, 40_000);
            for (k, e) in worst.iter().enumerate() {
                assert!(*e < 2e-10, "{n} laminae, sum {k}: worst relative error {e:.2e}");
            }
        }
    }

    #[test]
    fn a_table_is_built_for_every_lamina_count_the_descriptions_allow_and_no_other() {
        let mut tables = RollerTables::default();
        assert!(tables.for_laminae(0).is_none());
        assert!(tables.for_laminae(MAX_LAMINAE + 1).is_none());
        let ten = tables.for_laminae(10).unwrap();
        assert_eq!(ten.laminae, 10);
        // one table per lamina count, shared
        assert!(Arc::ptr_eq(&ten, &tables.for_laminae(10).unwrap()));
    }
}
