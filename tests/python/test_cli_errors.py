"""Every windrive command refuses bad input with a non-zero exit and a message naming the culprit."""

import subprocess

import pytest


@pytest.mark.parametrize("args,words", [
    (["modes", "--preset", "Z"], ["Z", "A, B, C, D or P"]),
    (["modes", "--fidelity", "7"], ["7", "2, 5 or full"]),
    (["modes", "--generator", "floating"], ["floating", "connected"]),
    (["modes", "--lumping", "lumpy"], ["lumpy", "physical or thesis"]),
    (["modes", "--plot", "shapes.gif"], ["shapes.gif", ".png or .svg"]),
    (["pack", "nosuch"], ["nosuch", "torsional"]),
    (["bench", "nosuch"], ["nosuch", "torsional, gearbox, rainflow"]),
    (["aero", "--blade", "/nonexistent/blade"], ["/nonexistent/blade/blade.csv"]),
    (["aero", "--preset", "Z"], ["Z", "A, B, C, D or P"]),
    (["step-response", "--fmu", "/nonexistent/x.fmu", "--out", "/tmp/windrive-x.csv"], ["/nonexistent/x.fmu"]),
    (["gearbox", "--bearings", "balls"], ["balls", "linear, lamina or lamina-table"]),
    (["gears", "s.csv", "--face-load", "model"], ["--face-load model", "--fmu gearbox6dof"]),
    (["gears", "s.csv", "--face-load", "iso"], ["iso", "one", "model"]),
    (["gears", "s.csv", "--dynamic-factor", "0.9"], ["--dynamic-factor 0.9", "≥ 1", "K_v"]),
    (["gearbox", "--dynamic-factor", "--step=-1e-5"], ["step -0.00001 s", "positive"]),
    (["gearbox", "--dynamic-factor", "--step", "0.01"], ["step 0.01 s", "663.3 Hz"]),
    (["bearings", "s.csv", "--contamination", "2"], ["--contamination", "e_C 2", "0 to 1"]),
    (["bearings", "s.csv", "--oil-viscosity", "24,320"], ["--oil-viscosity", "24 mm²/s at 40 °C"]),
    (["bearings", "s.csv", "--oil-viscosity", "320"], ["--oil-viscosity [320.0]", "two values"]),
    (["bearings", "s.csv", "--oil-temperature", "nan"], ["--oil-temperature", "NaN °C"]),
    (["gearbox", "--gearbox", "planetary-spur", "--fit-webs", "1.4"], ["planetary-spur", "carrier_webs"]),
    (["gearbox", "--fit-webs", "0.5"], ["0.5", "outside what the webs can give"]),
    (["climate", "--weibull", "2", "--cut-in", "4", "--cut-out", "25"], ["--weibull", "shape,scale"]),
    (["climate", "--rayleigh", "10", "--cut-in", "25", "--cut-out", "4"], ["--cut-in 25", "cut-in < cut-out"]),
    (["climate", "--rayleigh", "10", "--cut-in", "4", "--cut-out", "25", "--class", "D"], ["\"D\"", "A, B or C"]),
])
def test_bad_arguments_are_named(windrive, tmp_path, args, words):
    out = subprocess.run([windrive, *args], capture_output=True, text=True, cwd=tmp_path)
    assert out.returncode != 0
    for w in words:
        assert w in out.stderr, out.stderr


def test_thesis_lumping_moves_the_fourth_five_mass_mode(windrive):
    """`modes --lumping thesis` reproduces the thesis's Eq. 4.9: D's fourth 5-mass mode (free-free) is
    476.7 Hz without the planets' spin, 435.8 Hz with it (8.6 % lower, to 0.2 %)."""
    import json

    def fourth(lumping):
        out = subprocess.run([windrive, "modes", "--preset", "D", "--fidelity", "5", "--generator", "disconnected",
                              "--lumping", lumping, "--json"], capture_output=True, text=True, check=True)
        return json.loads(out.stdout)["frequencies_hz"][3]

    assert abs(1 - fourth("physical") / fourth("thesis") - 0.086) < 0.002


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


ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]
GRID_STEP = str(ROOT / "scenes" / "d-grid-step")


