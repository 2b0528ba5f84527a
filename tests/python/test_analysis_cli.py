"""The analysis commands against independent evaluations: `rainflow --matrix` and `del --goodman`
against the `rainflow` package's cycles binned / corrected with NumPy, `spectrum` against known sines,
`ldd` against its definition, `life` against a direct lifetime-DEL evaluation, `campbell` against the
thesis's printed mesh orders, and bad input named."""

import json
import subprocess

import numpy as np
import pytest
import rainflow

from test_rainflow import write_csv, windrive_json


@pytest.mark.parametrize("bins,shape", [("12", (12, 12)), ("10,16", (10, 16))])
def test_range_mean_matrix_equals_numpy_histogram(windrive, tmp_path, bins, shape):
    rng = np.random.default_rng(11)
    t = np.arange(5000) * 0.01
    x = np.cumsum(rng.normal(size=t.size))
    path = tmp_path / "m.csv"
    write_csv(path, t, {"x": x})
    m = windrive_json(windrive, "rainflow", str(path), "--channel", "x", "--matrix", "range-mean", "--bins", bins)["matrix"]
    assert np.array(m["counts"]).shape == shape
    c = np.array([[r, mean, n] for r, mean, n, _, _ in rainflow.extract_cycles(x.tolist())])
    rows, cols = m["rows"], m["cols"]
    h, _, _ = np.histogram2d(c[:, 0], c[:, 1], bins=[np.linspace(rows[0], rows[1], rows[2] + 1),
                                                      np.linspace(cols[0], cols[1], cols[2] + 1)], weights=c[:, 2])
    assert rows[0] == 0 and rows[1] == pytest.approx(c[:, 0].max(), rel=1e-12)
    assert np.allclose(np.array(m["counts"]), h, atol=1e-12)


def test_from_to_matrix_conserves_counts(windrive, tmp_path):
    x = np.array([-2.0, 1, -3, 5, -1, 3, -4, 4, -2])
    path = tmp_path / "ft.csv"
    write_csv(path, np.arange(x.size), {"x": x})
    m = windrive_json(windrive, "rainflow", str(path), "--channel", "x", "--matrix", "from-to", "--bins", "9")["matrix"]
    assert np.sum(m["counts"]) == pytest.approx(0.5 + 1.5 + 0.5 + 1.0 + 0.5)


def test_goodman_del_equals_numpy(windrive, tmp_path):
    """MLife's correction L_RF = L_R (L_ult − |L_MF|)/(L_ult − |L_M|) on the package's cycles."""
    rng = np.random.default_rng(3)
    t = np.arange(8000) * 0.01
    x = 20 + np.cumsum(rng.normal(size=t.size)) * 0.5
    path = tmp_path / "g.csv"
    write_csv(path, t, {"x": x})
    ult, fixed = 200.0, 5.0
    ours = windrive_json(windrive, "del", str(path), "--channel", "x", "--m", "4", "--goodman", str(ult),
                         "--fixed-mean", str(fixed))["del"]["4"]
    c = np.array([[r, mean, n] for r, mean, n, _, _ in rainflow.extract_cycles(x.tolist())])
    corrected = c[:, 0] * (ult - abs(fixed)) / (ult - np.abs(c[:, 1]))
    expected = (np.sum(c[:, 2] * corrected ** 4) / (t[-1] - t[0])) ** 0.25
    assert ours == pytest.approx(expected, rel=1e-12)


def test_spectrum_peaks_of_two_sines(windrive, tmp_path):
    t = np.arange(40000) * 1e-3
    x = 3.0 * np.sin(2 * np.pi * 2.61 * t) + 0.5 * np.sin(2 * np.pi * 17.3 * t) + 4 * t
    path = tmp_path / "s.csv"
    write_csv(path, t, {"hss": x})
    r = windrive_json(windrive, "spectrum", str(path), "--channel", "hss", "--peaks", "2", "--band", "0.5,100")
    (f1, a1), (f2, a2) = r["peaks"]
    # Hann window, 40 s: resolution 0.025 Hz, the parabolic refinement lands within a few mHz
    assert f1 == pytest.approx(2.61, abs=0.005) and a1 == pytest.approx(3.0, rel=0.03)
    assert f2 == pytest.approx(17.3, abs=0.005) and a2 == pytest.approx(0.5, rel=0.03)
    assert r["resolution"] == pytest.approx(1 / (t[-1] - t[0] + 1e-3), rel=1e-3)


