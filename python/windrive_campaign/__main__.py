"""Command line: `python -m windrive_campaign run|cases|job-script|report|paper CAMPAIGN.toml`
(scripts/campaign wraps it with the virtual environment and the windrive build in a checkout; installed
from the windrive wheel it runs as it is, with the wheel's windrive binary)."""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
from pathlib import Path

from . import cases as cases_mod
from . import binary
from . import cluster as cluster_mod
from . import driver, schema
from .errors import CampaignError

EPILOG = """\
examples (from the repository's root):
  scripts/campaign run campaigns/c-dlc12.toml
      DLC 1.2 of drivetrain C on all cores; results in results/campaigns/c-dlc12/
  scripts/campaign run campaigns/c-dlc12.toml --workers 1
      the same on one core; rerun after Ctrl-C: finished cases are not run again
  scripts/campaign cases campaigns/c-dlc12.toml
      list the cases, their parameters and weights without running them
  scripts/campaign run campaigns/c-dlc12.toml --scheduler tcp://HOST:8786
      on a running dask cluster (docs/CAMPAIGNS.md: starting one; the same paths on every worker)
  scripts/campaign job-script campaigns/c-dlc12.toml
      the Slurm job script its [slurm] profile submits with --slurm
  scripts/campaign report campaigns/c-dlc12.toml
      its lifetime report (after run): lifetime.csv/.json/_ldd.csv/.png in results/campaigns/c-dlc12/
  scripts/campaign paper campaigns/tiny-paper.toml
      the paper's Tables 6 and 7 beside ours, η heat maps, shape checks (a grid with [gears], after run)
  scripts/campaign sensitivity A --out docs/sensitivity
      drivetrain A's estimates over their ranges (Morris): which reproduction verdicts hold across them
  scripts/campaign seeds campaigns/c-seeds.toml --windows 60,120,300 --out docs/seed-study
      how many seeds and how long a window DLC 1.2 needs: the scatter of every DEL over the seeds

The campaign file's keys: docs/CAMPAIGNS.md.
"""

REPORT_EPILOG = """\
examples (from the repository's root):
  scripts/campaign run campaigns/c-dlc12.toml && scripts/campaign report campaigns/c-dlc12.toml
      DLC 1.2 + a shutdown, then its 20-year report in results/campaigns/c-dlc12/
  scripts/campaign report results/campaigns/c-dlc12 --out /tmp/c-dlc12-life
      the same report from the folder, written elsewhere
"""


PAPER_EPILOG = """\
examples (from the repository's root):
  scripts/campaign run campaigns/tiny-paper.toml && scripts/campaign paper campaigns/tiny-paper.toml
      a small wind speed x TI grid of the paper's turbine with [gears], then the comparison
      in results/campaigns/tiny-paper/paper_*
  scripts/campaign paper results/campaigns/tiny-paper --out /tmp/paper
      the same from the folder, written elsewhere
"""


SENSITIVITY_EPILOG = """\
examples (from the repository's root):
  scripts/campaign sensitivity A --out docs/sensitivity
      drivetrain A's brake, trip and damping estimates: 4 trajectories x 5 points, a few seconds
  scripts/campaign sensitivity A --sobol 64 --out docs/sensitivity
      the same, then Sobol indices of the rows whose verdict flips: 64 x (4 + 2) more evaluations
  scripts/campaign sensitivity 2MW --trajectories 3 --out docs/sensitivity
      the 2 MW gearbox's bearing and carrier estimates through the 6-DOF shutdown (a minute per evaluation)
  windrive reproduce --out docs/REPRODUCTION.md
      afterwards: the reproduction page with each row's verdict across the bands
"""


SEEDS_EPILOG = """\
examples (from the repository's root):
  scripts/campaign seeds campaigns/c-seeds.toml --windows 60,120,300 --other-sampling --out docs/seed-study --doc docs/CAMPAIGNS.md
      drivetrain C's three wind bins x 20 seeds at 600 s (the file's window) and at 60, 120 and 300 s,
      and at 600 s with the rotor-averaged wind beside the blades' full field;
      the cases run in results/seed-study/ (rerun to resume), the table and chart go to docs/seed-study/
  scripts/campaign seeds docs/seed-study/c-seeds_seeds.csv --doc docs/CAMPAIGNS.md
      the page's block and the chart beside the table again from the committed table, nothing run
"""


