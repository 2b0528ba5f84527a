"""The life tables a page quotes are the report's (python/windrive_campaign/life_doc.py): rendered from a
report folder as the tests compute them by hand, refused without their markers, and in docs/GEARBOX.md
equal to what the committed report folders give."""

import json
import pathlib
import re
import sys

import pandas as pd
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))

from windrive_campaign import life_doc  # noqa: E402
from windrive_campaign.errors import CampaignError  # noqa: E402


def write_report(folder: pathlib.Path):
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "lifetime.csv").write_text(
        "channel,m,lifetime_del,lifetime_del_lo,lifetime_del_hi,damage_sum,share:DLC 1.2 10 m/s,share:stop-a,share:stop-b\n"
        "gearbox.lss_torque,6,123456.7,nan,nan,1e30,0.2,0.5,0.3\n"
    )
    (folder / "lifetime_bearings.csv").write_text(
        "bearing,dynamic_load_rating,damage,damage_lo,damage_hi,life_years,events_share,thesis_damage,"
        "thesis_events_share,share:DLC 1.2 10 m/s,share:stop-a,share:stop-b\n"
        "planet_1_uw,979000.0,1.354,nan,nan,14.77,0.0005,0.2,0.065,0.9995,0.0003,0.0002\n"
        "carrier_b,2408000.0,1.6e-07,nan,nan,inf,0.0001,1e-09,0.0001,0.9999,0.0001,0.0\n"
    )
    rows = ["tooth,kind,damage,damage_lo,damage_hi,life_years,share:DLC 1.2 10 m/s,share:stop-a,share:stop-b"]
    for k, (tooth, flank, root) in enumerate(
        [("p3", 0.074, 9.4e-4), ("g3", 0.018, 1.9e-4), ("r1", 1e-7, 1.8e-4), ("s1", 1e-4, 1.6e-8),
         ("s2", 3e-5, 4e-7), ("p2", 1e-6, 5e-7)]  # fmt: skip
    ):
        for kind, d in (("flank", flank), ("root", root)):
            rows.append(f"{tooth},{kind},{d!r},nan,nan,{20 / d!r},0.99,0.005,{0.005 + k * 0.001!r}")
    (folder / "lifetime_gears.csv").write_text("\n".join(rows) + "\n")


def test_tables_by_hand(tmp_path):
    write_report(tmp_path / "r")
    text = life_doc.tables(tmp_path / "r")
    # the events' share is every group's but the DLC 1.2 bins'
    assert "| gearbox.lss_torque | 6 | 1.235e+05 | – | 80.0 % |" in text  # one seed a bin: no interval
    assert life_doc._interval(1.0e5, 1.5e5) == "1e+05 to 1.5e+05" and life_doc._interval(2.0, 2.0) == "–"
    assert "| planet_1_uw | 979 | 1.4 | 14.8 | 0.05 % | 6.5 % |" in text
    assert "| carrier_b | 2408 | 1.6e-07 | ∞ | 0.01 % | 0.01 % |" in text
    # the teeth by their larger damage, the four worst alone, the rest as bounds; a tooth's life the shorter
    lines = [x for x in text.splitlines() if x.startswith("| ") and "tooth" not in x]
    teeth = [x.split(" | ")[0][2:] for x in lines if x.split(" | ")[0][2:] in {"p3", "g3", "r1", "s1"}]
    assert teeth == ["p3", "g3", "r1", "s1"]
    assert "| p3 | 0.074 | 0.00094 | 270 | 1 % / 1 % |" in text
    assert "| every other (2) | ≤ 3e-05 | ≤ 5e-07 | | |" in text
    assert "Bearings failing within the design life (D ≥ 1, ISO 281): planet_1_uw; under the thesis's count: none." in text
    assert "Teeth failing within the design life (D ≥ 1, flank or root): none." in text


def test_a_page_without_its_markers_is_refused(tmp_path):
    write_report(tmp_path / "r")
    page = tmp_path / "PAGE.md"
    page.write_text("# nothing here\n")
    with pytest.raises(CampaignError, match="PAGE.md: needs one line"):
        life_doc.replace(page, "demo", tmp_path / "r")


