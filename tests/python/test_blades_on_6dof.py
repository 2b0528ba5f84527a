"""scripts/blades-on-6dof, the GRC's bearings under the blades' sampled tilt and yaw moments with and
without the rotor's aerodynamic damping (docs/WIND.md): the page's table between its markers is what the
script prints, the damping does what the page says of it, and the page's figures are the table's."""

import re
import subprocess
import sys

from conftest import ROOT


def test_the_page_is_the_script_and_the_damping_works(windrive):
    out = subprocess.run([sys.executable, str(ROOT / "scripts/blades-on-6dof"), windrive], check=True,
                         capture_output=True, text=True, cwd=ROOT).stdout
    page = (ROOT / "docs/WIND.md").read_text()
    block = re.search(r"<!-- blades-on-6dof: begin -->\n(.*?)<!-- blades-on-6dof: end -->", page, re.S)
    assert block and block.group(1) == out, "docs/WIND.md's table differs from scripts/blades-on-6dof's output"

    rows = {cells[0]: cells[1:] for cells in
            ([c.strip() for c in line.strip("|").split("|")] for line in out.splitlines()[2:])}
    num = lambda text: float(text.rstrip("%"))
    average, undamped, damped = (num(x) for x in rows["main bearing: standard deviation"])
    # the damping at least halves the main bearing's fluctuation and takes most of it below 4 Hz
    assert damped < 0.5 * undamped and damped > average
    share = [num(x) for x in rows["main bearing: share of the variance above 4 Hz"]]
    assert share[1] > 40 and share[2] < 0.5 * share[1]
    peaks = [num(x) for x in rows["main bearing: largest spectral line above 2 Hz, Hz"]]
    assert 6.5 < peaks[1] < 8.5 and peaks[2] < 5.0

    # the prose's figures
    text = " ".join(page.split())
    assert (f"standard deviation from {undamped:.0f} to {damped:.0f} kN" in text and
            f"above 4 Hz from {share[1]:.0f} % to {share[2]:.0f} %" in text and
            f"moves from {peaks[1]} to {peaks[2]} Hz, beside the rotor-averaged wind's {peaks[0]} Hz" in text and
            f"at {peaks[1]} Hz)" in text), "docs/WIND.md's figures differ from the table"
    words = "zero one two three four five six seven eight nine ten eleven twelve".split()
    assert f"{words[round(damped / average)]} times the rotor-averaged wind's standard deviation" in text
    carrier = rows["upwind carrier bearing: mean"]
    assert f"mean radial load rises from {carrier[0]} to {carrier[2]} kN" in text
