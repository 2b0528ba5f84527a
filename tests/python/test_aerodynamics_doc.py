"""docs/AERODYNAMICS.md's numbers about our results, against the commands that give them today.

- "Blades and the presets": the rated-point table row by row (`windrive aero --preset A|B|C|D|P`, the paper's
  1.5 MW nameplate through `--radius 35 --rated-power 1.5e6 --rated-rpm 17.5`, the analytic C_p's column and the
  fitted radii from the rotor FMU with `aerodynamics = analytic`), and the shipped blade's C_P peak over the grid
  the page names;
- "Aerodynamic damping of the parked, feathered rotor": the hand calculation (c_aero from the scaled stations of
  `windrive aero` and the polar files, the BEM's own −∂Q/∂Ω, the held mode of `windrive modes --generator
  locked`, its modal inertia from `windrive bode` far below the mode), the measured decrement of
  tests/it/rotor_aero_damping.rs's parked release and of the shutdown scene in steady wind, both rerun here with
  `windrive run` on c-shutdown-spring and the same overrides, read the way that test reads them.

Each number is formatted as the page prints it and looked for in the page's text (whitespace collapsed)."""

import bisect
import csv
import json
import math
import shutil
import subprocess
import xml.etree.ElementTree as ET

import pytest
from conftest import ROOT

PAGE = ROOT / "docs/AERODYNAMICS.md"
BLADE = ROOT / "fmus/rotor/resources/blades/windpact-1.5mw"
AIR_DENSITY = 1.225
WIND = 16.0  # the shutdown scene's mean wind
SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def text():
    return " ".join(PAGE.read_text().split())


def says(*quoted):
    page = text()
    for q in quoted:
        assert " ".join(q.split()) in page, f"docs/AERODYNAMICS.md should read: {q}"


def json_of(windrive, *args):
    return json.loads(subprocess.run([windrive, *args], check=True, capture_output=True, text=True).stdout)


def sci(x, digits):
    """6.592·10⁶, the page's way."""
    mantissa, exponent = f"{x:.{digits}e}".split("e")
    return f"{mantissa}·10{str(int(exponent)).translate(SUPERSCRIPT)}"


def signed(x, fmt):
    return format(x, fmt).replace("-", "−")


def feather():
    """The rotor FMU's feathered pitch (pitch_max's start value, rad): where the parked rotor stands."""
    root = ET.parse(ROOT / "modelDescription/rotor.xml").getroot()
    v = next(v for v in root.iter("ScalarVariable") if v.get("name") == "pitch_max")
    return float(next(iter(v)).get("start"))


# ---------------------------------------------------------------------------------------------------
# the rated points


