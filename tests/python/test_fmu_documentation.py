"""The numbers the FMUs' documentation quotes, against what the packed FMUs and the windrive binary
compute today (issue 35 §8, "documentation from one source").

Each test reads a number from the sentence or table of fmus/<name>/documentation.html, or from a
`description` attribute of modelDescription/<name>.xml, where the documentation prints it, and
compares it with the FMU (instantiated in fmpy with that preset, its calculated parameters read) or
with `windrive ... --json`, within the rounding the documentation prints it with. The patterns are
written against those sentences: a reworded sentence fails loudly ("the documentation no longer
says ...") rather than passing unchecked; change the pattern with the sentence.

The second half checks the default values the documentation.html files quote for a parameter
against the parameter's start value in modelDescription/<name>.xml, and that every "default" in
them is one of those checked.
"""

import html
import json
import math
import pathlib
import re
import subprocess
import sys
import tomllib
import xml.etree.ElementTree as ET

import pytest
from packed_fmu import packed

ROOT = pathlib.Path(__file__).resolve().parents[2]
PRESETS = "ABCD"
AIR_DENSITY = 1.225


# ---------------------------------------------------------------------------------------------------
# reading the documentation


def raw_html(fmu):
    return (ROOT / "fmus" / fmu / "documentation.html").read_text(encoding="utf-8")


def plain(text):
    """Text without tags and entities, whitespace collapsed: what a reader sees."""
    text = re.sub(r"<[^>]+>", "", text)
    return re.sub(r"\s+", " ", html.unescape(text)).strip()


def doc(fmu):
    return plain(raw_html(fmu))


def xml_variables(fmu):
    """name -> (description, start as written, or None) of modelDescription/<fmu>.xml."""
    root = ET.parse(ROOT / "modelDescription" / f"{fmu}.xml").getroot()
    out = {}
    for v in root.iter("ScalarVariable"):
        typed = next(iter(v))
        out[v.get("name")] = (v.get("description", ""), typed.get("start"))
    return out


def description(fmu, name):
    return plain(xml_variables(fmu)[name][0])


def one(pattern, text, where):
    """The one match of `pattern` in `text`: a sentence reworded or duplicated fails here."""
    found = list(re.finditer(pattern, text))
    assert len(found) == 1, (
        f"{where}: expected exactly one match of {pattern!r}, found {len(found)}; the documentation was "
        "reworded, so update this test's pattern with it (and check the numbers it quotes)"
    )
    return found[0]


def quoted(number):
    """A number as the documentation prints it (spaces between thousands, e-notation) and half a
    unit of its last printed digit."""
    s = re.sub(r"[\s\u202f\u2009\xa0]", "", number).replace("−", "-")
    m = re.fullmatch(r"-?\d+(?:\.(\d+))?(?:e([-+]?\d+))?", s)
    assert m, f"{number!r} is not a number as the documentation prints them"
    return float(s), 0.5 * 10.0 ** (int(m.group(2) or 0) - len(m.group(1) or ""))


def check(number, value, what):
    """The printed `number` is `value` rounded as printed."""
    q, tol = quoted(number)
    assert abs(q - value) <= tol * (1 + 1e-9) + 1e-12, (
        f"{what}: the documentation says {number}, the code gives {value:.6g}"
    )


# ---------------------------------------------------------------------------------------------------
# asking the FMUs and the binary


@pytest.fixture(scope="module")
def fmus(windrive):
    yield from packed(windrive, ("rotor", "generator", "torsional", "gearbox6dof"))


def rotor(fmus, preset, **start):
    start = {"preset": preset, "turbulence": "none", **start}
    return fmus["rotor"].read(start, ["radius_used", "rated_wind_speed", "rated_rotor_torque",
                                      "rated_tip_speed_ratio"])


def rated_rotor_speed(r):
    """rad/s, from the rotor FMU's rated point: λ V / R."""
    return r["rated_tip_speed_ratio"] * r["rated_wind_speed"] / r["radius_used"]


def rpm(omega):
    return omega * 30.0 / math.pi


