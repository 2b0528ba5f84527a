"""docs/DRIVETRAINS.md's numbers about our presets and models, each from the command that gives it, in the
digits the page prints:
- the rated-speed table, D's rated generator torque, the per-unit K_gen, C's design tip-speed ratio and the
  radii: `windrive aero --preset X` (rated point, radius) and the calculated parameters of the torsional,
  generator and rotor FMUs (gear ratio, rated torques, K_gen, rated tip-speed ratio); the figures "before" the
  generator basis are the same computations on Table 4.1's rotor speeds;
- the 6-DOF presets' rated speeds and the carrier webs' fit (`windrive gearbox`, `--fit-webs 1.4333`);
- D's cage machine at rated torque (1809.7 rpm): the generator FMU's torque, bisected over its speed;
- the disc admittance: the rotor FMU's rotor-effective wind over its hub wind (one seed draws the same phases,
  so the ratio of their spectra at a bin is χ there), and a Monte Carlo average over point pairs beside it;
- the modes and what the text draws from them against the thesis's: `windrive modes --json`.
The thesis's own figures (Tables 4.1 and 4.6, its modes and braking frequencies) are inputs, read from the
page. "What the scenes show" is tests/it/scenes_as_simulated.rs's, the calibration tests/python/test_calibration.py's.
"""

import functools
import json
import math
import re
import subprocess
import tomllib

import numpy as np
import pytest
from fmpy import extract, simulate_fmu

from conftest import ROOT

PAGE = ROOT / "docs/DRIVETRAINS.md"
PRESETS = "ABCD"


def text():
    """The page with its whitespace normalised, for matching prose across line breaks."""
    return " ".join(PAGE.read_text().split())


def section(title):
    """The page's text from the heading `title` to the next heading of any level."""
    page = PAGE.read_text()
    start = page.index(title)
    end = re.search(r"\n#+ ", page[start + len(title):])
    return page[start:start + len(title) + (end.start() if end else len(page))]


def row(block, label):
    """The cells of the table row of `block` whose first cell is `label`."""
    line = next((l for l in block.splitlines() if l.startswith(f"| {label} |")), None)
    assert line, f"docs/DRIVETRAINS.md: no table row {label!r}"
    return [c.strip() for c in line.strip().strip("|").split("|")]


def says(*quoted):
    page = text()
    for q in quoted:
        assert q in page, f"docs/DRIVETRAINS.md should read: {q}"


def minus(s):
    return s.replace("-", "−")


def span(values, fmt):
    lo, hi = fmt(min(values)), fmt(max(values))
    return lo if lo == hi else f"{lo}–{hi}"


def percent(x):
    return f"{100 * x:.0f}"


def rpm(rad_s):
    return rad_s * 30 / math.pi


def rad_s(rev_min):
    return rev_min * math.pi / 30


def approx(x, rel=1e-9):
    return pytest.approx(x, rel=rel)


def cli(windrive, *args):
    return subprocess.run([windrive, *args], check=True, capture_output=True, text=True, cwd=ROOT).stdout


@functools.cache
def modes(windrive, preset, fidelity, generator="disconnected", lumping="physical"):
    out = cli(windrive, "modes", "--preset", preset, "--fidelity", fidelity, "--generator", generator,
              "--lumping", lumping, "--json")
    return json.loads(out)["frequencies_hz"]


@functools.cache
def fmu(windrive, name):
    """The packed FMU `name`, unzipped once."""
    path = ROOT / "target" / "fmu" / f"{name}.fmu"
    if not path.is_file():
        subprocess.run([windrive, "pack", name], check=True, cwd=ROOT)
    return extract(str(path))


def at_start(windrive, name, outputs, **start):
    """The FMU's `outputs` (calculated parameters or outputs) right after initialisation."""
    r = simulate_fmu(fmu(windrive, name), stop_time=0.001, step_size=0.001, start_values=start, output=outputs)
    return {k: float(r[k][0]) for k in outputs}