@pytest.mark.parametrize("args,words", [
    (["run", "/nonexistent/scene"], ["/nonexistent/scene", "no such file"]),
    (["run", GRID_STEP, "--algorithm", "explicit"], ["explicit", "jacobi, gauss-seidel, iterative, adaptive"]),
    (["run", GRID_STEP, "--order", "3", "--stop-time", "0.1"], ["extrapolation order 3"]),
    (["run", GRID_STEP, "--step=-0.001", "--stop-time", "0.1"], ["step size -0.001"]),
    (["run", GRID_STEP, "--param", "torsional.fidelity"], ["torsional.fidelity", "component.variable=value"]),
    (["run", GRID_STEP, "--param", "torsional.damping_scale=soft"], ["damping_scale", "not a number"]),
    (["run", GRID_STEP, "--record", "generator.nosuch"], ["generator.nosuch", "no variable nosuch"]),
    (["run", GRID_STEP, "--analyse", '{"channels": [{"name": "a.x", "m": [0]}]}'], ["--analyse", "a.x", "m = 0"]),
    (["run", GRID_STEP, "--analyse", '{"feq": 1, "chanels": []}'], ["--analyse", "unknown field `chanels`"]),
    (["run", GRID_STEP, "--analyse", "/nonexistent/spec.json"], ["/nonexistent/spec.json"]),
    (["run", GRID_STEP, "--stop-time", "0.1", "--analyse", '{"channels": [{"name": "generator.nosuch"}]}'],
     ["analysis: generator.nosuch not in the series"]),
    (["pack-scene", GRID_STEP + "/SystemStructure.ssd"], ["SystemStructure.ssd", "scene folder"]),
    (["shutdown", "--preset", "Z"], ["Z", "C, D or P"]),
    (["shutdown", "--preset", "A", "--spring"], ["a-normal-spring", "spring scenes for C and D"]),
    (["shutdown", "--aerodynamics", "vortex"], ["vortex", "bem, analytic or scene"]),
    (["reproduce", "--out", "/proc/nonexistent/x.md"], ["/proc/nonexistent"]),
    (["calibrate", "--no-fit", "--out", "/proc/nonexistent/x.md"], ["/proc/nonexistent"]),
])
def test_bad_master_arguments_are_named(windrive, tmp_path, args, words):
    out_csv = ["--out", str(tmp_path / "x.csv")] if args[0] == "run" else []
    out = subprocess.run([windrive, *args, *out_csv], capture_output=True, text=True, cwd=ROOT,
                         env={**__import__("os").environ, "RUST_BACKTRACE": "0"})
    assert out.returncode != 0
    for w in words:
        assert w in out.stderr, out.stderr


def one_fmu_scene(tmp_path, name):
    import shutil
    (tmp_path / "resources").mkdir()
    shutil.copy(ROOT / "target" / "fmu" / f"{name}.fmu", tmp_path / "resources" / f"{name}.fmu")
    (tmp_path / "SystemStructure.ssd").write_text(f"""<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" version="1.0" name="one">
<ssd:System name="s"><ssd:Elements><ssd:Component name="{name}" source="resources/{name}.fmu"/></ssd:Elements></ssd:System>
</ssd:SystemStructureDescription>""")
    return str(tmp_path)


