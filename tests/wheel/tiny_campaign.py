"""scripts/check-wheel's campaign, in the fresh venv the wheel was installed into:

    python tiny_campaign.py prepare SCENE DIR   DIR/scene: SCENE's files with the wheel's FMUs (fmu_path) in
                                                resources/, and DIR/tiny.toml: two 1 s cases of it
    python tiny_campaign.py verify DIR          after `python -m windrive_campaign run DIR/tiny.toml --out
                                                DIR/out`: every case landed ok, run by the wheel's windrive on
                                                the wheel's FMUs

A failure is one line on stderr and exit 1."""

import shutil
import sys
from pathlib import Path

import windrive_fmus

CASES = 2
CAMPAIGN = """# scripts/check-wheel: drivetrain C in normal operation for 1 s, the torsional model at two fidelities
scene = "scene"
stop_time = 1.0
transient = 0.2

[[channel]]
name = "torsional.lss_torque"
m = [3]

[grid]
torsional.fidelity = ["2", "5"]
"""


def components(scene: Path) -> list[str]:
    """The FMUs the scene's SSD names under resources/ (all of them ours)."""
    text = (scene / "SystemStructure.ssd").read_text()
    return sorted({name for name in windrive_fmus.NAMES if f'source="resources/{name}.fmu"' in text})


def prepare(source: Path, work: Path) -> None:
    scene = work / "scene"
    shutil.copytree(source, scene, ignore=shutil.ignore_patterns("resources", "__pycache__"))
    (scene / "resources").mkdir()
    used = components(scene)
    if not used:
        raise SystemExit(f"error: {source}: its SystemStructure.ssd names none of {', '.join(windrive_fmus.NAMES)}")
    for name in used:
        shutil.copy(windrive_fmus.fmu_path(name), scene / "resources" / f"{name}.fmu")
    (work / "tiny.toml").write_text(CAMPAIGN)


def verify(work: Path) -> None:
    """From the result files (json: no pandas start-up) and the table's presence."""
    import json

    from windrive_campaign.cases import windrive_digest

    out = work / "out"
    results = [json.loads(p.read_text()) for p in sorted((out / "cases").glob("*.json"))]
    bad = [r for r in results if r["status"] != "ok"]
    if len(results) != CASES or bad:
        why = f"; {bad[0]['case']['name']}: {bad[0].get('error')}" if bad else ""
        raise SystemExit(f"error: {len(results)} case results, {len(results) - len(bad)} ok, {CASES} expected{why}")
    if not (out / "tiny.parquet").is_file():
        raise SystemExit(f"error: no table {out / 'tiny.parquet'}")
    installed = Path(sys.prefix) / "bin" / "windrive"
    digest = windrive_digest(str(installed))[:12]
    ran = [p.name for p in (out / "bin").glob("windrive-*")]
    if ran != [f"windrive-{digest}"]:
        raise SystemExit(f"error: the campaign ran {ran}, not the wheel's windrive ({installed}, windrive-{digest})")
    for name in components(work / "scene"):
        shipped = Path(windrive_fmus.fmu_path(name)).read_bytes()
        if (work / "scene" / "resources" / f"{name}.fmu").read_bytes() != shipped:
            raise SystemExit(f"error: windrive replaced the scene's {name}.fmu: the cases did not run the wheel's FMUs")
    print(f"  {len(results)} cases ok: {', '.join(sorted(r['case']['name'] for r in results))}")


if __name__ == "__main__":
    if sys.argv[1:2] == ["prepare"] and len(sys.argv) == 4:
        prepare(Path(sys.argv[2]), Path(sys.argv[3]))
    elif sys.argv[1:2] == ["verify"] and len(sys.argv) == 3:
        verify(Path(sys.argv[2]))
    else:
        raise SystemExit(__doc__)
