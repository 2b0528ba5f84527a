"""The gearbox6dof FMU (the NREL GRC 750 kW description) alone in fmpy and libcosim: rated torque in,
the torsional statics out, the same outputs from both tools, and a bad description named in the log.
(fmpy's validator, the fmu-manipulation-toolbox checker and a default run: test_every_fmu.py.)"""

import math
import pathlib
import subprocess

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu

ROOT = pathlib.Path(__file__).resolve().parents[2]
RATIO = (1 + 99 / 21) * (82 / 23) * (88 / 22)
T_GEN = 750e3 / (1809 * math.pi / 30)
T_ROTOR = T_GEN * RATIO
CHANNELS = ["rotor_speed", "generator_speed", "lss_torque", "hss_torque", "mesh_force_sun_planet_1",
            "load_sharing_factor", "planet_1_uw_radial_load", "hss_a_radial_load"]


@pytest.fixture(scope="module")
def gearbox(windrive):
    path = ROOT / "target" / "fmu" / "gearbox6dof.fmu"
    if not path.is_file():
        subprocess.run([windrive, "pack", "gearbox6dof"], check=True, cwd=ROOT)
    return str(path)


def fmpy_rated(path, stop=0.5):
    inputs = np.array([(0.0, T_ROTOR, T_GEN)], dtype=[("time", float), ("rotor_torque", float), ("generator_torque", float)])
    return simulate_fmu(path, stop_time=stop, output_interval=1e-3, input=inputs, output=CHANNELS,
                        start_values={"initial_rotor_torque": T_ROTOR})


def test_fmpy_runs_it_at_rated_torque_with_the_torsional_statics(gearbox):
    r = fmpy_rated(gearbox)
    # started in its loaded equilibrium at rated speed, it stays there: the torque splits as the
    # gear ratio says, the bearings are loaded
    assert r["rotor_speed"][-1] == pytest.approx(1809 / RATIO * math.pi / 30, rel=1e-4)
    assert r["generator_speed"][-1] == pytest.approx(RATIO * r["rotor_speed"][-1], rel=1e-4)
    assert r["lss_torque"][-1] == pytest.approx(T_ROTOR, rel=0.01)
    assert r["hss_torque"][-1] == pytest.approx(T_GEN, rel=0.01)
    # K_γ: the carrier's plates twist (fitted to the thesis's upwind/downwind bearing loads) and
    # gravity loads the planets unevenly: 1.05 at the start angle
    assert 1.0 <= r["load_sharing_factor"][-1] < 1.08
    assert r["planet_1_uw_radial_load"][-1] > 1e5 and r["hss_a_radial_load"][-1] > 1e3


def test_alone_with_its_defaults_it_shows_the_upwind_planet_bearings_carrying_more(gearbox):
    # nothing connected, no start values: the GRC at rated torque, gravity and the rotor's weight,
    # lamina bearings; the thesis's upwind planet bearings carry 41-47 % more than the downwind ones
    r = simulate_fmu(gearbox, stop_time=0.2, output_interval=1e-3,
                     output=["lss_torque", "planet_1_uw_radial_load", "planet_1_dw_radial_load",
                             "planet_1_uw_rollers_in_contact", "planet_1_uw_inner_race_pressure",
                             "max_contact_pressure_gear_pinion_2", "hss_a_max_shear_depth"])
    assert r["lss_torque"][-1] == pytest.approx(T_ROTOR, rel=0.01)
    assert r["planet_1_uw_radial_load"][-1] > 1.2 * r["planet_1_dw_radial_load"][-1]
    assert 6 <= r["planet_1_uw_rollers_in_contact"][-1] <= 10
    assert 1.3e9 < r["planet_1_uw_inner_race_pressure"][-1] < 2.2e9
    assert 0.8e9 < r["max_contact_pressure_gear_pinion_2"][-1] < 1.6e9
    assert 0.05e-3 < r["hss_a_max_shear_depth"][-1] < 0.65e-3