@pytest.mark.parametrize("fmu,params,words", [
    ("rotor", ["mode=wind"], ["mode", "wind", "aero or playback"]),
    ("rotor", ["turbulence=gusty"], ["turbulence", "gusty", "none, ntm or etm"]),
    ("rotor", ["mode=playback"], ["needs the parameter series"]),
    ("rotor", ["mode=playback", "series=/nonexistent/torque.csv"], ["/nonexistent/torque.csv"]),
    ("rotor", ["mode=playback", "series=c-shutdown-pu.csv", "source_rotor_diameter=80"], ["source_rotor_diameter", "absolute series"]),
    ("rotor", ["radius=5", "preset=C"], ["radius 5 m", "never reaches rated power"]),
    ("generator", ["kind=squirrel"], ["kind", "squirrel", "spring, fixed, dfig or pmg"]),
    ("generator", ["kind=dfig", "torque_control=pid"], ["torque_control", "pid", "law or speed"]),
    ("generator", ["kind=dfig", "current_bandwidth=-5"], ["current_bandwidth = -5", "below its minimum 0"]),
    ("generator", ["kind=dfig", "current_bandwidth=0"], ["current_bandwidth = 0", "positive"]),
    ("generator", ["kind=pmg", "poles=7"], ["poles = 7", "even"]),
    ("rotor", ["mode=playback", "series=c-shutdown-pu.csv", "source_preset=Q"], ["source_preset", "Q", "A, B, C, D or P"]),
    ("rotor", ["mode=playback", "series=c-shutdown-pu.csv", "source_preset=C", "source_rotor_diameter=80"], ["source_preset or source_rotor_diameter"]),
    ("generator", ["preset=Z"], ["preset", "A, B, C, D or P"]),
    ("gearbox6dof", ["gearbox=grc751"], ["gearbox", "grc751", "presets are grc750"]),
    ("gearbox6dof", ["integrator=rk4"], ["integrator", "RK4 is not offered"]),
    ("gearbox6dof", ["mesh_stiffness=wavy"], ["mesh_stiffness", "wavy", "mean or varying"]),
    ("gearbox6dof", ["slices=500"], ["slices = 500", "above its maximum 200"]),
    ("gearbox6dof", ["bearing_model=balls"], ["bearing_model", "balls", "linear, lamina or lamina-table"]),
    ("rotor", ["aerodynamics=vortex"], ["aerodynamics", "vortex", "bem or analytic"]),
    ("rotor", ["blade=no-such-blade"], ["no-such-blade/blade.csv"]),
    ("rotor", ["scale_blade_to_radius=false", "radius=40"], ["radius = 40 m", "scale_blade_to_radius = false", "tip radius 35 m"]),
    ("rotor", ["initial_pitch=2"], ["initial_pitch = 2", "pitch_max"]),
    ("rotor", ["turbulence=ntm", "turbulence_period=0.5"], ["turbulence_period = 0.5", "0 (3276.8 s) or 1 to 86 400 s"]),
    ("rotor", ["turbulence=ntm", "turbulence_period=1e6"], ["turbulence_period = 1000000", "above its maximum 86400"]),
    ("rotor", ["turbulence=ntm", "turbulence_scaling=window"], ["turbulence_scaling", "window", "ten_minute or period"]),
])
def test_bad_fmu_parameters_are_named(windrive, tmp_path, fmu, params, words):
    scene = one_fmu_scene(tmp_path, fmu)
    args = [a for p in params for a in ("--param", f"{fmu}.{p}")]
    out = subprocess.run([windrive, "run", scene, "--step", "0.01", "--stop-time", "0.1", "--out", str(tmp_path / "x.csv"), *args],
                         capture_output=True, text=True, cwd=ROOT, env={**__import__("os").environ, "RUST_BACKTRACE": "0"})
    assert out.returncode != 0
    for w in words:
        assert w in out.stderr, out.stderr


