"""What gearbox6dof's Newton tolerance (`newton_tolerance`) moves, against what the step itself moves.

    .venv/bin/python benches/newton_tolerance.py [--stop-time 10] [--tolerances 1e-8 3e-8 1e-7 3e-7 1e-6]

Runs scenes/d-shutdown-6dof (every output recorded) once at a tight tolerance (1e-10) and once per tolerance
asked for, all at the FMU's default 1 ms step, once with the defaults before 2026-12-01 (dense LU, tolerance
1e-8: `--param gearbox.linear_solver=dense --param gearbox.newton_tolerance=1e-8`), and once with the default
tolerance at a 0.25 ms step. Each run's
outputs are compared column by column with the tight run's, per phase (normal operation 0.5-5 s, the brake
from 5 s): the peak magnitude's and the RMS's relative difference, as the median and 90th percentile over the
load, torque and stress columns (slice positions, face-load factors, load sharing, contact counts, transmission
errors and shear depths left out: ratios and positions at near-zero load). The tight run against the 0.25 ms run
is the step's own error; a tolerance is safe while its row stays well below that one. What a tolerance saves is
counted in instructions (callgrind, docs/PERFORMANCE.md): single runs' times on a shared VM move by more."""

import argparse
import pathlib
import subprocess
import tempfile

import numpy as np
import pandas as pd

ROOT = pathlib.Path(__file__).resolve().parents[1]
WINDRIVE = ROOT / "target" / "release" / "windrive"
SCENE = ROOT / "scenes" / "d-shutdown-6dof"
TIGHT = 1e-10
SKIPPED = ("max_slice_position", "face_load_factor", "load_sharing", "contact", "transmission_error", "depth")
PHASES = {"normal operation 0.5-5 s": (0.5, 5.0), "braking and held, 5 s on": (5.0, np.inf)}


def run(out: pathlib.Path, stop: float, params: list[str]):
    args = [str(WINDRIVE), "run", str(SCENE), "--stop-time", str(stop), "--out", str(out)]
    for p in params:
        args += ["--param", p]
    subprocess.run(args, check=True, capture_output=True, text=True)


def differences(base: pd.DataFrame, other: pd.DataFrame) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    cols = [c for c in base.columns if c.startswith("gearbox.") and not any(s in c for s in SKIPPED)]
    t = base["time"].to_numpy()
    out = {}
    for phase, (a, b) in PHASES.items():
        m = (t >= a) & (t <= b)
        peaks, rms = [], []
        for c in cols:
            x, y = base[c].to_numpy()[m], other[c].to_numpy()[m]
            p, r = np.abs(x).max(), np.sqrt(np.mean(x**2))
            if p == 0.0 or r == 0.0:
                continue
            peaks.append(abs(np.abs(y).max() / p - 1.0))
            rms.append(abs(np.sqrt(np.mean(y**2)) / r - 1.0))
        out[phase] = (np.array(peaks), np.array(rms))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--stop-time", type=float, default=10.0)
    ap.add_argument("--tolerances", type=float, nargs="+", default=[1e-8, 3e-8, 1e-7, 3e-7, 1e-6])
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        runs = {}
        for tol in [TIGHT, *a.tolerances]:
            path = tmp / f"tol{tol:g}.csv"
            run(path, a.stop_time, [f"gearbox.newton_tolerance={tol:g}"])
            runs[f"tolerance {tol:g}"] = path
            print(f"ran tolerance {tol:g}", flush=True)
        path = tmp / "before.csv"
        run(path, a.stop_time, ["gearbox.linear_solver=dense", "gearbox.newton_tolerance=1e-8"])
        runs["dense LU, 1e-8 (defaults before)"] = path
        print("ran the defaults before", flush=True)
        path = tmp / "quarter.csv"
        run(path, a.stop_time, ["gearbox.max_internal_step=2.5e-4"])
        runs["0.25 ms step (the step's error)"] = path
        base = pd.read_csv(runs[f"tolerance {TIGHT:g}"])
        print(f"\ndifferences from the run at tolerance {TIGHT:g} (1 ms), relative: median and 90th percentile over columns")
        print(f"{'run':<34} " + "  ".join(f"{p + ': peaks, RMS':<44}" for p in PHASES))
        for label, path in runs.items():
            if label == f"tolerance {TIGHT:g}":
                continue
            d = differences(base, pd.read_csv(path))
            cells = []
            for peaks, rms in d.values():
                cells.append(
                    f"{np.median(peaks):.1e} {np.quantile(peaks, 0.9):.1e}, {np.median(rms):.1e} {np.quantile(rms, 0.9):.1e}"
                    .ljust(44)
                )
            print(f"{label:<34} " + "  ".join(cells))


if __name__ == "__main__":
    main()
