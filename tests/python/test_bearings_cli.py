"""`windrive bearings` against an independent ISO 281 evaluation: the GRC gearbox's roller sets read
from its description, f_c interpolated in ISO 281 Table 7 (not the closed form the binary uses),
ring speeds from the tooth counts, X and Y from ISO 281 Table 8; and bad input named."""

import json
import subprocess
import tomllib
from pathlib import Path

import numpy as np
import pytest

from test_rainflow import write_csv

GRC = Path(__file__).resolve().parents[2] / "fmus/gearbox6dof/resources/grc750.toml"

# ISO 281:2007 Table 7, f_c of radial roller bearings at γ = 0.01 … 0.30
FC_TABLE = [52.1, 60.8, 66.5, 70.7, 74.1, 76.9, 79.2, 81.2, 82.8, 84.2, 85.4, 86.4, 87.1, 87.7, 88.2, 88.5,
            88.7, 88.8, 88.8, 88.7, 88.5, 88.2, 87.9, 87.5, 87.0, 86.4, 85.8, 85.2, 84.5, 83.8]


def iso_281_rating(r):
    """C_r in N from a description's roller set, f_c interpolated in the table."""
    cos = np.cos(np.radians(r.get("contact_angle_deg", 0.0)))
    gamma = r["diameter_mm"] * cos / r["pitch_diameter_mm"]
    fc = np.interp(gamma, np.arange(1, 31) / 100, FC_TABLE)
    b_m = 1.15 if r.get("contact") == "point" else 1.1
    return (b_m * fc * (r.get("rows", 1) * r["length_mm"] * cos) ** (7 / 9) * r["count"] ** 0.75
            * r["diameter_mm"] ** (29 / 27))


def grc_bearings():
    """Every GRC bearing with rollers: its roller set and its rings' speed over the rotor's."""
    d = tomllib.loads(GRC.read_text())
    planetary, intermediate, high = (s.get("planetary") or s.get("parallel") for s in d["stage"])
    t = planetary["teeth"]
    lss = 1 + t["ring"] / t["sun"]
    ims = lss * intermediate["teeth"]["gear"] / intermediate["teeth"]["pinion"]
    hss = ims * high["teeth"]["gear"] / high["teeth"]["pinion"]
    bodies = [
        (planetary["carrier"], "", 1.0),
        (intermediate["gear"], "", lss),
        (intermediate["pinion"], "", ims),
        (high["gear"], "", ims),
        (high["pinion"], "", hss),
    ]
    # a planet bearing turns with the planet against its carrier: z_ring / z_planet
    bodies += [(planetary["planet"], f"planet_{k}_", t["ring"] / t["planet"]) for k in (1, 2, 3)]
    out = {}
    for body, prefix, ratio in bodies:
        for b in body.get("bearings", []):
            if "rollers" in b:
                out[prefix + b["name"]] = (b["rollers"], ratio)
    return out, hss


def constant_series(path, radial, axial, rotor_speed, generator_speed, seconds=10.0):
    t = np.arange(0, seconds + 1e-9, 0.01)
    bearings, _ = grc_bearings()
    columns = {}
    for name in bearings:
        columns[f"gearbox.{name}_radial_load"] = np.full_like(t, radial)
        columns[f"gearbox.{name}_axial_load"] = np.full_like(t, axial)
    columns["gearbox.rotor_speed"] = np.full_like(t, rotor_speed)
    columns["gearbox.generator_speed"] = np.full_like(t, generator_speed)
    write_csv(path, t, columns)


