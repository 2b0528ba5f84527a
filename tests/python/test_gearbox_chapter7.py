"""scripts/gearbox-chapter7, the thesis's chapter 7 beside the GRC's numbers (docs/GEARBOX.md), on a
short run of its scene: every row has a number of ours and a difference, and the rows read the
channels they name (checked here from the CSV and the JSON without the script). And the page's table
between its markers against the whole scene."""

import csv
import json
import re
import subprocess
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]


def test_the_chapter_7_table_reads_the_scene_and_the_rated_point(windrive, tmp_path):
    series, rated = tmp_path / "d.csv", tmp_path / "grc.json"
    # normal operation to the trip at 5 s, then 0.5 s of the shutdown
    subprocess.run([windrive, "run", str(ROOT / "scenes/d-shutdown-6dof"), "--stop-time", "5.5",
                    "--out", str(series)], check=True, cwd=ROOT, capture_output=True)
    rated.write_text(subprocess.run([windrive, "gearbox", "--json"], check=True, capture_output=True,
                                    text=True).stdout)
    out = subprocess.run([str(ROOT / "scripts/gearbox-chapter7"), str(series), str(rated)], check=True,
                         capture_output=True, text=True).stdout
    rows = [[c.strip() for c in line.strip("|").split("|")] for line in out.splitlines()[2:]]
    assert len(rows) == 17
    for quantity, thesis, ours, difference, why in rows:
        assert ours and difference and why, quantity
        assert any(ch.isdigit() for ch in ours), quantity

    bearings = {b["name"]: b["radial_n"] for b in json.loads(rated.read_text())["bearings"]}
    ratio = sum(bearings[f"planet_{p}_uw"] for p in (1, 2, 3)) / sum(bearings[f"planet_{p}_dw"] for p in (1, 2, 3))
    assert rows[0][2] == f"{ratio:.3f}"
    assert abs(ratio - 1.4333) < 5e-3, "the carrier webs are fitted to this ratio"

    with open(series, newline="") as f:
        table = list(csv.DictReader(f))
    t = np.array([float(r["time"]) for r in table])
    normal = (t >= 0.5) & (t < 5.0)
    pressure = max(np.array([float(r[f"gearbox.planet_{p}_{e}_inner_race_pressure"]) for r in table])[normal].max()
                   for p in (1, 2, 3) for e in ("uw", "dw"))
    assert rows[4][2] == f"{pressure / 1e9:.2f}"


def test_the_page_holds_the_table_the_commands_give(windrive, tmp_path):
    """docs/GEARBOX.md's GRC table between its markers is what the three commands above it give today
    (the whole 30 s scene at 1 ms, about 15 s)."""
    series, rated = tmp_path / "d.csv", tmp_path / "grc.json"
    subprocess.run([windrive, "run", str(ROOT / "scenes/d-shutdown-6dof"), "--step", "1e-3", "--out", str(series)],
                   check=True, cwd=ROOT, capture_output=True)
    rated.write_text(subprocess.run([windrive, "gearbox", "--json"], check=True, capture_output=True,
                                    text=True).stdout)
    out = subprocess.run([str(ROOT / "scripts/gearbox-chapter7"), str(series), str(rated)], check=True,
                         capture_output=True, text=True).stdout
    page = (ROOT / "docs" / "GEARBOX.md").read_text()
    block = re.search(r"<!-- GRC chapter-7 table: [^\n]*-->\n(.*?)<!-- end of the GRC chapter-7 table -->", page,
                      re.DOTALL)
    assert block, "docs/GEARBOX.md lost the GRC chapter-7 table's markers"
    assert block.group(1) == out, "rerun the commands above the table in docs/GEARBOX.md and paste their output"
