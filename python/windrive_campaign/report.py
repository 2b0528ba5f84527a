"""`scripts/campaign report`: a finished campaign's lifetime figures (lifetime.py) as lifetime.csv,
lifetime.json, lifetime_ldd.csv, a bar chart of each group's share of the damage (lifetime.png) and a
printed table; with `[gears]` also the teeth's lifetime damage (windrive life --cases) as lifetime_gears.csv,
a section of lifetime.json, lifetime_gears.png and a printed table, and with `[bearings]` the bearings'
(windrive life --cases) as lifetime_bearings.csv, a section, lifetime_bearings.png and a table. Cases that
are not finished are left out and counted, never guessed."""

from __future__ import annotations

import csv
import json
import math
import sys
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

from . import life_doc
from . import lifetime as lt
from . import schema
from .errors import CampaignError

# what the lifetime reads besides the statistics (store.table writes them all)
TABLE_COLUMNS = ("name", "group", "status", "wind_speed", "hours", "events", "analysed_s")

# the gear section's own statement of what its damage is (docs/CAMPAIGNS.md, Lifetime report)
GEAR_METHOD = ("Miner's sum per tooth flank (pitting) and root (bending) over the design life: nominal ISO 6336 "
               "stresses without load factors, two-slope S-N curve, as the paper (windrive gears)")  # fmt: skip
GEAR_KINDS = ("flank", "root")  # a tooth's rows in this order (windrive life --cases)
GEAR_KIND_TITLES = {"flank": "flank (pitting)", "root": "root (bending)"}
# the bearing section's (docs/CAMPAIGNS.md, Lifetime report)
BEARING_METHOD = ("ISO 281 basic rating life L10 (C_r from the roller geometry, P = X·F_r + Y·F_a, Miner over "
                  "revolutions). modified_damage: the same over ISO 281's modified life a_ISO·L10 with the oil of "
                  "[bearings] (by default ISO VG 320 at 65 °C, e_C 0.5: estimates, windrive bearings). thesis_damage: the thesis's count for "
                  "comparison (rainflow cycles of P as load cycles over the same law, its ch. 5.4)")  # fmt: skip
# the bearing figures written after the life in lifetime_bearings.csv
BEARING_EXTRA = ("events_share", "modified_damage", "modified_events_share", "thesis_damage", "thesis_events_share")


def locate_table(given: Path) -> Path:
    """The campaign's table from its folder, the table itself, or the campaign file (whose results are
    in results/campaigns/<name>, relative to the working directory as `run` writes them)."""
    if given.suffix == ".toml":
        given = Path("results") / "campaigns" / schema.load(given).name
        if not given.is_dir():
            raise CampaignError(f"{given}: no campaign folder: run `scripts/campaign run` first")
    if not given.exists():
        raise CampaignError(f"{given}: no such campaign folder, table or campaign file")
    if given.is_file():
        if given.suffix != ".parquet":
            raise CampaignError(f"{given}: neither a campaign folder, its .parquet table nor a campaign file (.toml)")
        return given
    tables = sorted(given.glob("*.parquet"))
    if not tables:
        raise CampaignError(f"{given}: no campaign table (*.parquet): run `scripts/campaign run` first")
    if len(tables) > 1:
        names = ", ".join(p.name for p in tables)
        raise CampaignError(f"{given}: {len(tables)} tables ({names}): give the one to report")
    return tables[0]


def read_table(path: Path, required: tuple[str, ...] = TABLE_COLUMNS):
    """The campaign's table as pandas and its metadata (climate years, f_eq, LDD bins); `required` are
    the columns the caller needs (the lifetime report's weights by default)."""
    try:
        t = pq.read_table(path)
    except (OSError, pa.ArrowInvalid) as e:
        raise CampaignError(f"{path}: cannot read the table: {e}") from None
    missing = [c for c in required if c not in t.column_names]
    if missing:
        raise CampaignError(f"{path}: not a campaign table (no column {', '.join(missing)})")
    return t.to_pandas(), lt.read_metadata(t.schema.metadata)