@pytest.mark.parametrize("axial", [0.0, 50e3])
def test_constant_loads_rate_as_iso_281_by_hand(windrive, tmp_path, axial):
    """C within 0.1 %: f_c interpolated linearly between table rows rounded to 0.1 (≤ 0.06 %); the
    damage, ∝ C^(-10/3), within 0.4 %."""
    bearings, hss = grc_bearings()
    path = tmp_path / "c.csv"
    radial, speed, seconds = 100e3, 2.0, 10.0
    constant_series(path, radial, axial, speed, speed * hss, seconds)
    out = subprocess.run([windrive, "bearings", str(path), "--json"], capture_output=True, text=True, check=True)
    rated = {r["name"]: r for r in json.loads(out.stdout)}
    assert set(rated) == set(bearings)
    for name, (rollers, ratio) in bearings.items():
        r = rated[name]
        c = iso_281_rating(rollers)
        alpha = np.radians(abs(rollers.get("contact_angle_deg", 0.0)))
        if alpha > 0 and axial > 1.5 * np.tan(alpha) * radial:
            p = 0.4 * radial + 0.4 / np.tan(alpha) * axial
        else:
            p = radial
        revolutions = speed * ratio * seconds / (2 * np.pi)
        damage = revolutions / ((c / p) ** (10 / 3) * 1e6)
        assert r["dynamic_load_rating"] == pytest.approx(c, rel=1e-3), name
        assert r["speed_ratio"] == pytest.approx(ratio, rel=1e-9), name
        assert r["revolutions"] == pytest.approx(revolutions, rel=1e-9), name
        assert r["equivalent_load"] == pytest.approx(p, rel=1e-9), name
        assert r["damage"] == pytest.approx(damage, rel=4e-3), name
        assert r["damage_per_day"] == pytest.approx(damage * 86400 / seconds, rel=4e-3), name
        assert r["thesis_damage"] == 0, name  # a constant load has no load cycles
    # the tapered pair's axial load shows only beyond e = 1.5 tan 13° = 0.35
    assert (rated["hss_b"]["equivalent_load"] > radial) == (axial > 0.35 * radial)


def test_a_series_of_another_gearbox_is_refused(windrive, tmp_path):
    _, hss = grc_bearings()
    path = tmp_path / "other.csv"
    constant_series(path, 100e3, 0.0, 2.0, 2.0 * 100.75)
    out = subprocess.run([windrive, "bearings", str(path)], capture_output=True, text=True)
    assert out.returncode != 0
    for w in ["other.csv", "100.75", f"{hss:.4f}", "not from this gearbox"]:
        assert w in out.stderr, out.stderr


def test_channels_list_what_the_rating_reads(windrive):
    out = subprocess.run([windrive, "bearings", "--channels"], capture_output=True, text=True, check=True)
    names = out.stdout.split()
    bearings, _ = grc_bearings()
    assert len(names) == 2 * len(bearings) + 2
    assert "gearbox.planet_3_uw_radial_load" in names and "gearbox.generator_speed" in names


@pytest.mark.parametrize("args,words", [
    (["bearings", "{csv}", "--gearbox", "nosuch"], ["--gearbox", "nosuch", "grc750"]),
    (["bearings", "{csv}", "--gearbox", "nrel5mw"], ["nrel5mw", "no bearing has a roller set"]),
    (["bearings", "{csv}", "--transient=-1"], ["--transient -1"]),
    (["bearings", "{csv}"], ["x.csv", "gearbox.carrier_a_radial_load"]),
    (["bearings", "{csv}", "--component", "gb"], ["x.csv", "gb.carrier_a_radial_load"]),
])
def test_bad_bearing_input_is_named(windrive, tmp_path, args, words):
    csv = tmp_path / "x.csv"
    t = np.arange(100) * 0.01
    write_csv(csv, t, {"x": np.sin(t * 7)})
    args = [a.format(csv=csv) for a in args]
    out = subprocess.run([windrive, *args], capture_output=True, text=True, env={"RUST_BACKTRACE": "0"})
    assert out.returncode != 0
    for w in words:
        assert w in out.stderr, out.stderr