def test_libcosim_gives_fmpys_outputs(gearbox):
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    md = read_model_description(gearbox)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    ex = CosimExecution.from_step_size(step_size=int(1e-3 * 1e9))
    idx = ex.add_local_slave(CosimLocalSlave(fmu_path=gearbox, instance_name="gearbox"))
    ex.real_initial_value(idx, vr["rotor_torque"], T_ROTOR)
    ex.real_initial_value(idx, vr["generator_torque"], T_GEN)
    ex.real_initial_value(idx, vr["initial_rotor_torque"], T_ROTOR)
    obs = CosimObserver.create_last_value()
    ex.add_observer(obs)
    assert ex.simulate_until(target_time=int(0.5e9))
    values = obs.last_real_values(slave_index=idx, variable_references=[vr[c] for c in CHANNELS])
    ours = fmpy_rated(gearbox)
    for name, value in zip(CHANNELS, values):
        # the tools' step sizes differ in their last bits (integer nanoseconds against accumulated
        # floats) and the Newton iteration stops at 1e-9 of the forces: agreement to 1e-6 of the
        # channel's size is what identical physics gives
        scale = max(np.max(np.abs(ours[name])), 1e-12)
        assert abs(value - ours[name][-1]) <= 1e-6 * scale, (name, value, ours[name][-1])


def test_an_unknown_description_is_named_in_the_log(gearbox, tmp_path):
    logs = []
    with pytest.raises(Exception):
        simulate_fmu(gearbox, stop_time=0.01, start_values={"gearbox": str(tmp_path / "missing.toml")},
                     logger=lambda *args: logs.append(str(args[-1])))
    assert any("missing.toml" in m and "cannot read it" in m for m in logs), logs


def test_a_main_shaft_moment_loads_the_main_bearing(gearbox):
    """The rotor's tilt moment (an input, e.g. rotor.pitching_moment) reaches the bearings that carry
    the rotor: the main bearing's radial load changes, the gear forces hardly. The GRC is a three-point
    mount, so the moment reaches the main bearing through the main shaft's lever, ≈ M/0.88 m; this sign
    adds to the rotor weight's lever (the other would first take the load through zero)."""
    def run(moment):
        inputs = np.array([(0.0, T_ROTOR, T_GEN, moment)],
                          dtype=[("time", float), ("rotor_torque", float), ("generator_torque", float),
                                 ("main_shaft_tilt_moment", float)])
        return simulate_fmu(gearbox, stop_time=0.2, output_interval=1e-3, input=inputs,
                            output=["main_radial_load", "mesh_force_gear_pinion_2"],
                            start_values={"initial_rotor_torque": T_ROTOR})
    still, tilted = run(0.0), run(-5e5)
    assert tilted["main_radial_load"][-1] - still["main_radial_load"][-1] > 4e5
    assert tilted["mesh_force_gear_pinion_2"][-1] == pytest.approx(still["mesh_force_gear_pinion_2"][-1], rel=0.01)


def test_fmpy_starts_balanced_at_its_input_torque(gearbox):
    """With initial_torque_from_input, the equilibrium carries the rotor torque fmpy sets before the first
    step (here half the rated torque, initial_rotor_torque left at rated): the LSS torque starts at it and
    stays there (0.1 %, the rated start would swing it by half the rated torque)."""
    half = 0.5 * T_ROTOR
    inputs = np.array([(0.0, half, half / RATIO)],
                      dtype=[("time", float), ("rotor_torque", float), ("generator_torque", float)])
    r = simulate_fmu(gearbox, stop_time=0.2, output_interval=1e-3, input=inputs, output=["lss_torque"],
                     start_values={"initial_torque_from_input": True})
    assert r["lss_torque"][0] == pytest.approx(half, rel=1e-3)
    assert np.abs(r["lss_torque"] / half - 1).max() < 1e-3
