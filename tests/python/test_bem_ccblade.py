"""The rotor FMU's blade-element momentum model (through `windrive aero`) against NREL's CCBlade on the
same blade, stations and polars (issue 13 §1).

CCBlade ships inside the `wisdem` wheel with its compiled core (`_bem`). `wisdem/__init__.py` imports the
whole WISDEM stack, so scripts/test installs the wheel without dependencies and this test loads only
`wisdem.ccblade` under a bare parent package.

Settings made equal: tip and hub loss, wake rotation and drag in the induction all on, ρ = 1.225 kg/m³,
no precone, tilt, yaw or shear (one azimuth sector), the stations `windrive aero` reports (CCBlade would
otherwise move end nodes inward by its own rule; we hand it ours), and linear interpolation of the polars:
CCBlade's own airfoil class fits smoothing splines (s = 0.01 on C_l), which on the WindPACT tables' coarse
15°→30° post-stall step moves C_l by several per cent, so the test passes CCBlade an airfoil object with
the same `evaluate(alpha, Re)` interface that interpolates linearly, as ours does (Reynolds number ignored
by both). Both solve Ning's residual in φ with Brent's method to ~1e-12 rad, so what remains is the
solver tolerance and floating-point order: the 0.5 % tolerance of the issue is generous; the measured
maximum is printed.
"""

import importlib.util
import json
import pathlib
import subprocess
import sys
import types

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BLADES = ROOT / "fmus" / "rotor" / "resources" / "blades"


def load_ccblade():
    if "wisdem" not in sys.modules:
        spec = importlib.util.find_spec("wisdem")
        if spec is None:
            pytest.fail("wisdem (CCBlade) missing: scripts/test installs it from tests/python/requirements-nodeps.txt")
        # a bare parent package: wisdem/__init__.py would import openmdao, pandas, ...
        parent = types.ModuleType("wisdem")
        parent.__path__ = [str(pathlib.Path(spec.origin).parent)]
        sys.modules["wisdem"] = parent
    from wisdem.ccblade.ccblade import CCBlade

    return CCBlade


class LinearAirfoil:
    """CCBlade's airfoil interface (evaluate(alpha [rad], Re) -> (cl, cd)) over a polar CSV of ours,
    read here independently of the Rust reader, interpolated linearly."""

    def __init__(self, path):
        rows = [line.split(",") for line in path.read_text().splitlines() if line.strip() and not line.startswith("#")]
        assert rows[0] == ["alpha_deg", "cl", "cd"], path
        table = np.array([[float(x) for x in r] for r in rows[1:]])
        self.alpha = np.radians(table[:, 0])
        self.cl = table[:, 1]
        self.cd = table[:, 2]

    def evaluate(self, alpha, Re, return_cm=False):
        a = (alpha + np.pi) % (2 * np.pi) - np.pi
        return float(np.interp(a, self.alpha, self.cl)), float(np.interp(a, self.alpha, self.cd))


def aero(windrive, *args):
    out = subprocess.run([windrive, "aero", *args], check=True, capture_output=True, text=True, cwd=ROOT).stdout
    return json.loads(out)


def ccblade_for(ours, blade_name):
    CCBlade = load_ccblade()
    st = ours["stations"]
    folder = BLADES / blade_name
    polars = {}
    af = [polars.setdefault(s["airfoil"], LinearAirfoil(folder / f"{s['airfoil']}.csv")) for s in st]
    opts = ours["options"]
    return CCBlade(
        [s["radius_m"] for s in st],
        [s["chord_m"] for s in st],
        [s["twist_deg"] for s in st],
        af,
        ours["hub_radius_m"],
        ours["radius_m"],
        B=ours["blades"],
        rho=ours["air_density_kg_m3"],
        precone=0.0,
        tilt=0.0,
        yaw=0.0,
        shearExp=0.0,
        hubHt=80.0,
        nSector=1,
        tiploss=opts["tip_loss"],
        hubloss=opts["hub_loss"],
        wakerotation=opts["wake_rotation"],
        usecd=opts["use_cd"],
    )


TSR = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 14]
PITCH = [-2, 0, 2, 5, 10, 15, 30, 60, 90]