@functools.cache
def preset(windrive, p):
    """The preset's rated point and radius (`windrive aero`), its gear ratio and rated torques (torsional FMU),
    and the spring generator's K_gen."""
    rated = json.loads(cli(windrive, "aero", "--preset", p, "--tsr", "7"))
    torsional = at_start(windrive, "torsional", ["gear_ratio", "rated_rotor_torque", "rated_generator_torque"],
                         preset=p)
    spring = at_start(windrive, "generator", ["stiffness_used", "rated_torque"], preset=p, kind="spring")
    return {"power": rated["rated"]["power_w"], "rpm": rated["rated"]["rotor_speed_rpm"],
            "radius": rated["radius_m"], **torsional, "k_gen": spring["stiffness_used"],
            "generator_torque": spring["rated_torque"]}


def table_4_1_rpm(p):
    """Table 4.1's rotor speed of preset `p`, the page's input."""
    return float(row(section("## Rated speeds"), p)[1].split()[0])


def test_the_rated_speed_table_is_the_presets(windrive):
    block = section("## Rated speeds")
    for p in PRESETS:
        d, cells = preset(windrive, p), row(block, p)
        generator_rpm = float(cells[2].split()[0])
        # the rule: the generator's rated speed (Table 4.6) over the gear ratio
        assert d["rpm"] == approx(generator_rpm / d["gear_ratio"])
        torque = d["power"] / rad_s(d["rpm"])
        assert torque == approx(d["rated_rotor_torque"])
        basis = d["power"] / rad_s(table_4_1_rpm(p))
        expected = [f"{d['gear_ratio']:.2f}", f"{d['rpm']:.3f} rpm",
                    f"{basis / 1e6:.5g} → {torque / 1e6:.5g} MN·m", minus(f"{100 * (torque / basis - 1):+.1f} %")]
        assert cells[3:] == expected, (p, cells, expected)


def test_why_the_generator_basis(windrive):
    c, d = preset(windrive, "C"), preset(windrive, "D")
    says(f"1680 rpm over {c['gear_ratio']:.2f} is {c['rpm']:.2f} rpm, {percent(c['rpm'] / 18.1 - 1)} % from 18.1 rpm")
    # D: the thesis's 22.44 and 22.4 rpm, the preset's speed, the GRC's 22.1 rpm and 324 kN·m
    basis = d["power"] / rad_s(table_4_1_rpm("D"))
    others = [d["power"] / rad_s(n) for n in (22.44, 22.4, d["rpm"], 22.1)] + [324e3]
    says(f"Table 4.1's 18.6 rpm puts D's rated torque {span([basis / t - 1 for t in others], percent)} % above all")
    # A and B: both bases within 1 %
    for p in "AB":
        assert abs(round(100 * (table_4_1_rpm(p) / preset(windrive, p)["rpm"] - 1), 1)) <= 1.0
    says("Both bases agree within 1 %")


