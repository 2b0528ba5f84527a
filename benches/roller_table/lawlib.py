"""Normalised roller sums without crowning, n laminae, and the lamina loop they replace (benches/roller_table/study.py).

Pose (c, p), p >= 0 by symmetry. Lamina j counted from the MOST loaded end:
  s_j = (L/2 - w/2) - j*w,  sigma_j = s_j/(L/2) = (n-1-2j)/n
  m   = c + |p|(L/2 - w/2)        (approach of most loaded lamina)
  v   = |p| w / m,  u = 1/v       (kinks at u = 1..n-1, i.e. v = 1/j)
  delta_j = m (1 - j v)  -> loaded iff j < u
Normalised sums F (order E0, E1, S0, S1, S2):
  E0 = m^(10/9) F0, E1 = sgn(p) m^(10/9) (L/2) F1,
  S0 = m^(1/9) F2,  S1 = sgn(p) m^(1/9) (L/2) F3,  S2 = m^(1/9) (L/2)^2 F4
"""
import numpy as np

N = 10
B = 1.0 / 9.0
SIG = (N - 1 - 2 * np.arange(N)) / N
NAMES = ["E0", "E1", "S0", "S1", "S2"]


def sums_v(v, jlo=0, jhi=None, only_loaded=True):
    """Normalised sums over laminae j in [jlo, jhi) (per-point arrays allowed),
    restricted to loaded ones (1 - j v > 0)."""
    v = np.atleast_1d(np.asarray(v, float))
    j = np.arange(N)[:, None]
    x = 1.0 - j * v[None, :]
    mask = x > 0
    jlo = np.broadcast_to(np.asarray(jlo), v.shape)
    jhi = np.broadcast_to(np.asarray(N if jhi is None else jhi), v.shape)
    mask &= (j >= jlo[None, :]) & (j < jhi[None, :])
    xs = np.where(mask, x, 0.0)
    xb = np.where(mask, np.abs(xs) ** B, 0.0)
    xe = xb * xs
    sg = SIG[:, None]
    return np.array([xe.sum(0), (xe * sg).sum(0), xb.sum(0),
                     (xb * sg).sum(0), (xb * sg * sg).sum(0)])


def exact_cp(c, p, L):
    """Direct lamina loop (today's law), returns E0,E1,S0,S1,S2."""
    L = np.broadcast_to(np.asarray(L, float), c.shape)
    w = L / N
    S = -L[None, :] / 2 + (np.arange(N)[:, None] + 0.5) * w[None, :]
    d = c[None, :] + p[None, :] * S
    mask = d > 0
    dp = np.where(mask, d, 0.0)
    db = np.where(mask, dp ** B, 0.0)
    de = db * dp
    return np.array([de.sum(0), (de * S).sum(0), db.sum(0), (db * S).sum(0),
                     (db * S * S).sum(0)])


def errors(approx, ex):
    """Relative errors: even sums vs own value, odd vs E0*L/2 / S0*L/2
    (in normalised units L/2 = 1)."""
    e = np.empty_like(ex)
    e[0] = np.abs(approx[0] - ex[0]) / np.abs(ex[0])
    e[1] = np.abs(approx[1] - ex[1]) / np.abs(ex[0])
    e[2] = np.abs(approx[2] - ex[2]) / np.abs(ex[2])
    e[3] = np.abs(approx[3] - ex[3]) / np.abs(ex[2])
    e[4] = np.abs(approx[4] - ex[4]) / np.abs(ex[4])
    return e


def sweep_v():
    """Dense sweep over the whole loaded domain in v = |p|w/m in [0, inf).
    Includes points hugging every kink from both sides and extreme edge loading."""
    pts = [np.linspace(0, 1.0 / 16, 20001),
           1.0 / np.linspace(1.0, 16.0, 150001)]
    eps = 10.0 ** -np.arange(1, 15)
    for J in range(1, N):
        pts.append(1.0 / (J + eps))
        pts.append(1.0 / (J - eps))
    pts.append(np.array([1.0, 1.5, 3.0, 1e3, 1e12]))  # single lamina
    v = np.concatenate(pts)
    return v[v >= 0]
