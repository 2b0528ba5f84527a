"""The sensitivity campaign (python/windrive_campaign/sensitivity.py, docs/SENSITIVITY.md): Morris's
elementary effects of a function whose derivatives are known, the band and verdict bookkeeping, bands.json
as `windrive reproduce` reads it, and one real run of drivetrain A's group on a one-worker LocalCluster
(each evaluation about a second)."""

import csv
import json
import math
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))

from windrive_campaign import sensitivity  # noqa: E402

WINDRIVE = ROOT / "target" / "release" / "windrive"


def test_morris_finds_the_inputs_a_linear_function_depends_on():
    """y = 3 a + 0 b + 0.5 c on [0, 1]³: every elementary effect of a linear function is its slope, so
    μ* is |slope| exactly and σ is 0; relative to |y(nominal)| = 2."""
    problem, x = sensitivity.design(
        [sensitivity.Estimate(n, "T", "", "-", 0.5, 0.0, 1.0, "") for n in "abc"], trajectories=4, levels=4, seed=3
    )
    assert x.shape == (4 * 4, 3)
    y = 3 * x[:, 0] + 0.5 * x[:, 2]
    nominal = [{"quantity": "y", "ours": 2.0, "verdict": "holds"}]
    sampled = [[{"quantity": "y", "ours": float(v), "verdict": "holds" if v > 1.0 else "contradicts"}] for v in y]
    (row,) = sensitivity.analyse(problem, x, nominal, sampled, levels=4)
    mu = {d["name"]: d["mu_star"] for d in row["drivers"]}
    assert mu["a"] == pytest.approx(3 / 2) and mu["c"] == pytest.approx(0.5 / 2) and mu["b"] == pytest.approx(0)
    assert [d["name"] for d in row["drivers"]][0] == "a"
    assert all(d["sigma"] == pytest.approx(0, abs=1e-12) for d in row["drivers"])
    assert row["low"] == pytest.approx(min(y.min(), 2.0)) and row["high"] == pytest.approx(max(y.max(), 2.0))
    assert row["evaluations"] == len(y) + 1
    # y ranges over [0, 3.5]: the verdict flips, and the counts add up
    assert not row["holds"] and sum(row["verdicts"].values()) == len(y) + 1


def test_sobol_indices_share_an_additive_functions_variance_as_computed():
    """y = a + 2 b² + 0 c, inputs uniform on [0, 1]: Var(a) = 1/12 and Var(2 b²) = 4 (1/5 − 1/9) = 16/45, so
    S_a = S_T,a = (1/12) / (1/12 + 16/45) and S_b likewise, S_c = 0; additive, so first-order equals total.
    4096·5 points: SALib's estimators are within 0.02 of the exact shares, and each bootstrap half-width
    covers its own error."""
    problem = {"num_vars": 3, "names": ["a", "b", "c"], "bounds": [[0.0, 1.0]] * 3}
    x = sensitivity.sobol(problem, 4096, seed=5)
    assert x.shape == (4096 * 5, 3)
    y = x[:, 0] + 2 * x[:, 1] ** 2
    si = sensitivity.sobol_indices(problem, y, seed=5)
    va, vb = 1 / 12, 16 / 45
    exact = {"a": va / (va + vb), "b": vb / (va + vb), "c": 0.0}
    for name, share in exact.items():
        for k in ("S1", "ST"):
            assert si[name][k] == pytest.approx(share, abs=0.02), (name, k, si[name])
            assert abs(si[name][k] - share) <= max(si[name][f"{k}_conf"], 1e-3), (name, k, si[name])


def test_bands_merge_per_group(tmp_path):
    path = tmp_path / "bands.json"
    row = {"quantity": "q", "nominal": 1.0, "low": 0.5, "high": 2.0, "nominal_verdict": "holds",
           "verdicts": {"holds": 3}, "holds": True, "drivers": [], "evaluations": 3}  # fmt: skip
    sensitivity.merge_bands(path, "A", [row])
    sensitivity.merge_bands(path, "B", [{**row, "quantity": "r"}])
    sensitivity.merge_bands(path, "A", [{**row, "quantity": "s"}])
    bands = json.loads(path.read_text())
    assert [(b["group"], b["quantity"]) for b in bands] == [("A", "s"), ("B", "r")]
    # a row without a finite value is left out rather than written as NaN, which JSON readers refuse
    sensitivity.merge_bands(path, "C", [{**row, "quantity": "t", "nominal": math.nan}])
    assert [b["quantity"] for b in json.loads(path.read_text())] == ["s", "r"]


