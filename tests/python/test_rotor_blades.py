"""The rotor FMU's blades sampling a full field (wind_sampling = blades), in fmpy, against calculations made
here with numpy alone.

- Pure power-law shear, no turbulence, constant rotor speed, fine pitch held: each blade element sees the
  wind at its own height as the blades turn, so torque, tilt and yaw moment vary at 3P. Here the rotor is
  summed independently: every station's loads per unit span come from `windrive aero --elements` (the BEM
  in uniform wind, one call per wind speed, interpolated in wind speed), are placed at each blade's height
  for the azimuth, integrated over the span with numpy's trapezoidal rule and summed over the three blades.
  The FMU reads its loads from its per-station table instead of solving each element; the two agree to the
  table's interpolation error.
- A TurbSim file (WINDRIVE_TURBSIM_BTS, as in test_wind_bts.py) through the rotor: its hub wind is the file's
  grid, read here with numpy, interpolated linearly to the hub point and the time.
"""

import json
import math
import os
import re
import subprocess

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from conftest import ROOT, WINDRIVE
from test_wind_bts import read_bts, turbsim_files

ROTOR = ROOT / "target" / "fmu" / "rotor.fmu"
HUB, V_HUB, ALPHA = 80.0, 11.0, 0.2


def rotor(strings, reals):
    """An initialised rotor FMU (fmpy) and its value references."""
    if not ROTOR.is_file():
        subprocess.run([str(WINDRIVE), "pack", "rotor"], check=True, cwd=ROOT)
    md = read_model_description(str(ROTOR))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(ROTOR)), modelIdentifier="rotor", instanceName="blades")
    fmu.instantiate()
    fmu.setupExperiment(startTime=0.0)
    for name, value in strings.items():
        fmu.setString([vr[name]], [value])
    for name, value in reals.items():
        fmu.setReal([vr[name]], [value])
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    return fmu, vr


def run(fmu, vr, omega, h, steps, names):
    """Outputs at t = 0, h, ..., steps·h with the rotor speed held at omega."""
    fmu.setReal([vr["rotor_speed"]], [omega])
    rows = []
    for k in range(steps + 1):
        if k:
            fmu.doStep(currentCommunicationPoint=(k - 1) * h, communicationStepSize=h)
        rows.append([k * h] + fmu.getReal([vr[n] for n in names]))
    return np.array(rows)


def station_loads(omega, speeds):
    """Every station's radius and its normal and tangential load per unit span (N/m) at each wind speed
    with the rotor at omega and fine pitch: windrive aero's elements for drivetrain C's rotor."""
    normal, tangential = [], []
    for v in speeds:
        out = subprocess.run([str(WINDRIVE), "aero", "--preset", "C", "--tsr", repr(float(omega * 40.0 / v)), "--pitch", "0",
                              "--wind", repr(float(v)), "--elements"], check=True, capture_output=True, text=True)
        doc = json.loads(out.stdout)
        elements = doc["points"][0]["elements"]
        normal.append([e["normal_n_per_m"] for e in elements])
        tangential.append([e["tangential_n_per_m"] for e in elements])
    radii = np.array([e["radius"] for e in elements])
    return doc["hub_radius_m"], doc["radius_m"], radii, np.array(normal), np.array(tangential)


def summed_rotor(omega, azimuths, speeds, radius, wind):
    """Torque, thrust, tilt and yaw moment of C's rotor at omega summed here for each azimuth of blade 1:
    blade b at psi + 2πb/3 (0 = up), an element at radius r at height HUB + r·cos, lateral -r·sin,
    seeing the longitudinal wind wind(r, sin, cos); its loads per unit span interpolated in wind speed
    (over `speeds`) from windrive aero's elements, integrated over the span by the trapezoidal rule."""
    hub_r, tip_r, radii, normal, tangential = station_loads(omega, speeds)
    assert tip_r == radius == 40.0
    span = np.concatenate([[hub_r], radii, [tip_r]])

    def integral(values):
        return np.trapezoid(np.concatenate([[0.0], values, [0.0]]), span)

    expected = []
    for psi in azimuths:
        q = f = m_tilt = m_yaw = 0.0
        for b in range(3):
            s, c = math.sin(psi + 2 * math.pi * b / 3), math.cos(psi + 2 * math.pi * b / 3)
            v = wind(radii, s, c)
            assert speeds[0] <= v.min() and v.max() <= speeds[-1]
            n = np.array([np.interp(v[i], speeds, normal[:, i]) for i in range(len(radii))])
            tt = np.array([np.interp(v[i], speeds, tangential[:, i]) for i in range(len(radii))])
            q += integral(tt * radii)
            f += integral(n)
            m_tilt += integral(n * radii * c)
            m_yaw += integral(n * radii * s)
        expected.append((q, f, m_tilt, m_yaw))
    return np.array(expected).T


