"""docs/SPEED-ACCURACY.md's readings of its committed chart tables (docs/speed-accuracy/*.csv, written by the
`windrive chart` commands the page shows): each number the page quotes from a table is the table's, and what the
page reads from it holds. The tables are not rerun here (minutes each); the chart commands' own tests check them."""

import csv
import re

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
