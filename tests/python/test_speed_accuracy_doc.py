"""docs/SPEED-ACCURACY.md's readings of its committed chart tables (docs/speed-accuracy/*.csv, written by the
`windrive chart` commands the page shows): each number the page quotes from a table is the table's, and what the
page reads from it holds. The tables are not rerun here (minutes each); the chart commands' own tests check them."""

import csv
import math
import json
import re
import subprocess
import sys

import pytest

from conftest import ROOT

PAGE = ROOT / "docs/SPEED-ACCURACY.md"
TABLES = ROOT / "docs/speed-accuracy"


def rows(name):
    with open(TABLES / f"{name}.csv", newline="") as f:
        return list(csv.DictReader(f))


def section(title):
    """The page's text from the heading `title` to the next heading of any level."""
    text = PAGE.read_text()
    start = text.index(title)
    end = re.search(r"\n#+ ", text[start + len(title):])
    return text[start:start + len(title) + (end.start() if end else len(text))]


def sci(x):
    """1 significant digit after the point, the page's way: 7.7e-5, not 7.7e-05."""
    mantissa, exponent = f"{x:.1e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def span(values, fmt):
    lo, hi = fmt(min(values)), fmt(max(values))
    return lo if lo == hi else f"{lo}–{hi}"


def test_the_non_smooth_reading_is_its_table():
    table = rows("non-smooth")
    assert all(len(r) == 6 and None not in r for r in table), "a label's comma split a row"
    assert all(r["brake_locked_changes"] == "0" and float(r["max_speed_locked"]) == 0.0 for r in table)
    step = lambda r: float(r["step_s"])
    rate = lambda r: float(r["contact_changes_per_1000_points"])
    coupled = [r for r in table if r["algorithm"] in ("gauss-seidel p0", "jacobi p0", "iterative iqn-ils")]
    reference = next(r for r in coupled if r["algorithm"] == "iterative iqn-ils" and step(r) == 0.00025)
    rattling = [r for r in coupled if step(r) >= 0.001]
    remedied = [r for r in table if r["algorithm"].startswith("gs p0,")]
    # every rattling run changes contact more often than any remedied one
    assert min(map(rate, rattling)) > 5 * max(map(rate, remedied))
    text = " ".join(section("## Chatter at the non-smooth places").split())
    for quoted in [
        f"changes the sun–planet contact state {reference['contact_changes']} times in 30 s "
        f"({rate(reference):.2f} per 1000 points",
        f"changes it at {span(list(map(rate, rattling)), lambda x: f'{x:.0f}')} per 1000 points",
        f"brings it back to {span(list(map(rate, remedied)), lambda x: f'{x:.1f}')} per 1000 points "
        f"({span([int(r['contact_changes']) for r in remedied], str)} changes",
    ]:
        assert quoted in text, f"docs/SPEED-ACCURACY.md should read: {quoted}"


def test_the_shutdown_order_reading_is_its_table():
    error = {(r["method"][-1], r["setting"]): float(r["max_relative_error"]) for r in rows("c-shutdown-order")}
    at = lambda order, ms: error[(str(order), f"H = {ms} ms")]
    # holding (order 0) is the most accurate from 1 to 4 ms, extrapolation below and at 8 ms
    for ms in (1, 2, 4):
        assert at(0, ms) < min(at(1, ms), at(2, ms)), ms
    for ms in (0.25, 0.5, 8):
        assert at(0, ms) > min(at(1, ms), at(2, ms)), ms
    assert sci(at(1, 1)) == sci(at(2, 1))
    text = " ".join(section("### Shutdown, extrapolation order").split())
    for quoted in [
        "is the more accurate from 1 to 4 ms",
        f"({sci(at(0, 1))} at 1 ms against {sci(at(1, 1))} with order 1 or 2)",
        f"order 2 is ahead ({sci(at(2, 8))} against {sci(at(0, 8))})",
        f"(order 0: {100 * at(0, 32):.1f} %, 1: {100 * at(1, 32):.1f} %, 2: {100 * at(2, 32):.1f} %)",
    ]:
        assert quoted in text, f"docs/SPEED-ACCURACY.md should read: {quoted}"


def fmt_step(s, unit="ms"):
    return f"{s * 1e3:.0f} ms" if unit == "ms" else f"{s:.1f} s"


def test_the_stability_tables_runs_are_the_maps():
    """Per algorithm: the largest macro step whose run held at the nominal stiffness (every shorter one holding
    too), its H·ω, and how many of the map's cells the theory calls as the runs do. The theory's own limits
    come from the command's printout, not the table, and are not checked here."""
    text = PAGE.read_text()
    for name, heading in [("stability-map", "## Where each coupling algorithm is stable"),
                          ("stability-map-shaft", "### The second split: the main shaft cut across two FMUs")]:
        table = rows(name)
        block = section(heading)
        for algorithm in dict.fromkeys(r["algorithm"] for r in table):
            cells = [r for r in table if r["algorithm"] == algorithm]
            agree = sum(r["stable_measured"] == r["stable_theory"] for r in cells)
            nominal = sorted((float(r["step_s"]), r["stable_measured"] == "true", float(r["h_omega"]))
                             for r in cells if float(r["stiffness_factor"]) == 1.0)
            held = None
            for step, stable, h_omega in nominal:
                if not stable:
                    break
                held = (step, h_omega)
            if held is None:
                runs = "none"
            elif held[0] == nominal[-1][0]:
                runs = f"every step to {fmt_step(held[0], 's')}"
            else:
                runs = f"{fmt_step(held[0])} ({held[1]:.2f})"
            label = algorithm if algorithm != "iterative p1" else "iterative p1 (plain)"
            row = next((line for line in block.splitlines() if line.startswith(f"| {label} |")), None)
            assert row, f"{heading}: no row for {label}"
            cols = [c.strip() for c in row.strip("|").split("|")]
            assert cols[2] == runs and cols[3] == f"{agree}/{len(cells)}", (name, row, runs, agree)


