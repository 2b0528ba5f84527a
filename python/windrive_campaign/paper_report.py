"""`scripts/campaign paper`: the paper's comparison (paper.py) as files and a printed summary:

    paper_table6.csv, .md   Table 6 beside ours: 1-day damage at 11.5 and 18 m/s, TI 14 %, ratio, ranks
    paper_table7.csv, .md   Table 7 beside ours: η per wind speed × TI, the paper's, ours, the difference
    paper_eta.png           heat maps of η, ours above the paper's, one colour scale per damage
    paper_summary.json      the shape checks (a)-(d) for both, D_const,rated, cells, cases left out,
                            the verdicts of η's intervals over seeds (inside, sign at rated, TI trend)
    paper_cases.csv         the table's columns this comparison reads, one row per case: the page
                            (--doc, paper_doc.py) is generated from it, so a test can regenerate it

Cases that are not finished are left out and named, never guessed; the exit status is then 1.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from . import paper, paper_doc, paper_sampling
from . import paper_data as data
from .errors import CampaignError
from .report import locate_table, read_table

TABLE_COLUMNS = ("name", "group", "status")  # the grid cases' columns this report reads
FILES = ("paper_table6.csv", "paper_table6.md", "paper_table7.csv", "paper_table7.md", "paper_eta.png",
         "paper_summary.json", "paper_cases.csv")  # fmt: skip


def _num(x: float, digits: int = 4) -> str:
    return "-" if x is None or x != x else f"{x:.{digits}g}"


def _rank(x: float) -> str:
    return "-" if x != x else f"{int(x)}"


def _ti(ti: float) -> str:
    return "0 (steady)" if ti == 0 else f"{ti:g}"


# ---------------------------------------------------------------------------------------------------
# Table 6 and Table 7


def write_table6(t6: pd.DataFrame, csv_path: Path, md_path: Path):
    t6.to_csv(csv_path, index=False, float_format="%.17g")
    speeds = [f"{s:g}" for s in data.TABLE6_SPEEDS]
    head = ["stage", "gear", "damage", "tooth"]
    for s in speeds:
        head += [f"{s} m/s paper", f"{s} m/s ours", "ours/paper", "stress factor", "rank paper", "rank ours"]
    lines = [
        f"# Table 6: 1-day damage at TI {data.TABLE6_TI_PCT:g} % (×1e-6): the paper's and ours",
        "",
        "Ours is the mean over the seeds of `gear.<tooth>.root_day` (bending) or `.flank_day` (pitting); the "
        "rank is within the stage and kind of damage, 1 the most damaged; the paper's \"-\" is too small to "
        "display (ranked last). The stress factor is what our stresses would have to be multiplied by to give "
        "the paper's damage: (paper/ours)^(1/k), k = 2m − 1 the rating's S-N exponent below the knee (a lower "
        "bound if the raised stresses crossed the knee).",
        "",
        "| " + " | ".join(head) + " |",
        "|" + "---|" * len(head),
    ]
    for _, r in t6.iterrows():
        cells = [r.stage, r.gear, r.damage, r.tooth]
        for s in speeds:
            cells += [_num(r[f"paper_{s}"] / data.TABLE6_UNIT), _num(r[f"ours_{s}"] / data.TABLE6_UNIT),
                      _num(r[f"ratio_{s}"], 3), _num(r[f"factor_{s}"], 3), _rank(r[f"rank_paper_{s}"]),
                      _rank(r[f"rank_ours_{s}"])]  # fmt: skip
        lines.append("| " + " | ".join(cells) + " |")
    md_path.write_text("\n".join(lines) + "\n")


def _interval_text(lo: float, hi: float) -> str:
    return "-" if lo != lo else f"[{lo:.3g}, {hi:.3g}]"


def write_table7(t7: pd.DataFrame, csv_path: Path, md_path: Path):
    t7.to_csv(csv_path, index=False, float_format="%.17g")
    head = ["V [m/s]", "TI [%]", "seeds"]
    for name in paper.TABLE7_LABELS:
        head += [f"{name} paper", "ours", f"{paper.CONFIDENCE:.0%} interval", "inside"]
    lines = [
        "# Table 7: η = (D − D_const,rated) / D_const,rated × 100 %: the paper's, ours with its interval over seeds",
        "",
        f"D_const,rated is steady wind at {data.RATED_SPEED:g} m/s; TI 0 is steady wind; ours is the mean "
        "over the seeds of each cell, its interval the percentile bootstrap over them "
        f"({paper.BOOTSTRAP_DRAWS} draws, generator seed {paper.BOOTSTRAP_SEED}); `inside` says whether the "
        "paper's value lies in it. Bending is the tooth root, contacting the flank.",
        "",
        "| " + " | ".join(head) + " |",
        "|" + "---|" * len(head),
    ]
    for _, r in t7.iterrows():
        cells = [f"{r.wind_speed:g}", _ti(r.ti_pct), f"{int(r.seeds)}" if "seeds" in r else "-"]
        for name in paper.TABLE7_LABELS:
            lo, hi = r.get(f"{name} lo", math.nan), r.get(f"{name} hi", math.nan)
            inside = r.get(f"{name} inside", math.nan)
            cells += [_num(r[f"{name} paper"]), _num(r[f"{name} ours"]), _interval_text(lo, hi),
                      "-" if inside != inside else ("yes" if inside else "no")]  # fmt: skip
        lines.append("| " + " | ".join(cells) + " |")
    md_path.write_text("\n".join(lines) + "\n")


# ---------------------------------------------------------------------------------------------------
# heat maps


def _grid(eta: pd.DataFrame, name: str, speeds: list[float], tis: list[float]) -> np.ndarray:
    m = np.full((len(speeds), len(tis)), np.nan)
    for (v, ti), x in eta[name].items():
        m[speeds.index(v), tis.index(ti)] = x
    return m


def heat_maps(rel_ours: pd.DataFrame, path: Path):
    """η over wind speed × TI, one column per Table 7 damage: ours on top, the paper's below, on the
    same axes (the union of both grids) and the same colour scale (diverging about 0 when η changes
    sign), each cell labelled with its value."""
    import matplotlib

    matplotlib.use("Agg")  # files only: no display on a cluster node or in CI
    import matplotlib.pyplot as plt
    from matplotlib.colors import Normalize, TwoSlopeNorm

    ours = (rel_ours - 1.0) * 100.0
    theirs = (paper.paper_relative() - 1.0) * 100.0
    index = ours.index.union(theirs.index)
    speeds = sorted(set(index.get_level_values("wind_speed")))
    tis = sorted(set(index.get_level_values("ti_pct")))
    names = paper.TABLE7_LABELS
    fig, axes = plt.subplots(2, len(names), figsize=(3.3 * len(names), 2.2 + 0.45 * len(speeds) * 2),
                             squeeze=False, constrained_layout=True)  # fmt: skip
    for k, name in enumerate(names):
        grids = [_grid(ours, name, speeds, tis), _grid(theirs, name, speeds, tis)]
        values = np.concatenate([g[np.isfinite(g)] for g in grids])
        lo, hi = (values.min(), values.max()) if len(values) else (-1.0, 1.0)
        if lo == hi:
            lo, hi = lo - 1.0, hi + 1.0
        norm = TwoSlopeNorm(0.0, lo, hi) if lo < 0.0 < hi else Normalize(lo, hi)
        for row, (g, who) in enumerate(zip(grids, ("ours", "paper"))):
            ax = axes[row, k]
            im = ax.imshow(np.ma.masked_invalid(g), origin="lower", aspect="auto", cmap="RdBu_r", norm=norm)
            for i in range(len(speeds)):
                for j in range(len(tis)):
                    if np.isfinite(g[i, j]):
                        shade = float(norm(g[i, j]))  # white on the dark ends of the colour map
                        colour = "white" if shade < 0.2 or shade > 0.8 else "black"
                        ax.text(j, i, f"{g[i, j]:.0f}", ha="center", va="center", fontsize=6, color=colour)
            ax.set_xticks(range(len(tis)), ["st." if t == 0 else f"{t:g}" for t in tis], fontsize=7)
            ax.set_yticks(range(len(speeds)), [f"{v:g}" for v in speeds], fontsize=7)
            ax.set_title(f"{name}: {who}", fontsize=9)
            if row == 1:
                ax.set_xlabel("TI [%] (st. = steady)", fontsize=8)
            if k == 0:
                ax.set_ylabel("wind speed [m/s]", fontsize=8)
        fig.colorbar(im, ax=list(axes[:, k]), shrink=0.8, label="η [%]")
    fig.suptitle(f"η = (D − D_const,rated) / D_const,rated, D_const,rated = steady {data.RATED_SPEED:g} m/s "
                 "(paper: Table 7)", fontsize=10)  # fmt: skip
    fig.savefig(path, dpi=100)
    plt.close(fig)


# ---------------------------------------------------------------------------------------------------
# summary and printing

DEFINITIONS = {
    "eta": "(D - D_const,rated) / D_const,rated x 100 %, D_const,rated the steady (rotor.turbulence = none) "
    "11.5 m/s cell (paper Eq. 5); D per cell the mean over its cases (seeds)",
    "flat_above_14": "(a) per damage, the TI-averaged D (mean over the turbulent cells of a speed) at each speed "
    "from 14 to 20 m/s, and its max/min",
    "steady_above_turbulent": "(b) per damage, of the turbulent cells at 14 m/s and above with a steady cell at "
    "their speed, how many have less damage than it",
    "speed_sensitivity": "(c) per damage, linear finite differences of the TI-averaged D / D_const,rated between "
    "consecutive speeds (over the TIs both speeds have), per m/s, and the interval where it peaks",
    "rankings": "(d) the teeth by damage, most damaged first, ours and the paper's (Table 6, TI 14 %), and the "
    "pairs both order alike",
}


def _clean(x):
    """JSON without NaN (not JSON): null instead."""
    if isinstance(x, dict):
        return {str(k): _clean(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [_clean(v) for v in x]
    if isinstance(x, float | np.floating):
        return None if not math.isfinite(x) else float(x)
    if isinstance(x, np.integer):
        return int(x)
    return x


def summary(cmp: paper.Comparison, table: Path, meta: dict) -> dict:
    c = cmp.cells
    return _clean({
        "campaign": meta.get("campaign"),
        "table": str(table),
        "paper": "Xiang, Jiang, You, Shen: Influence of Quasi-Steady Wind Loads on the Fatigue Damage of Wind "
                 "Turbine Gearboxes, Tables 6 and 7",
        "definitions": DEFINITIONS,
        "cases_used": c.used,
        "cells": [{"wind_speed": v, "ti_pct": ti, "cases": int(n)} for (v, ti), n in c.count.items()],
        "cases_left_out": c.left_out,
        "paper_cells_missing": [{"wind_speed": v, "ti_pct": ti} for v, ti in cmp.missing],
        "d_const_rated": {
            "ours": {paper.label(k, t): cmp.const_rated[paper.damage_column(k, t)] for k, t in data.TABLE7_COLUMNS},
            "paper_from_table6": paper.paper_const_rated(),
        },
        "shapes": {"ours": cmp.shapes_ours, "paper": cmp.shapes_paper},
        "rankings": cmp.rankings,
        "intervals": {"confidence": paper.CONFIDENCE, "bootstrap_draws": paper.BOOTSTRAP_DRAWS,
                      "bootstrap_seed": paper.BOOTSTRAP_SEED, **cmp.verdicts},
    })  # fmt: skip


def print_report(cmp: paper.Comparison, meta: dict, out=sys.stdout):
    c = cmp.cells
    n_rated = int(c.count.get((data.RATED_SPEED, 0.0), 0))
    print(f"campaign {meta.get('campaign', '?')}: {c.used} grid cases in {len(c.count)} cells; "
          f"D_const,rated = steady {data.RATED_SPEED:g} m/s ({n_rated} case{'s' if n_rated != 1 else ''})", file=out)
    print(f"\nTable 6: 1-day damage at TI {data.TABLE6_TI_PCT:g} % [1e-6], paper / ours (ours/paper), "
          "rank in stage paper/ours", file=out)  # fmt: skip
    t6 = cmp.table6
    for _, r in t6.iterrows():
        parts = []
        for s in (f"{v:g}" for v in data.TABLE6_SPEEDS):
            parts.append(f"{s:>4} m/s {_num(r[f'paper_{s}'] / data.TABLE6_UNIT):>6} / "
                         f"{_num(r[f'ours_{s}'] / data.TABLE6_UNIT):>9} ({_num(r[f'ratio_{s}'], 3):>6}) "
                         f"{_rank(r[f'rank_paper_{s}'])}/{_rank(r[f'rank_ours_{s}'])}")  # fmt: skip
        print(f"  {r.stage} {r.gear:15} {r.damage:8} {r.tooth:4} " + "   ".join(parts), file=out)
    print("\nTable 7: η [%], paper / ours (* the paper's value outside our interval over seeds)", file=out)
    print(f"  {'V':>4} {'TI':>3}  " + "".join(f"{n:>17}" for n in paper.TABLE7_LABELS), file=out)
    for _, r in cmp.table7.iterrows():
        cells = "".join(f"{_num(r[f'{n} paper'], 4):>7} /{_num(r[f'{n} ours'], 4):>7}"
                        f"{'*' if r.get(f'{n} inside', 1.0) == 0.0 else ' '}" for n in paper.TABLE7_LABELS)  # fmt: skip
        print(f"  {r.wind_speed:>4g} {r.ti_pct:>3g}  {cells}", file=out)
    v = cmp.verdicts
    tot = v["inside_total"]
    print(f"\nthe paper's η inside our {paper.CONFIDENCE:.0%} interval: {tot['inside']} of {tot['cells']} "
          "turbulent values", file=out)  # fmt: skip
    print(f"sign of η at {data.RATED_SPEED:g} m/s (intervals): " +
          ", ".join(f"{s} {n}" for s, n in v["sign_counts"].items() if n), file=out)  # fmt: skip
    print_shapes(cmp, out)


def print_shapes(cmp: paper.Comparison, out):
    ours, theirs = cmp.shapes_ours, cmp.shapes_paper
    print("\nshape checks, ours | paper (its Table 7)", file=out)
    print("(a) damage flat above 14 m/s: max/min of the TI-averaged D over 14-20 m/s", file=out)
    for n in paper.TABLE7_LABELS:
        a, b = ours["flat_above_14"][n], theirs["flat_above_14"][n]
        print(f"    {n:15} {_num(a['max_over_min'], 4):>7} ({len(a['speeds'])} speeds) | "
              f"{_num(b['max_over_min'], 4):>7} ({len(b['speeds'])} speeds)", file=out)  # fmt: skip
    print(f"(b) steady more damaging than turbulent: turbulent cells at V >= {paper.STEADY_ABOVE:g} m/s below "
          "the steady cell of their speed", file=out)  # fmt: skip
    for n in paper.TABLE7_LABELS:
        a, b = ours["steady_above_turbulent"][n], theirs["steady_above_turbulent"][n]
        print(f"    {n:15} {a['steady_higher']:>3}/{a['cells']:<3} ({_num(a['fraction'], 3):>5}) | "
              f"{b['steady_higher']:>3}/{b['cells']:<3} ({_num(b['fraction'], 3):>5})", file=out)  # fmt: skip
    print("(c) where ∂D/∂V peaks: linear finite differences of the TI-averaged D/D_const,rated between "
          "consecutive speeds, per m/s", file=out)  # fmt: skip
    for n in paper.TABLE7_LABELS:
        a, b = ours["speed_sensitivity"][n], theirs["speed_sensitivity"][n]
        print(f"    {n:15} {_interval(a):>24} | {_interval(b):>24}", file=out)
    print(f"(d) teeth by damage at TI {data.TABLE6_TI_PCT:g} %, most damaged first (pairs in the paper's order)",
          file=out)  # fmt: skip
    for key, r in cmp.rankings.items():
        print(f"    {key:18} ours  {' > '.join(r['ours']) or '-'}   ({r['pairs_in_the_same_order']}/{r['pairs']})",
              file=out)  # fmt: skip
        print(f"    {'':18} paper {' > '.join(r['paper'])}", file=out)


def _interval(s: dict) -> str:
    if s["peak_per_m_s"] != s["peak_per_m_s"]:
        return "- (fewer than 2 speeds)"
    return f"{s['peak_from']:g}-{s['peak_to']:g} m/s ({s['peak_per_m_s']:.3g})"


# ---------------------------------------------------------------------------------------------------
# the command


CASE_COLUMNS = ("name", "group", "status", paper.WIND, paper.TI, paper.TURBULENCE, "param.rotor.seed",
                paper_sampling.SAMPLING, "run_s")  # fmt: skip


def write_cases(t: pd.DataFrame, path: Path):
    """The columns the comparison and its page read, one row per case, floats to the bit."""
    extra = [c for c in t.columns if c.startswith("gear.") and c.endswith((".root_day", ".flank_day"))]
    extra += [c for c in paper_doc.GLOBAL_COLUMNS if c in t.columns]
    cols = [c for c in CASE_COLUMNS if c in t.columns] + extra
    t[cols].sort_values("name", kind="stable").to_csv(path, index=False, float_format="%.17g")


def report(given: Path, out_dir: Path | None, doc: Path | None = None, against: Path | None = None) -> int:
    """Writes the comparison (and with `doc` the page, generated from paper_cases.csv as a test regenerates
    it); 0 when every grid case counted, 1 when some are pending, failed or timed out."""
    table = locate_table(given)
    t, meta = read_table(table, TABLE_COLUMNS)
    try:
        cmp = paper.compare(t)
    except CampaignError as e:
        raise CampaignError(f"{table}: {e}") from None
    out_dir = out_dir or table.parent
    out_dir.mkdir(parents=True, exist_ok=True)
    write_table6(cmp.table6, out_dir / "paper_table6.csv", out_dir / "paper_table6.md")
    write_table7(cmp.table7, out_dir / "paper_table7.csv", out_dir / "paper_table7.md")
    heat_maps(cmp.relative, out_dir / "paper_eta.png")
    (out_dir / "paper_summary.json").write_text(json.dumps(summary(cmp, table, meta), indent=1))
    write_cases(t, out_dir / "paper_cases.csv")
    if doc is not None:
        doc.write_text(paper_doc.page_from_csv(out_dir / "paper_cases.csv", meta.get("campaign"), against))
    print_report(cmp, meta)
    print(f"\nwritten: {out_dir}/{', '.join(FILES)}{f' and {doc}' if doc is not None else ''}")
    return _warn(cmp)


def _warn(cmp: paper.Comparison) -> int:
    unfinished = 0
    for why, names in cmp.cells.left_out.items():
        print(f"not compared: {len(names)} {why}: {', '.join(names[:5])}{' …' if len(names) > 5 else ''}",
              file=sys.stderr)  # fmt: skip
        unfinished += why in ("pending", "failed", "timeout")
    if cmp.missing:
        cells = ", ".join(f"{v:g} m/s TI {ti:g}" for v, ti in cmp.missing[:6])
        print(f"the campaign has no case in {len(cmp.missing)} of the paper's {len(paper.paper_cells())} "
              f"cells: {cells}{' …' if len(cmp.missing) > 6 else ''}", file=sys.stderr)  # fmt: skip
    if unfinished:
        print("run the campaign again to finish the cases left out", file=sys.stderr)
        return 1
    return 0
