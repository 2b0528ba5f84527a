"""`[gears]`: every gear tooth of the case's gearbox rated on the case's series, inside the case's own
`windrive run --analyse` (src/analysis/case.rs through src/analysis/rating/gear_set.rs, as `windrive gears`
rates a series): ISO 6336 contact and root stress from the mesh forces, load cycles from the speeds, a
two-slope S-N curve and Miner's sum per day, as the paper does it (its §1.3).

The campaign's figures are exactly what `windrive gears` prints for the same series (tested to 1e-12). The
gear table is P
(the paper's, hand-built) or any gearbox6dof description (a preset or a file), whose planetary stage k
has the teeth s<k>, p<k>, ps<k>, pr<k>, r<k> and parallel stage k p<k>, g<k>. Each tooth becomes five
columns of the table, `gear.<tooth>.<column>`, NaN where windrive rates no such thing (a planet's root is
`p1`, its flanks `ps1` and `pr1`).
"""

from __future__ import annotations

from dataclasses import dataclass

from . import rating

# each FMU whose outputs windrive gears reads (its --fmu), with the name the repository's scenes give it
FMUS = {"torsional": "torsional", "gearbox6dof": "gearbox"}
DEFAULT_FMU = "torsional"


class GearsError(Exception):
    """`windrive gears --channels` failed; the message is its stderr."""


@dataclass(frozen=True)
class Gears:
    """[gears]: the gear table (P, the paper's hand-built one, or a gearbox6dof description: a preset
    name or a description file), the FMU whose mesh forces the series holds (the torsional FMU with
    preset P gives transverse forces, the gearbox6dof FMU normal ones) and its name in the scene."""

    table: str
    fmu: str = DEFAULT_FMU
    component: str = FMUS[DEFAULT_FMU]
    # the face load factor K_Hβ: "one" (nominal stresses, as the paper) or "model" (each sample's from
    # gearbox6dof's face_load_factor_<mesh>, `windrive gears --face-load model`)
    face_load: str = "one"
    # ISO 6336-1's dynamic factor K_v on every mesh (`windrive gears --dynamic-factor`): 1 rates the simulated
    # load, which at mean mesh stiffness holds no tooth-mesh dynamics; IEC 61400-4 asks for at least 1.05
    dynamic_factor: float = 1.0

    def options(self) -> list[str]:
        """The table, FMU, component, face load and dynamic factor as `windrive gears` takes them."""
        face_load = ["--face-load", self.face_load] if self.face_load != "one" else []
        k_v = ["--dynamic-factor", repr(self.dynamic_factor)] if self.dynamic_factor != 1.0 else []
        return ["--gearbox", self.table, "--fmu", self.fmu, "--component", self.component, *face_load, *k_v]

    def spec(self) -> dict:
        """As the analysis spec holds it: the face load and the dynamic factor only when set, so campaigns
        without them keep their digests."""
        spec = {"table": self.table, "fmu": self.fmu, "component": self.component}
        if self.face_load != "one":
            spec["face_load"] = self.face_load
        if self.dynamic_factor != 1.0:
            spec["dynamic_factor"] = self.dynamic_factor
        return spec

    def channels(self, windrive: str) -> tuple[str, ...]:
        """What `windrive gears` reads: the mesh forces and the rotor speed (rating.channels)."""
        return rating.channels([windrive, "gears", "--channels", *self.options()], GearsError)


# table column suffix (as the analysis names it) -> the field of `windrive gears --json`
COLUMNS = {
    "flank_day": "flank_damage_per_day",
    "root_day": "root_damage_per_day",
    "max_contact": "max_contact_stress",
    "max_root": "max_root_stress",
    "cycles": "load_cycles",
}


def command(windrive: str, series: str, gears: Gears, transient: float) -> list[str]:
    """`windrive gears` on a series: the scene's probe is rated with it before any case runs."""
    return [windrive, "gears", series, *gears.options(), "--transient", repr(transient), "--json"]