def modes(windrive, *args):
    out = subprocess.run([windrive, "modes", *args, "--json"], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def lowest(freqs):
    return next(f for f in freqs if f > 1e-3)


# ---------------------------------------------------------------------------------------------------
# rotor


def test_rotor_radii_rated_winds_and_design_tip_speed_ratio(fmus):
    """The analytic-C_p design rule: C's rated tip-speed ratio, and A, B, D's radii and rated winds."""
    text = doc("rotor")
    m = one(r"Rotor radius: C (\S+) m \(thesis: 80 m rotor; with the analytic C_p it reaches rated power at rated "
            r"speed at (\S+) m/s, tip-speed ratio (\S+)\)\. A, B and D: the radius that gives rated power at rated "
            r"speed at the same tip-speed ratio under the analytic C_p \(A (\S+) m, B (\S+) m, D (\S+) m; rated wind "
            r"(\S+), (\S+), (\S+) m/s\)", text, "rotor documentation.html, Numbers that are estimates")
    c = rotor(fmus, "C", aerodynamics="analytic")
    check(m[1], c["radius_used"], "C's radius")
    check(m[2], c["rated_wind_speed"], "C's rated wind, analytic C_p")
    check(m[3], c["rated_tip_speed_ratio"], "C's rated tip-speed ratio, analytic C_p")
    for k, p in enumerate("ABD"):
        r = rotor(fmus, p, aerodynamics="analytic")
        check(m[4 + k], r["radius_used"], f"{p}'s radius")
        check(m[7 + k], r["rated_wind_speed"], f"{p}'s rated wind, analytic C_p")
        # the design rule itself: every preset at C's tip-speed ratio
        assert r["rated_tip_speed_ratio"] == pytest.approx(c["rated_tip_speed_ratio"], rel=1e-6), p

    x = one(r"\(0 = the preset's: C (\S+) m, thesis Table 3\.1; P (\S+) m, the paper's 70 m rotor; A, B, D the radius "
            r"that reaches rated power at rated speed at C's rated tip-speed ratio under the analytic power "
            r"coefficient, (\S+): (\S+), (\S+), (\S+) m\)", description("rotor", "radius"), "rotor.xml radius")
    check(x[1], c["radius_used"], "C's radius (rotor.xml)")
    check(x[2], rotor(fmus, "P")["radius_used"], "P's radius (rotor.xml)")
    check(x[3], c["rated_tip_speed_ratio"], "C's rated tip-speed ratio (rotor.xml)")
    for k, p in enumerate("ABD"):
        check(x[4 + k], rotor(fmus, p)["radius_used"], f"{p}'s radius (rotor.xml)")


def test_rotor_bem_rated_point(fmus, windrive):
    """The scaled WindPACT blade's rated wind, tip-speed ratio and power coefficient per preset."""
    m = one(r"BEM: A (\S+), B (\S+), C (\S+), D (\S+) m/s, all at λ = (\S+), C_P = (\S+) \(P: (\S+) m/s at λ = (\S+)\)\.",
            doc("rotor"), "rotor documentation.html, Rated point")
    for k, p in enumerate(PRESETS):
        r = rotor(fmus, p)
        check(m[1 + k], r["rated_wind_speed"], f"{p}'s rated wind, BEM")
        check(m[5], r["rated_tip_speed_ratio"], f"{p}'s rated tip-speed ratio, BEM")
        power = r["rated_rotor_torque"] * rated_rotor_speed(r)
        cp = power / (0.5 * AIR_DENSITY * math.pi * r["radius_used"] ** 2 * r["rated_wind_speed"] ** 3)
        check(m[6], cp, f"{p}'s rated C_P, BEM")
    p = rotor(fmus, "P")
    check(m[7], p["rated_wind_speed"], "P's rated wind, BEM")
    check(m[8], p["rated_tip_speed_ratio"], "P's rated tip-speed ratio, BEM")
    # the binary's blade-element report fits the same rated point
    out = subprocess.run([windrive, "aero", "--preset", "C", "--tsr", "7"], check=True, capture_output=True, text=True)
    rated = json.loads(out.stdout)["rated"]
    check(m[3], rated["wind_m_s"], "C's rated wind, windrive aero")
    check(m[6], rated["cp"], "C's rated C_P, windrive aero")


def test_rotor_preset_p(fmus):
    m = one(r"on the Fatigue Damage of Wind Turbine Gearboxes, its Tables 1–3 and Fig\. 3\): (\S+) m rotor, (\S+) m hub, "
            r"(\S+) rpm, (\S+) kW at the rotor \(its mean power above rated\); the WindPACT blade at (\S+) m then reaches "
            r"rated power at (\S+) m/s", doc("rotor"), "rotor documentation.html, Preset P")
    p = rotor(fmus, "P")
    check(m[1], 2 * p["radius_used"], "P's rotor diameter")
    check(m[3], rpm(rated_rotor_speed(p)), "P's rated rotor speed")
    check(m[4], p["rated_rotor_torque"] * rated_rotor_speed(p) / 1e3, "P's rated power")
    check(m[5], p["radius_used"], "P's blade radius")
    check(m[6], p["rated_wind_speed"], "P's rated wind")
    assert m[2] == "80"  # the hub height: test_rotor_hub_heights


def hub_heights_from(sentence, where):
    """{preset: metres} from 'A, B 90 m, C 80 m, D 55 m ... P 80 m'."""
    heights = {}
    for names, metres in re.findall(r"((?:[A-DP], )*[A-DP]) (\d+) m", sentence):
        for p in names.split(", "):
            heights[p] = metres
    assert sorted(heights) == list("ABCDP"), f"{where}: hub heights of {sorted(heights)}"
    return heights


def test_rotor_hub_heights(fmus):
    """Hub height 0 is the preset's: the same tilt moment as that height given explicitly (the thrust's
    offset above the hub under shear depends on it)."""
    in_doc = hub_heights_from(one(r"Hub heights are estimates \(([^)]*)\)", doc("rotor"), "rotor documentation.html")[1],
                              "rotor documentation.html")
    in_xml = hub_heights_from(one(r"\(0 = the preset's: ([^)]*)\)", description("rotor", "hub_height"), "rotor.xml")[1],
                              "rotor.xml hub_height")
    assert in_doc == in_xml
    for p, metres in in_doc.items():
        base = {"preset": p, "turbulence": "none", "shear_exponent": 0.2}
        r = rotor(fmus, p)
        speed = rated_rotor_speed(r)
        ask = ["pitching_moment", "thrust"]
        default = fmus["rotor"].read({**base, "rotor_speed": speed}, ask)
        given = fmus["rotor"].read({**base, "rotor_speed": speed, "hub_height": float(metres)}, ask)
        other = fmus["rotor"].read({**base, "rotor_speed": speed, "hub_height": float(metres) + 10}, ask)
        assert default["thrust"] > 0
        assert default["pitching_moment"] == pytest.approx(given["pitching_moment"], rel=1e-12), p
        assert abs(other["pitching_moment"] / default["pitching_moment"] - 1) > 1e-3, "the check cannot see the hub"


def test_rotor_d_real_radius_never_reaches_rated_power(fmus, capsys):
    m = one(r"with (\S+) m this C_p never reaches (\S+) kW at D's rated (\S+) rpm", doc("rotor"),
            "rotor documentation.html")
    d = rotor(fmus, "D", aerodynamics="analytic")
    check(m[2], d["rated_rotor_torque"] * rated_rotor_speed(d) / 1e3, "D's rated power")
    check(m[3], rpm(rated_rotor_speed(d)), "D's rated rotor speed")
    with pytest.raises(Exception):
        rotor(fmus, "D", aerodynamics="analytic", radius=float(m[1]))
    assert "never reaches rated power" in capsys.readouterr().out


def test_rotor_shipped_series_units(fmus):
    m = one(r"They were written per unit of (\S+ \S+ \S+) N·m, C's rated rotor torque when its rated speed was "
            r"Table 4\.1's (\S+) rpm; the FMU multiplies them by the preset's rated rotor torque of today \(C: "
            r"(\S+ \S+ \S+) N·m at (\S+) rpm\), so a played-back series loads C (\S+) % less than the run that made it\.",
            doc("rotor"), "rotor documentation.html, Shipped series")
    old = 2e6 / (float(m[2]) * math.pi / 30)
    check(m[1], old, "C's rated torque at Table 4.1's speed")
    for name in ("c-normal-pu.csv", "c-shutdown-pu.csv"):
        header = (ROOT / "fmus" / "rotor" / "resources" / name).read_text().splitlines()[0]
        check(one(r"per unit of (\S+) N\.m", header, name)[1], old, f"{name}'s header")
    c = rotor(fmus, "C")
    check(m[3], c["rated_rotor_torque"], "C's rated rotor torque")
    check(m[4], rpm(rated_rotor_speed(c)), "C's rated rotor speed")
    check(m[5], 100 * (1 - c["rated_rotor_torque"] / old), "the playback's change")


def test_rotor_turbulence_classes(fmus):
    m = one(r"\(I_ref (\S+), (\S+), (\S+)\); the ETM also takes V_ref = (\S+) m/s", description("rotor", "turbulence_class"),
            "rotor.xml turbulence_class")
    v = 10.0
    for k, cls in enumerate("ABC"):
        sigma = fmus["rotor"].read({"preset": "C", "wind_speed": v, "turbulence": "ntm", "turbulence_class": cls},
                                   ["turbulence_sigma"])["turbulence_sigma"]
        check(m[1 + k], sigma / (0.75 * v + 5.6), f"class {cls}'s I_ref")
    etm = fmus["rotor"].read({"preset": "C", "wind_speed": v, "turbulence": "etm", "turbulence_class": "A"},
                             ["turbulence_sigma"])["turbulence_sigma"]
    c, i_ref = 2.0, float(m[1])
    v_ref = ((etm / (c * i_ref) - 10) / (0.072 * (v / c - 4)) - 3) * c / 0.2
    check(m[4], v_ref, "the ETM's V_ref")


# ---------------------------------------------------------------------------------------------------
# generator


def generator(fmus, preset, kind, **start):
    return fmus["generator"].read({"preset": preset, "kind": kind, **start},
                                  ["stiffness_used", "synchronous_speed_used", "equivalent_stiffness",
                                   "equivalent_damping", "rated_torque", "generator_torque"])


def table_4_1_rotor_rpm():
    """Thesis Table 4.1's rated rotor speeds as the code keeps them (physics::drivetrain)."""
    src = (ROOT / "src" / "physics" / "drivetrain.rs").read_text()
    body = one(r"pub const TABLE_4_1_RATED_RPM: \[\(&str, f64\); 4\] = \[([^\]]*)\];", src, "drivetrain.rs")[1]
    speeds = {p: float(n) for p, n in re.findall(r'\("([A-D])", ([\d.]+)\)', body)}
    assert sorted(speeds) == list(PRESETS)
    return speeds


def test_generator_rated_speeds_and_torques(fmus):
    """The presets' rated generator speeds are Table 4.6's (the spring's field turns at them) and the
    rated torques follow; Table 4.1's rotor speeds times the gear ratio, as the doc compares them."""
    m = one(r"The rated generator speeds are the thesis's Table 4\.6, the speeds its own simulations ran at: A (\S+), "
            r"B (\S+), C (\S+), D (\S+) rpm; the presets' rated rotor speeds are these over the gear ratio, so the "
            r"drivetrain starts in equilibrium \(docs/DRIVETRAINS\.md in the repository\)\. Table 4\.1's rotor speeds "
            r"would imply (\S+), (\S+), (\S+) and (\S+) rpm\. P: the paper's (\S+) rpm × (\S+) = (\S+) rpm\. Rated "
            r"generator torque \(rated_torque\): A (\S+ \S+), B (\S+ \S+), C (\S+ \S+), D (\S+ \S+) N·m\.",
            doc("generator"), "generator documentation.html, Numbers")
    table_4_1 = table_4_1_rotor_rpm()
    for k, p in enumerate(PRESETS):
        g = generator(fmus, p, "spring")
        ratio = fmus["torsional"].read({"preset": p}, ["gear_ratio"])["gear_ratio"]
        check(m[1 + k], rpm(g["synchronous_speed_used"]), f"{p}'s rated generator speed")
        check(m[5 + k], table_4_1[p] * ratio, f"{p}'s Table 4.1 rotor speed × gear ratio")
        check(m[12 + k], g["rated_torque"], f"{p}'s rated generator torque")
    p = generator(fmus, "P", "spring")
    ratio = fmus["torsional"].read({"preset": "P"}, ["gear_ratio"])["gear_ratio"]
    check(m[9], rpm(p["synchronous_speed_used"]) / ratio, "P's rated rotor speed")
    check(m[10], ratio, "P's gear ratio")
    check(m[11], rpm(p["synchronous_speed_used"]), "P's rated generator speed")


def test_generator_synchronous_speeds_and_poles(fmus):
    m = one(r"fixed and dfig at the grid's, 2π·frequency/\(poles/2\): (\S+) rpm for B–D's (\d+) poles on (\S+) Hz "
            r"\(D's cage machine reaches its rated torque at (\S+) rpm, its rated slip with R_r = (\S+) pu\)",
            doc("generator"), "generator documentation.html, Synchronous speed")
    x = one(r"\(0 = the preset's: A (\d+), B-D and P (\d+)\)", description("generator", "poles"), "generator.xml poles")
    assert m[2] == x[2]
    variables = xml_variables("generator")
    check(m[3], float(variables["frequency"][1]), "the grid frequency's start value")
    check(m[5], float(variables["rotor_resistance"][1]), "R_r's start value")
    for p in "BCDP":
        for kind in ("fixed", "dfig"):
            check(m[1], rpm(generator(fmus, p, kind)["synchronous_speed_used"]), f"{p} {kind}'s synchronous speed")
    # A's 10 poles on the same grid
    a = generator(fmus, "A", "fixed")["synchronous_speed_used"]
    assert a == pytest.approx(2 * math.pi * float(m[3]) / (int(x[1]) / 2), rel=1e-12)
    # D's cage machine: the speed at which it delivers its rated torque
    rated = generator(fmus, "D", "spring")["rated_torque"]
    lo, hi = 1800.0, 1900.0
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        torque = generator(fmus, "D", "fixed", generator_speed=mid * math.pi / 30)["generator_torque"]
        lo, hi = (mid, hi) if torque < rated else (lo, mid)
    check(m[4], lo, "D's rated speed as a cage machine")


def test_generator_spring_stiffness(fmus):
    m = one(r"stiffness = 0 takes the preset's K_gen: (\S+) N·m/rad for D \(thesis, after Mandic et al\.\); "
            r"A–C estimated at D's per-unit value, K_gen/T_rated = (\S+) /rad: A (\S+), B (\S+), C (\S+) N·m/rad\.",
            doc("generator"), "generator documentation.html, spring")
    x = one(r"\(0 = the preset's: (\S+) for D, thesis; A-C estimated at D's per-unit value\)",
            description("generator", "stiffness"), "generator.xml stiffness")
    d = generator(fmus, "D", "spring")
    check(m[1], d["stiffness_used"], "D's K_gen")
    check(x[1], d["stiffness_used"], "D's K_gen (generator.xml)")
    check(m[2], d["stiffness_used"] / d["rated_torque"], "K_gen per unit of rated torque")
    for k, p in enumerate("ABC"):
        check(m[3 + k], generator(fmus, p, "spring")["stiffness_used"], f"{p}'s K_gen")


def test_generator_equivalent_stiffness(fmus):
    """The cage machine's linearised stiffness at 1 % slip, and the controlled kinds' at rated speed,
    at the default stiffness_frequency."""
    m = one(r"A cage machine at 1 % slip \(generating, 1 % above synchronous speed\): K = (\S+) \(C\) and (\S+) N·m/rad "
            r"\(D\) at (\S+) Hz beside D's K_gen (\S+), and mostly a damper at low frequency; the controlled kinds at "
            r"rated speed are nearly transparent \(\|K\| from (\S+) to (\S+) N·m/rad\)\.",
            doc("generator"), "generator documentation.html, equivalent_stiffness")
    check(m[3], float(xml_variables("generator")["stiffness_frequency"][1]), "stiffness_frequency's start value")
    for k, p in enumerate("CD"):
        sync = generator(fmus, p, "fixed")["synchronous_speed_used"]
        check(m[1 + k], generator(fmus, p, "fixed", generator_speed=1.01 * sync)["equivalent_stiffness"],
              f"{p}'s cage machine at 1 % slip")
    check(m[4], generator(fmus, "D", "spring")["stiffness_used"], "D's K_gen")
    controlled = []
    for p in PRESETS:
        rated = generator(fmus, p, "spring")["synchronous_speed_used"]
        for kind in ("dfig", "pmg"):
            controlled.append(abs(generator(fmus, p, kind, generator_speed=rated)["equivalent_stiffness"]))
    check(m[5], min(controlled), "the most transparent controlled kind")
    check(m[6], max(controlled), "the least transparent controlled kind")


# ---------------------------------------------------------------------------------------------------
# torsional


def test_torsional_preset_table(fmus, windrive):
    text = raw_html("torsional")
    table = one(r"<h2>Presets</h2>.*?<table>(.*?)</table>", text.replace("\n", " "), "torsional documentation.html")[1]
    rows = [[plain(c) for c in re.findall(r"<t[dh]>(.*?)</t[dh]>", r)] for r in re.findall(r"<tr>(.*?)</tr>", table)]
    assert rows[0] == ["preset", "rated power", "rated rotor speed", "gear ratio", "rated rotor torque",
                       "rated generator torque", "DOF (full)", "free–free mode"], rows[0]
    assert [r[0] for r in rows[1:]] == list("ABCDP")

    def unit(cell, suffix):
        assert cell.endswith(" " + suffix), f"{cell!r}: expected {suffix}"
        return cell[: -len(suffix) - 1]

    for p, power, speed, ratio, torque, gen_torque, dof, mode in rows[1:]:
        t = fmus["torsional"].read({"preset": p, "fidelity": "full"},
                                   ["gear_ratio", "rated_rotor_torque", "rated_generator_torque", "dof_count"])
        omega = generator(fmus, p, "spring")["synchronous_speed_used"] / t["gear_ratio"]
        check(unit(power, "MW"), t["rated_rotor_torque"] * omega / 1e6, f"{p}'s rated power")
        check(unit(speed, "rpm"), rpm(omega), f"{p}'s rated rotor speed")
        check(ratio, t["gear_ratio"], f"{p}'s gear ratio")
        check(unit(torque, "kN·m"), t["rated_rotor_torque"] / 1e3, f"{p}'s rated rotor torque")
        check(unit(gen_torque, "N·m"), t["rated_generator_torque"], f"{p}'s rated generator torque")
        assert int(dof) == t["dof_count"], f"{p}'s DOF: documentation {dof}, FMU {t['dof_count']}"
        free = modes(windrive, "--preset", p, "--fidelity", "full", "--generator", "disconnected")["frequencies_hz"]
        check(unit(mode, "Hz"), lowest(free), f"{p}'s free–free mode")
        # the rotor FMU carries the same rated point
        check(unit(torque, "kN·m"), rotor(fmus, p)["rated_rotor_torque"] / 1e3, f"{p}'s rated rotor torque (rotor FMU)")
    # and the full fidelity's DOF as the fidelity list and torsional.xml say
    dofs = {r[0]: int(r[6]) for r in rows[1:]}
    one(r"full: one DOF per body \(11 for C and D: rotor, carrier, 3 planets, sun, 2 gears, 2 pinions, generator\)",
        doc("torsional"), "torsional documentation.html, Fidelity")
    one(r"one DOF per component: 11 for C and D\)", description("torsional", "fidelity"), "torsional.xml fidelity")
    assert dofs["C"] == dofs["D"] == 11


def test_torsional_fidelities_agree_on_the_lowest_mode(windrive):
    m = one(r"they agree on the static torque split exactly and on the lowest mode within (\S+) % \(2 vs 5\) and "
            r"(\S+) % \(5 vs full", doc("torsional"), "torsional documentation.html, Fidelity")
    worst_2_5, worst_5_full = 0.0, 0.0
    for p in PRESETS:
        for g in ("connected", "disconnected", "locked"):
            f = {fid: lowest(modes(windrive, "--preset", p, "--fidelity", fid, "--generator", g)["frequencies_hz"])
                 for fid in ("2", "5", "full")}
            worst_2_5 = max(worst_2_5, abs(f["2"] / f["5"] - 1))
            worst_5_full = max(worst_5_full, abs(f["full"] / f["5"] - 1))
    assert 100 * worst_2_5 <= float(m[1]), f"2 vs 5: {100 * worst_2_5:.2f} %"
    assert 100 * worst_5_full <= float(m[2]), f"5 vs full: {100 * worst_5_full:.2f} %"


def test_torsional_planet_spin_moves_ds_fourth_mode(windrive):
    m = one(r"it moves D's fourth 5-mass mode from (\S+) to (\S+) Hz", doc("torsional"), "torsional documentation.html")
    args = ["--preset", "D", "--fidelity", "5", "--generator", "disconnected"]
    thesis = [f for f in modes(windrive, *args, "--lumping", "thesis")["frequencies_hz"] if f > 1e-3]
    physical = [f for f in modes(windrive, *args)["frequencies_hz"] if f > 1e-3]
    check(m[1], thesis[2], "D's fourth 5-mass mode, thesis lumping")
    check(m[2], physical[2], "D's fourth 5-mass mode, physical lumping")


def test_torsional_rk4_limit_and_brake(fmus):
    m = one(r"\(rk4_step_limit, ≈ (\S+) µs for D at full fidelity\)", doc("torsional"), "torsional documentation.html")
    d = fmus["torsional"].read({"preset": "D", "fidelity": "full"}, ["rk4_step_limit", "rated_generator_torque"])
    check(m[1], d["rk4_step_limit"] * 1e6, "D's RK4 step limit")
    b = one(r"applies brake_command × brake_torque_max against the motion \(0 = (\S+) × the preset's rated generator "
            r"torque\)", doc("torsional"), "torsional documentation.html, HSS brake")
    x = one(r"\(0 = (\S+) x rated generator torque of the preset\)", description("torsional", "brake_torque_max"),
            "torsional.xml brake_torque_max")
    assert b[1] == x[1]
    assert xml_variables("torsional")["brake_torque_max"][1] == "0"
    # slipping at rated speed with the full command, the brake gives its kinetic torque
    out = fmus["torsional"].step({"preset": "D", "fidelity": "full", "brake_command": 1.0}, 1e-3, ["brake_torque"])
    check(b[1], out["brake_torque"] / d["rated_generator_torque"], "the default brake torque / rated")


# ---------------------------------------------------------------------------------------------------
# gearbox6dof


def gearbox_presets():
    return sorted(p.stem for p in (ROOT / "fmus" / "gearbox6dof" / "resources").glob("*.toml"))


def test_gearbox_presets_and_slices(fmus):
    listed = one(r"The presets ship as files in this FMU's resources/ to copy and edit: (\S+) \(NREL GRC 750 kW, "
                 r"drivetrain D\), (\S+), (\S+), (\S+) and (\S+) \(one stage on its own\)\.",
                 doc("gearbox6dof"), "gearbox6dof documentation.html")
    names = list(listed.groups())
    x = one(r"a preset \(([^)]*)\)", description("gearbox6dof", "gearbox"), "gearbox6dof.xml gearbox")[1]
    assert sorted(names) == sorted(x.split(", ")) == gearbox_presets()
    for name in names:
        assert fmus["gearbox6dof"].read({"gearbox": name}, ["gear_ratio"])["gear_ratio"] > 1, name
    slices = {name: tomllib.loads((ROOT / "fmus" / "gearbox6dof" / "resources" / f"{name}.toml").read_text())
              ["model"]["slices"] for name in names}
    for where, text in [("gearbox6dof documentation.html", doc("gearbox6dof")),
                        ("gearbox6dof.xml slices", description("gearbox6dof", "slices"))]:
        m = one(r"(\d+) in the drivetrain presets, (\d+) in planetary-spur", text, where)
        assert slices["planetary-spur"] == int(m[2]), (where, slices)
        assert {n for k, n in slices.items() if k != "planetary-spur"} == {int(m[1])}, (where, slices)
    grc = tomllib.loads((ROOT / "fmus" / "gearbox6dof" / "resources" / "grc750.toml").read_text())
    one(r"The GRC preset's main shaft is such a beam \(three elements\)", doc("gearbox6dof"),
        "gearbox6dof documentation.html")
    assert grc["rotor"]["shaft"]["beam"]["elements"] == 3


def test_roller_update_distance_is_under_a_hundredth_of_the_smallest_clearance():
    m = one(r"\(3e-7 m by default, under a hundredth of the\s+presets' smallest diametral clearance, (\S+) µm\)",
            doc("gearbox6dof"), "gearbox6dof documentation.html")
    # the diametral (radial) clearances of every preset's roller sets, not the axial ones
    clearances = [float(x) for name in gearbox_presets() for x in re.findall(
        r"[^_]clearance_um = ([-\d.]+)", (ROOT / "fmus" / "gearbox6dof" / "resources" / f"{name}.toml").read_text())]
    assert clearances and min(clearances) > 0, clearances
    check(m[1], min(clearances), "the presets' smallest diametral clearance, µm")
    start = float(xml_variables("gearbox6dof")["roller_update_distance"][1])
    assert start == 3e-7 and start < min(clearances) * 1e-6 / 100


def test_gearbox_bearing_compliance_lowers_the_first_mode(windrive):
    m = one(r"the preset's bearing compliance lowers it by (\S+) % \((\S+) Hz against (\S+) Hz free–free\)",
            doc("gearbox6dof"), "gearbox6dof documentation.html, Estimates")
    six = next(x["frequency_hz"] for x in modes(windrive, "--gearbox", "grc750")["modes"] if x["family"] == "rotational")
    free = modes(windrive, "--preset", "D", "--fidelity", "full", "--generator", "disconnected")["frequencies_hz"]
    torsional = lowest(free)
    check(m[2], six, "grc750's first rotational mode")
    check(m[3], torsional, "torsional D's free–free mode")
    check(m[1], 100 * (1 - six / torsional), "the bearings' share")


def test_gearbox_start_values_are_grc750s_rated_point(fmus):
    one(r"the start is grc750's rated torque", description("gearbox6dof", "initial_rotor_torque"), "gearbox6dof.xml")
    one(r"starts at grc750's rated generator torque", description("gearbox6dof", "generator_torque"), "gearbox6dof.xml")
    v = xml_variables("gearbox6dof")
    grc = fmus["gearbox6dof"].read({"gearbox": "grc750"}, ["rated_rotor_torque", "rated_generator_torque"])
    for name in ("initial_rotor_torque", "rotor_torque"):
        check(v[name][1], grc["rated_rotor_torque"], f"{name}'s start value")
    assert float(v["generator_torque"][1]) == pytest.approx(grc["rated_generator_torque"], rel=1e-4)


def test_make_gearbox_xml_reproduces_the_committed_file(tmp_path):
    out = tmp_path / "gearbox6dof.xml"
    subprocess.run([sys.executable, str(ROOT / "scripts" / "make-gearbox-xml"), str(out)], check=True)
    assert out.read_text() == (ROOT / "modelDescription" / "gearbox6dof.xml").read_text(), (
        "modelDescription/gearbox6dof.xml differs from what scripts/make-gearbox-xml writes: edit the script, "
        "then rerun it")


# ---------------------------------------------------------------------------------------------------
# default values quoted in documentation.html against the XML's start values


def deg(x):
    return math.degrees(float(x))


def hz(x):
    return float(x) / (2 * math.pi)


# (FMU, pattern on the plain text with the quoted value as its group 1 or none, parameter, how the
# start value reads in the unit the documentation quotes, or the expected start string when there
# is no group). A `None` parameter marks a "default" that names no single parameter's start value.
DEFAULTS = [
    ("rotor", r"mean hub-height speed \(default: the preset's rated wind speed,", "wind_speed", "0"),
    ("rotor", r"With wind_averaging = rotor \(default\)", "wind_averaging", "rotor"),
    ("rotor", r"Aerodynamics, aerodynamics = bem \(default\)", "aerodynamics", "bem"),
    ("rotor", r"on the blade named by blade \(default (\S+),", "blade", str),
    ("rotor", r"while scale_blade_to_radius = true \(the start value\)", "scale_blade_to_radius", "true"),
    ("rotor", r"initial_pitch negative \(default\) starts at the trim pitch", "initial_pitch", "-1"),
    ("rotor", r"By default one record of 3276\.8 s with the spectrum's own variance", "turbulence_period", "0"),
    ("rotor", r"ten_minute \(default\) IEC 61400-1's 10-minute one", "turbulence_scaling", "ten_minute"),
    ("rotor", r"the paper's gains for its 1\.5 MW turbine by default", None, None),
    ("rotor", r"Its pitch gains are this FMU's defaults\.", None, None),
    ("rotor", r"startup_pitch_rate \((\S+)°/s, an estimate\)", "startup_pitch_rate", deg),
    ("rotor", r"connect_speed_ratio × rated speed \((\S+): the thesis's field start-up", "connect_speed_ratio", float),
    ("generator", r"R_s = R_r = (\S+) pu", "stator_resistance", float),
    ("generator", r"R_s = R_r = (\S+) pu", "rotor_resistance", float),
    ("generator", r"L_lr = (\S+) pu, current-loop", "rotor_leakage", float),
    ("generator", r"current-loop bandwidth (\S+) rad/s", "current_bandwidth", float),
    ("generator", r"speed filter (\S+) Hz, torque", "speed_filter_frequency", hz),
    ("generator", r"torque ≤ 1\.1 × rated, region-2½ slip (\S+) %", "transition_slip", lambda x: 100 * float(x)),
    ("generator", r"690 V, (\S+) Hz\.", "frequency", float),
    ("generator", r"spring: stiffness = (\S+) takes the preset's K_gen", "stiffness", float),
    ("torsional", r"ζ = shaft_damping_ratio \((\S+)\)", "shaft_damping_ratio", float),
    ("torsional", r"ζ = mesh_damping_ratio \((\S+)\)", "mesh_damping_ratio", float),
    ("torsional", r"lumping = thesis leaves it out as Eq\. 4\.9 does, physical is the default", "lumping", "physical"),
    ("torsional", r"implicit \(default\): Newmark average acceleration", "integrator", "implicit"),
    ("torsional", r"brake_torque_max against the motion \((\S+) = 1\.5 ×", "brake_torque_max", float),
    ("gearbox6dof", r"Integration: HHT-α with ρ∞ = (\S+) by default", "spectral_radius", float),
    ("gearbox6dof", r"Integration: HHT-α with ρ∞ = \S+ by default", "integrator", "hht"),
    ("gearbox6dof", r"Newmark's rule at the default (\S+) ms step", "max_internal_step", lambda x: 1e3 * float(x)),
    ("gearbox6dof", r"The default newton = kept\+predicted keeps one", "newton", "kept+predicted"),
    ("gearbox6dof", r"newton_tolerance \((\S+) by default\)", "newton_tolerance", float),
    ("gearbox6dof", r"The default linear_solver = sparse solves", "linear_solver", "sparse"),
    ("gearbox6dof", r"roller_update_distance \((\S+) m by default", "roller_update_distance", float),
    ("gearbox6dof", r"newton_motion_floor \((\S+) by default", "newton_motion_floor", float),
]


@pytest.mark.parametrize("fmu", ["rotor", "generator", "torsional", "gearbox6dof"])
def test_quoted_defaults_are_the_start_values(fmu):
    text = doc(fmu)
    starts = xml_variables(fmu)
    covered = []
    for name, pattern, parameter, reading in DEFAULTS:
        if name != fmu:
            continue
        m = one(pattern, text, f"{fmu} documentation.html")
        covered.append(m.span())
        if parameter is None:
            continue
        start = starts[parameter][1]
        if isinstance(reading, str):
            assert start == reading, f"{fmu}.{parameter}: the documentation's default {reading}, the XML's start {start}"
        elif reading is str:
            assert start == m[1], f"{fmu}.{parameter}: the documentation's default {m[1]}, the XML's start {start}"
        else:
            check(m[1], reading(start), f"{fmu}.{parameter}'s start value {start}")
    # <code>parameter</code> (number ...): every such quote is a default and must be in the list above
    for m in re.finditer(r"<code>(\w+)</code>\s*\(([-\d.e]+)", raw_html(fmu)):
        if m[1] in starts:
            listed = [p for n, _, p, _ in DEFAULTS if n == fmu and p == m[1]]
            assert listed, f"{fmu} documentation.html quotes {m[1]} ({m[2]} ...): add it to DEFAULTS"
    # every "default" in the text is one of the checks above
    for m in re.finditer(r"default", text):
        assert any(a <= m.start() < b for a, b in covered), (
            f"{fmu} documentation.html: a default this test does not check: ...{text[m.start() - 80:m.end() + 40]}... "
            "(add it to DEFAULTS)")


# (FMU, parameter, pattern on its XML description with the quoted value as group 1, how the start
# value reads in the unit the description quotes)
XML_DEFAULTS = [
    ("rotor", "shear_exponent", r"\(IEC normal wind profile (\S+)\)", float),
    ("rotor", "pitch_max_rate", r"\((\S+) deg/s\)", deg),
    ("rotor", "pitch_max", r"\((\S+) deg\)", deg),
    ("rotor", "startup_pitch_rate", r"\((\S+) deg/s: an estimate", deg),
    ("generator", "frequency", r"\(thesis: (\S+) Hz\)", float),
    ("generator", "transition_slip", r"\(NREL baseline: (\S+) %\)", lambda x: 100 * float(x)),
    ("generator", "speed_filter_frequency", r"\(NREL baseline: (\S+) Hz\)", hz),
    ("gearbox6dof", "integrator", r"^hht \(HHT-alpha with spectral_radius, the default:", "hht"),
    ("gearbox6dof", "spectral_radius", r"\((\S+) by default for both\)", float),
    ("gearbox6dof", "max_internal_step", r"no longer than this \((\S+) ms:", lambda x: 1e3 * float(x)),
    ("gearbox6dof", "newton_motion_floor", r"The default, (\S+), resolves", float),
]


@pytest.mark.parametrize("fmu,parameter,pattern,reading", XML_DEFAULTS, ids=[f"{f}.{p}" for f, p, _, _ in XML_DEFAULTS])
def test_xml_descriptions_quote_their_start_values(fmu, parameter, pattern, reading):
    text, start = xml_variables(fmu)[parameter]
    m = one(pattern, plain(text), f"{fmu}.xml {parameter}")
    if isinstance(reading, str):
        assert start == reading, f"{fmu}.{parameter}: the description's default {reading}, the start {start}"
    else:
        check(m[1], reading(start), f"{fmu}.{parameter}'s start value {start}")
