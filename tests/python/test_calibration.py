"""`windrive calibrate`: the scenes hold the fitted values, and the table in docs/ is what they give.

docs/calibration-c.md was written by `windrive calibrate --evaluations 250 --apply --out
docs/calibration-c.md`, which also wrote the fitted inputs into scenes/c-normal and scenes/c-shutdown.
Evaluating the scenes as they are (`--no-fit`) must then give the table's achieved column and its
objective: the runs are deterministic (seeded turbulence, fixed step), so to the table's printed digits.
"""
import re
import subprocess

from conftest import ROOT


def rows(markdown):
    """statistic -> (achieved text, misfit) from the first table."""
    out = {}
    for line in markdown.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 5 and re.match(r"[+-]\d", cells[4]):
            out[cells[0]] = (cells[3], float(cells[4]))
    return out


def objective(markdown):
    return float(re.search(r"Objective \(sum of squared misfits\): ([0-9.]+)", markdown).group(1))


def test_the_scenes_reproduce_the_documented_fit(windrive, tmp_path):
    documented = (ROOT / "docs" / "calibration-c.md").read_text()
    out = tmp_path / "now.md"
    subprocess.run([windrive, "calibrate", "--no-fit", "--out", str(out)], check=True, cwd=ROOT,
                   capture_output=True, text=True)
    now = out.read_text()
    assert objective(now) == objective(documented)
    want, got = rows(documented), rows(now)
    assert len(want) == 9 and want.keys() == got.keys()
    for name, (achieved, misfit) in want.items():
        assert got[name] == (achieved, misfit), name


def test_too_few_evaluations_are_refused(windrive):
    r = subprocess.run([windrive, "calibrate", "--evaluations", "3"], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode != 0
    assert "--evaluations 3" in r.stderr and "at least 7" in r.stderr
