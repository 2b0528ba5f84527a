"""scripts/gearbox-chapter7, the thesis's chapter 7 beside the GRC's numbers (docs/GEARBOX.md), on its
scene run as the page's commands run it (the whole 30 s at 1 ms, about 15 s, once for the module): every
row has a number of ours and a difference, the rows read the channels they name (checked here from the
CSV and the JSON without the script), and the page's table between its markers is the script's output."""

import csv
import json
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def chapter7(windrive, tmp_path_factory):
    """The three commands above the page's table: the series, the rated point and the script's table."""
    folder = tmp_path_factory.mktemp("chapter7")
    series, rated = folder / "d.csv", folder / "grc.json"
    subprocess.run([windrive, "run", str(ROOT / "scenes/d-shutdown-6dof"), "--step", "1e-3", "--out", str(series)],
                   check=True, cwd=ROOT, capture_output=True)
    rated.write_text(subprocess.run([windrive, "gearbox", "--json"], check=True, capture_output=True,
                                    text=True).stdout)
    out = subprocess.run([str(ROOT / "scripts/gearbox-chapter7"), str(series), str(rated)], check=True,
                         capture_output=True, text=True).stdout
    return series, rated, out


def test_the_chapter_7_table_reads_the_scene_and_the_rated_point(chapter7):
    series, rated, out = chapter7
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
    pressures = [np.array([float(r[f"gearbox.planet_{p}_{e}_inner_race_pressure"]) for r in table])
                 for p in (1, 2, 3) for e in ("uw", "dw")]
    assert rows[4][2] == f"{max(x[normal].max() for x in pressures) / 1e9:.2f}"
    assert rows[5][2] == f"{max(x[t >= 5.0].max() for x in pressures) / 1e9:.2f}", "the shutdown from the trip at 5 s"


def test_the_page_holds_the_table_the_commands_give(chapter7):
    """docs/GEARBOX.md's GRC table between its markers is what the three commands above it give today."""
    out = chapter7[2]
    page = (ROOT / "docs" / "GEARBOX.md").read_text()
    block = re.search(r"<!-- GRC chapter-7 table: [^\n]*-->\n(.*?)<!-- end of the GRC chapter-7 table -->", page,
                      re.DOTALL)
    assert block, "docs/GEARBOX.md lost the GRC chapter-7 table's markers"
    assert block.group(1) == out, "rerun the commands above the table in docs/GEARBOX.md and paste their output"


def test_the_face_load_table_is_what_windrive_gears_gives(windrive, chapter7):
    """docs/GEARBOX.md's `--face-load model` table: each tooth's largest contact stress with K_Hβ = 1 and
    with the model's, and the ratio of their flank damage, from `windrive gears` on the chapter-7 series;
    and the rated point's K_Hβ of the sun and intermediate meshes that the page names."""
    series = chapter7[0]

    def rated(face_load):
        out = subprocess.run([windrive, "gears", str(series), "--gearbox", "grc750", "--fmu", "gearbox6dof",
                              "--face-load", face_load, "--json"], check=True, capture_output=True, text=True).stdout
        return {t["name"]: t for t in json.loads(out)}

    one, model = rated("one"), rated("model")
    page = (ROOT / "docs" / "GEARBOX.md").read_text()
    block = re.search(r"<!-- GRC face load: [^\n]*-->\n(.*?)<!-- end of GRC face load -->", page, re.DOTALL)
    assert block, "docs/GEARBOX.md lost the face-load table's markers"
    rows = [[c.strip() for c in line.strip("|").split("|")] for line in block.group(1).splitlines()[2:]]
    assert len(rows) == 4
    for tooth, plain, with_model, ratio in rows:
        name = tooth.split()[0]
        assert plain == f"{one[name]['max_contact_stress'] / 1e6:.0f}", tooth
        assert with_model == f"{model[name]['max_contact_stress'] / 1e6:.0f}", tooth
        times = model[name]["flank_damage"] / one[name]["flank_damage"]
        assert ratio == f"{float(f'{times:.2g}'):g}×", tooth
        assert model[name]["max_contact_stress"] >= one[name]["max_contact_stress"], tooth

    meshes = {m["name"]: m["face_load_factor"] for m in json.loads(chapter7[1].read_text())["meshes"]}
    suns = [meshes[f"sun_planet_{p}"] for p in (1, 2, 3)]
    text = " ".join(page.split())
    assert f"K_Hβ as {min(suns):.2f}–{max(suns):.2f} and {meshes['gear_pinion_1']:.2f}" in text