def test_ldd_totals(windrive, tmp_path):
    rng = np.random.default_rng(5)
    t = np.arange(3000) * 0.01
    load = 100 + 10 * rng.normal(size=t.size)
    speed = 150 + rng.normal(size=t.size)
    path = tmp_path / "l.csv"
    write_csv(path, t, {"load": load, "w": speed})
    bins = np.array(windrive_json(windrive, "ldd", str(path), "--channel", "load", "--speed", "w", "--bins", "7")["bins"])
    assert bins[:, 1].sum() == pytest.approx(t[-1] - t[0], rel=1e-12)
    assert bins[:, 2].sum() == pytest.approx(np.sum(np.diff(t) * np.abs(speed[:-1])) / (2 * np.pi), rel=1e-12)


def test_life_dels_equal_a_direct_lifetime_evaluation(windrive, tmp_path):
    """DEL_life = [(Σ_normal n S^m · T_op/T_n + Σ_shutdown n S^m · N_sd) / (f_eq T_life)]^(1/m) with the
    operating hours of a Rayleigh climate (mean 10 m/s, 1 m/s bins (v - 1, v] from 4 to 25 m/s as thesis
    Table 7.1) over 20 years."""
    rng = np.random.default_rng(9)
    t = np.arange(2000) * 0.01
    normal = 100 + np.cumsum(rng.normal(size=t.size))
    shutdown = 100 * np.exp(-t) * np.cos(2 * np.pi * 2.5 * t)
    pn, ps = tmp_path / "n.csv", tmp_path / "s.csv"
    write_csv(pn, t, {"f": normal})
    write_csv(ps, t, {"f": shutdown})
    r = windrive_json(windrive, "life", "--normal", str(pn), "--shutdown", str(ps), "--channel", "f", "--m", "3,6")
    cdf = lambda v: 1 - np.exp(-np.pi / 4 * (v / 10.0) ** 2)
    life_h = 20 * 8760
    op_h = life_h * (cdf(25) - cdf(3))
    assert r["operating_hours"] == pytest.approx(op_h, rel=1e-12)
    for entry in r["lifetime_del"]:
        m = entry["m"]
        s = lambda x: sum(n * rr ** m for rr, _, n, _, _ in rainflow.extract_cycles(x.tolist()))
        a, b = s(normal) * op_h * 3600 / (t[-1] - t[0]), s(shutdown) * 1100 * 20
        assert entry["del"] == pytest.approx(((a + b) / (life_h * 3600)) ** (1 / m), rel=1e-12)
        assert entry["shutdown_share"] == pytest.approx(b / (a + b), rel=1e-12)


def test_bearing_life_equals_iso_281_miner_sum(windrive, tmp_path):
    """ISO 281: L10 = (C/P)^(10/3) million revolutions for a roller bearing (3 for a ball bearing);
    Miner over the samples, n_j = dt_j |w_j| / 2 pi, normal operation scaled to the operating hours and
    the shutdown repeated 1100 times a year; P_eq = (sum n P^p / sum n)^(1/p)."""
    rng = np.random.default_rng(11)
    t = np.arange(4000) * 0.005
    normal_p = 2e5 + 3e4 * rng.normal(size=t.size)
    normal_w = 2.0 + 0.1 * rng.normal(size=t.size)
    shutdown_p = -4e5 * np.exp(-t / 5) * np.cos(2 * np.pi * 1.3 * t)
    shutdown_w = 2.0 * np.exp(-t / 3)
    pn, ps = tmp_path / "n.csv", tmp_path / "s.csv"
    write_csv(pn, t, {"p": normal_p, "w": normal_w})
    write_csv(ps, t, {"p": shutdown_p, "w": shutdown_w})
    cdf = lambda v: 1 - np.exp(-np.pi / 4 * (v / 10.0) ** 2)
    op_s = 20 * 8760 * (cdf(25) - cdf(3)) * 3600
    for ball, p in ((False, 10 / 3), (True, 3.0)):
        args = ["life", "--normal", str(pn), "--shutdown", str(ps), "--channel", "p", "--speed", "w",
                "--bearing", "2.5e6"] + (["--ball"] if ball else [])
        r = windrive_json(windrive, *args)["bearing"]
        n_n = np.diff(t) * np.abs(normal_w[:-1]) / (2 * np.pi) * op_s / (t[-1] - t[0])
        n_s = np.diff(t) * np.abs(shutdown_w[:-1]) / (2 * np.pi) * 1100 * 20
        l10 = lambda load: (2.5e6 / np.abs(load)) ** p * 1e6
        d_n, d_s = np.sum(n_n / l10(normal_p[:-1])), np.sum(n_s / l10(shutdown_p[:-1]))
        assert r["damage"] == pytest.approx(d_n + d_s, rel=1e-12)
        assert r["shutdown_share"] == pytest.approx(d_s / (d_n + d_s), rel=1e-12)
        assert r["revolutions"] == pytest.approx(n_n.sum() + n_s.sum(), rel=1e-12)
        # the equivalent load's L10 over the lifetime's revolutions is the same damage
        assert r["revolutions"] / l10(r["equivalent_load"]) == pytest.approx(r["damage"], rel=1e-12)


