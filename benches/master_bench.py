"""The same SSP scene (scenes/bench-d-grid: drivetrain D at full fidelity + its generator spring, two
FMUs, 1 ms macro steps) in our master, libcosim and fmpy's SSP support, in one run.

    .venv/bin/python benches/master_bench.py [--macro-steps 100000]

Prints the wall time of each, their ratios to ours, and our overhead per FMU per macro step (our
master against the bare FMI calls it makes, from `windrive bench master`). Every master runs fixed-step
Jacobi over the same FMU binaries with the same (default) parameters."""

import argparse
import json
import pathlib
import subprocess
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
WINDRIVE = ROOT / "target" / "release" / "windrive"
SCENE = ROOT / "scenes" / "bench-d-grid"
STEP = 1e-3


def best(n, f):
    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return min(times)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--macro-steps", type=int, default=100_000)
    args = ap.parse_args()
    n = args.macro_steps
    stop = n * STEP
    ssp = ROOT / "target" / "ssp" / "bench-d-grid.ssp"
    # packs our FMUs into the scene folder (for libcosim) and the .ssp archive (for fmpy)
    subprocess.run([str(WINDRIVE), "pack-scene", str(SCENE), "--out", str(ssp)], check=True, cwd=ROOT)

    ours = json.loads(subprocess.run([str(WINDRIVE), "bench", "master", "--macro-steps", str(n)],
                                     check=True, capture_output=True, text=True, cwd=ROOT).stdout)

    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level

    log_output_level(CosimLogLevel.ERROR)  # its debug log would be timed too

    def libcosim():
        ex = CosimExecution.from_ssp_file(str(SCENE), step_size=int(STEP * 1e9))
        assert ex.simulate_until(int(round(stop * 1e9)))

    # libcosim's run includes its FMU loading; time that alone and take it off
    def libcosim_load():
        CosimExecution.from_ssp_file(str(SCENE), step_size=int(STEP * 1e9))

    t_lc = best(3, libcosim) - best(3, libcosim_load)

    from fmpy.ssp.simulation import simulate_ssp

    t_fm = best(1, lambda: simulate_ssp(str(ssp), stop_time=stop, step_size=STEP))

    t_ours = ours["master_s"]
    fmus = ours["fmus"]
    print(f"scene bench-d-grid: {int(fmus)} FMUs, {n} macro steps of {STEP * 1e3:g} ms, fixed-step Jacobi")
    print(f"{'master':<22} {'wall s':>9} {'µs/FMU-step':>12} {'× ours':>8}")
    for name, t in [("windrive (ours)", t_ours), ("libcosim 0.11 (C++)", t_lc), ("fmpy 0.3.32 SSP", t_fm)]:
        print(f"{name:<22} {t:>9.4f} {t / (n * fmus) * 1e6:>12.3f} {t / t_ours:>8.1f}")
    print(f"bare FMI calls (floor) {ours['bare_fmi_loop_s']:>9.4f} {ours['bare_us_per_fmu_step']:>12.3f}")
    print(f"our overhead per FMU-step: {ours['overhead_us_per_fmu_step']:.3f} µs (target ≤ 0.3)")
    print(json.dumps({"ours_s": t_ours, "libcosim_s": t_lc, "fmpy_s": t_fm, "libcosim_ratio": t_lc / t_ours,
                      "fmpy_ratio": t_fm / t_ours, "overhead_us_per_fmu_step": ours["overhead_us_per_fmu_step"]}))


if __name__ == "__main__":
    main()