@pytest.mark.parametrize("content,words", [
    ("name = 'x'\n[model]\nslicez = 3\n", ["line 3", "unknown field `slicez`"]),
    ("name = 'x'\n", ["missing field `stage`"]),
    ("name = 'x'\n[[stage]]\n[stage.planetary]\nplanets = 3\nteeth = { sun = 20, planet = 40, ring = 99 }\n"
     "toothing = { module_mm = 10, face_width_mm = 100 }\ncarrier = {}\nplanet = {}\nsun = {}\n",
     ["stage[1].teeth", "not an integer"]),
    ("name = 'x'\n[[stage]]\n[stage.parallel]\nteeth = { gear = 80, pinion = 20 }\n"
     "toothing = { module_mm = 5, face_width_mm = 100 }\n[stage.parallel.gear]\n"
     "bearings = [{ name = 'a', rollers = { count = 20, diameter_mm = 30, length_mm = 40, pitch_diameter_mm = 20 } }]\n"
     "[stage.parallel.pinion]\n",
     ["stage[1].gear.bearings[1].rollers.pitch_diameter_mm", "must exceed the roller diameter"]),
    ("name = 'x'\n[[stage]]\n[stage.parallel]\nteeth = { gear = 80, pinion = 20 }\n"
     "toothing = { module_mm = 5, face_width_mm = 100 }\n[stage.parallel.gear]\n"
     "bearings = [{ name = 'a', rollers = { count = 20, diameter_mm = 30, length_mm = 40, pitch_diameter_mm = 200, "
     "contact = 'point' } }]\n[stage.parallel.pinion]\n",
     ["point contact needs profile_radius_mm and race_profile_radii_mm, or roller_stiffness"]),
    *[("name = 'x'\n[[stage]]\n[stage.parallel]\nteeth = { gear = 80, pinion = 20 }\n"
       "toothing = { module_mm = 5, face_width_mm = 100 }\n[stage.parallel.gear]\n"
       "bearings = [{ name = 'a', rollers = { count = 20, diameter_mm = 30, length_mm = 30, pitch_diameter_mm = 200, "
       f"{extra} }} }}]\n[stage.parallel.pinion]\n", words)
      for extra, words in [
          ("contact = 'point', profile_radius_mm = 15, race_profile_radii_mm = [15.9, 14]",
           ["stage[1].gear.bearings[1].rollers.race_profile_radii_mm", "outer raceway's radius 14 mm must exceed"]),
          ("contact = 'point', profile_radius_mm = 15",
           ["stage[1].gear.bearings[1].rollers", "give profile_radius_mm and race_profile_radii_mm"]),
          ("profile_radius_mm = 15, race_profile_radii_mm = [15.9, 15.9]",
           ["stage[1].gear.bearings[1].rollers", "describe point contact"]),
          ("contact = 'point', profile_radius_mm = 15, race_profile_radii_mm = [15.9, 15.9], roller_stiffness = 1e10",
           ["stage[1].gear.bearings[1].rollers", "not both"]),
          ("contact = 'point', profile_radius_mm = 15, race_profile_radii_mm = [15.9, 15.9], crowning_um = 5",
           ["stage[1].gear.bearings[1].rollers.crowning_um", "describe the roller's crown already"]),
          ("contact = 'point', profile_radius_mm = 15, race_profile_radii_mm = [15.0000000000001, 15.9]",
           ["stage[1].gear.bearings[1].rollers", "a million times longer than wide"]),
          ("contact = 'point', profile_radius_mm = 15, race_profile_radii_mm = [nan, 15.9]",
           ["stage[1].gear.bearings[1].rollers.race_profile_radii_mm", "inner raceway's radius NaN"]),
      ]],
    *[("name = 'x'\n[[stage]]\n[stage.parallel]\nteeth = { gear = 80, pinion = 20 }\n"
       "toothing = { module_mm = 5, face_width_mm = 100 }\n[stage.parallel.gear]\n"
       f"shaft = {{ torsional = 1e7{extra}, beam = {{ {beam} }} }}\n[stage.parallel.pinion]\n", words)
      for extra, beam, words in [
          (", radial = 1e9", "length_m = 1, outer_diameter_mm = 300", ["stage[1].gear.shaft", "a beam or radial"]),
          ("", "length_m = 1, outer_diameter_mm = 300, inner_diameter_mm = 300",
           ["stage[1].gear.shaft.beam.inner_diameter_mm = 300", "below outer_diameter_mm"]),
          ("", "length_m = 0, outer_diameter_mm = 300", ["stage[1].gear.shaft.beam.length_m"]),
          ("", "length_m = 1, outer_diameter_mm = 300, density = 7850", ["unknown field `density`"]),
          ("", "length_m = 1, outer_diameter_mm = 300, elements = 0",
           ["stage[1].gear.shaft.beam.elements = 0", "outside 1..=10"]),
          ("", "length_m = 1, outer_diameter_mm = 300, elements = 11",
           ["stage[1].gear.shaft.beam.elements = 11", "outside 1..=10"]),
          ("", "length_m = 1, outer_diameter_mm = 300, elements = -1", ["elements"]),
      ]],
])
def test_bad_gearbox_description_is_named(windrive, tmp_path, content, words):
    """A description file's mistakes reach the user with the file, the line or the field."""
    path = tmp_path / "my-gearbox.toml"
    path.write_text(content)
    out = subprocess.run([windrive, "modes", "--gearbox", str(path)], capture_output=True, text=True, cwd=ROOT,
                         env={**__import__("os").environ, "RUST_BACKTRACE": "0"})
    assert out.returncode != 0 and "my-gearbox.toml" in out.stderr, out.stderr
    for w in words:
        assert w in out.stderr, out.stderr
    assert "panicked" not in out.stderr


@pytest.mark.parametrize("content,words", [
    ("time,torque\n0,1\n0,2\n", ["line 3", "time 0 does not increase"]),
    ("time,torque\n0,1\n1,x\n", ["line 3", "expected time,torque"]),
    ("time,torque\n0,1\n", ["fewer than two samples"]),
])
def test_bad_rotor_series_is_named(windrive, tmp_path, content, words):
    series = tmp_path / "torque.csv"
    series.write_text(content)
    scene = one_fmu_scene(tmp_path, "rotor")
    out = subprocess.run([windrive, "run", scene, "--step", "0.01", "--stop-time", "0.1", "--out", str(tmp_path / "x.csv"),
                          "--param", "rotor.mode=playback", "--param", f"rotor.series={series}"],
                         capture_output=True, text=True, cwd=ROOT, env={**__import__("os").environ, "RUST_BACKTRACE": "0"})
    assert out.returncode != 0
    assert str(series) in out.stderr, out.stderr
    for w in words:
        assert w in out.stderr, out.stderr


