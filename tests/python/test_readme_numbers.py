"""README.md's figures about our results that no other test checks, against the commands and FMUs that
produce them: each test computes the numbers, formats them as the README prints them and asserts the README
says so (whitespace normalised). A sentence reworded fails here loudly; change the expected text with it.

What is not rerun: `windrive chart stability` (about a minute); its figures are read from the committed table
docs/speed-accuracy/stability-map.csv that the command writes, and its theory's limits from the table of
docs/SPEED-ACCURACY.md (tests/python/test_speed_accuracy_doc.py checks that page's runs against the table).
The 6-DOF paper gearbox's agreement is stated as the tolerances tests/it/paper_turbine.rs asserts."""

import csv
import json
import math
import re
import subprocess

import pytest
from packed_fmu import packed

from conftest import ROOT


def readme():
    return " ".join((ROOT / "README.md").read_text(encoding="utf-8").split())


def says(*sentences):
    text = readme()
    for s in sentences:
        s = " ".join(s.split())
        assert s in text, f"README.md should say: {s}"


def sci(x, digits=1):
    """3.8e4, the README's way (not 3.8e+04)."""
    mantissa, exponent = f"{x:.{digits}e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def bound(x):
    """The tightest one-decimal bound a README "within x %" can state for x."""
    return f"{math.ceil(x * 10 - 1e-9) / 10:.1f}"


# ---------------------------------------------------------------------------------------------------
# FMUs, one instance per call (as tests/python/test_fmu_documentation.py does)


@pytest.fixture(scope="module")
def fmus(windrive):
    yield from packed(windrive, ("generator", "torsional"))


# ---------------------------------------------------------------------------------------------------
# torsional model


def modes(windrive, *args):
    out = subprocess.run([windrive, "modes", "--preset", "D", "--fidelity", "5", *args, "--json"],
                         check=True, capture_output=True, text=True)
    return json.loads(out.stdout)["frequencies_hz"]


def test_thesis_lumping_moves_one_mode(windrive):
    """`windrive modes --lumping thesis`: D's fourth 5-mass mode moves by 8.6 %, every other mode (connected,
    as the command's default, and free–free, as tests/it/physics_modes.rs) by at most the bound quoted."""
    others = []
    for generator in ("connected", "disconnected"):
        physical = modes(windrive, "--generator", generator)
        thesis = modes(windrive, "--generator", generator, "--lumping", "thesis")
        fourth = (physical[3], thesis[3], 100 * (1 - physical[3] / thesis[3]))
        if generator == "connected":
            quoted = fourth
        others += [100 * abs(1 - p / t) for k, (p, t) in enumerate(zip(physical, thesis)) if k != 3 and t > 0]
    says(f"which moves D's fourth 5-mass mode from {quoted[0]:.1f} to {quoted[1]:.1f} Hz ({quoted[2]:.1f} %) "
         f"and leaves every other mode within {bound(max(others))} %.")


def test_numerically_damped_integrators(fmus):
    """tests/it/torsional_dynamics.rs's scene through the packed FMU: D's rated torques applied after
    initialisation, 1000 steps of 1 ms; roughness = Σ|second difference| of the HSS torque."""
    t = fmus["torsional"]

    def step(integrator, rho):
        s = t.instance({"integrator": integrator, "spectral_radius": rho})
        try:
            rotor, generator = s.getReal([t.vr("rated_rotor_torque"), t.vr("rated_generator_torque")])
            s.setReal([t.vr("rotor_torque"), t.vr("generator_torque")], [rotor, generator])
            hss = []
            for i in range(1000):
                s.doStep(currentCommunicationPoint=i * 1e-3, communicationStepSize=1e-3)
                hss.append(s.getReal([t.vr("hss_torque")])[0])
        finally:
            s.terminate()
            s.freeInstance()
        roughness = sum(abs(a - 2 * b + c) for a, b, c in zip(hss, hss[1:], hss[2:]))
        return hss[-1], roughness, generator

    newmark, rough_newmark, rated = step("implicit", 1.0)
    ratio = {}
    for name, rho in (("hht", 0.6), ("generalized-alpha", 0.3)):
        torque, roughness, _ = step(name, rho)
        assert abs(torque - newmark) < 0.01 * rated, (name, torque, newmark)
        ratio[name] = rough_newmark / roughness
    says(f"the HSS torque's step-to-step roughness drops {ratio['hht']:.1f}× (hht, ρ∞ = 0.6) and "
         f"{ratio['generalized-alpha']:.0f}× (generalized-alpha, ρ∞ = 0.3) while the torque after 1 s stays "
         "within 1 % of rated of Newmark's.")