def test_k_gen_and_the_radii_follow_the_rated_speeds(windrive):
    d = preset(windrive, "D")
    torque = d["generator_torque"]
    assert torque == approx(d["rated_generator_torque"])
    # A–C's K_gen: D's per-unit value times their rated generator torque
    per_unit = d["k_gen"] / torque
    for p in "ABC":
        assert preset(windrive, p)["k_gen"] / preset(windrive, p)["generator_torque"] == approx(per_unit)
    before = d["power"] / (rad_s(table_4_1_rpm("D")) * d["gear_ratio"])
    says(f"D's rated generator torque is now {torque:.0f} N·m, the {torque / 1e3:.2f} kN·m",
         f"per-unit value is {per_unit:.1f} /rad. Before, the code divided by {before:.0f} N·m, which gave "
         f"{d['k_gen'] / before:.2f}.")
    # C's rated tip-speed ratio under the analytic C_p. Before, at Table 4.1's 16 rpm: the rated point depends on
    # R⁵ω³ only (P = ½ρπR⁵ω³ C_p(λ)/λ³), so C's rotor at its rated speed with R = 40·(16 rpm/ω)^(3/5) has it.
    c = preset(windrive, "C")
    rotor = lambda **start: at_start(windrive, "rotor", ["rated_tip_speed_ratio", "radius_used"], preset="C",
                                     aerodynamics="analytic", turbulence="none", **start)
    now = rotor()
    assert now["radius_used"] == 40.0
    then = rotor(radius=40.0 * (table_4_1_rpm("C") / c["rpm"]) ** 0.6)
    says(f"That ratio is now {now['rated_tip_speed_ratio']:.2f} ({then['rated_tip_speed_ratio']:.2f} before)")

    # the radii: R⁵ ∝ P/ω³ at that ratio, so R = R_C (P/P_C)^(1/5) (ω_C/ω)^(3/5), on either basis
    def radius(p, speed):
        return 40.0 * (preset(windrive, p)["power"] / c["power"]) ** 0.2 * (speed("C") / speed(p)) ** 0.6

    for p in "ABD":
        assert radius(p, lambda q: preset(windrive, q)["rpm"]) == approx(preset(windrive, p)["radius"])
        assert at_start(windrive, "rotor", ["radius_used"], preset=p, aerodynamics="analytic",
                        turbulence="none")["radius_used"] == approx(preset(windrive, p)["radius"])
    r = {p: preset(windrive, p)["radius"] for p in "ABD"}
    old = {p: radius(p, table_4_1_rpm) for p in "ABD"}
    says(f"the radii are A {r['A']:.2f} m, B {r['B']:.2f} m and D {r['D']:.2f} m (before: {old['A']:.2f}, "
         f"{old['B']:.2f} and {old['D']:.2f})")


def test_the_gearbox6dof_presets_follow(windrive):
    grc = json.loads(cli(windrive, "gearbox", "--json"))
    c2mw = json.loads(cli(windrive, "gearbox", "--gearbox", "c2mw", "--json"))
    assert f"{rpm(grc['rotor_speed_rad_s']):.3f}" == f"{preset(windrive, 'D')['rpm']:.3f}"
    assert f"{rpm(c2mw['rotor_speed_rad_s']):.3f}" == f"{preset(windrive, 'C')['rpm']:.3f}"
    fit = re.search(r"carrier webs torsional = (\S+) N·m/rad", cli(windrive, "gearbox", "--fit-webs", "1.4333"))
    webs = float(fit.group(1))
    description = tomllib.loads((ROOT / "fmus/gearbox6dof/resources/grc750.toml").read_text())
    assert description["stage"][0]["planetary"]["carrier_webs"]["torsional"] == approx(webs, rel=1e-4)
    mantissa, exponent = f"{webs:.3e}".split("e")
    says(f"grc750 is at {rpm(grc['rotor_speed_rad_s']):.3f} rpm and its carrier webs are refitted by "
         f"`windrive gearbox --fit-webs 1.4333`, to {mantissa}e{int(exponent)} N·m/rad",
         f"c2mw is at {rpm(c2mw['rotor_speed_rad_s']):.3f} rpm")


def test_d_cage_machine_reaches_rated_torque_near_1809_rpm(windrive):
    """The generator FMU's `fixed` kind starts in its electrical equilibrium at the speed it is given; its
    torque rises with the slip above the grid's 1800 rpm."""
    torque = lambda n: at_start(windrive, "generator", ["generator_torque"], preset="D", kind="fixed",
                                generator_speed=rad_s(n))["generator_torque"]
    rated = preset(windrive, "D")["rated_generator_torque"]
    lo, hi = 1800.5, 1820.0
    assert torque(lo) < rated < torque(hi)
    while hi - lo > 1e-3:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if torque(mid) < rated else (lo, mid)
    says(f"D's machine reaches its rated torque of {rated:.0f} N·m at **{lo:.1f} rpm**")


