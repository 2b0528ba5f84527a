"""How far the reproduction's numbers move when the inputs no source gives move over their ranges, and
whether each row's verdict survives: Morris screening (SALib) of one group of estimates at a time, then
(`--sobol N`) Sobol indices of every row that varies, the rows whose verdict flips first.

The estimates, their nominal values, ranges and reasons come from the binary
(`windrive reproduce --estimates`; src/studies/data/estimates.toml). One evaluation is one
`windrive reproduce --set NAME=VALUE ...` subprocess on a dask worker: it runs the scenes the group acts on
with those values and prints every affected reproduction row as JSON (ours and its verdict). The nominal
point runs first among the evaluations, so each row's band contains the value the reproduction shows.

Outputs, in the output folder:
  <group>_evaluations.csv   every evaluation: the inputs, then each row's value (reruns start from it)
  <group>.csv               per row: nominal, band (min–max), verdicts counted, whether the verdict holds
                            across the band, and each input's Morris mu* and sigma relative to |nominal|
  <group>_tornado.png       per row whose band is widest or whose verdict flips: the inputs by mu*
  bands.json                every group's rows in one list, which `windrive reproduce` reads to say on
                            docs/REPRODUCTION.md whether a verdict holds across the estimates
  <group>_sobol.csv         with --sobol: per varying row and input, the first-order and total Sobol
                            indices with their 95 % bootstrap half-widths (Saltelli sample of N·(k+2) points)
  <group>_sobol_evaluations.csv  its evaluations
"""

from __future__ import annotations

import csv
import json
import math
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from .errors import CampaignError

TIMEOUT_S = 1800.0  # one evaluation: the 6-DOF shutdown takes a minute or two on one core
BANDS = "bands.json"
BAND_COLUMNS = ["quantity", "group", "evaluations", "nominal", "low", "high", "nominal_verdict", "verdicts", "holds", "drivers"]


@dataclass(frozen=True)
class Estimate:
    name: str
    group: str
    description: str
    unit: str
    nominal: float
    low: float
    high: float
    reason: str


def estimates(windrive: str) -> list[Estimate]:
    """The estimates as the binary lists them."""
    out = subprocess.run([windrive, "reproduce", "--estimates"], capture_output=True, text=True, check=False)
    if out.returncode != 0:
        raise CampaignError(f"{windrive} reproduce --estimates: {out.stderr.strip()}")
    fields = Estimate.__dataclass_fields__
    return [Estimate(**{k: v for k, v in e.items() if k in fields}) for e in json.loads(out.stdout)]


def evaluate(windrive: str, values: dict[str, float]) -> list[dict]:
    """On a worker: the reproduction's rows the estimates act on, at these values (JSON rows)."""
    args = [windrive, "reproduce"] + [a for n, v in values.items() for a in ("--set", f"{n}={v!r}")]
    out = subprocess.run(args, capture_output=True, text=True, timeout=TIMEOUT_S, check=False)
    if out.returncode != 0:
        raise RuntimeError(f"{' '.join(args)}: {out.stderr.strip()[-2000:]}")
    return json.loads(out.stdout)


def design(chosen: list[Estimate], trajectories: int, levels: int, seed: int):
    """The SALib problem and its Morris sample (trajectories × (k + 1) points)."""
    from SALib.sample import morris as morris_sample

    problem = {
        "num_vars": len(chosen),
        "names": [e.name for e in chosen],
        "bounds": [[e.low, e.high] for e in chosen],
    }
    x = morris_sample.sample(problem, N=trajectories, num_levels=levels, seed=seed)
    return problem, x


def analyse(problem: dict, x, nominal_rows: list[dict], sampled_rows: list[list[dict]], levels: int) -> list[dict]:
    """Per row: the band over the nominal point and the samples, the verdicts, and Morris's mu* and
    sigma per input (relative to |nominal|, so rows of different units compare)."""
    import numpy as np
    from SALib.analyze import morris as morris_analyze

    result = []
    for i, row in enumerate(nominal_rows):
        q = row["quantity"]
        y = np.array([_number(rows[i]["ours"]) for rows in sampled_rows])
        verdicts = [row["verdict"]] + [rows[i]["verdict"] for rows in sampled_rows]
        values = np.concatenate(([_number(row["ours"])], y))
        finite = values[np.isfinite(values)]
        scale = abs(_number(row["ours"])) or 1.0
        drivers = []
        if np.all(np.isfinite(y)):
            m = morris_analyze.analyze(problem, x, y, num_levels=levels, print_to_console=False)
            drivers = sorted(
                ({"name": n, "mu_star": float(ms) / scale, "sigma": float(sg) / scale}
                 for n, ms, sg in zip(problem["names"], m["mu_star"], m["sigma"])),
                key=lambda d: -d["mu_star"],
            )  # fmt: skip
        counts = {v: verdicts.count(v) for v in dict.fromkeys(verdicts)}
        result.append({
            "quantity": q,
            "evaluations": len(verdicts),
            "nominal": _number(row["ours"]),
            "low": float(finite.min()) if finite.size else math.nan,
            "high": float(finite.max()) if finite.size else math.nan,
            "nominal_verdict": row["verdict"],
            "verdicts": counts,
            "holds": len(counts) == 1,
            "drivers": drivers,
        })  # fmt: skip
    return result