@pytest.mark.parametrize("flags", [[], ["--no-wake-rotation"], ["--no-tip-loss", "--no-hub-loss"]])
def test_cp_cq_ct_match_ccblade(windrive, flags):
    wind = 10.0
    ours = aero(
        windrive,
        "--blade", "windpact-1.5mw",
        "--tsr=" + ",".join(map(str, TSR)),
        "--pitch=" + ",".join(map(str, PITCH)),
        "--wind", str(wind),
        "--elements",
        *flags,
    )
    assert all(p["converged"] for p in ours["points"])
    cc = ccblade_for(ours, "windpact-1.5mw")
    radius = ours["radius_m"]
    worst = {"cp": (0.0, None), "cq": (0.0, None), "ct": (0.0, None)}
    # The compiled core of CCBlade 4.2.9 returns NaN for any inflow angle φ < 0 (the propeller-brake
    # region), so it has no solution where a station's only root lies there (it then zeroes that
    # station's loads with a warning). Such points are compared only by count: none with the default
    # settings, a few at the heaviest loading (λ 14, pitch −2°) without wake rotation.
    brake = [p for p in ours["points"] if min(e["inflow"] for e in p["elements"]) < 0]
    assert len(brake) <= (0 if not flags else 3), [(p["tsr"], p["pitch_deg"]) for p in brake]
    for p in ours["points"]:
        if p in brake:
            continue
        rpm = p["tsr"] * wind / radius * 30 / np.pi
        ref, _ = cc.evaluate([wind], [rpm], [p["pitch_deg"]], coefficients=True)
        for key, ref_key in (("cp", "CP"), ("cq", "CQ"), ("ct", "CT")):
            r = float(ref[ref_key][0])
            # relative to the larger of |value| and 0.05: C_P and C_Q pass through zero at high pitch
            # and tip-speed ratio, where a relative error means nothing
            err = abs(p[key] - r) / max(abs(r), 0.05)
            if err > worst[key][0]:
                worst[key] = (err, (p["tsr"], p["pitch_deg"], p[key], r))
    print(f"\nflags {flags or 'none'}: largest relative differences to CCBlade over "
          f"λ {TSR[0]}..{TSR[-1]}, pitch {PITCH[0]}..{PITCH[-1]} deg ({len(brake)} points in the propeller-brake "
          f"region left out):")
    for key, (err, where) in worst.items():
        print(f"  {key}: {100 * err:.2e} % at (λ, pitch, ours, CCBlade) = {where}")
    for key, (err, where) in worst.items():
        assert err < 0.005, f"{key}: {100 * err:.3f} % at {where}"
        # docs/AERODYNAMICS.md: "every difference below 1e-8 %", the round-off of one residual solved twice
        assert err < 1e-10, f"{key}: {100 * err:.2e} % at {where}, not round-off"


@pytest.mark.parametrize("tsr", [0.0, 1e-4, -1e-4])
def test_parked_feathered_rotor_matches_ccblade_near_standstill(windrive, tsr):
    """Drivetrain C's rotor feathered in 16 m/s, parked or creeping either way. CCBlade returns no loads at
    exactly Ω = 0 (its non-rotating branch needs V_y ≠ 0), so its reference is taken at a creep of
    |λ| = 1e-4 (ours is continuous through Ω = 0, checked here). Our standstill torque is the limit of the
    creeping one; the tolerance is the issue's 0.5 %."""
    wind = 16.0
    ours = aero(windrive, "--preset", "C", f"--tsr={tsr}", "--pitch=90", "--wind", str(wind), "--elements")
    p = ours["points"][0]
    assert p["converged"]
    for e in p["elements"]:
        assert abs(np.degrees(e["inflow"]) - 90) < 2.0, e
    cc = ccblade_for(ours, "windpact-1.5mw")
    creep = tsr if tsr != 0 else 1e-4
    rpm = creep * wind / ours["radius_m"] * 30 / np.pi
    ref, _ = cc.evaluate([wind], [rpm], [90.0])
    q_ref, t_ref = float(ref["Q"][0]), float(ref["T"][0])
    print(f"\nparked C rotor, 16 m/s, pitch 90°, λ = {tsr}: torque ours {p['torque_nm']:.1f} N·m, "
          f"CCBlade {q_ref:.1f} N·m (λ = {creep}); thrust {p['thrust_n']:.1f} / {t_ref:.1f} N")
    assert abs(p["torque_nm"] / q_ref - 1) < 0.005
    assert abs(p["thrust_n"] / t_ref - 1) < 0.005
    if tsr != 0:
        # docs/AERODYNAMICS.md quotes both creeping torques, ours equal to CCBlade's to the digits shown
        shown = f"{p['torque_nm']:,.1f}".replace(",", " ")
        assert shown == f"{q_ref:,.1f}".replace(",", " ")
        assert shown in (ROOT / "docs" / "AERODYNAMICS.md").read_text(), shown
