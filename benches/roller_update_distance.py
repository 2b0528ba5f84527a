"""What gearbox6dof's `roller_update_distance` saves and what it moves.

    .venv/bin/python benches/roller_update_distance.py [--stop-time 30] [--distances 1e-7 3e-7 1e-6] [--rounds 2]
    .venv/bin/python benches/roller_update_distance.py --part-load [--distances 3e-7 1e-6]

Runs scenes/d-shutdown-6dof as `windrive bench gearbox` does (the FMU's defaults at 1 ms, the bench's seven
channels recorded) with every roller set evaluated exactly (`roller_update_distance=0`) and with each distance
asked for, `--rounds` times in alternation, and once as the bench's reference (35 slices, the lamina loop,
Newmark at 0.25 ms, newton = pattern, dense LU, tolerance 1e-8). Per row: the gearbox FMU's steps and output
reads (`windrive run --profile`, the fastest and slowest round), the bench's accuracy columns against the
reference (the relative difference of each channel's peak and the HSS torque's RMS difference, as the bench
prints them), and the largest relative difference of the channels' peaks from the exact run in normal operation
(0.5-5 s; after the brake's trip a held gearbox rattles, and any change of the Newton path moves its peaks by a
few per cent whatever changed it).

With --part-load: scenes/c-normal-6dof (the 2 MW gearbox) at 4 m/s and 34.4 % turbulence, 30 s, after 15 s, the
bench's part-load columns (HSS torque's 99th percentile and largest value, the first parallel stage's largest
mesh force, the generator speed's RMS change per millisecond), exact and per distance."""

import argparse
import pathlib
import re
import subprocess
import tempfile

import numpy as np
import pandas as pd

ROOT = pathlib.Path(__file__).resolve().parents[1]
WINDRIVE = ROOT / "target" / "release" / "windrive"
SHUTDOWN = ROOT / "scenes" / "d-shutdown-6dof"
PART_LOAD = ROOT / "scenes" / "c-normal-6dof"
# the bench's channels (src/bench/gearbox.rs), in its order
CHANNELS = ["hss_torque", "mesh_force_sun_planet_1", "mesh_force_gear_pinion_2", "planet_1_uw_radial_load",
            "planet_1_uw_rollers_in_contact", "planet_1_uw_inner_race_pressure", "max_contact_pressure_gear_pinion_2"]
COLUMNS = {"sun-planet": 1, "gear-pinion": 2, "planet UW": 3, "UW p_max": 5, "HSS p_H": 6}
REFERENCE = ["max_internal_step=2.5e-4", "integrator=implicit", "newton=pattern", "newton_tolerance=1e-8",
             "linear_solver=dense", "bearing_model=lamina", "slices=35", "roller_update_distance=0"]


def run(scene: pathlib.Path, out: pathlib.Path, stop: float, record: list[str], params: list[str]) -> float:
    """Runs the scene; returns the gearbox FMU's steps and output reads, s."""
    args = [str(WINDRIVE), "run", str(scene), "--stop-time", str(stop), "--quiet", "--profile", "--out", str(out),
            "--record", ",".join(record)]
    for p in params:
        args += ["--param", p]
    r = subprocess.run(args, check=True, capture_output=True, text=True)
    line = next(x for x in (r.stdout + r.stderr).splitlines() if x.startswith("  gearbox "))
    return sum(float(x) for x in re.findall(r"(?:steps|reads)\s+([0-9.]+)", line))


def peak(x: np.ndarray) -> float:
    return float(np.abs(x).max())


