"""`scripts/campaign report`: a finished campaign's lifetime figures (lifetime.py) as lifetime.csv,
lifetime.json, lifetime_ldd.csv, a bar chart of each group's share of the damage (lifetime.png) and a
printed table. Cases that are not finished are left out and counted, never guessed."""

from __future__ import annotations

import csv
import json
import sys
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

from . import lifetime as lt
from . import schema
from .errors import CampaignError

# what the lifetime reads besides the statistics (store.table writes them all)
TABLE_COLUMNS = ("name", "group", "status", "wind_speed", "hours", "events", "analysed_s")


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


def read_table(path: Path):
    """The campaign's table as pandas and its metadata (climate years, f_eq, LDD bins)."""
    try:
        t = pq.read_table(path)
    except (OSError, pa.ArrowInvalid) as e:
        raise CampaignError(f"{path}: cannot read the table: {e}") from None
    missing = [c for c in TABLE_COLUMNS if c not in t.column_names]
    if missing:
        raise CampaignError(f"{path}: not a campaign table (no column {', '.join(missing)})")
    return t.to_pandas(), lt.read_metadata(t.schema.metadata)


def write_csv(life: lt.Lifetime, path: Path):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["channel", "m", "lifetime_del", "damage_sum", *(f"share:{g}" for g in life.groups)])
        for r in life.rows:
            w.writerow([r["channel"], f"{r['m']:g}", repr(r["lifetime_del"]), repr(r["damage_sum"]),
                        *(repr(r["share"][g]) for g in life.groups)])  # fmt: skip


def write_ldd_csv(life: lt.Lifetime, path: Path):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["channel", "bin", "load_lo", "load_hi", "seconds", "hours", "revolutions"])
        for ch, d in life.ldd.items():
            e = d["edges"]
            for i, (s, n) in enumerate(zip(d["seconds"], d["revolutions"])):
                w.writerow([ch, i, repr(e[i]), repr(e[i + 1]), repr(s), repr(s / 3600.0), repr(n)])


def as_json(life: lt.Lifetime) -> dict:
    return {
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
    }


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


def print_tables(life: lt.Lifetime, out=sys.stdout):
    print(f"campaign {life.campaign}: {life.used} cases over {life.years:g} years "
          f"({life.operating_hours:.0f} operating h, {life.events:g} events); "
          f"lifetime DEL over T_life = {life.life_s:.6g} s at f_eq = {life.feq_hz:g} Hz", file=out)  # fmt: skip
    print(f"{'channel':36} {'m':>3} {'lifetime DEL':>13} {'damage sum D':>13}", file=out)
    for r in life.rows:
        print(f"{r['channel']:36} {r['m']:>3g} {r['lifetime_del']:>13.5g} {r['damage_sum']:>13.4e}", file=out)
    heads = [f"{r['channel'].split('.')[-1]} m{r['m']:g}" for r in life.rows]
    print("\nshare of D [%]", file=out)
    print(f"{'group':24} " + " ".join(f"{h:>16}" for h in heads), file=out)
    for g in life.groups:
        print(f"{g:24} " + " ".join(f"{100 * r['share'][g]:>16.2f}" for r in life.rows), file=out)
    if life.ratios:
        print(f"\nDEL ratios at m = {lt.THESIS_M:g} (thesis: measured HSS and LSS torque, §3.4.3)", file=out)
        for q in life.ratios:
            print(f"  {q['channel']}: {q['shutdown']} / {q['versus']} ({q['versus_cases']}): "
                  f"ours {q['ours']:.2f}, thesis {q['thesis']:.2f}", file=out)  # fmt: skip


def report(given: Path, out_dir: Path | None) -> int:
    """Writes the report; 0 when every case counted, 1 when some are pending, failed or timed out."""
    table = locate_table(given)
    t, meta = read_table(table)
    life = lt.compute(t, meta)
    out_dir = out_dir or table.parent
    out_dir.mkdir(parents=True, exist_ok=True)
    write_csv(life, out_dir / "lifetime.csv")
    write_ldd_csv(life, out_dir / "lifetime_ldd.csv")
    (out_dir / "lifetime.json").write_text(json.dumps(as_json(life), indent=1))
    bar_chart(life, out_dir / "lifetime.png")
    print_tables(life)
    print(f"\nwritten: {out_dir}/lifetime.csv, lifetime.json, lifetime_ldd.csv, lifetime.png")
    return _warn_left_out(life)


def _warn_left_out(life: lt.Lifetime) -> int:
    unfinished = {k: v for k, v in life.left_out.items() if k != "grid (no weight)"}
    for k, v in life.left_out.items():
        print(f"not in the lifetime: {len(v)} {k}: {', '.join(v[:5])}{' …' if len(v) > 5 else ''}", file=sys.stderr)
    if unfinished:
        print("the damage above is a lower bound: run the campaign again to finish them", file=sys.stderr)
        return 1
    return 0
