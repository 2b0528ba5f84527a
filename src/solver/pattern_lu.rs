//! LU on the iteration matrix's own sparsity. A multibody gearbox's J couples each body to the few it
//! touches through bearings and meshes: the GRC's 84-DOF J has 1105 non-zero entries of 7056. Ordered
//! by minimum degree, its factors hold 1330 entries and its elimination takes 8.2 k multiply–adds
//! against dense LU's 198 k (n³/3), and a solve visits 1330 entries instead of 7056 (docs/PERFORMANCE.md, "J by its
//! own pattern").
//!
//! [`Ordering`] is the symbolic part: J's non-zero pattern made symmetric (J + Jᵀ: mechanical
//! systems couple both ways), its elimination order by minimum degree (ties to the lower index) and
//! the entries the elimination fills. It depends on the pattern alone, so the same pattern gives the
//! same order and the same bits whichever J it was first met with; the integrator keeps one while J's
//! pattern stays within it ([`Orderings`](super::factor::Orderings)). [`PatternLu`] is the numeric part: the elimination on
//! those entries only, without row exchanges. That is stable for the (nearly) symmetric positive
//! definite iteration matrices of mechanical systems (c_M·M + c_C·C + c_K·K with M positive definite);
//! for any other, every factorisation is probed: one solve's backward error must stay within
//! [`PROBE_BACKWARD_ERROR`], else the factorisation is refused and the caller takes dense LU with
//! partial pivoting.

use super::norms::max_abs;
use nalgebra::DMatrix;
use std::sync::Arc;

/// Largest normwise backward error ‖J·x − b‖∞ / (‖J‖∞·‖x‖∞ + ‖b‖∞) of the probe's solve: a stable
/// elimination gives about n·ε (1e-14 here); 1e-10 refuses only element growth of 10⁴ and more.
pub const PROBE_BACKWARD_ERROR: f64 = 1e-10;

/// Solves of up to this many DOFs keep their permuted right-hand side on the stack.
const STACK_DOFS: usize = 128;

/// The symbolic factorisation of one symmetric non-zero pattern.
#[derive(Debug, PartialEq)]
pub struct Ordering {
    n: usize,
    /// J's pattern it was made for (from [`pattern`]).
    pattern: Vec<u64>,
    /// order[k]: the DOF eliminated k-th; position[order[k]] = k.
    order: Vec<usize>,
    position: Vec<usize>,
    /// below[starts[k]..starts[k + 1]]: the positions (in elimination order, ascending) of the
    /// entries of L's column k below the diagonal, which are also U's row k right of it.
    starts: Vec<usize>,
    below: Vec<usize>,
    /// The same entries of L by rows: left[left_starts[i]..left_starts[i + 1]] the positions k < i
    /// (ascending) of the columns that hold row i, and left_entry the index of each such entry in
    /// `below` (and so in L's columns).
    left_starts: Vec<usize>,
    left: Vec<usize>,
    left_entry: Vec<usize>,
}

/// Bits per word of a pattern column.
const WORD: usize = 64;

fn words(n: usize) -> usize {
    n.div_ceil(WORD)
}

/// J's non-zero pattern: column c's rows as bits, `words(n)` u64 per column (NaN counts as
/// non-zero). On x86_64 four entries at a time with AVX where the CPU has it: the scan reads every
/// entry of J at each factorisation, as many as the gather and the elimination together.
pub fn pattern(j: &DMatrix<f64>) -> Vec<u64> {
    let n = j.nrows();
    let w = words(n);
    let mut bits = vec![0u64; n * w];
    for (column, out) in j.as_slice().chunks_exact(n).zip(bits.chunks_exact_mut(w)) {
        for (rows, word) in column.chunks(WORD).zip(out.iter_mut()) {
            *word = nonzero_bits(rows);
        }
    }
    bits
}

/// Bit r set where rows[r] is not zero (up to 64 rows).
fn nonzero_bits(rows: &[f64]) -> u64 {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the CPU has AVX.
        return unsafe { nonzero_bits_avx(rows) };
    }
    rows.iter()
        .enumerate()
        .fold(0, |b, (r, x)| b | (u64::from(*x != 0.0) << r))
}

