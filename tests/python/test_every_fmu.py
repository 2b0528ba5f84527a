"""Every FMU of ours (each folder under fmus/, packed by scripts/test) in tools nobody here wrote:
fmpy's validator, the fmu-manipulation-toolbox checker, and a run alone in fmpy with its defaults."""

import pathlib
import subprocess
import sys

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu

ROOT = pathlib.Path(__file__).resolve().parents[2]
NAMES = sorted(p.name for p in (ROOT / "fmus").iterdir() if (p / "Cargo.toml").is_file())


@pytest.fixture(params=NAMES)
def fmu(request, windrive):
    path = ROOT / "target" / "fmu" / f"{request.param}.fmu"
    if not path.is_file():
        subprocess.run([windrive, "pack", request.param], check=True, cwd=ROOT)
    return str(path)


def test_fmpy_validate_finds_no_problem(fmu):
    out = subprocess.run([sys.executable, "-m", "fmpy", "validate", fmu], capture_output=True, text=True)
    assert out.returncode == 0 and "No problems found" in out.stdout, out.stdout + out.stderr


def test_fmutool_check_finds_no_problem(fmu):
    fmutool = pathlib.Path(sys.executable).parent / "fmutool"
    out = subprocess.run([str(fmutool), "-input", fmu, "-check"], capture_output=True, text=True)
    assert out.returncode == 0 and "No semantic error" in out.stdout + out.stderr, out.stdout + out.stderr


def test_fmpy_runs_it_alone_with_its_defaults(fmu):
    md = read_model_description(fmu)
    result = simulate_fmu(fmu, output_interval=float(md.defaultExperiment.stepSize))
    assert len(result) > 100
    for name in result.dtype.names:
        assert np.all(np.isfinite(result[name].astype(float))), name


def test_rotor_plays_back_its_shipped_synthetic_series(windrive):
    """The rotor FMU finds a series under its resources/ by name and scales per-unit torque by the
    preset's rated rotor torque (C's here, A's for preset A: equal loading)."""
    path = ROOT / "target" / "fmu" / "rotor.fmu"
    if not path.is_file():
        subprocess.run([windrive, "pack", "rotor"], check=True, cwd=ROOT)
    rows = np.genfromtxt(ROOT / "fmus" / "rotor" / "resources" / "c-shutdown-pu.csv", delimiter=",", skip_header=2)
    start = {"preset": "C", "mode": "playback", "series": "c-shutdown-pu.csv"}
    r = simulate_fmu(str(path), stop_time=10.0, output_interval=0.01, start_values=start,
                     output=["rotor_torque", "pitching_moment", "rated_rotor_torque"])
    rated = r["rated_rotor_torque"][0]
    assert rated == pytest.approx(2e6 / (1680 / (6 * 4 * 111 / 29) * np.pi / 30), rel=1e-9)
    for k in (0, 100, 500, 731, 1000):
        assert r["rotor_torque"][k] == pytest.approx(rows[k, 1] * rated, rel=1e-9, abs=1e-6)
        assert r["pitching_moment"][k] == pytest.approx(rows[k, 2], rel=1e-9)
    other = simulate_fmu(str(path), stop_time=1.0, output_interval=0.01, output=["rotor_torque", "rated_rotor_torque"],
                         start_values={**start, "preset": "A"})
    assert other["rotor_torque"][50] == pytest.approx(rows[50, 1] * other["rated_rotor_torque"][0], rel=1e-9)
    # the thesis's scaling (Eq. 4.40): C's torque on A is T_C · (D_A / D_C)³
    scaled = simulate_fmu(str(path), stop_time=1.0, output_interval=0.01, output=["rotor_torque", "radius_used"],
                          start_values={**start, "preset": "A", "source_preset": "C"})
    factor = (scaled["radius_used"][0] / 40.0) ** 3
    assert scaled["rotor_torque"][50] == pytest.approx(rows[50, 1] * rated * factor, rel=1e-9)