@pytest.mark.parametrize("args,culprit", [
    (["modes", "--preset", "Z"], "Z"),
    (["run", "/nonexistent/scene"], "/nonexistent/scene"),
    (["life", "--normal", "/nonexistent/n.csv", "--channel", "x"], "/nonexistent/n.csv"),
    (["step-response", "--fmu", "/nonexistent/x.fmu", "--out", "/tmp/windrive-x.csv"], "/nonexistent/x.fmu"),
])
def test_user_errors_print_no_backtrace(windrive, tmp_path, args, culprit):
    """Rust users often keep RUST_BACKTRACE set: a user error is still its message and causes only."""
    env = {**__import__("os").environ, "RUST_BACKTRACE": "1", "RUST_LIB_BACKTRACE": "1"}
    out = subprocess.run([windrive, *args], capture_output=True, text=True, cwd=tmp_path, env=env)
    assert out.returncode != 0 and out.stderr.startswith("error: "), out.stderr
    assert "backtrace" not in out.stderr.lower(), out.stderr
    assert culprit in out.stderr, out.stderr


def help_examples(windrive):
    """Every example command line shown in `windrive --help` and the commands' `--help` texts."""
    top = subprocess.run([windrive, "--help"], capture_output=True, text=True, check=True).stdout
    verbs = [line.split()[0] for line in top.split("Commands:")[1].split("Options:")[0].splitlines()
             if line.strip() and line.startswith("  ") and not line.startswith("   ")]
    texts = [top] + [subprocess.run([windrive, v, "--help"], capture_output=True, text=True, check=True).stdout
                     for v in verbs if v != "help"]
    examples = []
    for text in texts:
        for line in text.splitlines():
            words = line.strip().split("  ")[0].split()
            if len(words) > 1 and words[0] == "windrive" and not words[1].startswith("<"):
                examples.append(words[1:])
    return verbs, top, examples


def test_help_examples_exist_and_run(windrive, tmp_path):
    """The main job is in `--help`; every example names a command that exists and scene paths that
    exist; the cheap ones run as shown (a scene for 0.05 s), the others parse (their own --help)."""
    verbs, top, examples = help_examples(windrive)
    assert "windrive shutdown --preset C" in top
    assert len(examples) >= 5, examples
    for args in examples:
        assert args[0] in verbs, args
        for a in args[1:]:
            if a.startswith("scenes/"):
                assert (ROOT / a).exists(), f"--help names {a}, which does not exist"
        if args[0] == "modes":
            extra = []
        elif args[0] == "run":
            extra = ["--stop-time", "0.05", "--out", str(tmp_path / "x.csv"), "--quiet"]
        else:
            extra = ["--help"]
        out = subprocess.run([windrive, *args, *extra], capture_output=True, text=True, cwd=ROOT)
        assert out.returncode == 0, (args, out.stderr)


@pytest.mark.parametrize("blade,polar,words", [
    ("hub_radius_m,1.75\nblades,3\nspan_m,chord_m,twist_deg,airfoil\n0,2,10,p\n30,1\n", None,
     ["blade.csv line 5", "expected 4 fields"]),
    ("hub_radius_m,1.75\nblades,3\nspan_m,chord_m,twist_deg,airfoil\n0,2,10,p\n30,1,0,p\n",
     "alpha_deg,cl,cd\n-180,0,0.5\n0,zero,0.01\n180,0,0.5\n", ["p.csv line 3", "cl = \"zero\" is not a number"]),
    ("hub_radius_m,1.75\nblades,3\nspan_m,chord_m,twist_deg,airfoil\n0,2,10,p\n30,1,0,p\n",
     "alpha_deg,cl,cd\n-20,0,0.5\n20,1,0.01\n", ["p.csv", "-180 to 180"]),
    ("hub_radius_m,1.75\nblades,3\nspan_m,chord_m,twist_deg,airfoil\n0,2,10,p\n30,1,0,p\n", None, ["p.csv", "No such file"]),
])
def test_bad_blade_data_is_named_by_file_and_line(windrive, tmp_path, blade, polar, words):
    """A user blade (parameter blade = an absolute folder) that cannot be read fails the rotor FMU's
    initialisation with fmi2Error, and its log names the file and line (no panic across the C boundary)."""
    folder = tmp_path / "myblade"
    folder.mkdir()
    (folder / "blade.csv").write_text(blade)
    if polar is not None:
        (folder / "p.csv").write_text(polar)
    scene = one_fmu_scene(tmp_path, "rotor")
    out = subprocess.run([windrive, "run", scene, "--step", "0.01", "--stop-time", "0.1", "--out", str(tmp_path / "x.csv"),
                          "--param", f"rotor.blade={folder}"],
                         capture_output=True, text=True, cwd=ROOT, env={**__import__("os").environ, "RUST_BACKTRACE": "0"})
    assert out.returncode != 0
    assert "panicked" not in out.stderr, out.stderr
    for w in words:
        assert w in out.stderr, out.stderr