def analytic_rotors(windrive):
    """{preset: (radius, rated wind, rated tip-speed ratio)} of the rotor FMU with Heier's analytic C_p."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    path = ROOT / "target/fmu/rotor.fmu"
    if not path.is_file():
        subprocess.run([windrive, "pack", "rotor"], check=True, cwd=ROOT)
    md = read_model_description(str(path))
    unzipped = extract(str(path))
    refs = {v.name: v.valueReference for v in md.modelVariables}
    out = {}
    try:
        for preset in "ABCD":
            s = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=md.coSimulation.modelIdentifier,
                          instanceName="doc")
            s.instantiate()
            s.setupExperiment(startTime=0.0)
            for name, value in [("preset", preset), ("turbulence", "none"), ("aerodynamics", "analytic")]:
                s.setString([refs[name]], [value])
            s.enterInitializationMode()
            s.exitInitializationMode()
            out[preset] = tuple(s.getReal([refs[n]])[0]
                                for n in ("radius_used", "rated_wind_speed", "rated_tip_speed_ratio"))
            s.terminate()
            s.freeInstance()
    finally:
        shutil.rmtree(unzipped, ignore_errors=True)
    return out


def row(label, report, analytic=None):
    r = report["rated"]
    return (f"| {label} | {report['radius_m']:.2f} m | {r['power_w'] / 1e6:g} MW"
            f"{' at the rotor' if label.startswith('P,') else ''}, {r['rotor_speed_rpm']:.2f} rpm | "
            f"{r['wind_m_s']:.2f} m/s | {r['tsr']:.2f} | {r['cp']:.3f} | "
            f"{'—' if analytic is None else f'{analytic:.2f} m/s'} |")


def test_the_rated_point_table_is_the_commands(windrive):
    analytic = analytic_rotors(windrive)
    lines = PAGE.read_text().splitlines()
    expected = [row(p, json_of(windrive, "aero", "--preset", p, "--tsr", "0"), analytic[p][1]) for p in "ABCD"]
    expected.append(row("P, the paper's turbine (WindPACT blade unscaled)",
                        json_of(windrive, "aero", "--preset", "P", "--tsr", "0")))
    expected.append(row("P's rotor at the paper's 1.5 MW nameplate (no preset)",
                        json_of(windrive, "aero", "--radius", "35", "--rated-power", "1.5e6", "--rated-rpm", "17.5",
                                "--tsr", "0")))
    for line in expected:
        assert line in lines, f"docs/AERODYNAMICS.md's rated-point table should have the row: {line}"
    # the radii A, B, D were fitted to: C's rated tip-speed ratio under the analytic C_p
    c_tsr = analytic["C"][2]
    assert all(abs(analytic[p][2] - c_tsr) < 1e-6 for p in "ABD")
    says(f"(C {analytic['C'][0]:.0f} m, thesis; A {analytic['A'][0]:.2f}, B {analytic['B'][0]:.2f}, "
         f"D {analytic['D'][0]:.2f} m: the radii at which Heier's analytic C_p gives rated power at rated speed "
         f"at C's rated tip-speed ratio, {c_tsr:.2f})")
    p = json_of(windrive, "aero", "--preset", "P", "--tsr", "0")["rated"]
    paper = json_of(windrive, "aero", "--radius", "35", "--rated-power", "1.5e6", "--rated-rpm", "17.5", "--tsr", "0")
    says(f"the WindPACT blade reaches {p['power_w'] / 1e3:.0f} kW at {p['wind_m_s']:.2f} m/s",
         f"rated at the **{p['power_w'] / 1e3:.0f} kW at the rotor**", f"At {p['rotor_speed_rpm']:g} rpm",
         f"the nameplate {paper['rated']['power_w'] / 1e6:g} MW on the same rotor")


def test_the_blades_cp_peak_is_the_grids(windrive):
    tsr = [k / 10 for k in range(40, 101)]
    pitch = [k / 2 for k in range(-6, 11)]
    says("λ 4–10 in steps of 0.1, pitch in steps of 0.5°: `windrive aero --tsr 4,4.1,…,10 --pitch=-3,-2.5,…,5`")
    points = json_of(windrive, "aero", "--tsr", ",".join(map(str, tsr)),
                     "--pitch=" + ",".join(map(str, pitch)))["points"]
    best = max(points, key=lambda q: q["cp"])
    fine = max((q for q in points if q["pitch_deg"] == 0.0), key=lambda q: q["cp"])
    says(f"C_P at fine pitch (0°) peaks at {fine['cp']:.3f} at λ = {fine['tsr']:g}; over pitch −3…5° at "
         f"{best['cp']:.3f} at λ = {best['tsr']:g}, β = {best['pitch_deg']:g}°")


# ---------------------------------------------------------------------------------------------------
# the parked, feathered rotor's damping


def polar(name):
    with open(BLADE / f"{name}.csv") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return ([math.radians(float(r["alpha_deg"])) for r in rows], [float(r["cl"]) for r in rows],
            [float(r["cd"]) for r in rows])


def hand_damping(report, pitch):
    """c_aero = ½ρVB∫c(C_lα + C_d)r² dr on the BEM's stations (zero at hub and tip, trapezoidal), C_lα the slope
    of the table segment holding α₀ = 90° − twist − pitch (src/physics/blade/mod.rs's segment rule)."""
    points = [(report["hub_radius_m"], 0.0)]
    for s in report["stations"]:
        alpha, cl, cd = polar(s["airfoil"])
        a0 = math.pi / 2 - math.radians(s["twist_deg"]) - pitch
        i = min(max(bisect.bisect_right(alpha, a0), 1), len(alpha) - 1) - 1
        w = min(max((a0 - alpha[i]) / (alpha[i + 1] - alpha[i]), 0.0), 1.0)
        slope = (cl[i + 1] - cl[i]) / (alpha[i + 1] - alpha[i])
        points.append((s["radius_m"], s["chord_m"] * (slope + cd[i] + w * (cd[i + 1] - cd[i])) * s["radius_m"] ** 2))
    points.append((report["radius_m"], 0.0))
    integral = sum(0.5 * (a[1] + b[1]) * (b[0] - a[0]) for a, b in zip(points, points[1:]))
    return 0.5 * AIR_DENSITY * WIND * report["blades"] * integral


def bem_damping(windrive, pitch_deg, radius, h=1e-4):
    """The BEM's own −∂Q/∂Ω at Ω = 0, central difference over ±h rad/s."""
    lam = h * radius / WIND
    a, b = json_of(windrive, "aero", "--preset", "C", "--pitch", repr(pitch_deg), "--wind", str(WIND),
                   "--tsr", f"{lam!r},{-lam!r}")["points"]
    return -(a["torque_nm"] - b["torque_nm"]) / (a["rotor_speed_rad_s"] - b["rotor_speed_rad_s"])


def held_mode(windrive):
    """(f Hz, modal inertia J kg·m²) of drivetrain C's lowest HSS-locked mode. J = 1/x_rotor² of the M-orthonormal
    shape, read from the rotor's receptance far below the mode, where that mode's term ω/(Jω₁²) is all of it (the
    others' rotor entries are 1e-5 of its)."""
    f = json_of(windrive, "modes", "--preset", "C", "--generator", "locked", "--json")["frequencies_hz"][0]
    b = json_of(windrive, "bode", "--preset", "C", "--generator", "locked", "--input", "rotor",
                "--output", "rotor-speed", "--range", "1e-4,1e-3", "--points", "2", "--json")
    w1 = 2 * math.pi * f
    return f, 2 * math.pi * b["frequency_hz"][0] / (b["magnitude"][0] * w1 ** 2)


def decrement_of(w_of, t, w, n=3):
    """tests/it/rotor_aero_damping.rs's reading: positive rotor-speed maxima (parabola through three samples),
    those above 1 % of the first among the first n + 1; mean ln ratio per period and the mean period."""
    peaks = []
    for k in range(1, len(w) - 1):
        if w[k] > w[k - 1] and w[k] >= w[k + 1]:
            a, b, c = w[k - 1], w[k], w[k + 1]
            d = 0.5 * (a - c) / (a - 2 * b + c)
            peaks.append((t[k] + d * (t[k + 1] - t[k]), b - 0.25 * (a - c) * d))
    peaks = [p for p in peaks if p[1] > 0]
    used = [p for p in peaks[:n + 1] if p[1] > 0.01 * peaks[0][1]]
    k = len(used) - 1
    assert k >= 2, f"{w_of}: the rocking died within {k} periods"
    return math.log(used[0][1] / used[k][1]) / k, (used[k][0] - used[0][0]) / k


@pytest.fixture(scope="module")
def scene(windrive, tmp_path_factory):
    """c-shutdown-spring with the FMUs of target/fmu (the scene's resources/ may hold older ones)."""
    dest = tmp_path_factory.mktemp("aero-doc") / "c-shutdown-spring"
    shutil.copytree(ROOT / "scenes/c-shutdown-spring", dest, ignore=shutil.ignore_patterns("resources"))
    (dest / "resources").mkdir()
    for name in ("rotor", "torsional", "generator"):
        fmu = ROOT / "target/fmu" / f"{name}.fmu"
        if not fmu.is_file():
            subprocess.run([windrive, "pack", name], check=True, cwd=ROOT)
        shutil.copy(fmu, dest / "resources")
    return dest


def run(windrive, scene, name, params, stop=None):
    """The scene through the master (Gauss–Seidel, its 1 ms step): {channel: series} of the recorded ones."""
    out = scene.parent / f"{name}.csv"
    args = [windrive, "run", str(scene), "--quiet", "--out", str(out),
            "--record", "torsional.rotor_speed,torsional.brake_locked,rotor.pitch"]
    if stop is not None:
        args += ["--stop-time", str(stop)]
    for p in params:
        args += ["--param", p]
    subprocess.run(args, check=True, capture_output=True)
    with open(out, newline="") as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]}


