"""Every windrive command refuses bad input with a non-zero exit and a message naming the culprit."""

import subprocess

import pytest


@pytest.mark.parametrize("args,words", [
    (["modes", "--preset", "Z"], ["Z", "A, B, C or D"]),
    (["modes", "--fidelity", "7"], ["7", "2, 5 or full"]),
    (["modes", "--generator", "floating"], ["floating", "connected"]),
    (["modes", "--plot", "shapes.gif"], ["shapes.gif", ".png or .svg"]),
    (["pack", "nosuch"], ["nosuch", "torsional"]),
    (["bench", "nosuch"], ["nosuch", "torsional, rainflow"]),
    (["step-response", "--fmu", "/nonexistent/x.fmu", "--out", "/tmp/windrive-x.csv"], ["/nonexistent/x.fmu"]),
])
def test_bad_arguments_are_named(windrive, tmp_path, args, words):
    out = subprocess.run([windrive, *args], capture_output=True, text=True, cwd=tmp_path)
    assert out.returncode != 0
    for w in words:
        assert w in out.stderr, out.stderr


def test_corrupt_fmu_archive_is_named(windrive, tmp_path):
    bad = tmp_path / "broken.fmu"
    bad.write_bytes(b"this is not a zip archive")
    out = subprocess.run([windrive, "step-response", "--fmu", str(bad), "--out", str(tmp_path / "x.csv")],
                         capture_output=True, text=True)
    assert out.returncode != 0 and "broken.fmu" in out.stderr and "zip" in out.stderr


def test_bad_wohler_slope_is_named(windrive, tmp_path):
    path = tmp_path / "s.csv"
    path.write_text("time,x\n0,1\n1,3\n2,0\n")
    out = subprocess.run([windrive, "del", str(path), "--channel", "x", "--m", "3,-1"], capture_output=True, text=True)
    assert out.returncode != 0 and "-1" in out.stderr