@pytest.mark.parametrize("preset,kind", [("A", "pmg"), ("B", "dfig"), ("C", "dfig"), ("D", "fixed"), ("D", "spring")])
def test_generator_kinds_run_alone_in_fmpy(windrive, preset, kind):
    """Every kind starts in electrical equilibrium at the speed it is given and holds it there:
    the controlled kinds deliver the law's region-3 torque (rated) at rated speed, the spring its
    initial torque, the cage machine a constant torque at its slip."""
    path = ROOT / "target" / "fmu" / "generator.fmu"
    if not path.is_file():
        subprocess.run([windrive, "pack", "generator"], check=True, cwd=ROOT)
    probe = simulate_fmu(str(path), stop_time=0.001, step_size=0.001, start_values={"preset": preset, "kind": "spring"},
                         output=["synchronous_speed_used", "rated_torque"])
    rated_speed, rated_torque = probe["synchronous_speed_used"][0], probe["rated_torque"][0]
    if kind == "fixed":  # the cage machine at 0.5 % slip above its grid's synchronous speed
        grid = simulate_fmu(str(path), stop_time=0.001, step_size=0.001, start_values={"preset": preset, "kind": kind},
                            output=["synchronous_speed_used"])
        speed = grid["synchronous_speed_used"][0] * 1.005
    else:
        speed = rated_speed
    r = simulate_fmu(str(path), stop_time=2.0, step_size=0.001, output_interval=0.01,
                     start_values={"preset": preset, "kind": kind, "generator_speed": speed, "initial_torque": rated_torque},
                     output=["generator_torque", "electrical_power", "stator_current", "equivalent_stiffness"])
    torque = r["generator_torque"]
    assert np.all(np.isfinite(torque))
    assert np.ptp(torque) < 1e-6 * abs(torque[0]), f"{preset} {kind} drifts: {torque.min()} .. {torque.max()}"
    if kind != "fixed":
        assert torque[0] == pytest.approx(rated_torque, rel=1e-6)
    # copper losses only: electrical power within 3 % of the shaft power
    assert r["electrical_power"][-1] == pytest.approx(torque[-1] * speed, rel=0.03)


@pytest.mark.parametrize("preset", ["A", "C", "D"])
def test_rotor_bem_gives_rated_torque_at_its_fitted_rated_point_in_fmpy(windrive, preset):
    """The rotor FMU's default BEM rotor, alone in fmpy: at the preset's rated rotor speed in steady wind at
    the reported rated_wind_speed (the wind at which the scaled WindPACT blade gives rated power at fine
    pitch) the torque is the rated torque. The fit is a bisection to 1e-12 of the wind speed, so only the
    first step's pitch action (none: the error is nil) could move it: 1e-6."""
    path = ROOT / "target" / "fmu" / "rotor.fmu"
    if not path.is_file():
        subprocess.run([windrive, "pack", "rotor"], check=True, cwd=ROOT)
    import math
    # rated rotor speed: the generator's rated speed (thesis Table 4.6) over the gear ratio
    speed = {"A": 515 / ((1 + 122 / 24) * (1 + 99 / 21)), "C": 1680 / (6 * 4 * 111 / 29),
             "D": 1809 / ((1 + 99 / 21) * (82 / 23) * 4)}[preset] * math.pi / 30
    r = simulate_fmu(str(path), stop_time=0.05, output_interval=0.01,
                     start_values={"preset": preset, "turbulence": "none", "rotor_speed": speed},
                     output=["rotor_torque", "rated_rotor_torque", "rated_wind_speed", "rated_tip_speed_ratio",
                             "pitch", "wind_speed_hub", "thrust"])
    assert r["wind_speed_hub"][0] == pytest.approx(r["rated_wind_speed"][0], rel=1e-12)
    assert r["pitch"][0] == 0.0
    assert r["rotor_torque"][0] == pytest.approx(r["rated_rotor_torque"][0], rel=1e-6)
    assert r["rated_tip_speed_ratio"][0] == pytest.approx(6.90, abs=0.01)  # docs/AERODYNAMICS.md
    assert r["thrust"][0] > 0