def shutdown(a, tmp: pathlib.Path):
    record = [f"gearbox.{c}" for c in CHANNELS]
    ref_path = tmp / "reference.csv"
    run(SHUTDOWN, ref_path, a.stop_time, record, [f"gearbox.{p}" for p in REFERENCE])
    print("ran the reference", flush=True)
    ref = pd.read_csv(ref_path)
    rows = {0.0: [], **{d: [] for d in a.distances}}
    frames = {}
    for k in range(a.rounds):
        for d in rows:
            path = tmp / f"d{d:g}.csv"
            rows[d].append(run(SHUTDOWN, path, a.stop_time, record, [f"gearbox.roller_update_distance={d:g}"]))
            frames[d] = pd.read_csv(path)
        print(f"round {k + 1} of {a.rounds}", flush=True)
    exact = frames[0.0]
    t = exact["time"].to_numpy()
    normal = (t >= 0.5) & (t <= 5.0)
    print(f"\nscenes/d-shutdown-6dof, {a.stop_time:g} s, the FMU's defaults but roller_update_distance; columns as "
          "windrive bench gearbox's (peaks against its 0.25 ms reference), then the largest difference of a channel's "
          "peak from the exact run's in normal operation (0.5-5 s)")
    head = f"{'roller_update_distance':<24} {'gearbox FMU, s':>16} {'× exact':>8} " + " ".join(
        f"{c:>11}" for c in COLUMNS) + f" {'HSS RMS':>8} {'0.5-5 s vs exact':>17}"
    print(head)
    base = min(rows[0.0])
    for d, times in rows.items():
        f = frames[d]
        cells = [f"{100 * (peak(f['gearbox.' + CHANNELS[k]]) / peak(ref['gearbox.' + CHANNELS[k]]) - 1):+10.2f}%"
                 for k in COLUMNS.values()]
        x, r = f["gearbox.hss_torque"].to_numpy(), ref["gearbox.hss_torque"].to_numpy()
        rms = 100 * np.sqrt(np.sum((x - r) ** 2) / np.sum(r**2))
        near = max(abs(peak(f["gearbox." + c].to_numpy()[normal]) / peak(exact["gearbox." + c].to_numpy()[normal]) - 1)
                   for i, c in enumerate(CHANNELS) if i != 4)
        label = "0 (exact)" if d == 0.0 else f"{d:g} m"
        span = f"{min(times):.3f}-{max(times):.3f}" if len(times) > 1 else f"{times[0]:.3f}"
        print(f"{label:<24} {span:>16} {base / min(times):>7.2f}× " + " ".join(cells) + f" {rms:7.3f}% {near:17.1e}")


def part_load(a, tmp: pathlib.Path):
    record = ["gearbox.hss_torque", "gearbox.mesh_force_gear_pinion_1", "gearbox.generator_speed"]
    wind = ["rotor.wind_speed=4", "rotor.turbulence_intensity=0.344"]
    print("scenes/c-normal-6dof (c2mw) at 4 m/s, 30 s, after 15 s")
    print(f"{'roller_update_distance':<24} {'gearbox FMU, s':>15} {'HSS T p99':>10} {'HSS T max':>10} "
          f"{'IMS mesh max':>13} {'gen speed jitter':>17}")
    for d in [0.0, *a.distances]:
        path = tmp / f"part{d:g}.csv"
        s = run(PART_LOAD, path, 30.0, record, [*wind, f"gearbox.roller_update_distance={d:g}"])
        f = pd.read_csv(path).iloc[15000:]
        hss = np.abs(f["gearbox.hss_torque"].to_numpy())
        jitter = np.sqrt(np.mean(np.diff(f["gearbox.generator_speed"].to_numpy()) ** 2))
        label = "0 (exact)" if d == 0.0 else f"{d:g} m"
        print(f"{label:<24} {s:>15.2f} {np.sort(hss)[len(hss) * 99 // 100]:>10.0f} {hss.max():>10.0f} "
              f"{peak(f['gearbox.mesh_force_gear_pinion_1']):>13.0f} {jitter:>17.4f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--stop-time", type=float, default=30.0)
    ap.add_argument("--distances", type=float, nargs="+", default=[1e-7, 3e-7, 1e-6])
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--part-load", action="store_true")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        (part_load if a.part_load else shutdown)(a, pathlib.Path(tmp))


if __name__ == "__main__":
    main()