def write_csv(life: lt.Lifetime, path: Path):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["channel", "m", "lifetime_del", "lifetime_del_lo", "lifetime_del_hi", "damage_sum",
                    *(f"share:{g}" for g in life.groups)])  # fmt: skip
        for r in life.rows:
            lo, hi = r["lifetime_del_ci"]
            w.writerow([r["channel"], f"{r['m']:g}", repr(r["lifetime_del"]), repr(lo), repr(hi), repr(r["damage_sum"]),
                        *(repr(r["share"][g]) for g in life.groups)])  # fmt: skip


def write_ldd_csv(life: lt.Lifetime, path: Path):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["channel", "bin", "load_lo", "load_hi", "seconds", "hours", "revolutions"])
        for ch, d in life.ldd.items():
            e = d["edges"]
            for i, (s, n) in enumerate(zip(d["seconds"], d["revolutions"])):
                w.writerow([ch, i, repr(e[i]), repr(e[i + 1]), repr(s), repr(s / 3600.0), repr(n)])


def write_miner_csv(rows: list[dict], labels: tuple[str, ...], groups: list[str], path: Path,
                    extra: tuple[str, ...] = ()):  # fmt: skip
    """The Miner rows of the lifetime (teeth, bearings): their `labels`, damage, life, the `extra`
    figures and the shares."""
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow([*labels, "damage", "damage_lo", "damage_hi", "life_years", *extra, *(f"share:{g}" for g in groups)])
        for r in rows:
            w.writerow([*(r[k] for k in labels), repr(r["damage"]), *map(repr, r["damage_ci"]), repr(r["life_years"]),
                        *(repr(r[k]) for k in extra), *(repr(r["share"][g]) for g in groups)])  # fmt: skip


def as_json(life: lt.Lifetime) -> dict:
    d = {
        "campaign": life.campaign,
        "years": life.years,
        "feq_hz": life.feq_hz,
        "reference_s": life.life_s,
        "reference": "the whole design life, years x 8760 h (windrive life's convention)",
        "operating_hours": life.operating_hours,
        "events": life.events,
        "cases_used": life.used,
        "cases_left_out": life.left_out,
        "groups": life.groups,
        "lifetime": life.rows,
        "ldd": life.ldd,
        "thesis_ratios": life.ratios,
        "intervals": {"level": 0.95, **life.intervals},
    }
    if life.gears:  # only then: a campaign without [gears] keeps the JSON it had
        d["gears"] = {"method": GEAR_METHOD, "lifetime": [_miner_json(r) for r in life.gears]}
    if life.bearings:  # likewise for [bearings]
        d["bearings"] = {"method": BEARING_METHOD, "lifetime": [_miner_json(r) for r in life.bearings]}
    return d


def _miner_json(row: dict) -> dict:
    """A tooth's or bearing's row with null for a damage-free part's infinite life and undefined shares,
    as JSON has neither (paper_summary.json does the same)."""
    finite = {k: _finite(v) for k, v in row.items() if isinstance(v, float)}
    intervals = {k: [_finite(x) for x in v] for k, v in row.items() if k.endswith("_ci") and isinstance(v, list)}
    return {**row, **finite, **intervals, "share": {g: _finite(s) for g, s in row["share"].items()},
            "share_ci": {g: [_finite(x) for x in ci] for g, ci in row["share_ci"].items()}}  # fmt: skip


def _finite(x: float) -> float | None:
    return x if math.isfinite(x) else None


