"""Reads a campaign file (TOML) into frozen dataclasses and rejects anything it does not know.

Every mistake is a CampaignError naming the file, the key (dotted, `event[2]` counting array tables from
1) and the line: tomllib gives the line of a syntax error; for a valid file with a wrong key or value the
line is found by looking for the key inside its table in the text (best effort: no line when the key is
not written literally). The reference of every key is docs/CAMPAIGNS.md; keep the two in step.
"""

from __future__ import annotations

import hashlib
import json
import math
import re
import tomllib
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from . import bearings as bearings_mod
from . import gears as gears_mod
from .errors import CampaignError

TURBULENCE_CLASSES = ("A", "B", "C")  # IEC 61400-1 ed. 3; I_ref: src/physics/turbulence.rs
# IEC 61400-1 ed. 3, DLC 1.2: 10-minute series, at least six seeds per wind bin: a campaign's
# defaults, so the lifetime's seed-to-seed scatter is what the standard accepts
IEC_WINDOW_S = 600.0
IEC_SEEDS = 6
# what the DLC 1.2 rotor blows unless the campaign says: IEC 61400-1's turbulence as a full field (u, v, w with
# coherence and shear) sampled by each blade element as it turns, so 3P, shear and the rotor's tilt and yaw
# moments are in the loads (docs/WIND.md); rotor_average is one longitudinal series, the cheaper option
WIND_SAMPLINGS = ("blades", "rotor_average")

ParamValue = str | int | float | bool


@dataclass(frozen=True)
class Ldd:
    """Load duration distribution of a channel over fixed bins (fixed so cases add up)."""

    speed: str  # speed channel in rad/s whose revolutions count the load cycles
    min: float
    max: float
    bins: int


@dataclass(frozen=True)
class Channel:
    name: str
    m: tuple[float, ...] = ()  # Wöhler slopes, one DEL each
    ldd: Ldd | None = None


@dataclass(frozen=True)
class Climate:
    k: float  # Weibull shape (2 for Rayleigh)
    a: float  # Weibull scale, m/s
    years: float
    source: str  # as the file gave it ("Weibull k = …, A = … m/s" or "Rayleigh mean … m/s"), for the table


@dataclass(frozen=True)
class Dlc12:
    cut_in: float
    cut_out: float
    bin_width: float
    seeds: tuple[int, ...]
    turbulence_class: str | None
    turbulence_intensity: float | None
    rotor: str  # component carrying wind_speed, seed, turbulence, turbulence_intensity
    params: dict[str, ParamValue] = field(default_factory=dict)
    # the rotor's wind_sampling; None: blades unless the campaign's params set it (cases.expand)
    wind_sampling: str | None = None


@dataclass(frozen=True)
class Event:
    name: str
    scene: Path
    per_year: float
    stop_time: float
    transient: float
    params: dict[str, ParamValue] = field(default_factory=dict)


@dataclass(frozen=True)
class Slurm:
    queue: str | None
    account: str | None
    cores: int
    memory: str
    walltime: str
    jobs: int
    job_extra_directives: tuple[str, ...]
    job_script_prologue: tuple[str, ...]
    python: str | None
    local_directory: str | None


@dataclass(frozen=True)
class Campaign:
    path: Path
    name: str
    scene: Path
    stop_time: float
    transient: float
    step: float | None
    timeout: float
    keep_series: bool
    record: tuple[str, ...]
    feq: float
    params: dict[str, ParamValue]
    channels: tuple[Channel, ...]
    climate: Climate | None
    dlc12: Dlc12 | None
    # one table of axes per [[grid]] (a single [grid] is one); the cases are the union of their products
    grids: tuple[dict[str, tuple[ParamValue, ...]], ...]
    events: tuple[Event, ...]
    slurm: Slurm | None
    gears: gears_mod.Gears | None = None  # [gears]: what `windrive gears` rates each case with
    bearings: bearings_mod.Bearings | None = None  # [bearings]: what `windrive bearings` rates each case with

    def analysis_spec(self) -> dict:
        """What the analysis of a series depends on (not the simulation): a result whose analysis
        digest differs is stale and its case runs again."""
        spec = {"channels": [asdict(c) for c in self.channels], "feq": self.feq}
        if self.gears is not None:  # only when rated: the digests of campaigns without [gears] stay as they were
            g = self.gears
            spec["gears"] = g.table if g == gears_mod.Gears(g.table) else g.spec()
        if self.bearings is not None:  # likewise: campaigns without [bearings] keep their digests
            spec["bearings"] = self.bearings.spec()
        return spec

    def analysis_digest(self) -> str:
        spec = json.dumps(self.analysis_spec(), sort_keys=True)
        return hashlib.sha256(spec.encode()).hexdigest()[:16]