def test_the_thesis_count_is_rainflow_cycles_of_the_load(windrive, tmp_path):
    """thesis_damage = Σ n_i / (10⁶ (C/ΔP_i)^(10/3)) over the `rainflow` package's cycles of P (here the
    radial load of a cylindrical bearing): the thesis's count, checked to 1e-9."""
    import rainflow

    bearings, hss = grc_bearings()
    t = np.arange(0, 10 + 1e-9, 0.01)
    rng = np.random.default_rng(3)
    radial = 100e3 + 40e3 * np.sin(2 * np.pi * 0.7 * t) + 10e3 * rng.normal(size=t.size)
    columns = {}
    for name in bearings:
        columns[f"gearbox.{name}_radial_load"] = radial
        columns[f"gearbox.{name}_axial_load"] = np.zeros_like(t)
    columns["gearbox.rotor_speed"] = np.full_like(t, 2.0)
    columns["gearbox.generator_speed"] = np.full_like(t, 2.0 * hss)
    path = tmp_path / "v.csv"
    write_csv(path, t, columns)
    out = subprocess.run([windrive, "bearings", str(path), "--json"], capture_output=True, text=True, check=True)
    r = next(b for b in json.loads(out.stdout) if b["name"] == "planet_1_uw")
    c = r["dynamic_load_rating"]
    expected = sum(n / (1e6 * (c / rng_) ** (10 / 3)) for rng_, n in rainflow.count_cycles(radial) if rng_ > 0)
    assert r["thesis_damage"] == pytest.approx(expected, rel=1e-9)
    assert r["thesis_damage_per_day"] == pytest.approx(expected * 8640, rel=1e-9)


def test_life_of_a_named_bearing_is_life_of_its_load_and_ring_speed(windrive, tmp_path):
    """`windrive life --bearing-of planet_2_uw` = `windrive life --bearing C --channel P --speed ω_rings`
    on the same series with P and the rings' speed written out by hand (P = F_r for the cylindrical
    bearing, ω_rings = ω_rotor · z_r/z_p): the lifetime's scaling is shared, the naming is what is new."""
    bearings, hss = grc_bearings()
    rollers, ratio = bearings["planet_2_uw"]
    t = np.arange(0, 10 + 1e-9, 0.01)
    radial = 150e3 + 30e3 * np.sin(2 * np.pi * 0.5 * t)
    rotor = 2.0 + 0.1 * np.sin(2 * np.pi * 0.2 * t)
    columns = {}
    for name in bearings:
        columns[f"gearbox.{name}_radial_load"] = radial
        columns[f"gearbox.{name}_axial_load"] = 0.2 * radial
    columns["gearbox.rotor_speed"] = rotor
    columns["gearbox.generator_speed"] = rotor * hss
    columns["p"] = radial
    columns["w"] = rotor * ratio
    path = tmp_path / "n.csv"
    write_csv(path, t, columns)
    named = json.loads(subprocess.run([windrive, "life", "--normal", str(path), "--shutdown", str(path),
                                       "--bearing-of", "planet_2_uw", "--json"],
                                      capture_output=True, text=True, check=True).stdout)["bearing"]  # fmt: skip
    c = named["capacity"]
    assert c == pytest.approx(iso_281_rating(rollers), rel=1e-3)
    by_hand = json.loads(subprocess.run([windrive, "life", "--normal", str(path), "--shutdown", str(path),
                                         "--bearing", repr(c), "--channel", "p", "--speed", "w", "--json"],
                                        capture_output=True, text=True, check=True).stdout)["bearing"]  # fmt: skip
    for key in ["damage", "revolutions", "equivalent_load", "shutdown_share", "l10_years"]:
        assert named[key] == pytest.approx(by_hand[key], rel=1e-12), key

    # another gearbox's series is refused, an unknown name lists the bearings there are
    columns["gearbox.generator_speed"] = rotor * 100.0
    write_csv(path, t, columns)
    out = subprocess.run([windrive, "life", "--normal", str(path), "--bearing-of", "planet_2_uw"],
                         capture_output=True, text=True)  # fmt: skip
    assert out.returncode != 0 and "not from this gearbox" in out.stderr, out.stderr
    out = subprocess.run([windrive, "life", "--normal", str(path), "--bearing-of", "planet_9"],
                         capture_output=True, text=True)  # fmt: skip
    assert out.returncode != 0 and "planet_9" in out.stderr and "hss_c" in out.stderr, out.stderr
