"""scripts/check-wheel, in the fresh venv the wheel was installed into: each of the four FMUs, found through
`windrive_fmus.fmu_path`, runs in fmpy for a fraction of a second in a state whose answer is known, and
every output is finite. Prints one line per FMU; the first failure is one line on stderr and exit 1.

Drivetrain D (the NREL GRC, every FMU's default preset): 750 kW at 1809 rpm at the generator, gear ratio
from the tooth counts (thesis Table 4.1)."""

import math
import sys
import time
from pathlib import Path

import numpy as np
from fmpy import simulate_fmu

import windrive_fmus
from windrive_fmus import fmu_path

RATIO = (1 + 99 / 21) * (82 / 23) * (88 / 22)
GENERATOR_SPEED = 1809 * math.pi / 30  # rad/s
ROTOR_SPEED = GENERATOR_SPEED / RATIO
T_GEN = 750e3 / GENERATOR_SPEED
T_ROTOR = T_GEN * RATIO


class Implausible(Exception):
    pass


def close(name, got, want, rel):
    if not abs(got - want) <= rel * abs(want):
        raise Implausible(f"{name} = {got:.6g}, expected {want:.6g} within {rel:g}")


def finite(result):
    for name in result.dtype.names:
        if not np.all(np.isfinite(result[name].astype(float))):
            raise Implausible(f"{name} is not finite")
    return result


def torsional(path):
    """Started in its loaded equilibrium at rated speed and held there by rated torques at both ends."""
    start = {"initial_rotor_torque": T_ROTOR, "rotor_torque": T_ROTOR, "generator_torque": T_GEN}  # inputs held
    r = finite(simulate_fmu(path, stop_time=0.5, output_interval=1e-3, start_values=start,
                            output=["rotor_speed", "generator_speed", "lss_torque", "hss_torque", "gear_ratio"]))
    close("gear_ratio", r["gear_ratio"][-1], RATIO, 1e-9)
    close("rotor_speed", r["rotor_speed"][-1], ROTOR_SPEED, 1e-3)
    close("lss_torque", r["lss_torque"][-1], T_ROTOR, 0.01)
    close("hss_torque", r["hss_torque"][-1], T_GEN, 0.01)
    return f"LSS {r['lss_torque'][-1] / 1e3:.1f} kN·m at {r['rotor_speed'][-1] * 30 / math.pi:.2f} rpm"


def generator(path):
    """The electrical spring at synchronous speed, started at its rated torque, keeps it."""
    probe = simulate_fmu(path, stop_time=0.001, step_size=0.001, start_values={"kind": "spring"},
                         output=["synchronous_speed_used", "rated_torque"])
    speed, rated = probe["synchronous_speed_used"][0], probe["rated_torque"][0]
    close("rated_torque", rated, T_GEN, 1e-6)
    r = finite(simulate_fmu(path, stop_time=0.5, step_size=0.001, output_interval=0.01,
                            start_values={"kind": "spring", "generator_speed": speed, "initial_torque": rated},
                            output=["generator_torque", "electrical_power"]))
    close("generator_torque", r["generator_torque"][-1], rated, 1e-6)
    return f"{r['generator_torque'][-1]:.1f} N·m, {r['electrical_power'][-1] / 1e3:.1f} kW"


def rotor(path):
    """The blade-element rotor at rated speed in steady wind at its fitted rated wind gives rated torque."""
    r = finite(simulate_fmu(path, stop_time=0.05, output_interval=0.01,
                            start_values={"turbulence": "none", "rotor_speed": ROTOR_SPEED},
                            output=["rotor_torque", "rated_rotor_torque", "wind_speed_hub", "rated_wind_speed"]))
    close("rated_rotor_torque", r["rated_rotor_torque"][0], T_ROTOR, 1e-6)
    close("wind_speed_hub", r["wind_speed_hub"][0], r["rated_wind_speed"][0], 1e-9)
    close("rotor_torque", r["rotor_torque"][0], T_ROTOR, 1e-4)
    return f"{r['rotor_torque'][0] / 1e3:.1f} kN·m at {r['wind_speed_hub'][0]:.2f} m/s"


def gearbox6dof(path):
    """Alone with its defaults: the GRC at rated torque, its upwind planet bearings the more loaded."""
    r = finite(simulate_fmu(path, stop_time=0.2, output_interval=1e-3,
                            output=["lss_torque", "hss_torque", "planet_1_uw_radial_load", "planet_1_dw_radial_load"]))
    close("lss_torque", r["lss_torque"][-1], T_ROTOR, 0.01)
    close("hss_torque", r["hss_torque"][-1], T_GEN, 0.01)
    if not r["planet_1_uw_radial_load"][-1] > r["planet_1_dw_radial_load"][-1] > 0:
        raise Implausible("planet 1's upwind bearing does not carry more than its downwind one")
    upwind = r["planet_1_uw_radial_load"][-1]
    return f"LSS {r['lss_torque'][-1] / 1e3:.1f} kN·m, planet 1 upwind bearing {upwind / 1e3:.1f} kN"


def main() -> int:
    installed = Path(windrive_fmus.__file__).resolve()
    if Path(sys.prefix).resolve() not in installed.parents:
        print(f"error: windrive_fmus imported from {installed}, not from this venv ({sys.prefix})", file=sys.stderr)
        return 1
    for check in (torsional, generator, rotor, gearbox6dof):
        name = check.__name__
        t0 = time.perf_counter()
        try:
            path = fmu_path(name)
            if Path(sys.prefix).resolve() not in Path(path).resolve().parents:
                raise Implausible(f"fmu_path gave {path}, outside this venv")
            what = check(path)
        except Exception as e:
            print(f"error: {name} FMU in fmpy: {type(e).__name__}: {e}".splitlines()[0], file=sys.stderr)
            return 1
        print(f"  {name:12} {time.perf_counter() - t0:5.1f} s  {what}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