/// [`nonzero_bits`] four rows per comparison (not-equal or unordered: NaN is non-zero, as `!=` says).
///
/// # Safety
/// The CPU has AVX.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
unsafe fn nonzero_bits_avx(rows: &[f64]) -> u64 {
    use std::arch::x86_64::{_CMP_NEQ_UQ, _mm256_cmp_pd, _mm256_loadu_pd, _mm256_movemask_pd, _mm256_setzero_pd};
    let quads = rows.chunks_exact(4);
    let tail = quads.remainder();
    let mut bits = 0u64;
    for (q, four) in quads.enumerate() {
        // SAFETY: `four` holds four f64; the CPU has AVX (the caller's contract).
        let mask = unsafe {
            _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_NEQ_UQ>(
                _mm256_loadu_pd(four.as_ptr()),
                _mm256_setzero_pd(),
            ))
        };
        bits |= (mask as u64) << (4 * q);
    }
    let first = rows.len() - tail.len();
    tail.iter()
        .enumerate()
        .fold(bits, |b, (r, x)| b | (u64::from(*x != 0.0) << (first + r)))
}

/// Whether bit i of a bitset is set.
fn bit(set: &[u64], i: usize) -> bool {
    set[i / WORD] & (1 << (i % WORD)) != 0
}

/// Whether a pattern of `w` words a column (from [`pattern`]) has the entry (row, column).
fn has(bits: &[u64], w: usize, row: usize, column: usize) -> bool {
    bit(&bits[column * w..(column + 1) * w], row)
}

impl Ordering {
    /// Minimum-degree order of J's pattern (from [`pattern`]) made symmetric, and the fill its
    /// elimination makes: eliminating a DOF joins its remaining neighbours to one another, and those
    /// neighbours are its column of L and its row of U.
    pub fn new(n: usize, pattern: Vec<u64>) -> Self {
        let w = words(n);
        assert_eq!(pattern.len(), n * w, "a pattern of {n} columns");
        // the symmetric graph: J + Jᵀ's pattern without the diagonal
        let mut graph = vec![0u64; n * w];
        for c in 0..n {
            for r in 0..n {
                if r != c && (has(&pattern, w, r, c) || has(&pattern, w, c, r)) {
                    graph[c * w + r / WORD] |= 1 << (r % WORD);
                }
            }
        }
        let mut alive = vec![0u64; w];
        for i in 0..n {
            alive[i / WORD] |= 1 << (i % WORD);
        }
        let degree = |graph: &[u64], alive: &[u64], i: usize| -> u32 {
            graph[i * w..(i + 1) * w]
                .iter()
                .zip(alive)
                .map(|(g, a)| (g & a).count_ones())
                .sum()
        };
        let mut order = Vec::with_capacity(n);
        let mut neighbours_of = Vec::with_capacity(n);
        let mut neighbours = vec![0u64; w];
        for _ in 0..n {
            let v = (0..n)
                .filter(|&i| bit(&alive, i))
                .min_by_key(|&i| (degree(&graph, &alive, i), i))
                .expect("a DOF left to eliminate");
            alive[v / WORD] &= !(1 << (v % WORD));
            for k in 0..w {
                neighbours[k] = graph[v * w + k] & alive[k];
            }
            let list: Vec<usize> = (0..n).filter(|&i| bit(&neighbours, i)).collect();
            for &a in &list {
                for k in 0..w {
                    graph[a * w + k] |= neighbours[k];
                }
                graph[a * w + a / WORD] &= !(1 << (a % WORD));
            }
            order.push(v);
            neighbours_of.push(list);
        }
        let mut position = vec![0; n];
        for (k, &v) in order.iter().enumerate() {
            position[v] = k;
        }
        let mut starts = Vec::with_capacity(n + 1);
        let mut below = Vec::new();
        starts.push(0);
        for list in neighbours_of {
            let first = below.len();
            below.extend(list.iter().map(|&i| position[i]));
            below[first..].sort_unstable();
            starts.push(below.len());
        }
        // L's rows from its columns: the columns in ascending order leave each row's list ascending
        let mut left_starts = vec![0; n + 1];
        for &i in &below {
            left_starts[i + 1] += 1;
        }
        for i in 0..n {
            left_starts[i + 1] += left_starts[i];
        }
        let mut next = left_starts.clone();
        let (mut left, mut left_entry) = (vec![0; below.len()], vec![0; below.len()]);
        for k in 0..n {
            for (p, &i) in below.iter().enumerate().take(starts[k + 1]).skip(starts[k]) {
                left[next[i]] = k;
                left_entry[next[i]] = p;
                next[i] += 1;
            }
        }
        Self {
            n,
            pattern,
            order,
            position,
            starts,
            below,
            left_starts,
            left,
            left_entry,
        }
    }