def three_harmonic(psi, x):
    """Mean and amplitude of the 3P harmonic of x(psi), by least squares."""
    basis = np.column_stack([np.ones_like(psi), np.cos(3 * psi), np.sin(3 * psi)])
    (mean, a, b), *_ = np.linalg.lstsq(basis, x, rcond=None)
    return mean, math.hypot(a, b)


def test_shear_gives_the_3p_torque_summed_here():
    fmu, vr = rotor({"preset": "C", "turbulence": "none", "wind_sampling": "blades"},
                    {"wind_speed": V_HUB, "shear_exponent": ALPHA, "initial_pitch": 0.0, "pitch_kp": 0.0,
                     "pitch_ki": 0.0})
    radius = fmu.getReal([vr["radius_used"]])[0]
    omega = fmu.getReal([vr["rated_tip_speed_ratio"]])[0] * fmu.getReal([vr["rated_wind_speed"]])[0] / radius
    h = 0.01
    steps = int(math.ceil(2 * math.pi / omega / h)) + 1
    series = run(fmu, vr, omega, h, steps, ["rotor_torque", "thrust", "tilt_moment", "yaw_moment", "pitch"])
    fmu.terminate()
    fmu.freeInstance()
    t, torque, thrust, tilt, yaw, pitch = series.T
    assert np.all(pitch == 0.0)

    # the summation here, each element in the wind at its own height from the power law
    q, f, m_tilt, m_yaw = summed_rotor(omega, omega * t, np.arange(9.25, 12.26, 0.125), radius,
                                       lambda r, s, c: V_HUB * ((HUB + r * c) / HUB) ** ALPHA)
    psi = omega * t

    # point by point: the table's interpolation error, 0.25 % of the torque, 0.1 % of the thrust
    assert np.max(np.abs(torque - q)) < 2.5e-3 * np.mean(q)
    assert np.max(np.abs(thrust - f)) < 1e-3 * np.mean(f)
    assert np.max(np.abs(tilt - m_tilt)) < 1e-3 * np.mean(f) * radius
    assert np.max(np.abs(yaw - m_yaw)) < 1e-3 * np.mean(f) * radius
    # the 3P harmonics: there, and as large as summed here
    (q_mean, q_3p), (mean_fmu, amp_fmu) = three_harmonic(psi, q), three_harmonic(psi, torque)
    # shear alone gives a 3-bladed rotor a small 3P torque (1.1e-4 of the mean here: the 1P parts of the
    # blades cancel); the table's interpolation error, which moves as the elements' inflow moves, adds a
    # 3P of its own of up to 2e-4 of the mean, so the FMU's amplitude is checked to that, not relatively
    assert q_3p > 1e-4 * q_mean, "shear gives a 3P torque"
    assert abs(amp_fmu - q_3p) < 2.5e-4 * q_mean, (amp_fmu, q_3p, q_mean)
    moments = []
    for fmu_series, here in [(tilt, m_tilt), (yaw, m_yaw)]:
        (_, a_here), (_, a_fmu) = three_harmonic(psi, here), three_harmonic(psi, fmu_series)
        print(f"3P moment amplitude {a_fmu:.4f} N·m (summed here {a_here:.4f})")
        assert abs(a_fmu - a_here) < 0.1 * a_here + 2.5e-4 * np.mean(f) * radius, (a_fmu, a_here)
        moments.append((a_fmu, a_here))
    # shear puts the thrust above the hub
    assert np.mean(m_tilt) > 0 and abs(np.mean(tilt) / np.mean(m_tilt) - 1) < 1e-2
    print(f"3P torque amplitude: {amp_fmu:.4f} N·m (summed here {q_3p:.4f}) of mean {mean_fmu:.0f} N·m")
    # docs/WIND.md quotes these amplitudes
    n = lambda x: f"{x:,.0f}".replace(",", " ")
    page = " ".join((ROOT / "docs" / "WIND.md").read_text().split())
    for quoted in [
        f"the 3P of the tilt and yaw moments {n(moments[0][0])} and {n(moments[1][0])} N·m against "
        f"{n(moments[0][1])} and {n(moments[1][1])} N·m summed there",
        f"tiny 3P ({n(q_3p)} N·m on {q_mean / 1e6:.1f} MN·m",
        f"(the FMU shows {n(amp_fmu)} N·m)",
    ]:
        assert quoted in page, f"docs/WIND.md should read: {quoted}"