def bar_chart(life: lt.Lifetime, path: Path):
    """One panel per channel: each group's share of the damage sum, a bar per Wöhler slope."""
    import matplotlib

    matplotlib.use("Agg")  # files only: no display on a cluster node or in CI
    import matplotlib.pyplot as plt

    channels = list(dict.fromkeys(r["channel"] for r in life.rows))
    fig, axes = plt.subplots(len(channels), 1, figsize=(max(6.0, 1.1 * len(life.groups) + 2), 2.8 * len(channels)),
                             squeeze=False)  # fmt: skip
    for ax, ch in zip(axes[:, 0], channels):
        rows = [r for r in life.rows if r["channel"] == ch]
        width = 0.8 / len(rows)
        for k, r in enumerate(rows):
            x = [i + (k - (len(rows) - 1) / 2) * width for i in range(len(life.groups))]
            ax.bar(x, [100 * r["share"][g] for g in life.groups], width, label=f"m = {r['m']:g}")
        ax.set_title(f"{ch}: share of the {life.years:g}-year damage", fontsize=10)
        ax.set_ylabel("share of D [%]")
        ax.set_xticks(range(len(life.groups)), life.groups, rotation=20, ha="right", fontsize=8)
        ax.legend(fontsize=8)
    fig.suptitle(f"campaign {life.campaign}", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def gear_chart(life: lt.Lifetime, path: Path):
    """A panel for the flanks and one for the roots: per tooth, a bar stacked from each group's share of
    its lifetime damage, with the damage and life written above it. Shares rather than damage on the
    axis because the teeth's damage spans decades: on one linear axis the small ones would vanish."""
    import matplotlib

    matplotlib.use("Agg")  # files only, as bar_chart
    import matplotlib.pyplot as plt

    kinds = [k for k in GEAR_KINDS if any(r["kind"] == k for r in life.gears)]
    teeth = max(sum(r["kind"] == k for r in life.gears) for k in kinds)
    fig, axes = plt.subplots(len(kinds), 1, figsize=(max(6.0, 0.8 * teeth + 3.5), 3.4 * len(kinds)), squeeze=False)
    colours = _group_colours(plt, life.groups)
    for ax, kind in zip(axes[:, 0], kinds):
        rows = [r for r in life.gears if r["kind"] == kind]
        heading = f"{GEAR_KIND_TITLES[kind]}: each group's share of the {life.years:g}-year Miner damage"
        _share_panel(ax, rows, [r["tooth"] for r in rows], life.groups, colours, heading)
    title = f"campaign {life.campaign}: gear damage (nominal ISO 6336, two-slope S-N)"
    _save_with_legend(plt, fig, axes[0, 0], title, path)


def bearing_chart(life: lt.Lifetime, path: Path):
    """Per bearing, its lifetime damage (top) and a bar stacked from each group's share of it (bottom,
    as gear_chart). The damage goes on a log axis when it spans more than two decades, as it does from
    a planet bearing to a carrier bearing: on a linear one the small ones would vanish."""
    import matplotlib

    matplotlib.use("Agg")  # files only, as bar_chart
    import matplotlib.pyplot as plt

    rows = life.bearings
    names = [r["bearing"] for r in rows]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(max(6.0, 0.7 * len(rows) + 3.5), 7.0))
    top.bar(range(len(rows)), [r["damage"] for r in rows], 0.7, color="0.45")
    positive = [r["damage"] for r in rows if r["damage"] > 0]
    if positive and max(positive) > 100 * min(positive):
        top.set_yscale("log")
    top.set_title(f"Miner damage over {life.years:g} years", fontsize=10)
    top.set_ylabel("D_life")
    top.set_xticks(range(len(rows)), names, fontsize=8, rotation=30, ha="right")
    colours = _group_colours(plt, life.groups)
    _share_panel(bottom, rows, names, life.groups, colours, "each group's share of the damage")
    bottom.tick_params(axis="x", labelrotation=30)
    title = f"campaign {life.campaign}: bearing damage (ISO 281 L10)"
    _save_with_legend(plt, fig, bottom, title, path)


def _group_colours(plt, groups: list[str]):
    return plt.get_cmap("tab10" if len(groups) <= 10 else "tab20")


def _save_with_legend(plt, fig, ax, title: str, path: Path):
    """The groups' legend beside `ax`, outside the axes, the title, the file."""
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=110, bbox_inches="tight")  # the legend sits outside the axes: bbox takes it in
    plt.close(fig)