# ---------------------------------------------------------------------------------------------------
# reading


def load(path: str | Path) -> Campaign:
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as e:
        raise CampaignError(f"{path}: cannot read the campaign file: {e.strerror}") from None
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        # tomllib's message ends with "(at line L, column C)" (Python < 3.14 has no e.lineno); lead
        # with the location as compilers do
        found = re.search(r"\s*\(at line (\d+), column \d+\)$", str(e))
        message = str(e)[: found.start()] if found else str(e)
        line = found.group(1) if found else None
        where = f"{path}:{line}" if line else f"{path}"
        raise CampaignError(f"{where}: not valid TOML: {message}") from None
    return _Reader(path, text).campaign(doc)


class _Reader:
    def __init__(self, path: Path, text: str):
        self.path = path
        self.text = text
        self.base = path.resolve().parent  # relative scene paths are relative to the campaign file

    # -- errors --------------------------------------------------------------------------------------

    def fail(self, key: tuple, message: str):
        line = _locate(self.text, key)
        where = f"{self.path}:{line}" if line else f"{self.path}"
        raise CampaignError(f"{where}: {_dotted(key)}: {message}")

    def check_keys(self, table: dict, key: tuple, known: tuple[str, ...]):
        for k in table:
            if k not in known:
                self.fail(key + (k,), f"unknown key (known here: {', '.join(known)})")

    # -- typed getters ---------------------------------------------------------------------------------

    def table(self, doc: dict, key: tuple, name: str, required=False) -> dict | None:
        v = doc.get(name)
        if v is None:
            if required:
                self.fail(key + (name,), "missing (a table)")
            return None
        if not isinstance(v, dict):
            self.fail(key + (name,), f"must be a table, not {_kind(v)}")
        return v

    def number(self, doc: dict, key: tuple, name: str, default=None, minimum=None, above=None) -> float:
        v = doc.get(name, default)
        if v is None:
            self.fail(key + (name,), "missing (a number)")
        if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v):
            self.fail(key + (name,), f"must be a finite number, not {v!r}")
        if minimum is not None and v < minimum:
            self.fail(key + (name,), f"must be at least {minimum}, not {v!r}")
        if above is not None and v <= above:
            self.fail(key + (name,), f"must be above {above}, not {v!r}")
        return float(v)

    def integer(self, doc: dict, key: tuple, name: str, default=None, minimum=None) -> int:
        v = doc.get(name, default)
        if v is None:
            self.fail(key + (name,), "missing (an integer)")
        if isinstance(v, bool) or not isinstance(v, int):
            self.fail(key + (name,), f"must be an integer, not {v!r}")
        if minimum is not None and v < minimum:
            self.fail(key + (name,), f"must be at least {minimum}, not {v!r}")
        return v

    def string(self, doc: dict, key: tuple, name: str, default=None, choices=None) -> str | None:
        v = doc.get(name, default)
        if v is None:
            return None
        if not isinstance(v, str) or not v:
            self.fail(key + (name,), f"must be a non-empty string, not {v!r}")
        if choices and v not in choices:
            self.fail(key + (name,), f"must be one of {', '.join(choices)}, not {v!r}")
        return v

    def boolean(self, doc: dict, key: tuple, name: str, default: bool) -> bool:
        v = doc.get(name, default)
        if not isinstance(v, bool):
            self.fail(key + (name,), f"must be true or false, not {v!r}")
        return v

    def strings(self, doc: dict, key: tuple, name: str) -> tuple[str, ...]:
        v = doc.get(name, [])
        if not isinstance(v, list) or not all(isinstance(s, str) and s for s in v):
            self.fail(key + (name,), f"must be a list of non-empty strings, not {v!r}")
        return tuple(v)

    def channel_name(self, doc: dict, key: tuple, name: str) -> str:
        v = self.string(doc, key, name)
        if v is None:
            self.fail(key + (name,), "missing (component.variable)")
        if not _PARAM_NAME.fullmatch(v):
            self.fail(key + (name,), f"must be component.variable, not {v!r}")
        return v

    def channel_names(self, doc: dict, key: tuple, name: str) -> tuple[str, ...]:
        names = self.strings(doc, key, name)
        for n in names:
            if not _PARAM_NAME.fullmatch(n):
                self.fail(key + (name,), f"channels are named component.variable, not {n!r}")
        return names

    def scene(self, doc: dict, key: tuple, name: str, default: Path | None = None) -> Path:
        v = doc.get(name)
        if v is None:
            if default is None:
                self.fail(key + (name,), "missing (a scene folder or .ssp, relative to the campaign file)")
            return default
        if not isinstance(v, str) or not v:
            self.fail(key + (name,), f"must be a path, not {v!r}")
        p = (self.base / v).resolve()
        if p.is_dir():
            if not (p / "SystemStructure.ssd").is_file():
                self.fail(key + (name,), f"{p} has no SystemStructure.ssd")
        elif not (p.is_file() and p.suffix == ".ssp"):
            self.fail(key + (name,), f"{p}: no such scene folder or .ssp file")
        return p

    def params(self, doc: dict, key: tuple, name: str | None, lists: bool = False) -> dict:
        """Scene parameters as component.variable → value, written either as quoted dotted keys
        ("torsional.fidelity" = "5") or as TOML's dotted keys (torsional.fidelity = "5", a nested
        table); with `lists` each value is a non-empty list of values (a grid axis)."""
        table = doc if name is None else doc.get(name, {})
        here = key if name is None else key + (name,)
        if not isinstance(table, dict):
            self.fail(here, f"must be a table of component.variable = value, not {_kind(table)}")
        flat: dict = {}
        for k, v in table.items():
            if isinstance(v, dict) and "." not in k:
                for var, value in v.items():
                    flat[f"{k}.{var}"] = (here + (k, var), value)
            else:
                flat[k] = (here + (k,), v)
        out = {}
        for pname, (pkey, value) in flat.items():
            if not _PARAM_NAME.fullmatch(pname):
                self.fail(pkey, "a parameter is named component.variable")
            if lists:
                if not isinstance(value, list) or not value:
                    self.fail(pkey, f"a grid axis is a non-empty list of values, not {value!r}")
                for v in value:
                    self.param_value(pkey, v)
                if len(set(map(repr, value))) != len(value):
                    self.fail(pkey, f"repeated value in {value!r}")
                out[pname] = tuple(value)
            else:
                out[pname] = self.param_value(pkey, value)
        return out

    def param_value(self, key: tuple, v: Any) -> ParamValue:
        if isinstance(v, bool | str | int) or (isinstance(v, float) and math.isfinite(v)):
            return v
        self.fail(key, f"a parameter value is a string, integer, finite number or boolean, not {v!r}")

    # -- the campaign ----------------------------------------------------------------------------------

    def campaign(self, doc: dict) -> Campaign:
        top = (
            "name", "scene", "stop_time", "transient", "step", "timeout", "keep_series", "record", "feq",
            "params", "channel", "climate", "dlc12", "grid", "event", "slurm", "gears", "bearings",
        )  # fmt: skip
        self.check_keys(doc, (), top)
        root = ()
        name = self.string(doc, root, "name", default=self.path.stem)
        if not re.fullmatch(r"[A-Za-z0-9._-]+", name):
            self.fail(("name",), f"letters, digits, '.', '_' and '-' only (it names a folder), not {name!r}")
        transient = self.number(doc, root, "transient", default=0.0, minimum=0.0)
        # with [dlc12], IEC 61400-1's 10-minute series after the transient unless the file says otherwise
        window = IEC_WINDOW_S if "dlc12" in doc else None
        stop_time = self.number(doc, root, "stop_time", default=None if window is None else transient + window, above=0.0)
        if transient >= stop_time:
            self.fail(("transient",), f"{transient} s leaves nothing of stop_time = {stop_time} s to analyse")
        step = doc.get("step")
        step = None if step is None else self.number(doc, root, "step", above=0.0)
        channels = self.channels(doc)
        climate = self.climate(doc)
        dlc12 = self.dlc12(doc)
        if dlc12 is not None and climate is None:
            self.fail(("dlc12",), "DLC 1.2 cases are weighted by the wind climate: add a [climate] table")
        grids = self.grids(doc)
        scene = self.scene(doc, root, "scene")
        events = self.events(doc, scene, stop_time, transient)
        if dlc12 is None and not grids and not events:
            self.fail(("dlc12",), "the campaign has no load cases: give [dlc12], [grid] or [[event]]")
        return Campaign(
            path=self.path,
            name=name,
            scene=scene,
            stop_time=stop_time,
            transient=transient,
            step=step,
            timeout=self.number(doc, root, "timeout", default=3600.0, above=0.0),
            keep_series=self.boolean(doc, root, "keep_series", False),
            record=self.channel_names(doc, root, "record"),
            feq=self.number(doc, root, "feq", default=1.0, above=0.0),
            params=self.params(doc, root, "params"),
            channels=channels,
            climate=climate,
            dlc12=dlc12,
            grids=grids,
            events=events,
            slurm=self.slurm(doc),
            gears=self.gears(doc),
            bearings=self.bearings(doc),
        )

    def channels(self, doc: dict) -> tuple[Channel, ...]:
        entries = doc.get("channel")
        if entries is None:
            self.fail(("channel",), "missing: at least one [[channel]] with name = \"component.variable\"")
        if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
            self.fail(("channel",), "must be an array of tables, [[channel]]")
        out = []
        for i, e in enumerate(entries, 1):
            key = (("channel", i),)
            self.check_keys(e, key, ("name", "m", "ldd"))
            name = self.channel_name(e, key, "name")
            m = e.get("m", [])
            if not isinstance(m, list) or not all(
                not isinstance(x, bool) and isinstance(x, int | float) and x > 0 for x in m
            ):
                self.fail(key + ("m",), f"Wöhler slopes are a list of positive numbers, e.g. [3, 6, 9], not {m!r}")
            ldd = None
            if "ldd" in e:
                t = self.table(e, key, "ldd")
                lk = key + ("ldd",)
                self.check_keys(t, lk, ("speed", "min", "max", "bins"))
                lo = self.number(t, lk, "min")
                hi = self.number(t, lk, "max")
                if hi <= lo:
                    self.fail(lk + ("max",), f"must be above min = {lo}, not {hi}")
                ldd = Ldd(self.channel_name(t, lk, "speed"), lo, hi, self.integer(t, lk, "bins", default=20, minimum=1))
            out.append(Channel(name, tuple(float(x) for x in m), ldd))
        names = [c.name for c in out]
        for i, n in enumerate(names, 1):
            if names.index(n) != i - 1:
                self.fail((("channel", i), "name"), f"{n} is analysed twice")
        return tuple(out)

    def grids(self, doc: dict) -> tuple[dict[str, tuple[ParamValue, ...]], ...]:
        """`[grid]` (one table of axes, as before) or `[[grid]]` (several, counted from 1 in errors).
        An empty [grid] adds no case, as it always did; an empty [[grid]] entry is surely a mistake."""
        v = doc.get("grid")
        if v is None:
            return ()
        if isinstance(v, dict):
            axes = self.params(doc, (), "grid", lists=True)
            return (axes,) if axes else ()
        if not isinstance(v, list) or not v or not all(isinstance(e, dict) for e in v):
            self.fail(("grid",), "must be a table [grid] or an array of tables [[grid]] of axes, "
                      "component.variable = [values]")  # fmt: skip
        out = []
        for i, e in enumerate(v, 1):
            axes = self.params(e, (("grid", i),), None, lists=True)
            if not axes:
                self.fail((("grid", i),), "no axis: give component.variable = [values]")
            out.append(axes)
        return tuple(out)

    def gears(self, doc: dict) -> gears_mod.Gears | None:
        t = self.table(doc, (), "gears")
        if t is None:
            return None
        key = ("gears",)
        self.check_keys(t, key, ("table", "fmu", "component", "face_load", "dynamic_factor"))
        table = self.description(t, key, "table")
        if table is None:
            self.fail(key + ("table",), "missing (the gear table: P, a gearbox6dof preset or a description file)")
        fmu = self.string(t, key, "fmu", choices=tuple(gears_mod.FMUS)) or gears_mod.DEFAULT_FMU
        face_load = self.string(t, key, "face_load", choices=("one", "model")) or "one"
        if face_load == "model" and fmu != "gearbox6dof":
            self.fail(key + ("face_load",), "model reads gearbox6dof's face_load_factor_<mesh> outputs: "
                                             'set fmu = "gearbox6dof"')  # fmt: skip
        # ISO 6336-1's K_v on every mesh (IEC 61400-4 asks for at least 1.05; `windrive gearbox --dynamic-factor`)
        dynamic_factor = self.number(t, key, "dynamic_factor", default=1.0, minimum=1.0)
        return gears_mod.Gears(table, fmu, self.component(t, key, "component", gears_mod.FMUS[fmu]), face_load,
                               dynamic_factor)

    def bearings(self, doc: dict) -> bearings_mod.Bearings | None:
        t = self.table(doc, (), "bearings")
        if t is None:
            return None
        key = ("bearings",)
        self.check_keys(t, key, ("gearbox", "component", "oil_viscosity", "oil_temperature", "contamination"))
        gearbox = self.description(t, key, "gearbox", default=bearings_mod.DEFAULT_GEARBOX)
        viscosity = t.get("oil_viscosity")
        if viscosity is not None:
            def positive(x) -> bool:
                return isinstance(x, int | float) and not isinstance(x, bool) and math.isfinite(x) and x > 0

            if not (isinstance(viscosity, list) and len(viscosity) == 2 and all(map(positive, viscosity))):
                self.fail(key + ("oil_viscosity",), f"must be [ν at 40 °C, ν at 100 °C] in mm²/s, not {viscosity!r}")
            if viscosity[0] <= viscosity[1]:
                self.fail(key + ("oil_viscosity",), f"the viscosity at 40 °C is the larger: {viscosity!r}")
        contamination = t.get("contamination")
        if contamination is not None:
            contamination = self.number(t, key, "contamination", minimum=0.0)
            if contamination > 1.0:
                self.fail(key + ("contamination",), f"ISO 281's e_C lies in 0 to 1, not {contamination!r}")
        return bearings_mod.Bearings(
            gearbox,
            self.component(t, key, "component", bearings_mod.DEFAULT_COMPONENT),
            oil_viscosity=None if viscosity is None else (float(viscosity[0]), float(viscosity[1])),
            oil_temperature=None if t.get("oil_temperature") is None else self.number(t, key, "oil_temperature"),
            contamination=contamination,
        )

    def description(self, doc: dict, key: tuple, name: str, default: str | None = None) -> str | None:
        """A gearbox as windrive's --gearbox takes it: a name (a preset, or [gears]' P) as it is, or a
        description file, a value with a `/` or ending in `.toml`, which like a scene is relative to the
        campaign file (the workers' working directory is not the user's) and must exist. A name is
        checked by windrive itself: driver.recorded asks it for the channels before any case runs."""
        v = self.string(doc, key, name, default=default)
        if v is None or not ("/" in v or v.endswith(".toml")):
            return v
        path = (self.base / v).resolve()
        if not path.is_file():
            self.fail(key + (name,), f"{path}: no such gearbox description file")
        return str(path)

    def component(self, doc: dict, key: tuple, name: str, default: str) -> str:
        """A scene component's name, the prefix of the channels a rating reads."""
        component = self.string(doc, key, name, default=default)
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", component):
            self.fail(key + (name,), f"{component!r}: a scene component's name ([A-Za-z_][A-Za-z0-9_]*)")
        return component

    def climate(self, doc: dict) -> Climate | None:
        t = self.table(doc, (), "climate")
        if t is None:
            return None
        key = ("climate",)
        self.check_keys(t, key, ("weibull", "rayleigh", "years"))
        years = self.number(t, key, "years", default=20.0, above=0.0)
        if ("weibull" in t) == ("rayleigh" in t):
            self.fail(key, "give exactly one of weibull = { k = …, A = … } and rayleigh = { mean = … }")
        if "weibull" in t:
            w = self.table(t, key, "weibull")
            self.check_keys(w, key + ("weibull",), ("k", "A"))
            k = self.number(w, key + ("weibull",), "k", above=0.0)
            a = self.number(w, key + ("weibull",), "A", above=0.0)
            return Climate(k, a, years, f"Weibull k = {k}, A = {a} m/s")
        r = self.table(t, key, "rayleigh")
        self.check_keys(r, key + ("rayleigh",), ("mean",))
        mean = self.number(r, key + ("rayleigh",), "mean", above=0.0)
        # Rayleigh = Weibull with k = 2 and mean A·Γ(1.5) = A·√π/2
        return Climate(2.0, 2.0 * mean / math.sqrt(math.pi), years, f"Rayleigh mean {mean} m/s")

    def dlc12(self, doc: dict) -> Dlc12 | None:
        t = self.table(doc, (), "dlc12")
        if t is None:
            return None
        key = ("dlc12",)
        self.check_keys(
            t,
            key,
            ("cut_in", "cut_out", "bin_width", "seeds", "turbulence_class", "turbulence_intensity", "rotor",
             "wind_sampling", "params"),
        )  # fmt: skip
        cut_in = self.number(t, key, "cut_in", above=0.0)
        cut_out = self.number(t, key, "cut_out", above=0.0)
        if cut_out <= cut_in:
            self.fail(key + ("cut_out",), f"must be above cut_in = {cut_in}, not {cut_out}")
        seeds = t.get("seeds", IEC_SEEDS)
        if isinstance(seeds, int) and not isinstance(seeds, bool) and seeds >= 1:
            seeds = tuple(range(1, seeds + 1))
        elif (
            isinstance(seeds, list)
            and seeds
            and all(isinstance(s, int) and not isinstance(s, bool) for s in seeds)
            and len(set(seeds)) == len(seeds)
        ):
            seeds = tuple(seeds)
        else:
            self.fail(key + ("seeds",), f"a count (seeds 1..N) or a list of distinct integers, not {seeds!r}")
        tc = self.string(t, key, "turbulence_class", choices=TURBULENCE_CLASSES)
        ti = None
        if "turbulence_intensity" in t:
            ti = self.number(t, key, "turbulence_intensity", minimum=0.0)
        if (tc is None) == (ti is None):
            self.fail(key, "give exactly one of turbulence_class (A, B, C: the IEC NTM) and turbulence_intensity")
        rotor = self.string(t, key, "rotor", default="rotor")
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", rotor):
            self.fail(key + ("rotor",), f"a component name, not {rotor!r}")
        return Dlc12(
            cut_in=cut_in,
            cut_out=cut_out,
            bin_width=self.number(t, key, "bin_width", default=2.0, above=0.0),
            seeds=seeds,
            turbulence_class=tc,
            turbulence_intensity=ti,
            rotor=rotor,
            params=self.params(t, key, "params"),
            wind_sampling=self.string(t, key, "wind_sampling", choices=WIND_SAMPLINGS),
        )

    def events(self, doc: dict, scene: Path, stop_time: float, transient: float) -> tuple[Event, ...]:
        entries = doc.get("event", [])
        if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
            self.fail(("event",), "must be an array of tables, [[event]]")
        out = []
        for i, e in enumerate(entries, 1):
            key = (("event", i),)
            self.check_keys(e, key, ("name", "scene", "per_year", "stop_time", "transient", "params"))
            name = self.string(e, key, "name")
            if name is None:
                self.fail(key + ("name",), "missing (the event's name, e.g. \"shutdown-rated\")")
            st = self.number(e, key, "stop_time", default=stop_time, above=0.0)
            tr = self.number(e, key, "transient", default=transient, minimum=0.0)
            if tr >= st:
                self.fail(key + ("transient",), f"{tr} s leaves nothing of stop_time = {st} s to analyse")
            out.append(
                Event(
                    name=name,
                    scene=self.scene(e, key, "scene", default=scene),
                    per_year=self.number(e, key, "per_year", minimum=0.0),
                    stop_time=st,
                    transient=tr,
                    params=self.params(e, key, "params"),
                )
            )
        names = [e.name for e in out]
        for i, n in enumerate(names, 1):
            if names.index(n) != i - 1:
                self.fail((("event", i), "name"), f"two events are named {n!r}")
        return tuple(out)

    def slurm(self, doc: dict) -> Slurm | None:
        t = self.table(doc, (), "slurm")
        if t is None:
            return None
        key = ("slurm",)
        known = (
            "queue", "account", "cores", "memory", "walltime", "jobs", "job_extra_directives",
            "job_script_prologue", "python", "local_directory",
        )  # fmt: skip
        self.check_keys(t, key, known)
        walltime = self.string(t, key, "walltime", default="01:00:00")
        if not re.fullmatch(r"(\d+-)?\d+(:\d\d){0,2}", walltime):
            self.fail(key + ("walltime",), f"Slurm's time format, e.g. \"04:00:00\", not {walltime!r}")
        return Slurm(
            queue=self.string(t, key, "queue"),
            account=self.string(t, key, "account"),
            cores=self.integer(t, key, "cores", default=1, minimum=1),
            memory=self.string(t, key, "memory", default="4GB"),
            walltime=walltime,
            jobs=self.integer(t, key, "jobs", default=1, minimum=1),
            job_extra_directives=self.strings(t, key, "job_extra_directives"),
            job_script_prologue=self.strings(t, key, "job_script_prologue"),
            python=self.string(t, key, "python"),
            local_directory=self.string(t, key, "local_directory"),
        )