def test_the_disc_admittance(windrive):
    """At 16 m/s on C's rotor: the rotor FMU's wind series over one 100 s period (0.05 s spacing, bins every
    0.01 Hz), rotor-averaged and at the hub."""
    def series(averaging):
        r = simulate_fmu(fmu(windrive, "rotor"), stop_time=100.0, step_size=0.05, output_interval=0.05,
                         start_values={"preset": "C", "aerodynamics": "analytic", "wind_speed": 16.0,
                                       "turbulence_period": 100.0, "wind_sampling": "rotor_average",
                                       "wind_averaging": averaging}, output=["wind_speed_hub"])
        return np.fft.rfft(r["wind_speed_hub"][:2000])

    rotor, hub = series("rotor"), series("hub")
    chi = {}
    for f in (0.01, 0.1, 1.0):
        k = round(f * 100)
        ratio = rotor[k] / hub[k]
        assert abs(ratio.imag) < 1e-9 * abs(ratio), "the two series should share their phases"
        chi[f] = ratio.real ** 2
    says(f"At 16 m/s on C's 40 m radius the admittance is {chi[0.01]:.2f} at 0.01 Hz, {chi[0.1]:.2f} at 0.1 Hz "
         f"and {chi[1.0]:.3f} at 1 Hz")
    # the IEC coherence averaged over 2·10⁶ random point pairs in the disc (L_c = 8.1·42 m above a 60 m hub)
    rng = np.random.default_rng(1)

    def points(n):
        p = rng.uniform(-1.0, 1.0, (2 * n, 2))
        return 40.0 * p[(p ** 2).sum(axis=1) <= 1.0][:n]

    n = 2_000_000
    r = np.hypot(*(points(n) - points(n)).T)
    for f, ours in chi.items():
        brute = np.exp(-12.0 * np.sqrt((f * r / 16.0) ** 2 + (0.12 * r / 340.2) ** 2)).mean()
        assert abs(ours - brute) < 1e-3, (f, ours, brute)
    says("a Monte Carlo average over 2·10⁶ point pairs (to 1e-3)")


def test_the_calibration_reads_the_presets(windrive):
    c = preset(windrive, "C")
    shutdown_range = 2e6 / c["rated_rotor_torque"]
    says(f"Below the first drivetrain mode ({modes(windrive, 'C', 'full')[1]:.1f} Hz)",
         f"about {c['gear_ratio']:.1f} × 3.8 = {c['gear_ratio'] * 3.8:.0f} kN·m at the LSS",
         f"imply a ratio of {250 / 3.8:.0f}",
         f"LSS shutdown range > 2 MN·m** ({shutdown_range:.2f}× rated)",
         minus(f"the reversal would have to reach {1.38 - shutdown_range:.2f}× rated"),
         f"It is a mode: ours is {modes(windrive, 'D', 'full')[1]:.3f} Hz free–free")


def test_the_mode_table_is_the_commands(windrive):
    block = section("## Modes")
    second = lambda p, *args: modes(windrive, p, *args)[1]
    rows = {
        "`--fidelity full`": lambda p: f"{second(p, 'full'):.3f}",
        "`--fidelity 5` / with `--lumping thesis`":
            lambda p: f"{second(p, '5'):.3f} / {second(p, '5', 'disconnected', 'thesis'):.3f}",
        "`--fidelity 2` / with `--lumping thesis`":
            lambda p: f"{second(p, '2'):.3f} / {second(p, '2', 'disconnected', 'thesis'):.3f}",
        "`--fidelity full --generator connected` (K_gen to ground), second mode":
            lambda p: f"{second(p, 'full', 'connected'):.3f}",
    }
    for label, value in rows.items():
        assert row(block, label)[1:] == [value(p) for p in "ABC"], label