def parked(windrive, scene, aerodynamics):
    """Parked at feather from t = 0 in steady 16 m/s, brake holding, only the blades damping (the Rust test's
    overrides); the rotor speed from the lock on."""
    s = run(windrive, scene, f"parked-{aerodynamics}", [
        f"rotor.aerodynamics={aerodynamics}", "rotor.turbulence=none", "rotor.wind_speed=16",
        f"rotor.initial_pitch={feather()!r}", "rotor.shutdown_time=0", "rotor.trip_delay=0", "rotor.brake_delay=0",
        "rotor.brake_ramp_time=0", "torsional.initial_speed_ratio=0", "torsional.initial_rotor_torque=0",
        "torsional.damping_scale=0", "generator.initial_torque=0", "generator.synchronous_speed=1e-9"], stop=6)
    lock = next(k for k, x in enumerate(s["torsional.brake_locked"]) if x > 0.5)
    assert s["time"][lock] < 0.05 and all(x > 0.5 for x in s["torsional.brake_locked"][lock:])
    return s["time"][lock:], s["torsional.rotor_speed"][lock:]


def test_the_hand_calculation_and_the_measured_decrement(windrive, scene):
    pitch = feather()
    report = json_of(windrive, "aero", "--preset", "C", "--tsr", "0", "--pitch", repr(math.degrees(pitch)),
                     "--wind", str(WIND))
    c_hand = hand_damping(report, pitch)
    c_bem = bem_damping(windrive, math.degrees(pitch), report["radius_m"])
    # the page's command, at 90° rather than the FMU's 1.570796 rad, prints the same
    assert sci(bem_damping(windrive, 90.0, report["radius_m"]), 3) == sci(c_bem, 3)
    f, j = held_mode(windrive)
    omega = 2 * math.pi * f

    def one_dof(c):
        """(ζ, δ) of the 1-DOF mode: ζ = c/(2Jω), δ = 2πζ/√(1 − ζ²)."""
        z = c / (2 * j * omega)
        return z, 2 * math.pi * z / math.sqrt(1 - z * z)

    zeta, delta_hand = one_dof(c_hand)
    _, delta_bem = one_dof(c_bem)
    says(f"c_aero = {sci(c_hand, 3)} N·m·s/rad",
         f"at ±10⁻⁴ rad/s: {sci(c_bem, 3)}, {100 * (1 - c_bem / c_hand):.0f} % lower",
         f"stiffness at the HSS-locked mode ({f:.3f} Hz)",
         f"f = {f:.4f} Hz, ω = {omega:.3f} rad/s", f"J = 1/x_rotor² = {sci(j, 3)} kg·m²",
         f"ζ = c_aero/(2Jω) = {zeta:.4f}, δ = 2πζ/√(1 − ζ²) = **{delta_hand:.3f}**; "
         f"damped period {2 * math.pi / (omega * math.sqrt(1 - zeta ** 2)):.4f} s")

    t, w = parked(windrive, scene, "bem")
    delta, period = decrement_of("bem", t, w)
    tip_sweep = math.degrees(max(map(abs, w)) * report["radius_m"] / WIND)
    says(f"**δ = {delta:.4f}** ({signed(100 * (delta / delta_hand - 1), '.1f')} % from the hand value; "
         f"{signed(100 * (delta / delta_bem - 1), '.2f')} % from the 1-DOF formula with the BEM's own slope, "
         f"{delta_bem:.3f}), damped period {period:.4f} s",
         f"the rocking sweeps α by ±{tip_sweep:.2f}° at the tip")
    t, w = parked(windrive, scene, "analytic")
    delta_analytic, _ = decrement_of("analytic", t, w)
    assert abs(delta_analytic) < 5e-5
    says("With `aerodynamics = analytic` the same release gives δ = 0.0000.")