    /// Whether every entry of `pattern` (from [`pattern`], of as many DOFs) is in this ordering's.
    pub fn covers(&self, pattern: &[u64]) -> bool {
        self.pattern.len() == pattern.len() && self.pattern.iter().zip(pattern).all(|(o, p)| p & !o == 0)
    }

    /// `each(row, column, entry)` for the entries of `j` (column-major, n × n) in this ordering's
    /// pattern, column by column and down each column: every non-zero entry of a J the ordering
    /// covers, and no other but zeros.
    #[inline(always)]
    fn each_entry(&self, j: &[f64], mut each: impl FnMut(usize, usize, f64)) {
        let (n, w) = (self.n, words(self.n));
        for (c, column) in j.chunks_exact(n).enumerate() {
            for (word, &mask) in self.pattern[c * w..(c + 1) * w].iter().enumerate() {
                let mut bits = mask;
                while bits != 0 {
                    let r = word * WORD + bits.trailing_zeros() as usize;
                    each(r, c, column[r]);
                    bits &= bits - 1;
                }
            }
        }
    }

    /// `pattern` ∪ this ordering's pattern, into `pattern`.
    pub fn add_pattern_to(&self, pattern: &mut [u64]) {
        for (p, o) in pattern.iter_mut().zip(&self.pattern) {
            *p |= o;
        }
    }

    pub fn dofs(&self) -> usize {
        self.n
    }

    /// Multiply–adds of the elimination (each L entry's scaling counted as one).
    pub fn flops(&self) -> usize {
        (0..self.n)
            .map(|k| {
                let m = self.starts[k + 1] - self.starts[k];
                m + m * m
            })
            .sum()
    }

    /// Dense LU's multiply–adds for the same size: n³/3.
    pub fn dense_flops(&self) -> usize {
        self.n * self.n * self.n / 3
    }

    fn below(&self, k: usize) -> &[usize] {
        &self.below[self.starts[k]..self.starts[k + 1]]
    }
}

/// The elimination in `a` (J in elimination order, column-major): per column, L's column scaled by
/// the pivot's reciprocal, then each column of U's row updated by y − l·u on L's column's rows.
/// L's columns, U's rows and the reciprocals of U's diagonal packed as [`PatternLu`] keeps them; None
/// at a zero or non-finite pivot.
#[allow(clippy::type_complexity)]
fn eliminate(o: &Ordering, a: &mut [f64]) -> Option<(Vec<f64>, Vec<f64>, Vec<f64>)> {
    let n = o.n;
    let mut l = vec![0.0; o.below.len()];
    let mut u = vec![0.0; o.below.len()];
    let mut inverse_pivots = vec![0.0; n];
    for k in 0..n {
        let pivot = a[k * n + k];
        if pivot == 0.0 || !pivot.is_finite() {
            return None;
        }
        let (rows, span) = (o.below(k), o.starts[k]..o.starts[k + 1]);
        let lk = &mut l[span.clone()];
        let inv = 1.0 / pivot;
        inverse_pivots[k] = inv;
        let pivot_column = &a[k * n..(k + 1) * n];
        for (li, &i) in lk.iter_mut().zip(rows) {
            *li = pivot_column[i] * inv;
        }
        for (u_kc, &c) in u[span].iter_mut().zip(rows) {
            let column = &mut a[c * n..(c + 1) * n];
            let ukc = column[k];
            *u_kc = ukc;
            if ukc == 0.0 {
                continue;
            }
            for (li, &i) in lk.iter().zip(rows) {
                // SAFETY: every entry of `below` is a position < n (`Ordering::new`), and the column
                // has n entries (unchecked: a tenth fewer instructions per factorisation)
                unsafe { *column.get_unchecked_mut(i) -= li * ukc };
            }
        }
    }
    Some((l, u, inverse_pivots))
}

