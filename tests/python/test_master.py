"""The co-simulation master (`windrive run`) against software nobody here wrote:
- FMUs made by PythonFMU, alone and coupled with our torsional FMU;
- fmpy's simulate_fmu on a single FMU (same step, same outputs to 1e-12);
- the same SSP scene in libcosim (fixed-step Jacobi), fmpy's SSP support (Jacobi) and our master
  (Jacobi): identical trajectories once fmpy's row time stamps are shifted (see the test);
- an FMU that fails halfway: every row before it kept, exit status 1, the FMU named.
"""
import os
import pathlib
import re
import shutil
import subprocess
import sys
import sysconfig

import numpy as np
import pytest

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
STEP = 1e-3


def python_runtime_env():
    """PythonFMU binaries expect the Python runtime in the host process (their .so is not linked to
    libpython on Linux): a non-Python host preloads it and points PYTHONPATH at pythonfmu."""
    libdir = sysconfig.get_config_var("LIBDIR") or ""
    for name in (sysconfig.get_config_var("INSTSONAME"), sysconfig.get_config_var("LDLIBRARY")):
        if name and (pathlib.Path(libdir) / name).is_file() and name.endswith(tuple(".so" + s for s in ("", ".1.0"))):
            env = dict(os.environ, LD_PRELOAD=str(pathlib.Path(libdir) / name), RUST_BACKTRACE="0")
            env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
            return env
    pytest.skip("this Python has no shared libpython, which PythonFMU FMUs need in a non-Python host")


@pytest.fixture(scope="session")
def pyfmus(tmp_path_factory):
    """The PythonFMU FMUs of tests/python/pyfmus, built once per session."""
    out = tmp_path_factory.mktemp("pyfmus")
    exe = pathlib.Path(sys.executable).with_name("pythonfmu")
    for src in sorted((HERE / "pyfmus").glob("py_*.py")):
        subprocess.run([str(exe), "build", "-f", str(src), "-d", str(out)], check=True, capture_output=True)
    return out


@pytest.fixture(scope="session")
def our_fmus(windrive):
    target = ROOT / "target" / "fmu"
    for name in ("torsional", "generator"):
        if not (target / f"{name}.fmu").is_file():
            subprocess.run([windrive, "pack", name], check=True, cwd=ROOT)
    return target


def connector(name, kind, type_="Real"):
    return f'<ssd:Connector name="{name}" kind="{kind}"><ssc:{type_}/></ssd:Connector>'


def write_scene(folder, components, connections, stop_time):
    """An SSD all three tools read: literal ssd:/ssc: prefixes (libcosim), every connector declared and
    every input connected (fmpy), no parameter bindings (fmpy ignores them)."""
    elements = "\n".join(
        f'<ssd:Component name="{name}" source="resources/{fmu.name}" type="application/x-fmu-sharedlibrary">'
        f'<ssd:Connectors>{"".join(connector(*c) for c in conns)}</ssd:Connectors></ssd:Component>'
        for name, fmu, conns in components
    )
    links = "\n".join(
        f'<ssd:Connection startElement="{a}" startConnector="{b}" endElement="{c}" endConnector="{d}"/>'
        for a, b, c, d in connections
    )
    (folder / "resources").mkdir(parents=True, exist_ok=True)
    for _, fmu, _ in components:
        shutil.copy(fmu, folder / "resources" / fmu.name)
    (folder / "SystemStructure.ssd").write_text(f"""<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription"
  xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" version="1.0" name="{folder.name}">
<ssd:System name="system"><ssd:Elements>
{elements}
</ssd:Elements><ssd:Connections>
{links}
</ssd:Connections></ssd:System>
<ssd:DefaultExperiment startTime="0" stopTime="{stop_time}"/>
</ssd:SystemStructureDescription>
""")
    return folder


def run_master(windrive, scene, out, *args):
    proc = subprocess.run(
        [windrive, "run", str(scene), "--out", str(out), "--quiet", *args],
        capture_output=True, text=True, env=python_runtime_env(), cwd=ROOT,
    )
    return proc


def read_csv(path):
    return np.genfromtxt(path, delimiter=",", names=True, deletechars="")