def test_the_block_is_replaced_and_nothing_else(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    write_report(pathlib.Path("docs/campaigns/demo"))
    page = pathlib.Path("docs/PAGE.md")
    page.write_text(f"before\n{life_doc.begin_marker('demo')}\nstale 1.23\n{life_doc.end_marker('demo')}\nafter\n")
    text = life_doc.replace(page, "demo", pathlib.Path("docs/campaigns/demo"))
    assert text.startswith("before\n") and text.endswith("\nafter\n")
    assert "stale" not in text
    assert "From [campaigns/demo](campaigns/demo), written by `scripts/campaign report campaigns/demo.toml" in text
    page.write_text(text)  # regenerating a fresh block changes nothing
    assert life_doc.replace(page, "demo", pathlib.Path("docs/campaigns/demo")) == text


@pytest.mark.parametrize(("page", "name"), [("GEARBOX.md", "d-6dof-life"), ("GEARBOX.md", "c-6dof-life"),
                                           ("CAMPAIGNS.md", "c-dlc12"), ("CAMPAIGNS.md", "c-events"),
                                           ("CAMPAIGNS.md", "c-dlc12-iec")])  # fmt: skip
def test_pages_quote_the_committed_reports(page, name, monkeypatch):
    """docs/GEARBOX.md's and docs/CAMPAIGNS.md's life tables are what the committed report folders give. To
    refresh after a rerun: scripts/campaign run campaigns/NAME.toml && scripts/campaign report
    campaigns/NAME.toml --out docs/campaigns/NAME --doc docs/PAGE"""
    monkeypatch.chdir(ROOT)
    page = pathlib.Path("docs") / page
    assert life_doc.replace(page, name, pathlib.Path("docs/campaigns") / name) == page.read_text()


def _shares(name):
    return pd.read_csv(ROOT / "docs" / "campaigns" / name / "lifetime.csv").set_index(["channel", "m"])


def test_what_campaigns_md_says_of_its_examples():
    """The prose beside the generated tables: c-dlc12's shutdowns take a share of the LSS damage that grows
    with m until they carry nearly all of it at m = 9, while at m = 3 the DLC 1.2 bins outweigh them; its
    HSS ratio is above the LSS's; in c-events the grid loss carries the largest share at m = 6 and most of
    it at m = 9."""
    d = _shares("c-dlc12")
    s = [d.at[("torsional.lss_torque", m), "share:shutdown-rated"] for m in (3, 6, 9)]
    assert s[0] < s[1] < s[2] and s[0] < 0.5 < 0.9 < s[2], s
    ratios = {(q["channel"], q["versus_cases"]): q["ours"] for q in json.loads(
        (ROOT / "docs" / "campaigns" / "c-dlc12" / "lifetime.json").read_text())["thesis_ratios"]}  # fmt: skip
    for against in {a for _, a in ratios}:
        assert ratios[("torsional.hss_torque", against)] > ratios[("torsional.lss_torque", against)]
    # the hours the page sets against each other: the shutdowns' (events × the event scene's stop time) and
    # the climate's operation in the example's bins
    report = json.loads((ROOT / "docs" / "campaigns" / "c-dlc12" / "lifetime.json").read_text())
    ssd = (ROOT / "scenes" / "c-shutdown" / "SystemStructure.ssd").read_text()
    stop = float(re.search(r'stopTime="([0-9.eE+-]+)"', ssd).group(1))
    page = " ".join((ROOT / "docs" / "CAMPAIGNS.md").read_text().split())
    hours = f"{report['operating_hours']:,.0f}".replace(",", " ")
    quoted = f"The {report['events']:.0f} shutdowns last {report['events'] * stop / 3600:.1f} h in all, against the " \
             f"climate's {hours} h of operation in these bins"
    assert quoted in page, f"docs/CAMPAIGNS.md should read: {quoted}"
    e = _shares("c-events")
    groups = [c for c in e.columns if c.startswith("share:")]
    for m, most in ((6, 0.0), (9, 0.5)):
        row = e.loc[("torsional.lss_torque", m), groups]
        assert row.idxmax() == "share:grid-loss" and row.max() > most, row


def _failing(table: pd.DataFrame, column: str) -> set[str]:
    return set(table.index[table[column] >= 1.0])


def test_what_gearbox_md_says_beside_the_thesis_for_the_grc():
    """docs/GEARBOX.md's GRC rows beside the thesis, from the committed d-6dof-life report: with a_ISO·L10 the
    thesis's failing bearings (every planet bearing, HSS A and C) and IMS C; under the thesis's count the
    upwind planet bearings and carrier A; HSS pinion and gear the most damaged teeth; the events a small
    part of every bearing's and tooth's damage under every count."""
    folder = ROOT / "docs" / "campaigns" / "d-6dof-life"
    b = pd.read_csv(folder / "lifetime_bearings.csv").set_index("bearing")
    planets = {f"planet_{k}_{side}" for k in (1, 2, 3) for side in ("uw", "dw")}
    assert _failing(b, "modified_damage") == planets | {"hss_a", "hss_c", "ims_c"}
    assert _failing(b, "thesis_damage") == {"planet_1_uw", "planet_2_uw", "planet_3_uw", "carrier_a"}
    assert {"planet_1_uw", "planet_2_uw", "planet_3_uw", "hss_a", "hss_c"} <= _failing(b, "damage")
    assert (b[["events_share", "modified_events_share", "thesis_events_share"]] < 0.5).all().all()
    g = pd.read_csv(folder / "lifetime_gears.csv")
    assert set(g.sort_values("damage", ascending=False).tooth.head(2)) == {"p3", "g3"}
    events = g[[c for c in g.columns if c.startswith("share:shutdown")]].sum(axis=1)
    assert (events < 0.5).all()


def test_what_gearbox_md_says_beside_the_thesis_for_c2mw():
    """docs/GEARBOX.md's c2mw rows beside the thesis, from the committed c-6dof-life report: with a_ISO·L10 the
    upwind planet bearings the most damaged; the events at most about a per cent of every bearing's damage
    under ISO 281 and a_ISO and a few per cent of every tooth's; under the thesis's count the largest share
    the HSS bearings' (the figures the page gives), at most about two fifths of any bearing's, a few per
    cent of the planet bearings'."""
    folder = ROOT / "docs" / "campaigns" / "c-6dof-life"
    b = pd.read_csv(folder / "lifetime_bearings.csv").set_index("bearing")
    assert b.modified_damage.idxmax().startswith("planet_") and b.modified_damage.idxmax().endswith("_uw")
    assert (b[["events_share", "modified_events_share"]] < 0.01).all().all()
    thesis = b.thesis_events_share
    assert thesis.idxmax().startswith("hss_")
    hss = thesis[b.index.str.startswith("hss_")]
    page = " ".join((ROOT / "docs" / "GEARBOX.md").read_text().split())
    assert f"largest for the HSS bearings, {100 * hss.min():.0f}–{100 * hss.max():.0f} %" in page
    assert thesis.max() < 0.45, "at most about two fifths"
    assert (thesis[b.index.str.startswith("planet_")] < 0.1).all()
    g = pd.read_csv(folder / "lifetime_gears.csv")
    assert (g[[c for c in g.columns if c.startswith("share:shutdown")]].sum(axis=1) < 0.05).all()
    # README's first screen says the same
    readme = " ".join((ROOT / "README.md").read_text().split())
    assert "under the thesis's own count of load swings at most about two fifths of any bearing's damage, the " \
           "HSS bearings' the largest" in readme


def test_what_campaigns_md_says_of_iecs_six_seeds():
    """c-dlc12-iec (six 600 s seeds in each of eleven bins): every lifetime DEL's interval within a few per
    cent of it, while one bin's damage scatters by tens of per cent (the seed study)."""
    t = pd.read_csv(ROOT / "docs" / "campaigns" / "c-dlc12-iec" / "lifetime.csv")
    half = (t.lifetime_del_hi - t.lifetime_del_lo) / 2.0 / t.lifetime_del
    assert (half < 0.05).all() and (half > 0.0).all(), half
    text = " ".join((ROOT / "docs" / "CAMPAIGNS.md").read_text().split())
    assert "the lifetime DELs' intervals come out within a few per cent (the table)" in text
    readme = " ".join((ROOT / "README.md").read_text().split())
    assert "they give each lifetime DEL to within a few per cent" in readme