@pytest.mark.skipif(not WINDRIVE.is_file(), reason="needs the release build (scripts/test builds it)")
def test_group_a_runs_end_to_end(tmp_path):
    env = {**os.environ, "PYTHONPATH": str(ROOT / "python")}
    r = subprocess.run(
        [sys.executable, "-m", "windrive_campaign", "sensitivity", "A", "--trajectories", "2", "--sobol", "2",
         "--workers", "1", "--out", str(tmp_path), "--windrive", str(WINDRIVE)],
        capture_output=True, text=True, env=env, timeout=600,
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    estimates = [e for e in sensitivity.estimates(str(WINDRIVE)) if e.group == "A"]
    evaluations = (tmp_path / "A_evaluations.csv").read_text().splitlines()
    assert len(evaluations) == 1 + 1 + 2 * (len(estimates) + 1)  # the header, the nominal point, the sample
    bands = json.loads((tmp_path / "bands.json").read_text())
    assert bands and all(b["group"] == "A" for b in bands)
    for b in bands:
        assert b["low"] <= b["nominal"] <= b["high"], b
        assert b["evaluations"] == 2 * (len(estimates) + 1) + 1
    by = {b["quantity"]: b for b in bands}
    peak = by["peak torque / rated in A's shutdown, LSS"]
    # the brake's torque and the trip move A's shutdown peak: the band has a width and a driver
    assert peak["high"] > peak["low"] and peak["drivers"]
    assert (tmp_path / "A_tornado.png").stat().st_size > 10_000
    # the Sobol stage: 2·(k + 2) more evaluations, and per varying row one line per input
    assert len((tmp_path / "A_sobol_evaluations.csv").read_text().splitlines()) == 1 + 2 * (len(estimates) + 2)
    with open(tmp_path / "A_sobol.csv") as f:
        sobol = list(csv.DictReader(f))
    lss = [r for r in sobol if r["quantity"] == "peak torque / rated in A's shutdown, LSS"]
    assert sorted(r["input"] for r in lss) == sorted(e.name for e in estimates)
    assert all(math.isfinite(float(r["ST"])) for r in lss)
    # the evaluations' nominal row is the reproduction's own (an estimate at its nominal leaves the scene alone)
    trip = next(e for e in estimates if e.name == "a_trip_delay")
    listed = subprocess.run([str(WINDRIVE), "reproduce", "--set", f"a_trip_delay={trip.nominal!r}"],
                            capture_output=True, text=True, check=True)  # fmt: skip
    at_nominal = {row["quantity"]: row["ours"] for row in json.loads(listed.stdout)}
    assert np.isfinite(list(at_nominal.values())).all()
    assert at_nominal["peak torque / rated in A's shutdown, LSS"] == peak["nominal"]


def test_a_brake_that_locks_before_it_slips_leaves_its_frequency_undefined():
    """A strong brake on a long ramp (a corner of group A's ranges) locks the HSS before it is fully applied:
    no slipping phase, so the braking frequency rows have no value and are not reproduced, and every other
    row of the scenes is still given (before, the whole evaluation failed and with it the campaign)."""
    out = subprocess.run([str(WINDRIVE), "reproduce", "--set", "a_brake_torque=2.5", "--set", "a_brake_ramp_time=1.2",
                          "--set", "a_trip_delay=0.33", "--set", "a_mesh_damping_ratio=0.08"],
                         capture_output=True, text=True, check=True).stdout  # fmt: skip
    rows = json.loads(out)
    undefined = [r for r in rows if r["ours"] is None]
    assert undefined and all("frequency" in r["quantity"] and r["verdict"] == "not reproduced" for r in undefined)
    assert any(r["quantity"] == "peak torque / rated in A's shutdown, LSS" and r["ours"] > 1.0 for r in rows)


def test_what_sensitivity_md_says_of_a_and_b():
    """docs/SENSITIVITY.md's reading of the committed Sobol indices and bands of groups A and B."""
    def total(group):
        with open(ROOT / "docs" / "sensitivity" / f"{group}_sobol.csv") as f:
            out = {}
            for r in csv.DictReader(f):
                out.setdefault(r["quantity"], {})[r["input"]] = float(r["ST"])
            return out

    a, b = total("A"), total("B")
    for q in ("peak torque / rated in A's shutdown, LSS", "torque range, A's shutdown / normal operation, LSS"):
        assert max(a[q], key=a[q].get) == "a_brake_torque" and sum(a[q].values()) - a[q]["a_brake_torque"] < 0.1, q
    bands = {(x["group"], x["quantity"]): x for x in json.loads((ROOT / "docs" / "sensitivity" / "bands.json").read_text())}
    peak = bands[("B", "peak torque / rated in B's shutdown, LSS")]
    assert (peak["high"] - peak["low"]) / peak["nominal"] < 1e-3
    for q in ("torque range, B's shutdown / normal operation, LSS", "dominant HSS-torque frequency while the brake acts, B [Hz]"):
        assert all(b[q][n] > 0.3 for n in ("b_brake_torque", "b_brake_ramp_time", "b_trip_delay")), q
        assert b[q]["b_mesh_damping_ratio"] < 0.01, q
    for group, normal in (("A", a), ("B", b)):
        q = f"{group}'s LSS peak in normal operation stays below the 1.35 design factor"
        assert normal[q][f"{group.lower()}_mesh_damping_ratio"] > 0.9, q
    text = " ".join((ROOT / "docs" / "SENSITIVITY.md").read_text().split())
    assert "A's shaft peaks and its shutdown/normal range ratio take their spread from the brake torque almost alone" in text


def test_the_pages_counts_are_the_committed_runs():
    """docs/SENSITIVITY.md's estimates and evaluations per group are the estimates file's and the committed
    evaluation tables' (Morris: r·(k + 1) points; Sobol: N·(k + 2))."""
    import tomllib

    page = (ROOT / "docs" / "SENSITIVITY.md").read_text()
    estimates = tomllib.loads((ROOT / "src" / "studies" / "data" / "estimates.toml").read_text())["estimate"]
    folder = ROOT / "docs" / "sensitivity"
    rows = lambda name: sum(1 for _ in open(folder / name)) - 1
    for group in ("A", "C", "2MW"):
        k = sum(1 for e in estimates if e["group"] == group)
        n = rows(f"{group}_evaluations.csv")
        assert f"scripts/campaign sensitivity {group + ' ' * (4 - len(group))}--out docs/sensitivity     # {k} estimates, " \
               f"{n} evaluations" in page, group
    sobol = {rows(f"{g}_sobol_evaluations.csv") for g in ("A", "B")}
    assert len(sobol) == 1 and f"the same for B; {sobol.pop()}\nevaluations each" in page