# ---------------------------------------------------------------------------------------------------
# the master's stability on the generator split


def test_coupling_stability_limits():
    with open(ROOT / "docs/speed-accuracy/stability-map.csv", newline="") as f:
        table = list(csv.DictReader(f))

    def held(algorithm):
        """H·ω of the largest step that held at D's K_gen, every shorter one holding too."""
        nominal = sorted((float(r["step_s"]), r["stable_measured"] == "true", float(r["h_omega"]))
                         for r in table if r["algorithm"] == algorithm and float(r["stiffness_factor"]) == 1.0)
        last = None
        for _, stable, h_omega in nominal:
            if not stable:
                break
            last = h_omega
        return last

    page = (ROOT / "docs/SPEED-ACCURACY.md").read_text(encoding="utf-8")
    page = page[page.index("## Where each coupling algorithm is stable"):]

    def theory(label):
        row = next(line for line in page.splitlines() if line.startswith(f"| {label} |"))
        return float(re.search(r"\((?:H·ω )?([\d.]+)\)", row.split("|")[2])[1])

    assert held("jacobi p0") is None
    iqn = [r for r in table if r["algorithm"] == "iterative iqn-ils"]
    assert all(r["stable_measured"] == "true" for r in iqn)
    steps = max(float(r["step_s"]) for r in iqn)
    stiffness = max(float(r["stiffness_factor"]) for r in iqn)
    says(f"zero-order-hold Jacobi grows at any step; Gauss–Seidel with hold holds to H·ω ≈ "
         f"{held('gauss-seidel p0'):.1f} (theory {theory('gauss-seidel p0'):.1f}); Jacobi with `--order 2` to "
         f"{held('jacobi p2'):.2f}, the most accurate explicit choice with interpolating FMUs; plain `iterative` "
         f"to {held('iterative p1'):.1f} (theory {theory('iterative p1 (plain)'):.1f}, where its fixed-point "
         f"iteration stops contracting); `--acceleration iqn-ils` everywhere on the grid (steps to {steps:g} s, "
         f"stiffness to {stiffness:g}·K_gen)")


# ---------------------------------------------------------------------------------------------------
# the spring scenes: C's figures from the README's own `--spring` block (tests/it/readme.rs checks it
# against the command), D's from `windrive shutdown --preset D --spring`


def summary(text):
    """The shutdown summary's figures, as printed."""
    def grab(pattern):
        return re.search(pattern, text)[1]

    return {
        "lss": float(grab(r"(?m)^lss\s+\S+\s+(\S+)")),
        "lock": grab(r"HSS locked at (\S+) s"),
        "slip": grab(r"while the brake slips: (\S+) Hz"),
        "free": grab(r"lowest free-free mode (\S+) Hz"),
        "held": grab(r"with the HSS held:\s+(\S+) Hz"),
        "locked": grab(r"lowest HSS-locked mode (\S+) Hz"),
        "rock_first": float(grab(r"(\S+) rad/s in the first 2 s held")),
        "rock_last": float(grab(r"(\S+) rad/s in the last 2 s")),
        "sun_planet": float(grab(r"sun-planet min (\S+) kN")),
    }


def test_spring_scenes(windrive, tmp_path):
    blocks = re.findall(r"```\n(shaft .*?)```", (ROOT / "README.md").read_text(encoding="utf-8"), re.S)
    assert len(blocks) == 2, "README: the main job's block and the --spring one"
    c = summary(blocks[1])
    out = subprocess.run([windrive, "shutdown", "--preset", "D", "--spring", "--out-dir", str(tmp_path)],
                         check=True, capture_output=True, text=True, cwd=ROOT).stdout
    d = summary(out)
    says(
        f"reverses after the trip (C: down to −{-c['sun_planet']:.0f} kN,",
        f"while the brake slips the HSS torque rings at {c['slip']} Hz (C) / {d['slip']} Hz (D), the lowest "
        f"free–free modes being {c['free']} / {d['free']} Hz; once the brake holds ({c['lock']} s / {d['lock']} s) "
        f"at {c['held']} / {d['held']} Hz, the HSS-locked modes being {c['locked']} / {d['locked']} Hz",
        f"(first to last 2 s held: C {c['rock_first']:.3f} → {c['rock_last']:.3f} rad/s; D, with its published "
        f"near-zero damping, {d['rock_first']:.3f} → {d['rock_last']:.3f})",
        f"Peak LSS torque {c['lss']:.2f}× rated (C) and {d['lss']:.2f}× (D)",
    )


