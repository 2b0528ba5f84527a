"""scripts/gearbox-revolution, where the upwind planet bearings peak in a carrier revolution (docs/GEARBOX.md):
the page's table and sentence between their markers are what the script prints from `windrive gearbox
--revolution --json`, and the table reads the commands' numbers (checked here for the GRC preset)."""

import json
import re
import subprocess
import sys

from conftest import ROOT


def test_the_revolution_table_is_the_scripts(windrive):
    out = subprocess.run([sys.executable, str(ROOT / "scripts/gearbox-revolution"), windrive], check=True,
                         capture_output=True, text=True).stdout
    page = (ROOT / "docs/GEARBOX.md").read_text()
    block = re.search(r"<!-- gearbox-revolution: begin -->\n(.*?)<!-- gearbox-revolution: end -->", page, re.S)
    assert block and block.group(1) == out, "docs/GEARBOX.md's revolution table differs from scripts/gearbox-revolution"
    preset = json.loads(subprocess.run([windrive, "gearbox", "--revolution", "--json"], check=True,
                                       capture_output=True, text=True).stdout)
    row = next(line for line in out.splitlines() if line.startswith("| GRC, 14 t overhung"))
    assert " / ".join(f"{p:.1f}" for p in preset["peak_deg"]) in row
    # every configuration peaks left of the sun (what tests/it/gearbox_lamina.rs asserts for three of them)
    assert out.count("left of the sun") == 6