def test_life_operating_hours_and_years_as_the_thesis(windrive, tmp_path):
    """Thesis Table 7.1 sums to 161 950 h in operation over 20 years (Rayleigh, mean 10 m/s, 4-25 m/s):
    the default 1 m/s bins named by their upper edge give it to the table's rounding (0.05 %), while
    --bin-width 0 counts exactly 4-25 m/s (the 4 m/s bin's 8 733 h less). The reports name the years
    asked for."""
    t = np.arange(1000) * 0.01
    path = tmp_path / "y.csv"
    write_csv(path, t, {"f": 2e5 + 1e4 * np.sin(2 * np.pi * t), "w": np.full(t.size, 10.0)})
    base = ["life", "--normal", str(path), "--shutdown", str(path), "--channel", "f"]
    hours = windrive_json(windrive, *base)["operating_hours"]
    assert hours == pytest.approx(161_950, rel=5e-4)
    exact = windrive_json(windrive, *base, "--bin-width", "0")["operating_hours"]
    assert hours - exact == pytest.approx(8733, abs=0.6)
    for extra in (["--gear", "29,58,16,0,300"], ["--bearing", "2.5e6"]):
        out = subprocess.run([windrive, *base, "--years", "25", "--speed", "w", *extra],
                             capture_output=True, text=True, check=True).stdout
        assert "25-year Miner damage" in out and "20-year" not in out, out
        assert "over 25 years" in out and "(v − 1, v]" in out, out


def test_life_root_factors_from_geometry_or_given(windrive, tmp_path):
    """Without --y-fs the root factors come from the tooth geometry (ISO 6336-3 method B) and the root
    stress is F_t/(b m_n) Y_F Y_S K_A (spur, other factors 1); --y-fs overrides them."""
    t = np.arange(1000) * 0.01
    f = 2e5 + 1e4 * np.sin(2 * np.pi * t)
    path = tmp_path / "g.csv"
    write_csv(path, t, {"f": f, "w": np.full(t.size, 10.0)})
    base = ["life", "--normal", str(path), "--channel", "f", "--gear", "29,58,16,0,300", "--speed", "w", "--k-a", "1"]
    computed = windrive_json(windrive, *base)["gear"]
    given = windrive_json(windrive, *base, "--y-fs", "2.6,1.6")["gear"]
    assert 1.2 < computed["y_f"] < 2.5 and 1.5 < computed["y_s"] < 2.5
    assert (given["y_f"], given["y_s"]) == (2.6, 1.6)
    ft = f.max() * np.cos(np.radians(20))  # mesh force along the line of action -> tangential
    for g in (computed, given):
        root = g["cases"][0]["max_root_stress"]
        assert root == pytest.approx(ft / (0.3 * 0.016) * g["y_f"] * g["y_s"], rel=1e-12)


def test_campbell_orders_and_crossings(windrive):
    r = windrive_json(windrive, "campbell", "--preset", "C", "--harmonics", "1")
    orders = {name: (o, thesis) for name, o, thesis in r["orders"]}
    assert orders["stage 1 GMF"] == (145.0, 174.0)
    assert orders["stage 2 GMF"][0] == 648.0 and orders["stage 3 GMF"][0] == 2664.0
    lo, hi = r["operating_rpm"]
    assert (lo, hi) == (10.8, 19.1)
    for name, f, rpm in r["crossings"]:
        assert lo <= rpm <= hi
        assert rpm == pytest.approx(60 * f / orders[name][0], rel=1e-12)


def test_bode_resonance_at_the_first_mode(windrive):
    r = windrive_json(windrive, "bode", "--preset", "D", "--range", "1,5", "--points", "2001")
    f, mag = np.array(r["frequency_hz"]), np.array(r["magnitude"])
    peak = f[np.argmax(mag * f)]  # ω·|G| removes the rigid-body roll-off
    assert peak == pytest.approx(r["modes_hz"][0], rel=2e-3)