# ---------------------------------------------------------------------------------------------------
# the generator FMU


def test_generator_linearised_stiffness_and_rated_speed(fmus):
    g = fmus["generator"]

    def cage(preset, frequency):
        sync = g.read({"preset": preset, "kind": "fixed"}, ["synchronous_speed_used"])["synchronous_speed_used"]
        r = g.read({"preset": preset, "kind": "fixed", "generator_speed": 1.01 * sync,
                    "stiffness_frequency": frequency}, ["equivalent_stiffness", "equivalent_damping"])
        return sci(r["equivalent_stiffness"]), sci(r["equivalent_damping"])

    spring = g.read({"preset": "D", "kind": "spring"}, ["stiffness_used", "rated_torque", "synchronous_speed_used"])
    (kc, dc), (kd, dd), (kd_low, dd_low) = cage("C", 2.5), cage("D", 2.5), cage("D", 0.5)
    controlled = []
    for p in "ABCD":
        rated = g.read({"preset": p, "kind": "spring"}, ["synchronous_speed_used"])["synchronous_speed_used"]
        for kind in ("dfig", "pmg"):
            controlled.append(abs(g.read({"preset": p, "kind": kind, "generator_speed": rated},
                                         ["equivalent_stiffness"])["equivalent_stiffness"]))
    two = lambda x: f"{float(f'{x:.2g}'):.0f}"
    # D's cage machine: the speed at which it delivers D's rated torque
    lo, hi = 1800.0, 1900.0
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        torque = g.read({"preset": "D", "kind": "fixed", "generator_speed": mid * math.pi / 30},
                        ["generator_torque"])["generator_torque"]
        lo, hi = (mid, hi) if torque < spring["rated_torque"] else (lo, mid)
    says(
        f"whose synchronous speed is the grid's: "
        f"{g.read({'preset': 'D', 'kind': 'fixed'}, ['synchronous_speed_used'])['synchronous_speed_used'] * 30 / math.pi:.0f}"
        f" rpm, rated torque at {lo:.1f} rpm)",
        f"gives K = {kc} N·m/rad, D = {dc} N·m·s/rad (C) and K = {kd}, D = {dd} (D) against D's K_gen = "
        f"{sci(spring['stiffness_used'], 2)} — the same order",
        f"at 0.5 Hz it is mainly a damper (K = {kd_low}, D = {dd_low} for D)",
        f"(|K| ≈ {two(min(controlled))}–{two(max(controlled))} N·m/rad,",
    )


# ---------------------------------------------------------------------------------------------------
# the paper's turbine with the 6-DOF gearbox


def test_paper_6dof_agreement_is_the_tests_tolerance():
    """The README states the 6-DOF gearbox's agreement with the torsional model as the tolerances
    tests/it/paper_turbine.rs asserts (the campaign that measured it is minutes per cell)."""
    src = (ROOT / "tests/it/paper_turbine.rs").read_text(encoding="utf-8")
    body = src[src.index("fn six_dof_and_torsional_gearboxes_rate_alike"):]
    stress = set(re.findall(r"close\(a\.max_(?:contact|root)_stress, b\.max_(?:contact|root)_stress, ([\d.e-]+)\)", body))
    damage = set(re.findall(r"close\(a\.(?:flank|root)_damage, b\.(?:flank|root)_damage, ([\d.e-]+)\)", body))
    assert len(stress) == 1 and len(damage) == 1, (stress, damage)
    wind = re.search(r'\("rotor", "wind_speed", "(\d+)"\)', body)[1]
    says(f"every tooth's peak stresses within {100 * float(stress.pop()):g} % and damage within "
         f"{100 * float(damage.pop()):g} % of the torsional model's in steady {wind} m/s wind")
