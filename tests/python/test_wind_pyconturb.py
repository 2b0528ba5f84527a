"""Our IEC full field (`windrive wind`) against an independent generator's: pyconturb (DTU's constrained
turbulence generator, from PyPI), unconstrained, with the same IEC 61400-1 ed. 3 model (Kaimal spectra, the
exponential coherence of u with L_c = 8.1·42 m, NTM σ1, power-law shear) on the same grid. Both draw random
phases, so u's statistics scatter from seed to seed; four seeds of each, and every comparison of a scattering
statistic is Welch's t at the 99.9 % level on the seeds' means (the seeds are fixed, so the test is
deterministic; the level says how unlikely a pass would be were the two generators' statistics different).
Our file is read by NREL's reader (openfast_io), not ours.

What must agree:
- every point's mean u, the power law (both exact; ours to the file's i16 quantisation);
- v and w: σ = 0.8σ1 and 0.5σ1 at every point (both exact to the spectrum's discretisation: 1e-3);
- u: σ over the grid (ours σ1 exactly by construction; pyconturb's scatters about it), the band-averaged
  spectrum over the points in four bands, and the co-coherence of points 15 and 30 m apart across the wind
  in four bands.
"""
import subprocess

import numpy as np
import pytest
from scipy import stats

from openfast_io.turbsim_file import TurbSimFile
from pyconturb import gen_spat_grid, gen_turb
from pyconturb.sig_models import iec_sig
from pyconturb.spectral_models import kaimal_spectrum
from pyconturb.wind_profiles import power_profile

WIND, HUB, CLASS, ALPHA = 11.4, 90.0, "B", 0.2
PERIOD, DT = 600.0, 1.0
Y = np.linspace(-30.0, 30.0, 5)  # 15 m apart across the wind
Z = np.linspace(60.0, 120.0, 5)  # all at or above 60 m: Λ1 = 42 m at every point in both models
SIGMA1 = {"A": 0.16, "B": 0.14, "C": 0.12}[CLASS] * (0.75 * WIND + 5.6)
SEEDS = (1, 2, 3, 4)
BANDS = ((1 / 600, 0.02), (0.02, 0.05), (0.05, 0.15), (0.15, 0.45))


def ours(windrive, seed, folder):
    """(u, v, w) as arrays [time, y, z] from `windrive wind`, read by openfast_io."""
    path = folder / f"ours-{seed}.bts"
    subprocess.run([str(windrive), "wind", "--out", str(path), "--wind", str(WIND),
                    "--hub-height", str(HUB), "--class", CLASS, "--shear", str(ALPHA), "--grid", "5",
                    "--width", "60", "--period", str(PERIOD), "--dt", str(DT), "--seed", str(seed)],
                   check=True, capture_output=True)  # fmt: skip
    ts = TurbSimFile(str(path))
    assert np.allclose(ts["y"], Y) and np.allclose(ts["z"], Z), (ts["y"], ts["z"])
    return [np.asarray(ts["u"][k], dtype=float) for k in range(3)]


def theirs(seed):
    """(u, v, w) as arrays [time, y, z] from pyconturb on the same grid."""
    spat = gen_spat_grid(Y, Z)
    turb = gen_turb(spat, T=PERIOD, nt=int(PERIOD / DT), u_ref=WIND, z_ref=HUB, alpha=ALPHA, turb_class=CLASS,
                    l_c=8.1 * 42.0, seed=seed, wsp_func=power_profile, sig_func=iec_sig, spec_func=kaimal_spectrum,
                    coh_model="iec")  # fmt: skip
    out = []
    for k, name in enumerate("uvw"):
        field = np.empty((len(turb), len(Y), len(Z)))
        for column in spat.columns:
            if int(spat.loc["k", column]) == k:
                iy = int(np.argmin(np.abs(Y - spat.loc["y", column])))
                iz = int(np.argmin(np.abs(Z - spat.loc["z", column])))
                field[:, iy, iz] = turb[f"{name}_{column.split('_')[1]}"].to_numpy()
        out.append(field)
    return out