def test_d_five_mass_modes(windrive):
    def listed(freqs):
        return f"{freqs[1]:.3f}, {freqs[2]:.1f}, {freqs[3]:.1f} and {freqs[4]:.1f} Hz"

    says(f"with the physical lumping, ours are {listed(modes(windrive, 'D', '5'))};",
         f"with the thesis's Eq. 4.9 lumping (`--lumping thesis`), "
         f"{listed(modes(windrive, 'D', '5', 'disconnected', 'thesis'))}.",
         f"The thesis's own 2-mass model of D gives {modes(windrive, 'D', '2')[1]:.3f} Hz free–free, as ours does")
    # only the top mode agrees with the thesis's 2.957, 292, 372 and 1974 Hz
    for lumping in ("physical", "thesis"):
        ours = modes(windrive, "D", "5", "disconnected", lumping)[1:]
        agree = [abs(o / t - 1) < 0.001 for o, t in zip(ours, (2.957, 292.0, 372.0, 1974.0))]
        assert agree == [False, False, False, True], (lumping, ours)


def test_a_to_c_modes_against_the_thesis(windrive):
    """Ours over the thesis's lowest modes (the table's thesis row): over every free–free model, over the full
    one; the damping ratio that would lower ours to the thesis's; the inertia or stiffness it would take."""
    thesis = dict(zip("ABC", map(float, row(section("## Modes"), "thesis")[1:])))
    models = [("full",), ("5",), ("5", "disconnected", "thesis"), ("2",), ("2", "disconnected", "thesis")]
    every = [modes(windrive, p, *m)[1] / thesis[p] - 1 for p in "ABC" for m in models]
    full = {p: modes(windrive, p, "full")[1] / thesis[p] for p in "ABC"}
    over = [r - 1 for r in full.values()]
    says(f"Ours from its Table 4.3 are {span(every, percent)} % higher whatever the model "
         f"({span(over, percent)} % in the full one)")
    lower = [1 - 1 / r for r in full.values()]
    zeta = [math.sqrt(1 - 1 / r ** 2) for r in full.values()]
    says(f"to lower a damped one by the full model's {span(lower, percent)} % would take a damping ratio of "
         f"{span(zeta, lambda z: f'{z:.2f}')}",
         f"(to the full model, {span([r ** 2 - 1 for r in full.values()], percent)} % more inertia or "
         f"{span([1 - 1 / r ** 2 for r in full.values()], percent)} % less stiffness)")
    # the thesis's braking frequencies lie between its modes and ours
    braking = re.search(r"braking frequencies it reports \(([^)]*) Hz\)", text()).group(1).split(", ")
    for p, f in zip("ABC", map(float, braking)):
        assert thesis[p] < f < modes(windrive, p, "full")[1], p


def test_sources_md_quotes_the_same_rated_speeds_and_radii(windrive):
    """docs/SOURCES.md's estimates table repeats the rated rotor speeds, the radii and C's rated tip-speed ratio:
    the same values as the presets give."""
    sources = " ".join((ROOT / "docs" / "SOURCES.md").read_text(encoding="utf-8").split())
    rpm = {p: preset(windrive, p)["rpm"] for p in "ABCD"}
    radius = {p: preset(windrive, p)["radius"] for p in "ABD"}
    tsr = at_start(windrive, "rotor", ["rated_tip_speed_ratio"], preset="C", aerodynamics="analytic",
                   turbulence="none")["rated_tip_speed_ratio"]
    for quoted in [
        f"| rated rotor speeds | A {rpm['A']:.3f}, B {rpm['B']:.3f}, C {rpm['C']:.3f}, D {rpm['D']:.3f} rpm |",
        f"| rotor radii of A, B, D | A {radius['A']:.2f}, B {radius['B']:.2f}, D {radius['D']:.2f} m |",
        f"at C's rated tip-speed ratio ({tsr:.2f})",
    ]:
        assert quoted in sources, f"docs/SOURCES.md should read: {quoted}"
