"""docs/GEARBOX.md's readings of `windrive gearbox` at the GRC's rated point (lamina bearings, gravity, its main
shaft a beam) and of the committed life reports' hours: each figure the page quotes outside its generated
blocks is what the command or the report gives today. (The "springs (before)" column is the preset before
its shaft became a beam, a record, not rerun.)"""

import json
import subprocess

import pytest

from conftest import ROOT

PAGE = ROOT / "docs/GEARBOX.md"


def text():
    return " ".join(PAGE.read_text().split())


@pytest.fixture(scope="module")
def rated(windrive):
    out = subprocess.run([windrive, "gearbox", "--json"], check=True, capture_output=True, text=True).stdout
    r = json.loads(out)
    return r, {b["name"]: b for b in r["bearings"]}


def span(values, fmt):
    lo, hi = fmt(min(values)), fmt(max(values))
    return lo if lo == hi else f"{lo}–{hi}"


def test_the_beams_column_is_the_rated_point(rated):
    r, b = rated
    kn = lambda name: b[name]["radial_n"] / 1e3
    ratios = " / ".join(f"{b[f'planet_{p}_uw']['radial_n'] / b[f'planet_{p}_dw']['radial_n']:.2f}" for p in (1, 2, 3))
    page = text()
    for row in [
        f"| main bearing, kN | 17.9 | {kn('main'):.1f} |",
        f"| carrier bearings A / B, kN | 82.9 / 16.6 | {kn('carrier_a'):.1f} / {kn('carrier_b'):.1f} (B inside its clearance) |",
        f"| planets' upwind over downwind, 1 / 2 / 3 | 1.39 / 1.39 / 1.51 | {ratios} |",
        f"| K_γ | 1.081 | {r['load_sharing_factor']:.3f} |",
    ]:
        assert row in page, f"docs/GEARBOX.md should have the row {row}"
    assert f"at rated torque the main bearing carries {kn('main'):.0f} kN, " in page  # how far below the lever:
    # tests/it/gearbox_model.rs


def test_the_roller_sets_stiffness_row_is_the_rated_point(rated):
    _, b = rated
    gn = lambda names, key: [b[n][key] / 1e9 for n in names]
    planets = [n for n in b if n.startswith("planet_")]
    carrier = ["carrier_a", "carrier_b"]
    hss = [n for n in b if n.startswith("hss_")]
    one = lambda x: f"{x:.1f}"
    whole = lambda x: f"{x:.0f}" if x >= 1.95 else f"{x:.1f}"
    row = (f"planets {span(gn(planets, 'radial_stiffness_n_per_m'), one)} GN/m against "
           f"{span(gn(planets, 'linear_radial_stiffness_n_per_m'), one)}; carrier "
           f"{span(gn(carrier, 'radial_stiffness_n_per_m'), one)} against {span(gn(carrier, 'linear_radial_stiffness_n_per_m'), whole)}; "
           f"HSS {span(gn(hss, 'radial_stiffness_n_per_m'), one)} against {span(gn(hss, 'linear_radial_stiffness_n_per_m'), one)}")
    assert row in text(), f"docs/GEARBOX.md should read: {row}"
    rolled = [x for x in b.values() if x["radial_stiffness_n_per_m"]]
    stiffer = [x["radial_stiffness_n_per_m"] / x["linear_radial_stiffness_n_per_m"] for x in rolled]
    softer = [x["name"] for x, s in zip(rolled, stiffer) if s < 1]
    assert softer == ["carrier_b"], softer
    too_soft = span([s for s in stiffer if s > 1], lambda x: f"{x:.0f}")
    assert f"the catalogue-order linear values are {too_soft}× too soft for the loaded bearings (carrier B" in text()


def test_the_life_campaigns_hours_are_the_reports():
    page = text()
    for campaign in ("d-6dof-life", "c-6dof-life"):
        hours = json.loads((ROOT / "docs/campaigns" / campaign / "lifetime.json").read_text())["operating_hours"]
        assert f"{hours:,.0f}".replace(",", " ") + " h" in page, campaign


def test_both_gearboxes_webs_give_the_fitted_ratio_and_the_pages_quote_them(windrive):
    """The carrier webs' torsional stiffness of each description is fitted to upwind/downwind 1.433 at rated
    torque (`windrive gearbox --fit-webs 1.4333`): at the descriptions' values the rated point gives that
    ratio, and GEARBOX.md and SOURCES.md quote the values the descriptions hold."""
    import tomllib

    sources = " ".join((ROOT / "docs/SOURCES.md").read_text().split())
    webs = {}
    for gearbox in ("grc750", "c2mw"):
        r = json.loads(subprocess.run([windrive, "gearbox", "--gearbox", gearbox, "--json"], check=True,
                                      capture_output=True, text=True).stdout)
        b = {x["name"]: x["radial_n"] for x in r["bearings"]}
        ratio = sum(b[f"planet_{p}_uw"] for p in (1, 2, 3)) / sum(b[f"planet_{p}_dw"] for p in (1, 2, 3))
        assert abs(ratio - 1.4333) < 5e-3, (gearbox, ratio)
        d = tomllib.loads((ROOT / "fmus/gearbox6dof/resources" / f"{gearbox}.toml").read_text())
        (stage,) = [s["planetary"] for s in d["stage"] if "planetary" in s][:1]
        webs[gearbox] = stage["carrier_webs"]["torsional"]
    sci = lambda x, d: (lambda m, e: f"{m}e{int(e)}")(*f"{x:.{d}e}".split("e"))
    assert f"carrier webs | GRC {sci(webs['grc750'], 3)}, c2mw {sci(webs['c2mw'], 3)} N·m/rad" in sources
    assert f"of 1.433 at rated torque ({sci(webs['c2mw'], 2)} N·m/rad)" in text()