def _share_panel(ax, rows: list[dict], names: list[str], groups: list[str], colours, title: str):
    _stacked_shares(ax, rows, groups, colours)
    ax.set_title(title, fontsize=10)
    ax.set_ylabel("share of D [%]")
    ax.set_ylim(0, 125)  # room for the labels above the bars
    ax.set_xticks(range(len(rows)), names, fontsize=8)


def _stacked_shares(ax, rows: list[dict], groups: list[str], colours):
    bottom = [0.0] * len(rows)
    for k, g in enumerate(groups):
        heights = [100 * r["share"][g] if r["damage"] > 0 else 0.0 for r in rows]
        ax.bar(range(len(rows)), heights, 0.7, bottom=bottom, label=g, color=colours(k % colours.N))
        bottom = [b + h for b, h in zip(bottom, heights)]
    for i, r in enumerate(rows):
        ax.text(i, 102, f"D {r['damage']:.2g}\n{_years(r['life_years'])}", ha="center", va="bottom", fontsize=7)


def _years(life_years: float) -> str:
    return "no damage" if math.isinf(life_years) else f"{life_years:.3g} y"


def print_tables(life: lt.Lifetime, out=sys.stdout):
    print(f"campaign {life.campaign}: {life.used} cases over {life.years:g} years "
          f"({life.operating_hours:.0f} operating h, {life.events:g} events); "
          f"lifetime DEL over T_life = {life.life_s:.6g} s at f_eq = {life.feq_hz:g} Hz", file=out)  # fmt: skip
    print(f"{'channel':36} {'m':>3} {'lifetime DEL':>13} {'95 % interval':>25} {'damage sum D':>13}", file=out)
    for r in life.rows:
        lo, hi = r["lifetime_del_ci"]
        print(f"{r['channel']:36} {r['m']:>3g} {r['lifetime_del']:>13.5g} {f'{lo:.5g} .. {hi:.5g}':>25} "
              f"{r['damage_sum']:>13.4e}", file=out)  # fmt: skip
    one = life.intervals.get("one_seed") or []
    print("(95 % intervals: Student's t over each DLC 1.2 bin's seeds"
          + (f"; fixed, one case each: {', '.join(one[:6])}{' …' if len(one) > 6 else ''})" if one else ")"), file=out)
    heads = [f"{r['channel'].split('.')[-1]} m{r['m']:g}" for r in life.rows]
    print_shares("share of D [%]", life.groups, heads, life.rows, 16, out)
    if life.ratios:
        print(f"\nDEL ratios at m = {lt.THESIS_M:g} (thesis: measured HSS and LSS torque, §3.4.3)", file=out)
        for q in life.ratios:
            print(f"  {q['channel']}: {q['shutdown']} / {q['versus']} ({q['versus_cases']}): "
                  f"ours {q['ours']:.2f}, thesis {q['thesis']:.2f}", file=out)  # fmt: skip
    if life.gears:
        print_gear_tables(life, out)
    if life.bearings:
        print_bearing_tables(life, out)


def print_gear_tables(life: lt.Lifetime, out=sys.stdout):
    print(f"\ngear damage over {life.years:g} years (Miner; nominal ISO 6336 stresses, two-slope S-N)", file=out)
    print(f"{'tooth':8} {'kind':6} {'damage D':>11} {'life [years]':>13} {'95 % interval':>21}", file=out)
    for r in life.gears:
        lo, hi = r["life_years_ci"]
        print(f"{r['tooth']:8} {r['kind']:6} {r['damage']:>11.4e} {r['life_years']:>13.4g} "
              f"{f'{lo:.4g} .. {hi:.4g}':>21}", file=out)  # fmt: skip
    heads = [f"{r['tooth']} {r['kind']}" for r in life.gears]
    print_shares("share of gear damage [%]", life.groups, heads, life.gears, 10, out)