WINDRIVE_DEFAULT = binary.DEFAULT


def finished_campaign_arguments(parser: argparse.ArgumentParser, files: str):
    """The arguments of the commands that read a finished campaign: where it is and where `files` go."""
    parser.add_argument("campaign", type=Path, help="campaign folder, its .parquet table, or the campaign file")
    parser.add_argument("--out", type=Path, help=f"folder for {files} [default: the campaign folder]")
    parser.add_argument("--windrive", help=f"windrive binary [default: {WINDRIVE_DEFAULT}]")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(
        prog="scripts/campaign" if cluster_mod.IN_CHECKOUT else "python -m windrive_campaign",
        description="Load-case campaigns of `windrive run` jobs on dask.distributed: one result per case, "
        "resumable, one Parquet table per campaign.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")
    r = sub.add_parser(
        "run",
        help="run the campaign's missing cases, then write its table",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    r.add_argument("campaign", type=Path, help="campaign file (TOML)")
    r.add_argument("--out", type=Path, help="campaign folder [default: results/campaigns/<name>]")
    where = r.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, help="LocalCluster worker processes [default: all cores]")
    where.add_argument("--scheduler", metavar="ADDRESS", help="join a running dask scheduler instead")
    where.add_argument("--slurm", action="store_true", help="submit Slurm jobs from the [slurm] profile")
    r.add_argument("--retry-failed", action="store_true", help="run failed and timed-out cases again")
    r.add_argument("--windrive", help=f"windrive binary [default: {WINDRIVE_DEFAULT}]")
    c = sub.add_parser("cases", help="list the cases and their weights without running them")
    c.add_argument("campaign", type=Path)
    c.add_argument("--windrive", help=f"windrive binary [default: {WINDRIVE_DEFAULT}]")
    j = sub.add_parser("job-script", help="print the Slurm job script of the [slurm] profile")
    j.add_argument("campaign", type=Path)
    rep = sub.add_parser(
        "report",
        help="the lifetime report of a finished campaign: damage, lifetime DELs, shares, LDD, chart",
        description="Lifetime damage sums and DELs per channel and Wöhler slope, each load-case group's "
        "share, the lifetime LDD and the thesis's DEL ratios, from a campaign's table (docs/CAMPAIGNS.md, "
        "Lifetime report). Exit status 1 when some cases are pending or failed (they are left out).",
        epilog=REPORT_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    finished_campaign_arguments(rep, "the report files")
    rep.add_argument("--doc", type=Path, help="also regenerate this page's block of the campaign's life tables "
                     "(between the markers python/windrive_campaign/life_doc.py names, e.g. in docs/GEARBOX.md), "
                     "from the files written; give --out so the page can link them")  # fmt: skip
    pap = sub.add_parser(
        "paper",
        help="the paper's Tables 6 and 7 (docs/SOURCES.md §Paper) beside ours, η heat maps and shape checks",
        description="Gear damage of a finished wind speed x turbulence intensity grid with [gears] beside the "
        "paper's Table 6 (1-day damage, TI 14 %) and Table 7 (η against steady rated wind), heat maps of η, "
        "and the shapes the paper concludes from (docs/CAMPAIGNS.md, The paper's comparison). Exit status 1 "
        "when some grid cases are pending or failed (they are left out).",
        epilog=PAPER_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    finished_campaign_arguments(pap, "the files")
    pap.add_argument("--doc", type=Path, help="also write the comparison as a Markdown page (docs/PAPER.md), "
                     "generated from the paper_cases.csv written beside the other files")  # fmt: skip
    pap.add_argument("--against", type=Path, help="a paper_cases.csv of the same grid run with the other wind "
                     "sampling (e.g. docs/paper/rotor-average/paper_cases.csv): the page then compares the "
                     "blades' full field with the rotor-averaged series cell by cell")  # fmt: skip
    sen = sub.add_parser(
        "sensitivity",
        help="vary a group of estimates over their ranges (Morris) and judge the reproduction across them",
        description="The inputs no source gives (`windrive reproduce --estimates`) of one group varied together "
        "over their ranges by Morris screening (SALib); each evaluation is `windrive reproduce --set ...` on a "
        "dask worker. Writes per reproduction row its band, its verdicts across the band and each input's "
        "Morris mu* and sigma, a tornado chart, and bands.json, which `windrive reproduce` reads "
        "(docs/SENSITIVITY.md).",
        epilog=SENSITIVITY_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    sen.add_argument("group", help="estimate group: A, B, C or 2MW")
    sen.add_argument("--out", type=Path, default=Path("results/sensitivity"), help="output folder [default: %(default)s]")
    sen.add_argument("--trajectories", type=int, default=4, help="Morris trajectories r: r·(k+1) evaluations [default: %(default)s]")
    sen.add_argument("--levels", type=int, default=4, help="Morris grid levels [default: %(default)s]")
    sen.add_argument("--seed", type=int, default=1, help="seed of the Morris sample [default: %(default)s]")
    sen.add_argument("--sobol", type=int, default=0, metavar="N",
                     help="then Sobol indices (first-order and total) of the rows whose verdict flips, from a "
                     "Saltelli sample of N·(k+2) evaluations; N a power of 2 [default: no Sobol stage]")  # fmt: skip
    sen_where = sen.add_mutually_exclusive_group()
    sen_where.add_argument("--workers", type=int, help="LocalCluster worker processes [default: all cores]")
    sen_where.add_argument("--scheduler", metavar="ADDRESS", help="join a running dask scheduler instead")
    sen.add_argument("--windrive", help=f"windrive binary [default: {WINDRIVE_DEFAULT}]")
    see = sub.add_parser(
        "seeds",
        help="how many seeds and how long a window a DLC 1.2 campaign needs: its scatter over seeds, measured",
        description="Runs a campaign's DLC 1.2 cases at its own window and at each of --windows (new seeds per "
        "window), then gives per wind bin, window and DEL the seed-to-seed scatter, the 95 %% interval of the "
        "bin's damage with 3 to 20 seeds, the seeds and simulated time a ±10 %% interval needs, and the "
        "window's bias against the longest (docs/CAMPAIGNS.md, How many seeds, how long a window).",
        epilog=SEEDS_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    see.add_argument("campaign", type=Path, help="campaign file with [dlc12] (or a seeds table written before)")
    see.add_argument("--windows", default="", help="other analysed windows in s, comma-separated (e.g. 60,120,300)")
    see.add_argument("--out", type=Path, help="folder for the table and chart [default: results/seed-study/<name>]")
    see.add_argument("--runs", type=Path, help="folder of the cases' campaigns [default: results/seed-study/<name>/runs]")
    see.add_argument("--doc", type=Path, help="also regenerate this page's block (between the markers "
                     "python/windrive_campaign/seeds.py names, e.g. in docs/CAMPAIGNS.md)")  # fmt: skip
    see.add_argument("--other-sampling", action="store_true", help="also run the file's window with the other "
                     "wind sampling (blades or rotor_average) and give each bin's DEL ratio between the two")  # fmt: skip
    see_where = see.add_mutually_exclusive_group()
    see_where.add_argument("--workers", type=int, help="LocalCluster worker processes [default: all cores]")
    see_where.add_argument("--scheduler", metavar="ADDRESS", help="join a running dask scheduler instead")
    see.add_argument("--windrive", help=f"windrive binary [default: {WINDRIVE_DEFAULT}]")
    args = p.parse_args(argv)
    try:
        if args.command == "run" and args.workers is not None and args.workers < 1:
            raise CampaignError(f"--workers {args.workers}: at least 1")
        if args.command == "report":
            from . import report  # pandas and matplotlib: only the report pays their import time

            return report.report(args.campaign, args.out, binary.windrive(args.windrive), args.doc)
        if args.command == "paper":
            from . import paper_report  # pandas and matplotlib, as for report

            return paper_report.report(args.campaign, args.out, args.doc, args.against)
        if args.command == "sensitivity":
            from . import sensitivity  # SALib, numpy and matplotlib: only this command pays their import

            if args.trajectories < 2 or args.levels < 2:
                raise CampaignError("--trajectories and --levels: at least 2 (Morris needs two points per input)")
            if args.sobol and (args.sobol < 2 or args.sobol & (args.sobol - 1)):
                raise CampaignError(f"--sobol {args.sobol}: a power of 2, at least 2 (Sobol's sequence balances there)")
            return sensitivity.run(
                args.group, binary.windrive(args.windrive), args.out.resolve(), args.trajectories, args.levels,
                args.seed, args.workers, args.scheduler, sobol_samples=args.sobol,
            )  # fmt: skip
        if args.command == "seeds":
            return _seeds(args)
        campaign = schema.load(args.campaign)
        if args.command == "job-script":
            # the job logs' folder of a `run` without --out
            logs = (Path("results") / "campaigns" / campaign.name / "slurm").resolve()
            cluster = cluster_mod.slurm(campaign.slurm, campaign.path, logs)
            try:
                print(cluster.job_script())
            finally:
                cluster.close()
            return 0
        windrive = binary.windrive(args.windrive)
        if args.command == "cases":
            return _list_cases(campaign, windrive)
        out = args.out or Path("results") / "campaigns" / campaign.name
        opts = driver.Options(
            out=out.resolve(),
            windrive=windrive,
            workers=args.workers,
            scheduler=args.scheduler,
            slurm=args.slurm,
            retry_failed=args.retry_failed,
        )
        return driver.run(campaign, opts)
    except CampaignError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # before the cases started (the driver handles it while they run)
        print("interrupted", file=sys.stderr)
        return 130


def _seeds(args) -> int:
    import os

    import pandas as pd

    from . import seeds  # pandas, scipy and matplotlib: only this command pays their import

    if args.doc is not None and not args.doc.is_file():
        raise CampaignError(f"--doc {args.doc}: no such page (it must hold the block's two marker lines)")
    if args.campaign.suffix == ".csv":  # a table written before: the page's block only
        if args.doc is None:
            raise CampaignError(f"{args.campaign}: a seeds table is only read to regenerate a page: give --doc PAGE")
        if not args.campaign.is_file():
            raise CampaignError(f"{args.campaign}: no such seeds table (written by a run of scripts/campaign seeds)")
        table = pd.read_csv(args.campaign)
        name = args.campaign.name.removesuffix("_seeds.csv")
        args.doc.write_text(seeds.replace(args.doc, name, table, os.path.relpath(args.campaign, args.doc.parent)))
        seeds.chart(table, args.campaign.with_name(f"{name}_seeds.png"))
        print(f"{args.doc}: {name}'s block and chart regenerated from {args.campaign}", file=sys.stderr)
        return 0
    if args.workers is not None and args.workers < 1:
        raise CampaignError(f"--workers {args.workers}: at least 1")
    try:
        windows = [float(w) for w in args.windows.split(",") if w.strip()]
    except ValueError:
        raise CampaignError(f"--windows {args.windows}: seconds separated by commas, e.g. 60,120,300") from None
    campaign = schema.load(args.campaign)
    home = Path("results") / "seed-study" / campaign.name
    out = args.out or home
    opts = driver.Options(out=out, windrive=binary.windrive(args.windrive), workers=args.workers,
                          scheduler=args.scheduler, slurm=False, retry_failed=False)  # fmt: skip
    table, status = seeds.run(campaign, windows, args.runs or home / "runs", opts, args.other_sampling)
    if status == 130:
        return status
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"{campaign.name}_seeds.csv"
    table.to_csv(path, index=False)
    seeds.chart(table, out / f"{campaign.name}_seeds.png")
    print(f"{path}: {len(table)} cases; chart {out / f'{campaign.name}_seeds.png'}", file=sys.stderr)
    if args.doc is not None:
        args.doc.write_text(seeds.replace(args.doc, campaign.name, table, os.path.relpath(path, args.doc.parent)))
        print(f"{args.doc}: {campaign.name}'s block regenerated", file=sys.stderr)
    return status


def _list_cases(campaign, windrive: str) -> int:
    with tempfile.TemporaryDirectory() as tmp:
        scenes, _ = driver.snapshot_scenes(campaign, windrive, Path(tmp))
        found = cases_mod.expand(campaign, scenes, cases_mod.windrive_digest(windrive), windrive)
    hours = sum(k.hours for k in found if not math.isnan(k.hours))
    print(f"{'id':16}  {'name':32}  {'weight':>14}  parameters")
    for k in found:
        if not math.isnan(k.hours):
            weight = f"{k.hours:.1f} h"
        elif not math.isnan(k.events):
            weight = f"{k.events:g} events"
        else:
            weight = "-"
        params = " ".join(f"{n}={cases_mod.param_text(v)}" for n, v in k.params.items())
        print(f"{k.id:16}  {k.name:32}  {weight:>14}  {params}")
    print(f"{len(found)} cases; the DLC 1.2 cases stand for {hours:.0f} h")
    return 0


if __name__ == "__main__":
    sys.exit(main())
