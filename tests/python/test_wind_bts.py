"""`windrive wind` against TurbSim's binary full-field layout (.bts; TurbSim user's guide NREL/TP-500-46198,
the layout OpenFAST's InflowWind reads), read and written here with numpy alone: a header (ID 7, or 8 when
periodic; nz, ny, tower points, nt; dz, dy, dt, u_hub, z_hub, z_bottom; slope and offset of u, v, w; the
description), then per time step the grid as int16 (z slowest, then y, then the component) and the tower
points. A value is (stored - offset) / slope, so a writer that spreads a component's range over int16 keeps
it to within half a count, range / 131070.

Three files TurbSim wrote (openfast_toolbox's example files, tests/data/turbsim/, two with tower points) go
round our reader and writer, and are read by NREL's own reader (openfast_io's TurbSimFile) as the
independent check; a file of your own (say r-test's 5MW_Baseline/Wind/*.bts) joins them when named in
WINDRIVE_TURBSIM_BTS (paths separated by the OS's path separator)."""

import json
import os
import struct
import subprocess
from pathlib import Path

import numpy as np
import pytest
from openfast_io.turbsim_file import TurbSimFile

SHIPPED = sorted(str(p) for p in (Path(__file__).resolve().parents[1] / "data" / "turbsim").glob("*.bts"))

HEADER = "<h4i6f6fi"


def read_bts(path):
    with open(path, "rb") as f:
        raw = f.read()
    ident, nz, ny, ntwr, nt, dz, dy, dt, uhub, zhub, zbottom, *scaling, nchar = struct.unpack_from(HEADER, raw)
    start = struct.calcsize(HEADER) + nchar
    slope, offset = np.array(scaling[0::2]), np.array(scaling[1::2])
    counts = np.frombuffer(raw[start:], dtype="<i2").reshape(nt, ny * nz + ntwr, 3)
    values = (counts.astype(float) - offset) / slope
    return {
        "id": ident, "nz": nz, "ny": ny, "ntwr": ntwr, "nt": nt, "dz": dz, "dy": dy, "dt": dt,
        "uhub": uhub, "zhub": zhub, "zbottom": zbottom, "slope": slope,
        "info": raw[start - nchar:start].decode("ascii"),
        # [t, z, y, component]
        "grid": values[:, : ny * nz, :].reshape(nt, nz, ny, 3),
        "tower": values[:, ny * nz:, :],
    }


def write_bts(path, grid, tower, ident, dz, dy, dt, uhub, zhub, zbottom):
    """TurbSim's quantisation: each component's range over grid and tower spread over int16."""
    nt, nz, ny, _ = grid.shape
    both = np.concatenate([grid.reshape(nt, ny * nz, 3), tower], axis=1)
    lo, hi = both.min(axis=(0, 1)), both.max(axis=(0, 1))
    slope = (65535.0 / (hi - lo)).astype(np.float32)
    offset = (-32768.0 - slope * lo).astype(np.float32)
    counts = np.clip(np.rint(both * slope + offset), -32768, 32767).astype("<i2")
    info = b"written by numpy in test_wind_bts.py"
    scaling = [float(x) for pair in zip(slope, offset) for x in pair]
    with open(path, "wb") as f:
        f.write(struct.pack(HEADER, ident, nz, ny, tower.shape[1], nt, dz, dy, dt, uhub, zhub, zbottom, *scaling,
                            len(info)))
        f.write(info)
        f.write(counts.tobytes())


def half_count(values):
    """Half an int16 count of a component's range: the most a value moves when stored."""
    return 0.5 * (values.max() - values.min()) / 65535.0