def rotor_torsional_controller(tmp_path, pyfmus, our_fmus, stop_time):
    """Rotor torque ramp (PythonFMU) -> torsional D (ours) <-> region-2 torque law (PythonFMU)."""
    return write_scene(
        tmp_path / "mixed",
        [
            ("rotor", pyfmus / "PyRotor.fmu", [("rotor_torque", "output"), ("brake_command", "output")]),
            ("torsional", our_fmus / "torsional.fmu", [
                ("rotor_torque", "input"), ("generator_torque", "input"), ("brake_command", "input"),
                ("generator_speed", "output"), ("hss_torque", "output"), ("rotor_speed", "output")]),
            ("controller", pyfmus / "PyController.fmu", [("generator_speed", "input"), ("generator_torque", "output")]),
        ],
        [
            ("rotor", "rotor_torque", "torsional", "rotor_torque"),
            ("rotor", "brake_command", "torsional", "brake_command"),
            ("torsional", "generator_speed", "controller", "generator_speed"),
            ("controller", "generator_torque", "torsional", "generator_torque"),
        ],
        stop_time,
    )


def test_pythonfmu_fmus_alone_in_our_master(tmp_path, windrive, pyfmus):
    """Torque source -> damped two-inertia shaft, both PythonFMU. After the ramp the shaft carries
    T·J2/(J1+J2) once the 1.1 Hz mode has decayed (ζ ≈ 0.08), and both speeds grow at T/(J1+J2)."""
    scene = write_scene(
        tmp_path / "py",
        [
            ("rotor", pyfmus / "PyRotor.fmu", [("rotor_torque", "output")]),
            ("shaft", pyfmus / "PyShaft.fmu", [("torque", "input"), ("shaft_torque", "output")]),
        ],
        [("rotor", "rotor_torque", "shaft", "torque")],
        stop_time=8.0,
    )
    proc = run_master(windrive, scene, tmp_path / "py.csv", "--step", "0.01")
    assert proc.returncode == 0, proc.stderr
    r = read_csv(tmp_path / "py.csv")
    T, J1, J2 = 385000.0, 4.0e6, 1.0e6
    assert r["shaft.shaft_torque"][-1] == pytest.approx(T * J2 / (J1 + J2), rel=1e-3)
    late = r["time"] > 6.0
    accel = np.polyfit(r["time"][late], r["shaft.speed_2"][late], 1)[0]
    assert accel == pytest.approx(T / (J1 + J2), rel=1e-3)


def test_pythonfmu_fmus_coupled_with_ours(tmp_path, windrive, pyfmus, our_fmus):
    """Our master runs the mixed scene with every algorithm that needs no rollback (PythonFMU FMUs
    cannot save their state); the region-2 law brakes the ramped rotor torque to a steady speed."""
    scene = rotor_torsional_controller(tmp_path, pyfmus, our_fmus, stop_time=1.0)
    for algorithm in ("jacobi", "gauss-seidel"):
        out = tmp_path / f"{algorithm}.csv"
        proc = run_master(windrive, scene, out, "--step", str(STEP), "--algorithm", algorithm)
        assert proc.returncode == 0, proc.stderr
        r = read_csv(out)
        assert len(r) == 1001 and np.isfinite(r["torsional.hss_torque"]).all()
        assert r["controller.generator_torque"][-1] > 0
    proc = run_master(windrive, scene, tmp_path / "it.csv", "--step", str(STEP), "--algorithm", "iterative")
    assert proc.returncode == 1 and "canGetAndSetFMUstate=false" in proc.stderr


def test_single_fmu_matches_fmpy(tmp_path, windrive, our_fmus):
    """torsional alone: fmpy simulate_fmu and our master, same start values, same 1 ms step."""
    from fmpy import simulate_fmu

    fmu = our_fmus / "torsional.fmu"
    scene = tmp_path / "single"
    (scene / "resources").mkdir(parents=True)
    shutil.copy(fmu, scene / "resources" / "torsional.fmu")
    (scene / "SystemStructure.ssd").write_text("""<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" version="1.0" name="single">
<ssd:System name="s"><ssd:Elements><ssd:Component name="torsional" source="resources/torsional.fmu"/></ssd:Elements></ssd:System>
</ssd:SystemStructureDescription>""")
    start = {"rotor_torque": 385000.0, "generator_torque": 2000.0}
    outputs = ["rotor_speed", "generator_speed", "lss_torque", "hss_torque", "mesh_force_sun_planet_1"]
    ref = simulate_fmu(str(fmu), stop_time=2.0, output_interval=STEP, start_values=start, output=outputs)
    params = [a for k, v in start.items() for a in ("--param", f"torsional.{k}={v}")]
    proc = run_master(windrive, scene, tmp_path / "single.csv", "--step", str(STEP), "--stop-time", "2",
                      "--record", ",".join("torsional." + o for o in outputs), *params)
    assert proc.returncode == 0, proc.stderr
    ours = read_csv(tmp_path / "single.csv")
    assert len(ours) == len(ref)
    np.testing.assert_allclose(ours["time"], ref["time"], rtol=0, atol=1e-12)
    for o in outputs:
        np.testing.assert_allclose(ours["torsional." + o], ref[o], rtol=1e-12, atol=1e-9 * np.abs(ref[o]).max())