/// J = Pᵀ·L·U·P with P the ordering's permutation. L's rows and U's rows are packed beside the
/// ordering's lists (`l[left_starts[i]..left_starts[i + 1]]`: L's row i at the positions `left`,
/// `u[starts[k]..starts[k + 1]]`: U's row k at the positions `below(k)`), the reciprocals of U's
/// diagonal apart: a solve visits the factors' entries and nothing else.
#[derive(Debug, Clone)]
pub struct PatternLu {
    ordering: Arc<Ordering>,
    l: Vec<f64>,
    u: Vec<f64>,
    inverse_pivots: Vec<f64>,
}

impl PatternLu {
    /// Factorises `j` on `ordering` (made for its pattern); None when a pivot is zero or not finite,
    /// or when the probe's backward error says the elimination without row exchanges is unstable.
    /// `scratch` is n×n zeros on entry and on return (its factors' entries are zeroed after use, so
    /// no factorisation clears the whole array).
    pub fn new(j: &DMatrix<f64>, ordering: Arc<Ordering>, scratch: &mut Vec<f64>) -> Option<Self> {
        Self::unprobed(j, ordering, scratch)?.probed(j)
    }

    /// [`Self::new`] without the probe: None only at a zero or non-finite pivot.
    fn unprobed(j: &DMatrix<f64>, ordering: Arc<Ordering>, scratch: &mut Vec<f64>) -> Option<Self> {
        let o = &*ordering;
        let n = o.n;
        assert_eq!((j.nrows(), j.ncols()), (n, n), "a {n}×{n} matrix for this ordering");
        scratch.resize(n * n, 0.0);
        let a = &mut scratch[..];
        // J's non-zero entries in elimination order, column-major, by the pattern's bits
        o.each_entry(j.as_slice(), |r, c, x| a[o.position[c] * n + o.position[r]] = x);
        let factors = eliminate(o, a);
        // the factors' entries back to zero: the scratch is all zeros again
        for k in 0..n {
            a[k * n + k] = 0.0;
            for &i in o.below(k) {
                a[k * n + i] = 0.0;
                a[i * n + k] = 0.0;
            }
        }
        let (by_columns, u, inverse_pivots) = factors?;
        let l = o.left_entry.iter().map(|&p| by_columns[p]).collect();
        Some(Self {
            ordering,
            l,
            u,
            inverse_pivots,
        })
    }

    /// Self when one solve of J·x = J·1 has a backward error within [`PROBE_BACKWARD_ERROR`].
    fn probed(self, j: &DMatrix<f64>) -> Option<Self> {
        let (residual, scale) = self.probe(j);
        (residual <= PROBE_BACKWARD_ERROR * scale).then_some(self)
    }

    /// The probe's ‖J·x − b‖∞ (NaN when any entry of the residual is not finite) and its scale
    /// ‖J‖∞·‖x‖∞ + ‖b‖∞, for x = J⁻¹·b by these factors and b = J·1. The products run over the
    /// ordering's pattern, a sixth of the GRC's J, not over all of it: the entries left out are
    /// zeros, whose terms (±0) leave every sum as it is but for the sign of a zero one, which the
    /// magnitudes drop, and a non-finite x meets J's diagonal (every pivot was non-zero), so both
    /// figures are a dense pass's to the bit (`the_probe_over_the_pattern_is_the_dense_probe`).
    fn probe(&self, j: &DMatrix<f64>) -> (f64, f64) {
        let o = &*self.ordering;
        let n = o.n;
        let js = j.as_slice();
        // b = J·1 and ‖J‖∞ (the largest row sum of magnitudes), column by column
        let mut b = vec![0.0; n];
        let mut row_sums = vec![0.0f64; n];
        o.each_entry(js, |r, _, x| {
            b[r] += x;
            row_sums[r] += x.abs();
        });
        let mut x = vec![0.0; n];
        self.add_solution(&b, &mut x);
        // r = J·x − b
        let mut r: Vec<f64> = b.iter().map(|bi| -bi).collect();
        o.each_entry(js, |i, c, a| r[i] += a * x[c]);
        let scale = row_sums.iter().fold(0.0f64, |m, x| m.max(*x)) * max_abs(&x) + max_abs(&b);
        let residual = if r.iter().all(|x| x.is_finite()) {
            max_abs(&r)
        } else {
            f64::NAN
        };
        (residual, scale)
    }

