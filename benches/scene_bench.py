"""The 30 s shutdown scene of drivetrain C at full fidelity (scenes/c-shutdown-spring: rotor, torsional,
generator; 1 ms macro steps) in our master, libcosim and fmpy's SSP support, in one run.

    .venv/bin/python benches/scene_bench.py [--repeat 3]

Prints wall times (best of --repeat, FMU loading and initialisation left out for every master), real-time factors and
ratios to ours, and what recording every output at every step costs against the simulation alone, as CSV and as
Parquet (`--out FILE.parquet`), in wall time and in CPU time of the whole process (median of paired ratios),
and where a Parquet run's time went (`windrive run --profile`). Our master runs Jacobi like libcosim's fixed-step algorithm, and the default
Gauss–Seidel; recording every 1000th row (libcosim records nothing here), and every output at every
step (fmpy records every connector at every step).

The 30 s scene's file is short: completing it (the last row group, the footer) is a fixed cost of about 1.5 ms
that weighs a tenth of its recording. The bench therefore also records a case of the length a campaign runs,
scenes/c-normal-spring for 600 s (--stop-time; normal operation in NTM turbulence at 16 m/s, IEC DLC 1.2's
length), Gauss–Seidel, the simulation alone against every output at every step to Parquet, paired the same way.

fmpy's simulate_ssp cannot run this scene as written: it applies no parameter bindings, its
parameter_set cannot set String parameters (presets, kinds, modes) and it starts every connector
at 0 (the generator sees `connected = false` and trips at t = 0). Its time is for the same three
FMUs and the same number of steps with their default parameters — the cost of its Python loop over
the FMI calls, which does not depend on the parameters."""

import argparse
import json
import re
import statistics
import pathlib
import subprocess
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
WINDRIVE = ROOT / "target" / "release" / "windrive"
SCENE = ROOT / "scenes" / "c-shutdown-spring"
STEP = 1e-3
STOP = 30.0
# a case of a campaign's length: normal operation in turbulence, 600 s (the scene's own file says 20 s)
LONG_SCENE = ROOT / "scenes" / "c-normal-spring"
LONG_STOP = 600.0


def best(n, f):
    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return min(times)


def ours(n, configs, scene=SCENE, extra=()):
    """Wall and CPU times of the master's run loop as `windrive run` reports them (initialisation and
    FMU loading excluded, as for libcosim below) for each (algorithm, every, out) in `configs` on
    `scene` (with `extra` arguments), one list per configuration, one entry per repetition. The
    configurations take turns, repetition after repetition: this VM's speed changes by up to 2x over
    seconds, and a configuration timed in one slow stretch would carry it into every ratio."""
    walls = [[] for _ in configs]
    cpus = [[] for _ in configs]
    for _ in range(n):
        for k, (algorithm, every, out) in enumerate(configs):
            # a new file each run, as each case of a campaign writes its own: overwriting the last run's
            # file truncates it, and ext4 then starts writing it back when it is closed (auto_da_alloc), a
            # close(2) of 1-7 ms on this VM inside the timed loop that a fresh file does not pay
            out.unlink(missing_ok=True)
            cmd = [str(WINDRIVE), "run", str(scene), "--algorithm", algorithm, "--every", str(every),
                   "--out", str(out), *extra]
            done = subprocess.run(cmd, check=True, cwd=ROOT, capture_output=True, text=True)
            found = re.search(r"in ([0-9.]+) s wall, ([0-9.]+) s CPU", done.stdout + done.stderr)
            walls[k].append(float(found.group(1)))
            cpus[k].append(float(found.group(2)))
    return walls, cpus


def paired_ratio(full, alone):
    """The median over repetitions of full / alone, each pair timed one after the other: steadier than
    the ratio of two minima when the machine's speed drifts between them."""
    return statistics.median(f / a for f, a in zip(full, alone))


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
    recording = []  # (algorithm, [(wall ratio, CPU ratio) of every output every step as CSV, as Parquet])
    # per algorithm: the first and the last row (the simulation alone), every 1000th, every row as CSV, Parquet
    configs = [(alg, every, out) for alg in ("jacobi", "gauss-seidel")
               for every, out in ((10**9, csv), (1000, csv), (1, csv), (1, parquet))]
    walls, cpus = ours(n, configs)
    for a, alg in enumerate(("jacobi", "gauss-seidel")):
        w, c = walls[4 * a:4 * a + 4], cpus[4 * a:4 * a + 4]
        rows.append((f"windrive {alg}, first and last row only", min(w[0])))
        rows.append((f"windrive {alg}, every 1000th row", min(w[1])))
        rows.append((f"windrive {alg}, every output, every step, CSV", min(w[2])))
        rows.append((f"windrive {alg}, every output, every step, Parquet", min(w[3])))
        recording.append((alg, [(paired_ratio(w[k], w[0]), paired_ratio(c[k], c[0])) for k in (2, 3)]))
    t_ours = rows[0][1]

    # the campaign-length case: the simulation alone against every output at every step to Parquet
    long_walls, long_cpus = ours(n, [("gauss-seidel", 10**9, csv), ("gauss-seidel", 1, parquet)],
                                 scene=LONG_SCENE, extra=("--stop-time", str(LONG_STOP)))
    long_alone, long_full = min(long_walls[0]), min(long_walls[1])
    long_wall_ratio = paired_ratio(long_walls[1], long_walls[0])
    long_cpu_ratio = paired_ratio(long_cpus[1], long_cpus[0])

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
    print("  wall: what a single run takes; CPU: every thread of the process (the Parquet writer's own thread")
    print("  included), what a campaign running a case per core pays")
    print(f"  (median over the {n} repetitions of each full run's time over the simulation's run just before it)")
    for alg, ((csv_wall, csv_cpu), (pq_wall, pq_cpu)) in recording:
        print(f"  {alg:<13} wall: CSV {csv_wall:.2f}x   Parquet {pq_wall:.2f}x"
              f"     CPU: CSV {csv_cpu:.2f}x   Parquet {pq_cpu:.2f}x")
    print(f"  a campaign-length case ({LONG_SCENE.name}, {LONG_STOP:g} s, gauss-seidel): the simulation alone"
          f" {long_alone:.3f} s, every output to Parquet {long_full:.3f} s (best of {n})")
    print(f"  {'':<13} wall: Parquet {long_wall_ratio:.2f}x     CPU: Parquet {long_cpu_ratio:.2f}x")
    print()
    print("where the time of a Parquet run went (windrive run --profile, Gauss-Seidel, one run):")
    done = subprocess.run([str(WINDRIVE), "run", str(SCENE), "--out", str(parquet), "--profile"], check=True,
                          cwd=ROOT, capture_output=True, text=True)
    text = done.stdout + done.stderr
    print(text[text.index("profile "):].rstrip())
    print(json.dumps({**{name: t for name, t in rows},
                      "long case, simulation alone": long_alone, "long case, every output to Parquet": long_full}))


if __name__ == "__main__":
    main()
