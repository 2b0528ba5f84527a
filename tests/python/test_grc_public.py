"""docs/GEARBOX.md's table against NREL's published GRC measurements: our column is what `windrive gearbox
--rotor-mass 1 --json` gives today (the GRC at rated torque on the dynamometer, without the rotor's weight)."""

import json
import re
import subprocess

from conftest import ROOT

BLOCK = re.compile(r"<!-- public GRC measurements: checked by tests/python/test_grc_public.py -->\n(.*?)"
                   r"<!-- end of public GRC measurements -->", re.DOTALL)


def test_our_column_is_what_the_model_gives(windrive):
    report = json.loads(subprocess.run([windrive, "gearbox", "--rotor-mass", "1", "--json"], check=True,
                                       capture_output=True, text=True).stdout)
    rows = [b["radial_n"] for b in report["bearings"] if re.fullmatch(r"planet_\d_(uw|dw)", b["name"])]
    assert len(rows) == 6
    table = BLOCK.search((ROOT / "docs" / "GEARBOX.md").read_text()).group(1)
    ours = {line.split("|")[1].strip(): line.split("|")[3].strip() for line in table.splitlines()[2:]}
    assert ours["planetary load-sharing factor K_γ, no rotor moment"] == f"{report['load_sharing_factor']:.3f}"
    worst = max(rows) / (sum(rows) / 6)
    assert ours["most loaded planet-bearing row over an equal share of the six rows, pure torque"] == f"{worst:.2f}"
    # the page's observation: without the rotor's weight the carrier floats inside its bearings' clearance
    carrier = sum(b["radial_n"] for b in report["bearings"] if b["name"] in ("carrier_a", "carrier_b"))
    share = carrier / (sum(rows) / 6)
    assert share < 0.1, carrier
    assert f"its bearings carry {100 * share:.0f} % of a planet-bearing row's mean load" in " ".join(
        (ROOT / "docs" / "GEARBOX.md").read_text().split())