    /// x += J⁻¹·r
    pub fn add_solution(&self, r: &[f64], x: &mut [f64]) {
        assert_eq!(x.len(), r.len());
        self.with_solution(r, |y, order| {
            for (yk, &i) in y.iter().zip(order) {
                x[i] += yk;
            }
        })
    }

    /// J⁻¹·r in elimination order, handed to `take` with the order (on the stack up to
    /// [`STACK_DOFS`]: a Newton iteration solves once and allocates nothing).
    #[inline(always)]
    fn with_solution(&self, r: &[f64], take: impl FnOnce(&[f64], &[usize])) {
        let n = self.ordering.n;
        assert_eq!(r.len(), n);
        let mut stack = [0.0; STACK_DOFS];
        let mut heap = Vec::new();
        let y: &mut [f64] = if n <= STACK_DOFS {
            &mut stack[..n]
        } else {
            heap.resize(n, 0.0);
            &mut heap
        };
        for (yk, &i) in y.iter_mut().zip(&self.ordering.order) {
            *yk = r[i];
        }
        self.substitute(y);
        take(y, &self.ordering.order)
    }

    /// L·U·y = y in elimination order: forward by L's rows from the first, back by U's rows from the
    /// last. Without bounds checks: most rows have a few entries or none, and the checks of each
    /// row's slices and of each y index were half a solve's instructions.
    ///
    /// Both sweeps sum a row's terms in a register, the values solved longest ago first (L's row from
    /// its first column, U's from its last), and the back substitution multiplies by the pivot's
    /// reciprocal: consecutive rows' chains of dependent subtractions then overlap in the CPU, where
    /// the forward sweep by L's columns updated each value in memory once per column and the back
    /// substitution from the first column began each row's chain with the value the row before it
    /// had only just produced, and a multiplication waits a quarter as long as a division (`windrive
    /// bench solvers`, docs/PERFORMANCE.md; the back substitution's order rounds differently, as
    /// stably; the forward sweep subtracts in the columns' order as before).
    #[inline(always)]
    fn substitute(&self, y: &mut [f64]) {
        let o = &self.ordering;
        let n = o.n;
        assert!(
            y.len() == n
                && o.starts.len() == n + 1
                && o.left_starts.len() == n + 1
                && o.left.len() == o.below.len()
                && self.l.len() == o.below.len()
                && self.u.len() == o.below.len()
                && self.inverse_pivots.len() == n
        );
        // SAFETY (every unchecked access below): `starts` and `left_starts` rise from 0 to below.len()
        // (`Ordering::new`), so each span lies within `below`, `left`, `l` and `u` (asserted of equal
        // length); every entry of `below` and `left` is a position < n and y and the pivots'
        // reciprocals have n entries; i, k < n.
        unsafe {
            for i in 0..n {
                let span = *o.left_starts.get_unchecked(i)..*o.left_starts.get_unchecked(i + 1);
                if span.is_empty() {
                    continue;
                }
                let mut s = *y.get_unchecked(i);
                let columns = o.left.get_unchecked(span.clone());
                for (li, &k) in self.l.get_unchecked(span).iter().zip(columns) {
                    s -= li * *y.get_unchecked(k);
                }
                *y.get_unchecked_mut(i) = s;
            }
            for k in (0..n).rev() {
                let span = *o.starts.get_unchecked(k)..*o.starts.get_unchecked(k + 1);
                let mut s = *y.get_unchecked(k);
                let columns = o.below.get_unchecked(span.clone());
                for (uc, &c) in self.u.get_unchecked(span).iter().zip(columns).rev() {
                    s -= uc * *y.get_unchecked(c);
                }
                *y.get_unchecked_mut(k) = s * self.inverse_pivots.get_unchecked(k);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::factor::block_sparse;
    use crate::solver::lu::DenseLu;

    fn ordering_of(j: &DMatrix<f64>) -> Arc<Ordering> {
        Arc::new(Ordering::new(j.nrows(), pattern(j)))
    }

    /// The solution agrees with dense LU's within rounding on gearbox-shaped matrices of 1–40
    /// bodies, made unsymmetric in value (not in pattern) by a damping-like skew.
    #[test]
    fn solves_as_dense_lu_does() {
        for bodies in [1, 2, 5, 14, 22, 40] {
            let mut j = block_sparse(bodies, 7);
            let n = j.nrows();
            for c in 0..n {
                for r in 0..c {
                    if j[(r, c)] != 0.0 {
                        j[(r, c)] *= 1.1;
                    }
                }
            }
            let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
            let mut ours = vec![0.0; n];
            PatternLu::new(&j, ordering_of(&j), &mut Vec::new())
                .unwrap()
                .add_solution(&b, &mut ours);
            let mut dense = b.clone();
            DenseLu::new(j.clone()).unwrap().solve_in_place(&mut dense);
            let scale = max_abs(&dense);
            for (a, d) in ours.iter().zip(&dense) {
                assert!((a - d).abs() <= 1e-12 * scale, "{bodies} bodies: {a} against {d}");
            }
        }
    }

    /// A body coupled to the next and to a carrier: minimum degree eliminates the chain's ends
    /// first and fills far less than the natural order, and far less than dense.
    #[test]
    fn minimum_degree_keeps_the_fill_small() {
        let j = block_sparse(14, 3);
        let o = ordering_of(&j);
        assert_eq!(o.dofs(), 84);
        let mut order = o.order.clone();
        order.sort_unstable();
        assert_eq!(order, (0..84).collect::<Vec<_>>(), "a permutation");
        assert!(o.flops() * 4 < o.dense_flops(), "{} of {}", o.flops(), o.dense_flops());
        // every entry of the pattern is inside the factors' pattern
        let w = words(84);
        for r in 0..84 {
            for c in 0..84 {
                if has(&o.pattern, w, r, c) && r != c {
                    let (pr, pc) = (
                        o.order.iter().position(|&x| x == r).unwrap(),
                        o.order.iter().position(|&x| x == c).unwrap(),
                    );
                    let (lo, hi) = (pr.min(pc), pr.max(pc));
                    assert!(o.below(lo).contains(&hi), "J[{r},{c}] outside the factors");
                }
            }
        }
    }

    /// The ordering is the pattern's, not the values': two matrices of one pattern share it; a new
    /// entry is not covered, and a pattern with entries left out is.
    #[test]
    fn the_ordering_follows_the_pattern_alone() {
        let a = block_sparse(6, 1);
        let b = block_sparse(6, 2);
        assert!(ordering_of(&a).covers(&pattern(&b)));
        assert_eq!(*ordering_of(&a), *ordering_of(&b));
        let mut c = b.clone();
        c[(7, 35)] = 1.0; // body 1 with body 5: not coupled before
        assert!(!ordering_of(&a).covers(&pattern(&c)));
        let mut d = b.clone();
        d[(6, 0)] = 0.0;
        assert!(ordering_of(&a).covers(&pattern(&d)));
        let mut union = pattern(&d);
        ordering_of(&c).add_pattern_to(&mut union);
        assert_eq!(union, pattern(&c));
    }

    /// The scratch comes back all zeros, after a factorisation and after a refused one, so the next
    /// factorisation on it gives the bits a fresh scratch gives.
    #[test]
    fn the_scratch_is_left_zero() {
        let j = block_sparse(9, 5);
        let o = ordering_of(&j);
        let mut scratch = Vec::new();
        let first = PatternLu::new(&j, o.clone(), &mut scratch).unwrap();
        assert!(scratch.iter().all(|x| *x == 0.0));
        let mut singular = j.clone();
        for c in 0..singular.ncols() {
            singular[(0, c)] = 0.0;
            singular[(c, 0)] = 0.0;
        }
        assert!(PatternLu::new(&singular, o.clone(), &mut scratch).is_none());
        assert!(scratch.iter().all(|x| *x == 0.0));
        let again = PatternLu::new(&j, o, &mut scratch).unwrap();
        let bits = |f: &PatternLu| {
            f.l.iter()
                .chain(&f.u)
                .chain(&f.inverse_pivots)
                .map(|x| x.to_bits())
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&first), bits(&again));
    }

    /// The probe over the ordering's pattern gives the residual and scale of a dense pass over J to
    /// the bit: on gearbox-shaped matrices, on an ordering wider than J's own pattern, with a NaN
    /// entry in J, and on a small pivot that only the probe refuses.
    #[test]
    fn the_probe_over_the_pattern_is_the_dense_probe() {
        let dense_probe = |f: &PatternLu, j: &DMatrix<f64>| {
            let n = j.nrows();
            let ones = DMatrix::from_element(n, 1, 1.0);
            let b: Vec<f64> = (j * ones).iter().copied().collect();
            let mut x = vec![0.0; n];
            f.add_solution(&b, &mut x);
            let r: Vec<f64> = (0..n)
                .map(|i| (0..n).fold(-b[i], |s, c| s + j[(i, c)] * x[c]))
                .collect();
            let norm = (0..n)
                .map(|i| (0..n).fold(0.0, |s, c| s + j[(i, c)].abs()))
                .fold(0.0f64, f64::max);
            let residual = if r.iter().all(|x| x.is_finite()) {
                max_abs(&r)
            } else {
                f64::NAN
            };
            (residual, norm * max_abs(&x) + max_abs(&b))
        };
        let same = |a: (f64, f64), b: (f64, f64)| a.0.to_bits() == b.0.to_bits() && a.1.to_bits() == b.1.to_bits();
        let wider = block_sparse(6, 2);
        let mut cases = vec![
            (block_sparse(14, 3), None),
            (block_sparse(6, 1), Some(ordering_of(&wider))),
        ];
        let mut skewed = block_sparse(5, 4);
        for c in 0..skewed.ncols() {
            for r in 0..c {
                skewed[(r, c)] *= 1.3;
            }
        }
        cases.push((skewed, None));
        for (j, ordering) in cases {
            let o = ordering.unwrap_or_else(|| ordering_of(&j));
            let f = PatternLu::new(&j, o.clone(), &mut Vec::new()).unwrap();
            assert!(
                same(f.probe(&j), dense_probe(&f, &j)),
                "{:?} against {:?}",
                f.probe(&j),
                dense_probe(&f, &j)
            );
            // a NaN in an entry of the pattern: both residuals NaN
            let mut poisoned = j.clone();
            poisoned[(3, 3)] = f64::NAN;
            assert!(f.probe(&poisoned).0.is_nan() && dense_probe(&f, &poisoned).0.is_nan());
        }
        // a small pivot that the elimination passes and the probe refuses (growth 1e12)
        let tiny = DMatrix::from_row_slice(2, 2, &[1e-12, 1.0, 1.0, 1.0]);
        let f = PatternLu::unprobed(&tiny, ordering_of(&tiny), &mut Vec::new()).expect("non-zero pivots");
        assert!(same(f.probe(&tiny), dense_probe(&f, &tiny)));
        assert!(f.probe(&tiny).0 > PROBE_BACKWARD_ERROR * f.probe(&tiny).1, "refused");
        assert!(PatternLu::new(&tiny, ordering_of(&tiny), &mut Vec::new()).is_none());
    }

    /// Where elimination without row exchanges breaks down, the factorisation is refused rather
    /// than wrong: a zero pivot, and a tiny pivot that makes the factors grow.
    #[test]
    fn unstable_eliminations_are_refused() {
        let zero = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 1.0, 0.0]);
        assert!(PatternLu::new(&zero, ordering_of(&zero), &mut Vec::new()).is_none());
        let tiny = DMatrix::from_row_slice(3, 3, &[1e-17, 1.0, 1.0, 1.0, 1.0, 2.0, 1.0, 2.0, 1.0]);
        assert!(DenseLu::new(tiny.clone()).is_some(), "regular: dense LU pivots");
        assert!(PatternLu::new(&tiny, ordering_of(&tiny), &mut Vec::new()).is_none());
    }
}