def libcosim_jacobi(scene, stop_time, probes):
    """libcosim's fixed-step (Jacobi) run of the SSP folder: one step at a time, reading `probes`
    [(component, vr)] after each."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimObserver import CosimObserver

    ex = CosimExecution.from_ssp_file(str(scene), step_size=int(STEP * 1e9))
    index = {info.name.decode(): info.index for info in ex.slave_infos()}
    obs = CosimObserver.create_last_value()
    ex.add_observer(obs)
    rows = []
    for _ in range(round(stop_time / STEP)):
        assert ex.step(1)
        rows.append([obs.last_real_values(index[c], [vr])[0] for c, vr in probes])
    return np.array(rows)


def test_ssp_scene_in_libcosim_fmpy_and_our_master(tmp_path, windrive, pyfmus, our_fmus):
    """The mixed scene with fixed-step Jacobi in three masters.

    Documented differences, accounted for:
    - initial values: libcosim and we propagate outputs to inputs before the first step, fmpy sets
      every input to 0. The scene's sources are 0 until 5.5 ms (PyRotor ramp, PyController t_on), so
      every FMU sees the same inputs at every step in all three.
    - row time stamps: fmpy stamps each row with the step's start time but stores the values after
      the step; its row k is our row k+1.
    - fmpy accumulates time by repeated addition (last stamp 0.999000000000001): inside 1e-12.
    With that, nothing is left to differ: the same FMU calls in the same order give the same bits,
    asserted to 1e-9 relative.
    """
    from fmpy.ssp.simulation import simulate_ssp

    stop = 1.0
    scene = rotor_torsional_controller(tmp_path, pyfmus, our_fmus, stop_time=stop)
    proc = run_master(windrive, scene, tmp_path / "ours.csv", "--step", str(STEP), "--algorithm", "jacobi")
    assert proc.returncode == 0, proc.stderr
    ours = read_csv(tmp_path / "ours.csv")
    cols = ["torsional.hss_torque", "torsional.generator_speed", "controller.generator_torque"]

    archive = shutil.make_archive(str(tmp_path / "mixed"), "zip", scene)  # fmpy reads .ssp archives only
    fm = simulate_ssp(shutil.move(archive, tmp_path / "mixed.ssp"), stop_time=stop, step_size=STEP)
    assert len(fm) == len(ours) - 1
    np.testing.assert_allclose(fm["time"] + STEP, ours["time"][1:], atol=1e-12)
    for c in cols:
        np.testing.assert_allclose(fm[c], ours[c][1:], rtol=1e-9, atol=1e-9 * np.abs(ours[c]).max())

    # vr: torsional hss_torque 45, generator_speed 41; PyController generator_torque is its 4th variable (vr 3)
    lc = libcosim_jacobi(scene, stop, [("torsional", 45), ("torsional", 41), ("controller", 3)])
    for j, c in enumerate(cols):
        np.testing.assert_allclose(lc[:, j], ours[c][1:], rtol=1e-9, atol=1e-9 * np.abs(ours[c]).max())


def test_fmu_failing_halfway_keeps_rows(tmp_path, windrive, pyfmus, our_fmus):
    """PyRotor returns an error from t = 0.3 s: the master stops there, names the FMU, time and
    status, exits 1, and the CSV holds every step up to 0.3 s."""
    scene = rotor_torsional_controller(tmp_path, pyfmus, our_fmus, stop_time=1.0)
    ssv = f"""<ssd:ParameterBindings><ssd:ParameterBinding><ssd:ParameterValues>