def spectrum(u):
    """Frequencies and each point's Fourier coefficients of u's fluctuation [freq, y, z] (bin 0 dropped)."""
    x = np.fft.rfft(u - u.mean(axis=0), axis=0)[1:]
    return np.fft.rfftfreq(u.shape[0], DT)[1:], x


def u_statistics(u):
    """u's σ over the grid / σ1; its spectrum in each band over the whole, averaged over the points; and its
    co-coherence at 15 and 30 m across the wind in each band (summed over every pair and bin of the band)."""
    f, x = spectrum(u)
    power = np.abs(x) ** 2
    out = {"sigma": np.sqrt(u.var(axis=0).mean()) / SIGMA1}
    for lo, hi in BANDS:
        band = (f >= lo) & (f < hi)
        out[f"spectrum {lo:.3f}-{hi:.2f} Hz"] = power[band].sum() / power.sum()
        for gap in (1, 2):
            cross = (x[band, gap:, :] * np.conj(x[band, :-gap, :])).real.sum()
            norm = np.sqrt((power[band, gap:, :]).sum() * (power[band, :-gap, :]).sum())
            out[f"coherence {15 * gap} m, {lo:.3f}-{hi:.2f} Hz"] = cross / norm
    return out


@pytest.fixture(scope="module")
def fields(windrive, tmp_path_factory):
    folder = tmp_path_factory.mktemp("pyconturb")
    return [ours(windrive, s, folder) for s in SEEDS], [theirs(s) for s in SEEDS]


def test_means_and_the_lateral_components_agree(fields):
    profile = WIND * (Z / HUB) ** ALPHA
    for name, runs in zip(("ours", "pyconturb"), fields):
        for u, v, w in runs:
            assert np.allclose(u.mean(axis=0), profile[None, :], rtol=1e-3), name
            assert np.allclose(v.std(axis=0) / SIGMA1, 0.8, rtol=1e-3), name
            assert np.allclose(w.std(axis=0) / SIGMA1, 0.5, rtol=1e-3), name
            assert np.abs(v.mean(axis=0)).max() < 1e-3 * WIND and np.abs(w.mean(axis=0)).max() < 1e-3 * WIND, name


def test_u_has_the_same_statistics_as_pyconturbs(fields):
    ours_stats = [u_statistics(u) for u, _, _ in fields[0]]
    their_stats = [u_statistics(u) for u, _, _ in fields[1]]
    # ours holds σ1 over the grid exactly; pyconturb's scatters about it
    assert all(abs(s["sigma"] - 1.0) < 1e-3 for s in ours_stats)
    sigma = np.array([s["sigma"] for s in their_stats])
    assert stats.ttest_1samp(sigma, 1.0).pvalue > 1e-3, sigma
    for key in [k for k in their_stats[0] if k != "sigma"]:
        a = np.array([s[key] for s in ours_stats])
        b = np.array([s[key] for s in their_stats])
        t = stats.ttest_ind(a, b, equal_var=False)
        assert t.pvalue > 1e-3, f"{key}: ours {a.mean():.4f} ± {a.std(ddof=1):.4f}, pyconturb {b.mean():.4f} ± {b.std(ddof=1):.4f}"
    # the coherence falls with distance and frequency in both, as IEC's does
    for run in (ours_stats, their_stats):
        lo, hi = BANDS[0], BANDS[-1]
        assert np.mean([s[f"coherence 15 m, {lo[0]:.3f}-{lo[1]:.2f} Hz"] for s in run]) > \
            np.mean([s[f"coherence 30 m, {lo[0]:.3f}-{lo[1]:.2f} Hz"] for s in run]) > \
            np.mean([s[f"coherence 30 m, {hi[0]:.3f}-{hi[1]:.2f} Hz"] for s in run])