def sobol(problem: dict, samples: int, seed: int):
    """The Saltelli sample of Sobol's first-order and total indices: samples·(k + 2) points (no second order)."""
    from SALib.sample import sobol as sobol_sample

    return sobol_sample.sample(problem, samples, calc_second_order=False, seed=seed)


def sobol_indices(problem: dict, y, seed: int) -> dict:
    """Per input: S1 and ST with their 95 % bootstrap half-widths (SALib's estimators)."""
    from SALib.analyze import sobol as sobol_analyze

    si = sobol_analyze.analyze(problem, y, calc_second_order=False, print_to_console=False, seed=seed)
    return {n: {k: float(si[k][i]) for k in ("S1", "S1_conf", "ST", "ST_conf")} for i, n in enumerate(problem["names"])}


def _number(x) -> float:
    return math.nan if x is None else float(x)


def run(group: str, windrive: str, out: Path, trajectories: int, levels: int, seed: int,
        workers: int | None, scheduler: str | None, stream=sys.stderr, sobol_samples: int = 0) -> int:  # fmt: skip
    chosen = [e for e in estimates(windrive) if e.group == group]
    if not chosen:
        groups = sorted({e.group for e in estimates(windrive)})
        raise CampaignError(f"no estimates in group {group!r}; the groups are {', '.join(groups)}")
    problem, x = design(chosen, trajectories, levels, seed)
    points = [{e.name: e.nominal for e in chosen}] + [dict(zip(problem["names"], map(float, p))) for p in x]
    print(f"sensitivity of group {group}: {len(chosen)} estimates, {trajectories} Morris trajectories, "
          f"{len(points)} evaluations (the first at the nominal values)", file=stream, flush=True)  # fmt: skip
    results = _evaluate_all(windrive, points, workers, scheduler, stream)
    nominal_rows, sampled = results[0], results[1:]
    if any(len(r) != len(nominal_rows) or [a["quantity"] for a in r] != [a["quantity"] for a in nominal_rows]
           for r in sampled):  # fmt: skip
        raise CampaignError("the evaluations returned different rows; is the binary the same everywhere?")
    out.mkdir(parents=True, exist_ok=True)
    _write_evaluations(out / f"{group}_evaluations.csv", problem["names"], points, results)
    rows = analyse(problem, x, nominal_rows, sampled, levels)
    _write_rows(out / f"{group}.csv", group, rows)
    merge_bands(out / BANDS, group, rows)
    tornado(out / f"{group}_tornado.png", group, rows, chosen)
    held = sum(r["holds"] for r in rows)
    print(f"{held} of {len(rows)} rows keep their verdict across the band; written to {out}", file=stream)
    if sobol_samples:
        xs = sobol(problem, sobol_samples, seed)
        points = [dict(zip(problem["names"], map(float, p))) for p in xs]
        print(f"Sobol indices: {len(points)} evaluations", file=stream, flush=True)
        results = _evaluate_all(windrive, points, workers, scheduler, stream)
        _write_evaluations(out / f"{group}_sobol_evaluations.csv", problem["names"], points, results)
        write_sobol(out / f"{group}_sobol.csv", problem, results, rows, seed)
    return 0


def write_sobol(path: Path, problem: dict, results: list[list[dict]], rows: list[dict], seed: int) -> None:
    """Per row whose value varies over the Sobol sample, and per input: S1 and ST with their half-widths;
    `verdict_flips` says whether the Morris screening found the row's verdict to change (the rows that
    matter first). Rows first in the order of the flipping ones, then the others, each by the page's order."""
    import numpy as np

    quantities = [r["quantity"] for r in results[0]]
    ordered = [r for r in rows if not r["holds"]] + [r for r in rows if r["holds"]]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["quantity", "verdict_flips", "input", "S1", "S1_conf", "ST", "ST_conf"])
        for r in ordered:
            i = quantities.index(r["quantity"])
            y = np.array([_number(rows_[i]["ours"]) for rows_ in results])
            if not np.all(np.isfinite(y)) or np.ptp(y) == 0.0:
                continue  # no variance to share out (or an evaluation without the number)
            for name, si in sobol_indices(problem, y, seed).items():
                w.writerow([r["quantity"], not r["holds"], name] + [f"{si[k]:.4f}" for k in ("S1", "S1_conf", "ST", "ST_conf")])