def test_a_tilting_and_yawing_disc_is_damped_as_summed_here():
    """Uniform wind, the disc tilting and yawing at set rates (the inputs gearbox6dof's main-shaft rates
    feed): every element sees the wind less its own speed downwind, Ω_tilt·r·cos + Ω_yaw·r·sin, so the
    rotor's tilt and yaw moments oppose the motion (its aerodynamic damping). Summed here as in the shear
    test, point by point to the table's interpolation error; and the damping coefficients, the mean moment
    over the rate, equal for tilt and yaw on three blades."""
    tilt_rate, yaw_rate = 0.05, -0.03
    fmu, vr = rotor({"preset": "C", "turbulence": "none", "wind_sampling": "blades"},
                    {"wind_speed": V_HUB, "shear_exponent": 0.0, "initial_pitch": 0.0, "pitch_kp": 0.0,
                     "pitch_ki": 0.0, "tilt_rate": tilt_rate, "yaw_rate": yaw_rate})
    radius = fmu.getReal([vr["radius_used"]])[0]
    omega = fmu.getReal([vr["rated_tip_speed_ratio"]])[0] * fmu.getReal([vr["rated_wind_speed"]])[0] / radius
    h = 0.01
    steps = int(math.ceil(2 * math.pi / omega / h)) + 1
    series = run(fmu, vr, omega, h, steps, ["rotor_torque", "thrust", "tilt_moment", "yaw_moment"])
    fmu.terminate()
    fmu.freeInstance()
    t, torque, thrust, tilt, yaw = series.T
    q, f, m_tilt, m_yaw = summed_rotor(omega, omega * t, np.arange(7.25, 14.76, 0.125), radius,
                                       lambda r, s, c: V_HUB - tilt_rate * r * c - yaw_rate * r * s)
    assert np.max(np.abs(torque - q)) < 2.5e-3 * np.mean(q)
    assert np.max(np.abs(thrust - f)) < 1e-3 * np.mean(f)
    assert np.max(np.abs(tilt - m_tilt)) < 1e-3 * np.mean(f) * radius
    assert np.max(np.abs(yaw - m_yaw)) < 1e-3 * np.mean(f) * radius
    # damping: the moments oppose the rates, with one coefficient for both axes (to the rates' second order)
    c_tilt, c_yaw = -np.mean(m_tilt) / tilt_rate, -np.mean(m_yaw) / yaw_rate
    assert c_tilt > 0 and c_yaw > 0 and abs(c_tilt / c_yaw - 1) < 0.05, (c_tilt, c_yaw)
    assert abs(np.mean(tilt) / np.mean(m_tilt) - 1) < 1e-2 and abs(np.mean(yaw) / np.mean(m_yaw) - 1) < 1e-2
    print(f"aerodynamic damping of C's rotor at 11 m/s, rated speed: tilt {c_tilt:.4g}, yaw {c_yaw:.4g} N·m·s/rad "
          f"(FMU: {-np.mean(tilt) / tilt_rate:.4g}, {-np.mean(yaw) / yaw_rate:.4g})")
    # the FMU's documentation states the coefficient to the digits it prints
    page = (ROOT / "fmus" / "rotor" / "documentation.html").read_text()
    stated = re.search(r"C's rotor at 11 m/s and rated\s+speed: ([0-9.e+]+) N·m·s/rad", page)
    assert stated and abs(float(stated.group(1)) / c_tilt - 1) < 5e-3, (stated and stated.group(1), c_tilt)


def holds_c_disc(path):
    """Whether the file's grid holds C's rotor disc (40 m about an 80 m hub)."""
    g = read_bts(path)
    return (g["ny"] - 1) * g["dy"] / 2 >= 40 and g["zbottom"] <= 40 and g["zbottom"] + (g["nz"] - 1) * g["dz"] >= 120


@pytest.mark.parametrize("path", [p for p in turbsim_files() if holds_c_disc(p)])
def test_a_turbsim_file_drives_the_rotor(path):
    """C's 40 m rotor at its 80 m hub in a TurbSim file whose grid holds the disc (the shipped
    TurbSim_FAST.bts, and any named in WINDRIVE_TURBSIM_BTS): the hub wind the FMU reports is the file's grid
    interpolated here, and the torque is finite at every step."""
    grid = read_bts(path)
    ny, nz, dy, dz, dt, z0 = grid["ny"], grid["nz"], grid["dy"], grid["dz"], grid["dt"], grid["zbottom"]
    fmu, vr = rotor({"preset": "C", "wind_sampling": "blades", "wind_file": os.path.abspath(path)}, {})
    series = run(fmu, vr, 1.9, 0.01, int(round(grid["nt"] * dt / 0.01)) - 2,
                 ["wind_speed_hub", "rotor_torque", "tilt_moment"])
    fmu.terminate()
    fmu.freeInstance()
    t, hub, torque, tilt = series.T
    assert np.all(np.isfinite(torque)) and np.all(np.isfinite(tilt))
    # u at y = 0 (the middle column when ny is odd; else the two beside it) and the hub's height
    u = grid["grid"][..., 0]  # [time, z, y]
    column = u[:, :, (ny - 1) // 2] if ny % 2 else 0.5 * (u[:, :, ny // 2 - 1] + u[:, :, ny // 2])
    heights = z0 + dz * np.arange(nz)
    at_hub = np.array([np.interp(80.0, heights, column[k]) for k in range(grid["nt"])])
    times = dt * np.arange(grid["nt"])
    if grid["id"] == 8:  # periodic: after the last plane the field runs back to the first
        times, at_hub = np.append(times, grid["nt"] * dt), np.append(at_hub, at_hub[0])
    assert np.max(np.abs(hub - np.interp(t, times, at_hub))) < 1e-4 * np.max(np.abs(at_hub))
