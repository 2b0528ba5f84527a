"""The 30 s shutdown scene of drivetrain C at full fidelity (scenes/c-shutdown-spring: rotor, torsional,
generator; 1 ms macro steps) in our master, libcosim and fmpy's SSP support, in one run.

    .venv/bin/python benches/scene_bench.py [--repeat 3]

Prints wall times (best of --repeat, FMU loading and initialisation left out for every master), real-time factors and
ratios to ours, and what recording every output at every step costs against the simulation alone, as CSV and as
Parquet (`--out FILE.parquet`). Our master runs Jacobi like libcosim's fixed-step algorithm, and the default
Gauss–Seidel; recording every 1000th row (libcosim records nothing here), and every output at every
step (fmpy records every connector at every step).

fmpy's simulate_ssp cannot run this scene as written: it applies no parameter bindings, its
parameter_set cannot set String parameters (presets, kinds, modes) and it starts every connector
at 0 (the generator sees `connected = false` and trips at t = 0). Its time is for the same three
FMUs and the same number of steps with their default parameters — the cost of its Python loop over
the FMI calls, which does not depend on the parameters."""

import argparse
import json
import re
import pathlib
import subprocess
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
WINDRIVE = ROOT / "target" / "release" / "windrive"
SCENE = ROOT / "scenes" / "c-shutdown-spring"
STEP = 1e-3
STOP = 30.0


def best(n, f):
    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return min(times)


def ours(n, algorithm, every, out):
    """Best wall time of the master's run loop as `windrive run` reports it (initialisation and FMU
    loading excluded, as for libcosim below)."""
    cmd = [str(WINDRIVE), "run", str(SCENE), "--algorithm", algorithm, "--every", str(every), "--out", str(out)]
    walls = []
    for _ in range(n):
        done = subprocess.run(cmd, check=True, cwd=ROOT, capture_output=True, text=True)
        text = done.stdout + done.stderr
        walls.append(float(re.search(r"in ([0-9.]+) s wall", text).group(1)))
    return min(walls)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    n = args.repeat
    ssp = ROOT / "target" / "ssp" / "c-shutdown-spring.ssp"
    subprocess.run([str(WINDRIVE), "pack-scene", str(SCENE), "--out", str(ssp)], check=True, cwd=ROOT,
                   capture_output=True)
    csv = ROOT / "target" / "bench-scene.csv"
    parquet = ROOT / "target" / "bench-scene.parquet"

    rows = []
    recording = []  # (algorithm, simulation alone, every output every step: CSV, Parquet)
    for alg in ("jacobi", "gauss-seidel"):
        alone = ours(n, alg, 10**9, csv)  # the first and the last row: the simulation alone
        rows.append((f"windrive {alg}, first and last row only", alone))
        rows.append((f"windrive {alg}, every 1000th row", ours(n, alg, 1000, csv)))
        full = [ours(n, alg, 1, out) for out in (csv, parquet)]
        rows.append((f"windrive {alg}, every output, every step, CSV", full[0]))
        rows.append((f"windrive {alg}, every output, every step, Parquet", full[1]))
        recording.append((alg, alone, *full))
    t_ours = rows[0][1]

    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    log_output_level(CosimLogLevel.ERROR)
    final = {}

    def libcosim(stop):
        ex = CosimExecution.from_ssp_file(str(SCENE), step_size=int(STEP * 1e9))
        obs = CosimObserver.create_last_value()
        ex.add_observer(obs)
        assert ex.simulate_until(int(round(stop * 1e9)))
        final[stop] = obs.last_real_values(1, [41])[0]  # torsional.generator_speed

    t_lc = best(n, lambda: libcosim(STOP)) - best(n, lambda: libcosim(STEP))
    rows.append(("libcosim (Jacobi, no recording)", t_lc))
    # the same scene ran: the brake has stopped the generator
    assert abs(final[STOP]) < 1e-3, final

    from fmpy.ssp.simulation import simulate_ssp

    t_fm = best(1, lambda: simulate_ssp(str(ssp), stop_time=STOP, step_size=STEP))
    rows.append(("fmpy simulate_ssp (defaults, see above)", t_fm))

    print(f"scene c-shutdown-spring: 3 FMUs (rotor, torsional full fidelity, generator), {STOP:g} s in steps of {STEP * 1e3:g} ms")
    print(f"{'master':<48} {'wall s':>8} {'× real time':>12} {'÷ ours':>8}")
    for name, t in rows:
        print(f"{name:<48} {t:>8.3f} {STOP / t:>12.0f} {t / t_ours:>8.1f}")
    print()
    print("full recording (every output, every step) against the simulation alone (target: Parquet <= 1.5x)")
    for alg, alone, full_csv, full_parquet in recording:
        print(f"  {alg:<13} CSV {full_csv / alone:.2f}x   Parquet {full_parquet / alone:.2f}x")
    print(json.dumps({name: t for name, t in rows}))


if __name__ == "__main__":
    main()