def fidelity(scene):
    return json.loads((TABLES / f"{scene}-fidelity.json").read_text())


def errors(ladder, level):
    (found,) = [x for x in ladder["levels"] if x["name"] == level]
    return {q["quantity"]: q["error"] for q in found["errors"]}


@pytest.mark.parametrize("which,heading", [("torsional", "fidelity-torsional"), ("gearbox", "fidelity-gearbox")])
def test_the_fidelity_tables_are_the_scripts(which, heading):
    out = subprocess.run([sys.executable, str(ROOT / "scripts/fidelity-tables"), which], check=True,
                         capture_output=True, text=True).stdout
    block = re.search(rf"<!-- {heading}: begin -->\n(.*?)<!-- {heading}: end -->", PAGE.read_text(), re.S)
    assert block and block.group(1) == out, f"docs/SPEED-ACCURACY.md's {which} fidelity table differs from " \
                                            f"scripts/fidelity-tables {which}"


def test_the_torsional_fidelity_readings_are_the_ladders():
    normal, shutdown = fidelity("c-normal"), fidelity("c-shutdown")
    pct = lambda x, d: f"{100 * x:.{d}f} %"
    n2, n5, s2, s5 = (errors(normal, "2-mass"), errors(normal, "5-mass"), errors(shutdown, "2-mass"),
                      errors(shutdown, "5-mass"))
    full = normal["modes_hz"]["full torsional"]
    text = " ".join(section("## The fidelity a scene needs").split())
    for quoted in [
        f"99 % of the input torques' spectral energy lies below {normal['excitation_band_hz']:.1f} Hz in normal "
        f"operation and {shutdown['excitation_band_hz']:.2f} Hz in the shutdown",
        f"C's first free–free mode is {full[0]:.2f} Hz ({normal['modes_hz']['2-mass'][0]:.2f} in the 2- and 5-mass "
        f"models), the next {full[1]:.0f} Hz",
        f"The 2-mass model's LSS DEL is within {pct(n2['LSS torque DEL m=6'], 1)} of the full model's (tolerance 3 %), "
        f"its HSS torque RMS within {pct(n2['HSS torque RMS'], 2)}",
        f"Its HSS DEL is {pct(n2['HSS torque DEL m=6'], 0)} off in normal operation and "
        f"{pct(s2['HSS torque DEL m=6'], 0)} in the shutdown",
        f"within {pct(max(n5.values()), 1)}.",
        f"within {pct(s2['sun-planet mesh force max'], 1)} (2-mass) and {pct(s5['sun-planet mesh force max'], 2)} "
        f"(5-mass) of the full model's",
    ]:
        assert quoted in text, f"docs/SPEED-ACCURACY.md should read: {quoted}"
    assert normal["modes_hz"]["5-mass"][0] == pytest.approx(normal["modes_hz"]["2-mass"][0], abs=0.005)
    # both finer levels within every tolerance in both scenes: the page's recommendation
    for ladder in (normal, shutdown):
        assert all(x["within_tolerance"] for x in ladder["levels"] if x["name"] != "2-mass")


def test_the_gearbox_fidelity_reading_is_the_ladders():
    ladder = fidelity("d-shutdown-6dof")
    levels = {x["name"]: x for x in ladder["levels"]}
    assert all(x["within_tolerance"] for x in levels.values())
    worst = lambda name: max(q["error"] for q in levels[name]["errors"])
    lamina = [n for n in levels if "lamina" in n]
    linear = [n for n in levels if "linear" in n]
    # the lamina levels under half a per cent, each linear level cheaper than each lamina level
    assert max(worst(n) for n in lamina) < 0.005 < min(worst(n) for n in linear)
    assert max(levels[n]["cpu_s"] for n in linear) < 0.5 * min(levels[n]["cpu_s"] for n in lamina)
    assert ladder["recommended"] in linear


def test_the_integrator_table_is_its_map():
    """Per mesh-stiffness factor: the top mode (ω_max = the table's h·ω over its step), RK4's limit 2.785/ω_max
    and the largest RK4 step that held. The amplification radii are theory (`Alpha::amplification_radius`),
    not in the table."""
    table = [r for r in rows("integrator-stability") if r["method"] == "rk4"]
    block = section("## Where each integrator is stable")
    for factor in dict.fromkeys(r["mesh_stiffness_factor"] for r in table):
        cells = [r for r in table if r["mesh_stiffness_factor"] == factor]
        omega = float(cells[0]["h_omega_max"]) / float(cells[0]["step_s"])
        held = max(float(r["step_s"]) for r in cells if r["stable"] == "true")
        label = f"{float(factor):g}"
        row = f"| {label} | {omega / (2 * math.pi):.0f} Hz | {2.785 / omega * 1e6:.1f} µs | {held * 1e6:.1f} µs |"
        assert row in block, f"docs/SPEED-ACCURACY.md should have the row starting {row}"