def test_the_shutdown_scenes_decay_in_steady_wind(windrive, scene):
    """tests/it/rotor_aero_damping.rs's second test: c-shutdown-spring with the BEM rotor, the trimmed start pitch
    and no turbulence; δ and the amplitude from the moment the brake holds and the blades are feathered."""
    s = run(windrive, scene, "shutdown-steady",
            ["rotor.aerodynamics=bem", "rotor.initial_pitch=-1", "rotor.turbulence=none"])
    lock = next(k for k, x in enumerate(s["torsional.brake_locked"]) if x > 0.5)
    at_feather = feather() - 1e-9
    feathered = next(k for k, p in enumerate(s["rotor.pitch"]) if p >= at_feather)
    start = max(lock, feathered)
    t, w = s["time"][start:], s["torsional.rotor_speed"][start:]
    delta, _ = decrement_of("shutdown", t, w)

    def amplitude(a, b):
        return max(abs(x) for x, tt in zip(w, t) if a <= tt < b)

    first, later = amplitude(t[0], t[0] + 1.3), amplitude(t[0] + 5.0, t[0] + 6.3)
    says(f"the blades still pitching until {s['time'][feathered]:.1f} s): δ = {delta:.3f} once held and feathered, "
         f"rocking amplitude {sci(first, 1)} → {sci(later, 1)} rad/s within 5 s")