_PARAM_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\.[A-Za-z_][A-Za-z0-9_]*")


def _kind(v) -> str:
    return {dict: "a table", list: "a list", str: "a string"}.get(type(v), type(v).__name__)


def _dotted(key: tuple) -> str:
    parts = []
    for k in key:
        parts.append(f"{k[0]}[{k[1]}]" if isinstance(k, tuple) else (f'"{k}"' if "." in k else k))
    return ".".join(parts) if parts else "(top level)"


def _locate(text: str, key: tuple) -> int | None:
    """Line (1-based) where `key` is written: inside the table it belongs to (`[t]`, the n-th `[[t]]`,
    or the top level), the first line assigning its last name (plain, quoted, or as the last part of a
    dotted key, or inside an inline table); for a key missing from a table, the table's header. None
    when not found; then the message goes without a line."""
    if not key:
        return None
    lines = text.splitlines()
    headers = [(i, m.group(1), m.group(2).strip()) for i, line in enumerate(lines) if (m := _HEADER.match(line))]
    # the table the key lives in: its first part if that names a table written as [part] / [[part]]
    first = key[0]
    name, index = first if isinstance(first, tuple) else (first, None)
    region = None
    seen = 0
    for n, (i, brackets, header) in enumerate(headers):
        if header == name:
            seen += 1
            if index is None or seen == index:
                end = headers[n + 1][0] if n + 1 < len(headers) else len(lines)
                region = (i, end)
                break
    if region is None:  # a top-level key (or a table written inline): before the first header
        region = (0, headers[0][0] if headers else len(lines))
        rest = key
    else:
        rest = key[1:]
        if not rest:
            return region[0] + 1
    last = rest[-1]
    last = last[0] if isinstance(last, tuple) else last
    pattern = re.compile(r'(^|[\s{,.])"?' + re.escape(last) + r'"?\s*=')
    for i in range(*region):
        if pattern.search(lines[i].split("#", 1)[0]):
            return i + 1
    # a missing key: the line of the table it is missing from (none at the top level)
    return region[0] + 1 if rest is not key else None


_HEADER = re.compile(r"^\s*(\[\[?)\s*([^\]]+?)\s*\]\]?\s*(#.*)?$")
