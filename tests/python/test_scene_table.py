"""docs/AERODYNAMICS.md's scene table is what the scenes' files say: scripts/scene-table writes it from
scenes/*/ and the document holds its output between markers, so a scene added, removed or changed
without the document fails here."""
import re
import subprocess

from conftest import ROOT

BLOCK = re.compile(r"<!-- scripts/scene-table: begin -->\n(.*?)<!-- scripts/scene-table: end -->", re.DOTALL)


def test_the_documented_scene_table_is_what_the_scenes_say():
    documented = BLOCK.search((ROOT / "docs" / "AERODYNAMICS.md").read_text())
    assert documented, "docs/AERODYNAMICS.md has no scripts/scene-table block"
    now = subprocess.run([str(ROOT / "scripts" / "scene-table")], check=True, capture_output=True, text=True).stdout
    assert documented.group(1) == now
    # every scene folder with a rotor FMU is a row, and only those
    rows = {line.split("`")[1] for line in now.splitlines()[2:]}
    with_rotor = {p.name for p in (ROOT / "scenes").iterdir()
                  if (p / "SystemStructure.ssd").is_file()
                  and "resources/rotor.fmu" in (p / "SystemStructure.ssd").read_text()}
    assert rows == with_rotor