def wind_json(windrive, *args):
    out = subprocess.run([windrive, "wind", *args, "--json"], capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def test_generated_field_read_with_the_published_layout(windrive, tmp_path):
    """The header as asked; every point's mean and σ read back equal the generator's (before quantisation)
    to within half a count (an error of at most e per value moves a mean and a standard deviation by at most
    e); and, read from the file alone, the IEC field: over a 600 s period the power-law profile at every
    height, σ_v = 0.8σ1 and σ_w = 0.5σ1 at every point and u's σ1 over the grid, σ1 = 0.14·(0.75·12 + 5.6)
    for class B at 12 m/s."""
    path = tmp_path / "field.bts"
    ours = wind_json(windrive, "--out", str(path), "--wind", "12", "--class", "B", "--hub-height", "90",
                     "--grid", "7x5", "--width", "100", "--height", "80", "--period", "600", "--dt", "0.2",
                     "--seed", "4", "--shear", "0.2")
    f = read_bts(path)
    assert (f["id"], f["ny"], f["nz"], f["ntwr"], f["nt"]) == (8, 7, 5, 0, 3000)
    for key, value in [("dy", 100 / 6), ("dz", 20.0), ("dt", 0.2), ("zbottom", 50.0), ("zhub", 90.0), ("uhub", 12.0)]:
        assert f[key] == pytest.approx(value, rel=1e-6), key
    assert "seed 4" in f["info"]
    sigma1 = 0.14 * (0.75 * 12 + 5.6)
    for c in range(3):
        values = f["grid"][..., c]
        tolerance = half_count(values) * 1.01
        mean = values.mean(axis=0).ravel()
        std = values.std(axis=0).ravel()
        assert np.abs(mean - ours["mean"][c]).max() <= tolerance
        assert np.abs(std - ours["std"][c]).max() <= tolerance
        if c == 0:
            z = f["zbottom"] + f["dz"] * np.arange(f["nz"])
            profile = 12.0 * (z / 90.0) ** 0.2
            assert np.abs(values.mean(axis=(0, 2)) - profile).max() <= tolerance
            assert np.sqrt((std ** 2).mean()) == pytest.approx(sigma1, abs=tolerance)
        else:
            assert np.abs(mean).max() <= tolerance
            assert np.abs(std - [0.8, 0.5][c - 1] * sigma1).max() <= tolerance


def test_our_reader_and_writer_on_a_numpy_written_file(windrive, tmp_path):
    """A field with tower points and ID 7 written by numpy: our reader gives its header and every grid point's
    mean and σ as numpy does (to rounding), and our writer's copy holds the same values, tower points
    included, to within half a count of its own quantisation, still ID 7."""
    rng = np.random.default_rng(7)
    nt, nz, ny, ntwr = 40, 4, 6, 3
    grid = rng.normal([9.0, 0.0, 0.0], [1.5, 1.2, 0.7], size=(nt, nz, ny, 3))
    tower = rng.normal([7.0, 0.0, 0.0], 1.0, size=(nt, ntwr, 3))
    source, copy = tmp_path / "numpy.bts", tmp_path / "copy.bts"
    write_bts(source, grid, tower, 7, 12.5, 10.0, 0.05, 9.0, 80.0, 61.25)
    original = read_bts(source)
    ours = wind_json(windrive, "--from", str(source), "--out", str(copy))
    assert (ours["ny"], ours["nz"], ours["nt"], ours["periodic"]) == (ny, nz, nt, False)
    for key, theirs in [("dy", "dy"), ("dz", "dz"), ("dt", "dt"), ("z_bottom", "zbottom"), ("hub_height", "zhub"),
                        ("mean_hub", "uhub")]:
        assert ours[key] == pytest.approx(original[theirs], rel=1e-12), key
    for c in range(3):
        values = original["grid"][..., c]
        np.testing.assert_allclose(ours["mean"][c], values.mean(axis=0).ravel(), rtol=0, atol=1e-9)
        np.testing.assert_allclose(ours["std"][c], values.std(axis=0).ravel(), rtol=0, atol=1e-9)
    back = read_bts(copy)
    assert (back["id"], back["ntwr"], back["grid"].shape) == (7, ntwr, original["grid"].shape)
    for c in range(3):
        both = np.concatenate([original["grid"][..., c].ravel(), original["tower"][..., c].ravel()])
        assert np.abs(back["grid"][..., c] - original["grid"][..., c]).max() <= 1.01 * half_count(both)
        assert np.abs(back["tower"][..., c] - original["tower"][..., c]).max() <= 1.01 * half_count(both)


def test_a_broken_file_is_named(windrive, tmp_path):
    source = tmp_path / "short.bts"
    write_bts(source, np.ones((3, 2, 2, 3)) + np.arange(3)[:, None, None, None], np.zeros((3, 0, 3)), 8, 1.0, 1.0,
              0.1, 8.0, 90.0, 89.5)
    source.write_bytes(source.read_bytes()[:-4])
    out = subprocess.run([windrive, "wind", "--from", str(source), "--out", str(tmp_path / "x.bts")],
                         capture_output=True, text=True)
    assert out.returncode != 0
    assert str(source) in out.stderr and "nt = 3" in out.stderr, out.stderr


def turbsim_files():
    """The TurbSim files to test with: the shipped ones and those named in WINDRIVE_TURBSIM_BTS."""
    return SHIPPED + [p for p in os.environ.get("WINDRIVE_TURBSIM_BTS", "").split(os.pathsep) if p]


@pytest.mark.parametrize("path", turbsim_files())
def test_a_turbsim_file_round_trips(windrive, tmp_path, path):
    """A file TurbSim wrote, through our reader and writer: its header and grid, read here, to within half a
    count of the copy's quantisation."""
    original = read_bts(path)
    copy = tmp_path / "copy.bts"
    wind_json(windrive, "--from", path, "--out", str(copy))
    back = read_bts(copy)
    assert back["id"] == original["id"]
    for key in ["nz", "ny", "nt", "dz", "dy", "dt", "uhub", "zhub", "zbottom"]:
        assert back[key] == original[key], key
    for c in range(3):
        values = original["grid"][..., c]
        assert np.abs(back["grid"][..., c] - values).max() <= 1.01 * half_count(values)


@pytest.mark.parametrize("path", turbsim_files())
def test_nrel_reader_agrees_with_ours(windrive, tmp_path, path):
    """NREL's TurbSim reader (openfast_io, from PyPI) on a file TurbSim wrote and on our copy of it: the
    grid's coordinates, times, hub height and wind, and every grid and tower value agree to within half a
    count (our writer keeps TurbSim's scaling, so they come back equal); and every grid point's mean and σ
    our reader reports (`windrive wind --json`) is NREL's reader's to rounding."""
    copy = tmp_path / "copy.bts"
    ours = wind_json(windrive, "--from", path, "--out", str(copy))
    theirs, back = TurbSimFile(path), TurbSimFile(str(copy))
    assert back["ID"] == theirs["ID"]
    for key in ["y", "z", "t", "zTwr", "dt", "zRef", "uRef"]:
        np.testing.assert_allclose(np.asarray(back[key], float), np.asarray(theirs[key], float), rtol=1e-6, err_msg=key)
    u, tower = theirs["u"], theirs["uTwr"]  # [component, time, y, z] and [component, time, point]
    assert u.shape[1:] == (ours["nt"], ours["ny"], ours["nz"])
    for c in range(3):
        both = np.concatenate([u[c].ravel(), tower[c].ravel()])
        assert np.abs(back["u"][c] - u[c]).max() <= 1.01 * half_count(both)
        if tower.size:
            assert np.abs(back["uTwr"][c] - tower[c]).max() <= 1.01 * half_count(both)
        # ours lists the points z slowest, then y
        mean, std = u[c].mean(axis=0).T.ravel(), u[c].std(axis=0).T.ravel()
        np.testing.assert_allclose(ours["mean"][c], mean, rtol=0, atol=1e-9 * max(1.0, np.abs(mean).max()))
        np.testing.assert_allclose(ours["std"][c], std, rtol=0, atol=1e-9 * max(1.0, std.max()))


def test_nrel_reader_reads_our_generated_field(windrive, tmp_path):
    """A field we generate, read by NREL's reader: the grid's coordinates centred on the hub's column, the
    heights from z_bottom, the hub height and wind, and every point's mean the generator's to within half a
    count."""
    path = tmp_path / "field.bts"
    ours = wind_json(windrive, "--out", str(path), "--wind", "10", "--grid", "5x4", "--width", "60", "--height", "45",
                     "--period", "30", "--dt", "0.1", "--seed", "2")
    f = TurbSimFile(str(path))
    np.testing.assert_allclose(f["y"], 15.0 * (np.arange(5) - 2), atol=1e-5)
    np.testing.assert_allclose(f["z"], ours["z_bottom"] + 15.0 * np.arange(4), rtol=1e-6)
    assert (f["zRef"], f["uRef"], f["u"].shape) == (pytest.approx(90.0), pytest.approx(10.0), (3, 300, 5, 4))
    for c in range(3):
        # ours are the generator's values, NREL's reader's the file's: half a count apart at most
        np.testing.assert_allclose(ours["mean"][c], f["u"][c].mean(axis=0).T.ravel(), rtol=0,
                                   atol=1.01 * half_count(f["u"][c]))