<ssv:ParameterSet xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="p">
<ssv:Parameters><ssv:Parameter name="fail_time"><ssv:Real value="0.3"/></ssv:Parameter></ssv:Parameters>
</ssv:ParameterSet></ssd:ParameterValues></ssd:ParameterBinding></ssd:ParameterBindings>"""
    ssd = scene / "SystemStructure.ssd"
    text = ssd.read_text()
    marker = '<ssd:Connector name="brake_command" kind="output"><ssc:Real/></ssd:Connector></ssd:Connectors>'
    ssd.write_text(text.replace(marker, marker + ssv, 1))
    out = tmp_path / "fail.csv"
    proc = run_master(windrive, scene, out, "--step", str(STEP))
    assert proc.returncode == 1
    assert "rotor failed at t = 0.3" in proc.stderr and "fmi2DoStep" in proc.stderr, proc.stderr
    r = read_csv(out)
    assert r["time"][-1] == pytest.approx(0.3, abs=1e-12) and len(r) == 301
    assert np.isfinite(r["torsional.hss_torque"]).all()


def rotor_and_shaft(tmp_path, pyfmus):
    """PyRotor driving PyShaft for 5 s: the scene of the crash tests."""
    return write_scene(
        tmp_path / "crash",
        [
            ("rotor", pyfmus / "PyRotor.fmu", [("rotor_torque", "output")]),
            ("shaft", pyfmus / "PyShaft.fmu", [("torque", "input"), ("shaft_torque", "output")]),
        ],
        [("rotor", "rotor_torque", "shaft", "torque")],
        stop_time=5.0,
    )


def test_a_crashing_fmu_costs_only_the_last_quarter_second_of_rows(tmp_path, windrive, pyfmus):
    """A third-party FMU takes the whole process down (SIGSEGV at t = 3 s) after a slow step at
    t = 2.5 s: the master flushes rows at least every 0.25 s of wall time, so the CSV holds every row
    up to the slow step (before, a 64 kB buffer still held ~2000 of them and the file ended near
    2.2 s)."""
    scene = rotor_and_shaft(tmp_path, pyfmus)
    out = tmp_path / "crash.csv"
    proc = run_master(windrive, scene, out, "--step", "0.001", "--record", "rotor.rotor_torque",
                      "--param", "rotor.pause_time=2.5", "--param", "rotor.crash_time=3.0")
    assert proc.returncode != 0
    r = read_csv(out)
    assert 2.5 <= r["time"][-1] < 3.0, r["time"][-1]
    # whole rows only: every line has both columns
    assert np.isfinite(r["rotor.rotor_torque"]).all()


def test_isolated_a_crashing_fmu_ends_the_run_with_its_name_signal_and_time_and_every_row(tmp_path, windrive, pyfmus):
    """The same crash with --isolate: each FMU in its own process, so the segfault ends the rotor's
    host only. The master reports the component, the signal, the call and the time, exits 1, and
    the CSV holds every row up to the step that crashed."""
    scene = rotor_and_shaft(tmp_path, pyfmus)
    out = tmp_path / "crash.csv"
    proc = run_master(windrive, scene, out, "--step", "0.001", "--isolate",
                      "--param", "rotor.crash_time=3.0")
    assert proc.returncode == 1, proc.stderr
    failed = re.search(r"error: rotor failed at t = ([0-9.]+) s: rotor: its process ended during fmi2DoStep: "
                       r"killed by signal 11 \(Segmentation fault\)", proc.stderr)
    assert failed, proc.stderr
    assert "Traceback" not in proc.stderr and "panicked" not in proc.stderr
    # PyRotor crashes in the first step that starts at or after 3.0 s (by its own summed clock)
    t_crash = float(failed.group(1))
    assert 3.0 <= t_crash <= 3.001 + 1e-9
    r = read_csv(out)
    assert r["time"][-1] == pytest.approx(t_crash, abs=1e-12) and len(r) == round(t_crash / 0.001) + 1
    assert np.isfinite(r["rotor.rotor_torque"]).all() and np.isfinite(r["shaft.shaft_torque"]).all()


def test_isolated_an_fmu_that_stops_answering_is_killed_after_the_call_timeout(tmp_path, windrive, pyfmus):
    """PyRotor's step at t = 2.5 s hangs (an hour's sleep); with --call-timeout 5 its host is killed and
    the run ends there, naming the component, the call and the timeout, with every row before it. The
    timeout is far above any ordinary call (starting the Python host included) on a busy machine, and
    the hang far above the timeout, so the outcome does not depend on the machine's speed."""
    scene = rotor_and_shaft(tmp_path, pyfmus)
    out = tmp_path / "hang.csv"
    proc = run_master(windrive, scene, out, "--step", "0.001", "--isolate", "--call-timeout", "5",
                      "--param", "rotor.pause_time=2.5", "--param", "rotor.pause_length=3600")
    assert proc.returncode == 1, proc.stderr
    failed = re.search(r"error: rotor failed at t = ([0-9.]+) s: rotor: its process ended during fmi2DoStep: "
                       r"no answer within 5 s, killed", proc.stderr)
    assert failed, proc.stderr
    t_hang = float(failed.group(1))
    assert 2.5 <= t_hang <= 2.501 + 1e-9
    r = read_csv(out)
    assert r["time"][-1] == pytest.approx(t_hang, abs=1e-12) and len(r) == round(t_hang / 0.001) + 1
    # without --isolate the option is refused
    bad = run_master(windrive, scene, out, "--call-timeout", "1")
    assert bad.returncode == 2 and "--isolate" in bad.stderr, bad.stderr


