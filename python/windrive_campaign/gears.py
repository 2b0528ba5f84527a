"""`[gears]`: every gear tooth of the case's gearbox rated by `windrive gears` on the case's series
(src/cli/gears.rs, src/analysis/gear_set.rs): ISO 6336 contact and root stress from the mesh forces, load
cycles from the speeds, a two-slope S-N curve and Miner's sum per day, as the paper does it (seed 004).

The rating stays in Rust, run as a second subprocess on the series the case just wrote, so the campaign's
figures are exactly what `windrive gears` prints for that series (tested to 1e-12). Each tooth becomes
five columns of the table, `gear.<tooth>.<column>`, NaN where windrive rates no such thing (a planet's
root is `p1`, its flanks `ps1` and `pr1`).
"""

from __future__ import annotations

from dataclasses import dataclass

from . import rating

# The channels `windrive gears --gearbox <table> --component <component>` reads, less the component's
# name, which the cases must record (a campaign records only what it analyses). They mirror the table's
# force and speed channels in gear_set.rs (paper_1p5mw; `windrive gears --channels` prints them); a
# mismatch is caught before any case runs, because the driver rates the scene's probe series
# (cases.snapshot_scene).
_CHANNELS: dict[str, tuple[str, ...]] = {
    "P": (
        "mesh_force_sun_planet_1",
        "rotor_speed",
        "mesh_force_ring_planet_1",
        "mesh_force_sun_planet2_1",
        "mesh_force_ring_planet2_1",
        "mesh_force_gear_pinion_1",
    ),
}
TABLES = tuple(_CHANNELS)
# each FMU whose outputs windrive gears reads (its --fmu), with the name the repository's scenes give it
FMUS = {"torsional": "torsional", "gearbox6dof": "gearbox"}
DEFAULT_FMU = "torsional"


@dataclass(frozen=True)
class Gears:
    """[gears]: the gear table, the FMU whose mesh forces the series holds (the torsional FMU with
    preset P gives transverse forces, the gearbox6dof FMU with the paper's gearbox normal ones) and its
    name in the scene."""

    table: str
    fmu: str = DEFAULT_FMU
    component: str = FMUS[DEFAULT_FMU]

    def channels(self) -> tuple[str, ...]:
        return tuple(f"{self.component}.{c}" for c in _CHANNELS[self.table])


# table column suffix -> the field of `windrive gears --json`
COLUMNS = {
    "flank_day": "flank_damage_per_day",
    "root_day": "root_damage_per_day",
    "max_contact": "max_contact_stress",
    "max_root": "max_root_stress",
    "cycles": "load_cycles",
}


class GearsError(Exception):
    """`windrive gears` failed on the series; the message is its stderr."""


def command(windrive: str, series: str, gears: Gears, transient: float) -> list[str]:
    return [
        windrive, "gears", series, "--gearbox", gears.table, "--fmu", gears.fmu, "--component", gears.component,
        "--transient", repr(transient), "--json",
    ]  # fmt: skip


def rate(windrive: str, series: str, gears: Gears, transient: float, timeout: float) -> dict[str, float]:
    """The table's columns for one series; GearsError with windrive's stderr when it fails."""
    return rating.rate(command(windrive, series, gears, transient), "gear", COLUMNS, timeout, GearsError)