def print_bearing_tables(life: lt.Lifetime, out=sys.stdout):
    print(f"\nbearing damage over {life.years:g} years (Miner over L10, ISO 281's basic rating life; beside it over "
          f"the modified life a_ISO·L10 with an estimated oil, and the thesis's count)", file=out)  # fmt: skip
    print(f"{'bearing':14} {'C [kN]':>8} {'damage D':>11} {'life [years]':>13} {'events [%]':>11}   "
          f"{'a_ISO·L10: D':>13} {'events [%]':>11}   {'thesis count: D':>15} {'events [%]':>11}",
          file=out)  # fmt: skip
    for r in life.bearings:
        print(f"{r['bearing']:14} {r['dynamic_load_rating'] / 1e3:>8.0f} {r['damage']:>11.4e} "
              f"{r['life_years']:>13.4g} {100 * r['events_share']:>11.2f}   {r['modified_damage']:>13.4e} "
              f"{100 * r['modified_events_share']:>11.2f}   {r['thesis_damage']:>15.4e} "
              f"{100 * r['thesis_events_share']:>11.2f}", file=out)  # fmt: skip
    heads = [r["bearing"] for r in life.bearings]
    width = max([10, *(len(h) + 1 for h in heads)])  # wide enough for names such as planet_1_uw
    print_shares("share of bearing damage [%]", life.groups, heads, life.bearings, width, out)


def print_shares(title: str, groups: list[str], heads: list[str], rows: list[dict], width: int, out):
    """A table of each group's share in %, one column per row of `rows` (their `share` dicts)."""
    print(f"\n{title}", file=out)
    print(f"{'group':24} " + " ".join(f"{h:>{width}}" for h in heads), file=out)
    for g in groups:
        print(f"{g:24} " + " ".join(f"{100 * r['share'][g]:>{width}.2f}" for r in rows), file=out)


def report(given: Path, out_dir: Path | None, windrive: str | None = None, doc: Path | None = None) -> int:
    """Writes the report (and with `doc` that page's block of the campaign's life tables, life_doc.py); 0
    when every case counted, 1 when some are pending, failed or timed out."""
    table = locate_table(given)
    t, meta = read_table(table)
    life = lt.compute(t, meta, windrive)
    out_dir = out_dir or table.parent
    out_dir.mkdir(parents=True, exist_ok=True)
    written = ["lifetime.csv", "lifetime.json", "lifetime_ldd.csv"]
    write_csv(life, out_dir / "lifetime.csv")
    write_ldd_csv(life, out_dir / "lifetime_ldd.csv")
    (out_dir / "lifetime.json").write_text(json.dumps(as_json(life), indent=1))
    if life.rows:  # a campaign of channels without Wöhler slopes has no DEL to chart
        bar_chart(life, out_dir / "lifetime.png")
        written.append("lifetime.png")
    if life.gears:
        write_miner_csv(life.gears, ("tooth", "kind"), life.groups, out_dir / "lifetime_gears.csv")
        gear_chart(life, out_dir / "lifetime_gears.png")
        written += ["lifetime_gears.csv", "lifetime_gears.png"]
    if life.bearings:
        write_miner_csv(life.bearings, ("bearing", "dynamic_load_rating"), life.groups,
                        out_dir / "lifetime_bearings.csv", BEARING_EXTRA)  # fmt: skip
        bearing_chart(life, out_dir / "lifetime_bearings.png")
        written += ["lifetime_bearings.csv", "lifetime_bearings.png"]
    if doc is not None:
        doc.write_text(life_doc.replace(doc, life.campaign, out_dir))
        written.append(f"and {doc}'s block")
    print_tables(life)
    print(f"\nwritten: {out_dir}/{', '.join(written)}")
    return _warn_left_out(life)


def _warn_left_out(life: lt.Lifetime) -> int:
    unfinished = {k: v for k, v in life.left_out.items() if k != "grid (no weight)"}
    for k, v in life.left_out.items():
        print(f"not in the lifetime: {len(v)} {k}: {', '.join(v[:5])}{' …' if len(v) > 5 else ''}", file=sys.stderr)
    if unfinished:
        print("the damage above is a lower bound: run the campaign again to finish them", file=sys.stderr)
        return 1
    return 0