def test_parquet_results_read_as_is_by_pandas_and_pyarrow(tmp_path, windrive, our_fmus):
    """`windrive run --out FILE.parquet`: pandas and pyarrow read the file as it is (no conversion), with
    the CSV's columns, every one float64, and the CSV's values to the bit."""
    import pandas as pd
    import pyarrow.parquet as pq

    scene = tmp_path / "d-grid-step"
    (scene / "resources").mkdir(parents=True)
    for f in (ROOT / "scenes" / "d-grid-step").iterdir():
        if f.is_file():
            shutil.copy(f, scene / f.name)
    for name in ("torsional", "generator"):
        shutil.copy(our_fmus / f"{name}.fmu", scene / "resources" / f"{name}.fmu")
    for out in ("r.csv", "r.parquet"):
        proc = run_master(windrive, scene, tmp_path / out, "--stop-time", "0.5")
        assert proc.returncode == 0, proc.stderr
    csv = pd.read_csv(tmp_path / "r.csv")  # pandas >= 3 parses floats to the nearest double (round trip)
    table = pd.read_parquet(tmp_path / "r.parquet")
    assert list(table.columns) == list(csv.columns) and len(table) == len(csv) > 100
    assert (table.dtypes == "float64").all()
    assert (table.to_numpy() == csv.to_numpy()).all()
    schema = pq.read_schema(tmp_path / "r.parquet")
    assert schema.names[0] == "time" and all(str(t) == "double" for t in schema.types)


def test_series_commands_read_parquet_as_pandas_and_pyarrow_write_it(tmp_path, windrive):
    """A series written by pandas (pyarrow's defaults: dictionary pages, Snappy, nullable float columns)
    or by pyarrow in many row groups reads as its CSV does: the same DELs to the last digit. A column
    that is not float64, a null value, a codec windrive does not read and a file that is not Parquet are
    refused in one line naming the column, the row, the codec or the file."""
    import pandas as pd
    import pyarrow as pa
    import pyarrow.parquet as pq

    t = np.round(np.arange(0.0, 20.0, 0.001), 3)
    torque = 1e3 * np.sin(2 * np.pi * t) + 5e2 * np.sin(2 * np.pi * 7.3 * t) + 2e2 * np.cos(2 * np.pi * 13.1 * t)
    frame = pd.DataFrame({"time": t, "lss.torque": torque, "count": np.arange(len(t))})
    frame.to_csv(tmp_path / "s.csv", index=False, float_format="%.17g")
    frame.to_parquet(tmp_path / "pandas.parquet")
    pq.write_table(pa.Table.from_pandas(frame, preserve_index=False), tmp_path / "groups.parquet",
                   row_group_size=777, compression="none")
    assert pq.ParquetFile(tmp_path / "groups.parquet").metadata.num_row_groups > 20

    def dels(name):
        proc = subprocess.run([str(windrive), "del", str(tmp_path / name), "--channel", "lss.torque", "--json"],
                              capture_output=True, text=True)
        assert proc.returncode == 0, proc.stderr
        return proc.stdout

    assert dels("s.csv") == dels("pandas.parquet") == dels("groups.parquet")

    def refused(name, channel):
        proc = subprocess.run([str(windrive), "del", str(tmp_path / name), "--channel", channel],
                              capture_output=True, text=True)
        assert proc.returncode != 0 and len(proc.stderr.strip().splitlines()) == 1, proc.stderr
        return proc.stderr

    assert "column count is INT64" in refused("pandas.parquet", "count")
    holes = frame.drop(columns="count").astype({"lss.torque": "Float64"})
    holes.loc[1234, "lss.torque"] = pd.NA
    holes.to_parquet(tmp_path / "holes.parquet")
    assert "row 1235" in refused("holes.parquet", "lss.torque")
    pq.write_table(pa.Table.from_pandas(frame, preserve_index=False), tmp_path / "zstd.parquet", compression="zstd")
    assert 'compressed with ZSTD' in refused("zstd.parquet", "lss.torque")
    assert 'compression="snappy"' in refused("zstd.parquet", "lss.torque")
    (tmp_path / "garbage.parquet").write_text("not parquet")
    assert "garbage.parquet" in refused("garbage.parquet", "lss.torque")
