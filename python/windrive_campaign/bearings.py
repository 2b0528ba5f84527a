"""`[bearings]`: every rolling bearing of the case's gearbox6dof gearbox rated on the case's series, inside
the case's own `windrive run --analyse` (src/analysis/case.rs through src/analysis/rating/bearing_set.rs, as
`windrive bearings` rates a series): ISO 281's basic dynamic load rating C_r from each roller set, the
equivalent load P = X·F_r + Y·F_a per sample, the rings' revolutions from the gearbox's kinematics and
Miner's sum of revolutions over L10 per day.

The campaign's figures are exactly what `windrive bearings` prints for the same series (tested to 1e-12).
Each bearing with a roller set becomes six columns of the table, `bearing.<name>.<column>`.
"""

from __future__ import annotations

from dataclasses import dataclass

from . import rating

DEFAULT_GEARBOX = "grc750"
DEFAULT_COMPONENT = "gearbox"


class BearingsError(Exception):
    """`windrive bearings --channels` failed; the message is its stderr."""


@dataclass(frozen=True)
class Bearings:
    """[bearings]: the gearbox description the scene's gearbox6dof FMU runs (a preset or a description
    file) and the FMU's name in the scene, the prefix of the channels."""

    gearbox: str = DEFAULT_GEARBOX
    component: str = DEFAULT_COMPONENT
    # the oil ISO 281's a_ISO is taken with (windrive bearings --oil-viscosity, --oil-temperature,
    # --contamination); None: windrive's estimate
    oil_viscosity: tuple[float, float] | None = None
    oil_temperature: float | None = None
    contamination: float | None = None

    def oil(self) -> dict:
        """The oil settings given, as the analysis spec and `windrive bearings` take them."""
        given = {"oil_viscosity": self.oil_viscosity, "oil_temperature": self.oil_temperature,
                 "contamination": self.contamination}  # fmt: skip
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in given.items() if v is not None}

    def spec(self) -> dict:
        """[bearings] as `windrive run --analyse` reads it (unset oil keys left out: the digest of a campaign
        that sets none stays as it was)."""
        return {"gearbox": self.gearbox, "component": self.component, **self.oil()}

    def channels(self, windrive: str) -> tuple[str, ...]:
        """What `windrive bearings` reads: every roller set's loads, the rotor and generator speeds
        (rating.channels; a gearbox without roller sets fails here)."""
        cmd = [windrive, "bearings", "--channels", "--gearbox", self.gearbox, "--component", self.component]
        return rating.channels(cmd, BearingsError)


# table column suffix (as the analysis names it) -> the field of `windrive bearings --json`. The window's L10h is left out: it is
# 24 / day hours, and infinite (JSON null) for a bearing that did not turn.
COLUMNS = {
    "day": "damage_per_day",
    "p_eq": "equivalent_load",
    "p_max": "max_equivalent_load",
    "revolutions": "revolutions",
    "c": "dynamic_load_rating",
    "thesis_day": "thesis_damage_per_day",  # the thesis's count (rainflow cycles of P), for comparison
    "nm_day": "modified_damage_per_day",  # ISO 281's modified life a_ISO·L10, the default (estimated) oil
}


def command(windrive: str, series: str, bearings: Bearings, transient: float) -> list[str]:
    """`windrive bearings` on a series: the scene's probe is rated with it before any case runs."""
    oil = []
    for key, value in bearings.oil().items():
        flag = "--" + key.replace("_", "-")
        oil += [flag, ",".join(repr(float(x)) for x in value)] if isinstance(value, list) else [flag, repr(value)]
    return [
        windrive, "bearings", series, "--gearbox", bearings.gearbox, "--component", bearings.component,
        "--transient", repr(transient), *oil, "--json",
    ]  # fmt: skip
