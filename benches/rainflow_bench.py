"""Rainflow + DEL on a 10^7-sample random walk: windrive against the Python `rainflow` package and
fatpack in the same run, at equal resolution (fatpack with k large enough to keep every reversal).

    .venv/bin/python benches/rainflow_bench.py [--samples 10000000]

Installs fatpack into the running environment if it is missing. Prints times and ratios, and checks
that windrive's cycles equal the `rainflow` package's (count, sum of ranges, DELs)."""

import argparse
import json
import pathlib
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
WINDRIVE = ROOT / "target" / "release" / "windrive"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--samples", type=int, default=10_000_000)
    ap.add_argument("--k", type=int, default=1_000_000, help="fatpack bins (resolution)")
    args = ap.parse_args()
    try:
        import fatpack
    except ImportError:
        subprocess.run([sys.executable, "-m", "pip", "install", "--quiet", "fatpack==0.7.8"], check=True)
        import fatpack
    import rainflow

    rng = np.random.default_rng(1)
    x = np.cumsum(rng.normal(size=args.samples))
    with tempfile.TemporaryDirectory() as tmp:
        path = pathlib.Path(tmp) / "walk.f64"
        x.astype("<f8").tofile(path)
        out = subprocess.run([str(WINDRIVE), "bench", "rainflow", "--input", str(path)],
                             capture_output=True, text=True, check=True)
    ours = json.loads(out.stdout)

    started = time.perf_counter()
    cycles = np.array([(r, c) for r, _, c, _, _ in rainflow.extract_cycles(x)])
    n_eq = args.samples - 1
    dels = {m: (np.sum(cycles[:, 1] * cycles[:, 0] ** m) / n_eq) ** (1 / m) for m in (3, 6, 9)}
    t_rainflow = time.perf_counter() - started

    started = time.perf_counter()
    reversals, _ = fatpack.find_reversals(x, k=args.k)
    fp_cycles, residue = fatpack.find_rainflow_cycles(reversals)
    ranges = np.abs(fp_cycles[:, 1] - fp_cycles[:, 0])
    half = np.abs(np.diff(residue))  # the residue's ranges count as half cycles, as in ASTM E1049
    fp_dels = {m: ((np.sum(ranges ** m) + 0.5 * np.sum(half ** m)) / n_eq) ** (1 / m) for m in (3, 6, 9)}
    t_fatpack = time.perf_counter() - started

    same = (ours["cycles"] == len(cycles)
            and abs(ours["sum_count_range"] - float(np.sum(cycles[:, 0] * cycles[:, 1]))) <= 1e-9 * ours["sum_count_range"]
            and all(abs(ours["del"][str(m)] - dels[m]) <= 1e-12 * dels[m] for m in (3, 6, 9)))
    print(f"rainflow + DEL (m = 3, 6, 9) on a {args.samples:.0e}-sample random walk")
    print(f"  windrive              {ours['seconds']:8.3f} s   {ours['cycles']} cycles")
    print(f"  rainflow 3.2 (ASTM)   {t_rainflow:8.3f} s   {len(cycles)} cycles   ratio {t_rainflow / ours['seconds']:7.1f}x")
    print(f"  fatpack 0.7.8, k={args.k:.0e} {t_fatpack:8.3f} s   {len(fp_cycles)} full cycles + residue   ratio {t_fatpack / ours['seconds']:7.1f}x")
    print(f"  DEL m=6: windrive {ours['del']['6']:.6e}, rainflow {dels[6]:.6e}, fatpack (binned to k) {fp_dels[6]:.6e}")
    print(f"  identical to the rainflow package (count, Σ n·S, DELs to 1e-12): {'yes' if same else 'NO'}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