@pytest.mark.parametrize("args,words", [
    (["spectrum", "{csv}", "--channel", "x", "--window", "5,1"], ["--window", "two increasing numbers"]),
    (["spectrum", "{csv}", "--channel", "x", "--window", "0,0.01"], ["needs at least 16"]),
    (["ldd", "{csv}", "--channel", "x", "--speed", "nosuch"], ["nosuch"]),
    (["rainflow", "{csv}", "--channel", "x", "--matrix", "diagonal"], ["diagonal"]),
    (["rainflow", "{csv}", "--channel", "x", "--matrix", "from-to", "--bins", "4,5"], ["--bins", "range,mean"]),
    (["rainflow", "{csv}", "--channel", "x", "--matrix", "range-mean", "--bins", "4,0"], ["--bins", "at least one bin"]),
    (["rainflow", "{csv}", "--channel", "x", "--plot", "{tmp}/m.jpg"], ["m.jpg", ".png or .svg"]),
    (["del", "{csv}", "--channel", "x", "--goodman", "0.001"], ["Goodman", "ultimate"]),
    (["del", "{csv}", "--channel", "x", "--goodman=-1"], ["--goodman -1", "ultimate"]),
    (["life", "--normal", "{csv}", "--channel", "x", "--gear", "1,2"], ["--gear", "z1,z2"]),
    (["life", "--normal", "{csv}", "--channel", "x", "--gear", "20,40,10,0,100"], ["--speed"]),
    (["life", "--normal", "{csv}", "--channel", "x", "--gear", "20,80,10,0,100", "--internal", "--tooth", "ring",
      "--speed", "x"], ["ring", "--y-fs"]),
    (["life", "--normal", "{csv}", "--channel", "x", "--gear", "20,40,10,0,100", "--speed", "x", "--rack", "1.25,2"],
     ["--rack", "root radius"]),
    (["life", "--normal", "{csv}", "--channel", "x", "--cut-in", "30"], ["--cut-in"]),
    (["life", "--normal", "{csv}", "--channel", "x", "--bearing", "1e6"], ["--bearing needs --speed"]),
    (["life", "--normal", "{csv}", "--channel", "x", "--bearing=-5", "--speed", "x"], ["--bearing -5", "positive"]),
    (["campbell", "--preset", "Z"], ["Z", "A, B, C, D or P"]),
    (["gears", "{csv}", "--gearbox", "Q"], ["--gearbox", "Q", "use P"]),
    (["gears", "{csv}", "--transient=-1"], ["--transient -1"]),
    (["gears", "{csv}", "--fmu", "simpack"], ["simpack", "gearbox6dof"]),
    (["gears", "{csv}"], ["x.csv", "torsional.mesh_force_sun_planet_1"]),
    (["gears", "{csv}", "--fmu", "gearbox6dof"], ["x.csv", "gearbox.mesh_force_sun_planet_1"]),
    (["gears", "{csv}", "--gearbox", "{tmp}/none.toml"], ["none.toml", "use P", "grc750"]),
    (["campbell", "--harmonics", "0"], ["--harmonics 0"]),
    (["bode", "--generator", "locked", "--input", "generator"], ["locked", "no torque input"]),
    (["bode", "--range", "10,1"], ["--range"]),
])
def test_bad_analysis_input_is_named(windrive, tmp_path, args, words):
    csv = tmp_path / "x.csv"
    t = np.arange(100) * 0.01
    write_csv(csv, t, {"x": np.sin(t * 7)})
    args = [a.format(csv=csv, tmp=tmp_path) for a in args]
    out = subprocess.run([windrive, *args], capture_output=True, text=True, env={"RUST_BACKTRACE": "0"})
    assert out.returncode != 0
    for w in words:
        assert w in out.stderr, out.stderr


def test_gears_names_a_series_too_short_to_rate(windrive, tmp_path):
    """Every channel there, but nothing after the transient: the file, its length and the transient."""
    channels = subprocess.run([windrive, "gears", "--channels"], capture_output=True, text=True, check=True)
    csv = tmp_path / "short.csv"
    t = np.arange(101) * 0.01
    write_csv(csv, t, {c: np.ones_like(t) for c in channels.stdout.split()})
    out = subprocess.run([windrive, "gears", str(csv), "--transient", "5"], capture_output=True, text=True)
    assert out.returncode != 0
    for w in ["short.csv", "transient of 5 s", "nothing to rate"]:
        assert w in out.stderr, out.stderr
    # and the same series rates when the transient leaves a window
    assert subprocess.run([windrive, "gears", str(csv), "--transient", "0.5"], capture_output=True).returncode == 0