def _evaluate_all(windrive, points, workers, scheduler, stream) -> list[list[dict]]:
    from distributed import as_completed

    from . import cluster as cluster_mod

    with cluster_mod.connected(scheduler, lambda: cluster_mod.local(workers)) as (client, _):
        t0 = time.perf_counter()
        futures = client.map(evaluate, [windrive] * len(points), points, pure=False)
        index = {f.key: i for i, f in enumerate(futures)}
        results: list = [None] * len(points)
        for done, f in enumerate(as_completed(futures), 1):
            try:
                results[index[f.key]] = f.result()
            except Exception as e:
                raise CampaignError(f"evaluation {index[f.key]} {points[index[f.key]]}: {e}") from None
            print(f"  {done}/{len(points)} evaluations, {time.perf_counter() - t0:.0f} s", file=stream, flush=True)
        return results


def _write_evaluations(path: Path, names: list[str], points: list[dict], results: list[list[dict]]) -> None:
    quantities = [r["quantity"] for r in results[0]]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["evaluation"] + names + quantities)
        for i, (p, rows) in enumerate(zip(points, results)):
            w.writerow([i] + [repr(p[n]) for n in names] + [repr(_number(r["ours"])) for r in rows])


def _verdict_text(counts: dict) -> str:
    return "; ".join(f"{v} {n}" for v, n in counts.items())


def _drivers_text(drivers: list[dict], top: int = 3) -> str:
    return "; ".join(f"{d['name']} {d['mu_star']:.3g}" for d in drivers[:top])


def _band_record(group: str, r: dict) -> dict:
    """One row as bands.json holds it (src/studies/reproduce.rs `Band` reads it)."""
    return {
        "quantity": r["quantity"],
        "group": group,
        "evaluations": r["evaluations"],
        "nominal": r["nominal"],
        "low": r["low"],
        "high": r["high"],
        "nominal_verdict": r["nominal_verdict"],
        "verdicts": _verdict_text(r["verdicts"]),
        "holds": bool(r["holds"]),
        "drivers": _drivers_text(r["drivers"]),
    }


def _write_rows(path: Path, group: str, rows: list[dict]) -> None:
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        names = [d["name"] for d in rows[0]["drivers"]] if rows and rows[0]["drivers"] else []
        w.writerow(BAND_COLUMNS + [f"mu_star {n}" for n in sorted(names)] + [f"sigma {n}" for n in sorted(names)])
        for r in rows:
            rec = _band_record(group, r)
            by = {d["name"]: d for d in r["drivers"]}
            w.writerow([repr(rec[c]) if isinstance(rec[c], float) else rec[c] for c in BAND_COLUMNS]
                       + [repr(by[n]["mu_star"]) if n in by else "" for n in sorted(names)]
                       + [repr(by[n]["sigma"]) if n in by else "" for n in sorted(names)])  # fmt: skip


def merge_bands(path: Path, group: str, rows: list[dict]) -> None:
    """bands.json with this group's rows replaced, the other groups' kept, in a stable order."""
    kept = []
    if path.is_file():
        kept = [b for b in json.loads(path.read_text()) if b["group"] != group]
    # a row without a finite value (none today) has no band to state
    ours = [_band_record(group, r) for r in rows if all(map(math.isfinite, (r["nominal"], r["low"], r["high"])))]
    merged = sorted(kept + ours, key=lambda b: b["group"])
    path.write_text(json.dumps(merged, indent=1, ensure_ascii=False) + "\n")


def tornado(path: Path, group: str, rows: list[dict], chosen: list[Estimate], most: int = 8) -> None:
    """Bars of mu*/|nominal| per input for the rows whose verdict flips first, then the widest bands."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    def width(r):
        return (r["high"] - r["low"]) / (abs(r["nominal"]) or 1.0)

    shown = sorted((r for r in rows if r["drivers"]), key=lambda r: (r["holds"], -width(r)))[:most]
    if not shown:
        return
    cols = 2
    nrows = math.ceil(len(shown) / cols)
    fig, axes = plt.subplots(nrows, cols, figsize=(12, 2.4 * nrows + 0.8), squeeze=False)
    for ax, r in zip(axes.flat, shown):
        d = list(reversed(r["drivers"]))
        ax.barh([x["name"] for x in d], [x["mu_star"] for x in d], xerr=[x["sigma"] for x in d],
                color="#c0392b" if not r["holds"] else "#2e86c1", ecolor="#555555", capsize=2)  # fmt: skip
        verdict = "verdict flips" if not r["holds"] else f"always {r['nominal_verdict']}"
        ax.set_title(f"{r['quantity'][:60]}\nband {r['low']:.4g} to {r['high']:.4g}, {verdict}", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.set_xlabel("Morris μ* / |nominal| (bars: σ)", fontsize=7)
    for ax in list(axes.flat)[len(shown):]:
        ax.axis("off")
    fig.suptitle(f"Estimates of group {group}: which inputs move each reproduction row", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
