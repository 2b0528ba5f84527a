"""Tables of the normalised roller sums (benches/roller_table/study.py): uniform Hermite and kink-aligned Chebyshev."""
import numpy as np
from numpy.polynomial import chebyshev as C
import lawlib as LL

N, B = LL.N, LL.B


# ---------------------------------------------------------------- (a) Hermite
def dsums_dv(v):
    """Derivative d/dv of the normalised sums (loaded laminae only)."""
    v = np.atleast_1d(v)
    j = np.arange(N)[:, None]
    x = 1.0 - j * v[None, :]
    mask = x > 0
    xs = np.where(mask, x, 1.0)
    de = np.where(mask, -j * (1 + B) * xs ** B, 0.0)
    db = np.where(mask, -j * B * xs ** (B - 1), 0.0)
    sg = LL.SIG[:, None]
    return np.array([de.sum(0), (de * sg).sum(0), db.sum(0), (db * sg).sum(0),
                     (db * sg * sg).sum(0)])


def hermite_uniform(var, nknots):
    """Uniform cubic Hermite, full sums (1 pow). var='b': b=a/(1+a), a=v*N/2,
    grid on [0,1]; var='v': grid on v in [0,1] (v>=1 constant)."""
    x = np.linspace(0, 1, nknots)
    if var == "b":
        xx = np.minimum(x, 1 - 1e-15)
        v = xx / (1 - xx) / (N / 2)
        dvdx = 1.0 / (1 - xx) ** 2 / (N / 2)
    else:
        v, dvdx = x, np.ones_like(x)
    f = LL.sums_v(v)
    df = dsums_dv(v) * dvdx
    df[:, -1] = 0 if var == "b" else df[:, -1]
    h = x[1] - x[0]

    def ev(vq):
        if var == "b":
            a = vq * (N / 2)
            xq = a / (1 + a)
        else:
            xq = np.minimum(vq, 1.0)
        i = np.minimum((xq / h).astype(int), nknots - 2)
        t = xq / h - i
        h00 = 2 * t**3 - 3 * t**2 + 1; h10 = t**3 - 2 * t**2 + t
        h01 = -2 * t**3 + 3 * t**2; h11 = t**3 - t**2
        return (h00 * f[:, i] + h10 * h * df[:, i] + h01 * f[:, i + 1]
                + h11 * h * df[:, i + 1])
    return ev, 2 * nknots


# --------------------------------------------- (b)/(c) kink-aligned Chebyshev
class KinkTable:
    """Cells uniform in u = 1/v on [1, U) with 2**s cells per unit (so every
    kink u = 1..N-1 is a knot), plus nv cells uniform in v on [0, 1/U].
    u < 1: one lamina, closed form.  Chebyshev degree d per cell.
    mode 'full'  : tabulate the whole sum (1 pow: m^(1/9) only)
    mode 'exact' : last loaded lamina J = min(floor(u), N-1) done exactly
                   (2nd pow), table holds the remainder (smooth on each cell)
    u1           : use 'exact' only for u < u1, 'full' for u >= u1."""

    def __init__(self, U=16, s=1, nv=2, d=7, mode="exact", u1=np.inf):
        self.U, self.s, self.nv, self.d = U, s, nv, d
        self.ncu = (U - 1) * 2**s
        self.u1 = u1 if mode == "exact" else -np.inf
        tn = np.cos(np.pi * (np.arange(d + 1) + 0.5) / (d + 1))
        coef, excl = [], []
        for i in range(self.ncu):
            lo = 1 + i / 2**s; hi = lo + 1 / 2**s
            J = min(int(np.floor(lo)), N - 1)
            ex = J if lo < self.u1 else N  # jhi: exclude lamina J (and above)
            uu = 0.5 * (lo + hi) + 0.5 * (hi - lo) * tn
            vals = LL.sums_v(1 / uu, 0, ex)
            coef.append(C.chebfit(tn, vals.T, d).T); excl.append(ex)
        for i in range(nv):
            lo = i / (U * nv); hi = (i + 1) / (U * nv)
            ex = N - 1 if U < self.u1 else N
            vv = 0.5 * (lo + hi) + 0.5 * (hi - lo) * tn
            vals = LL.sums_v(vv, 0, ex)
            coef.append(C.chebfit(tn, vals.T, d).T); excl.append(ex)
        self.coef = np.array(coef)        # (cells, 5, d+1)
        self.excl = np.array(excl)
        self.entries = self.coef.shape[0] * (d + 1)

    def __call__(self, v, xphys=None):
        """xphys(j, idx): delta_j/m computed from the physical pose as today's
        loop does (c + p*s_j)/m. If given, the lamina-J term uses it and the
        kink cell is chosen consistently with the sign of delta (no
        rounding mismatch between 'u' and the laminae's own signs)."""
        v = np.asarray(v, float)
        out = np.zeros((5, v.size))
        if xphys is not None:
            ii = np.arange(v.size)
            uu = 1.0 / np.where(v > 0, v, 1e-300)
            J0 = np.minimum(np.floor(uu), N - 1).astype(int)    # last loaded lamina per u
            near = uu < self.U
            up = near & (J0 < N - 1) & (xphys(np.minimum(J0 + 1, N - 1), ii) > 0)
            dn = near & (J0 >= 1) & (xphys(np.maximum(J0, 0), ii) <= 0)
            # put u just inside the cell whose last loaded lamina matches the signs
            v = np.where(up, np.nextafter(1.0 / (J0 + 1.0), 0), v)
            v = np.where(dn & ~up, np.nextafter(1.0 / np.maximum(J0, 1), np.inf), v)
        single = v > 1.0
        out[:, single] = LL.sums_v(np.zeros(single.sum()), 0, 1)  # lamina 0 only
        inu = (~single) & (v > 1.0 / self.U)
        inv = v <= 1.0 / self.U
        cell = np.zeros(v.size, int); t = np.zeros(v.size)
        u = 1.0 / np.where(inu, v, 1.0)
        x = (u - 1) * 2**self.s
        ci = np.minimum(np.floor(x).astype(int), self.ncu - 1)
        cell[inu] = ci[inu]; t[inu] = 2 * (x - ci)[inu] - 1
        y = v * self.U * self.nv
        cv = np.minimum(np.floor(y).astype(int), self.nv - 1)
        cell[inv] = self.ncu + cv[inv]; t[inv] = 2 * (y - cv)[inv] - 1
        act = ~single
        cf = self.coef[cell[act]]            # (k, 5, d+1)
        tt = t[act]
        b1 = np.zeros((5, tt.size)); b2 = np.zeros_like(b1)
        for k in range(self.d, 0, -1):       # Clenshaw
            b1, b2 = cf[:, :, k].T + 2 * tt * b1 - b2, b1
        val = cf[:, :, 0].T + tt * b1 - b2
        # exact lamina J (when excluded from table)
        ex = self.excl[cell[act]]
        J = ex                                # lamina index added exactly
        add = J < N
        va = v[act]
        xJ = np.where(add, 1.0 - J * va, 0.0)
        if xphys is not None:
            xJ = np.where(add, xphys(np.minimum(J, N - 1), np.flatnonzero(act)), 0.0)
        xJ = np.where(xJ > 0, xJ, 0.0)
        xb = np.where(xJ > 0, xJ ** B, 0.0)   # the 2nd pow
        xe = xb * xJ
        sg = LL.SIG[np.minimum(J, N - 1)]
        val += np.array([xe, xe * sg, xb, xb * sg, xb * sg * sg]) * add
        out[:, act] = val
        return out
