"""A campaign expanded into cases, each with a stable id.

A case's id is the hash of what decides its simulation: the scene snapshot's bytes (the SSD, parameter
files and FMUs), the windrive binary's bytes, the stop time, the macro step and every parameter passed.
Same inputs, same id, on any machine and in any order of the campaign file: the driver skips a case whose
result file is already there. The analysis (channels, slopes, LDD bins, f_eq, transient) is not part of
the id but of the case's analysis digest, stored in the result: a result analysed differently is rerun.
The binary runs from a copy under the campaign's folder, so the id names the master that actually ran.

Scenes run from a snapshot: the scene folder zipped into an .ssp under the campaign's folder. `windrive
run` on a folder copies freshly packed FMUs into the folder's resources/ when target/fmu has newer ones
(src/cli/run.rs provide_own_fmus), in place and without a lock: parallel runs of one folder could read a
half-copied FMU, and a rebuild in the middle of a campaign would mix FMU versions. Running the snapshot
avoids both and makes the digest the bytes actually run.
"""

from __future__ import annotations

import hashlib
import io
import itertools
import json
import math
import os
import shutil
import subprocess
import tempfile
import zipfile
from dataclasses import dataclass
from pathlib import Path

from . import bearings as bearings_mod
from . import climate as climate_mod
from . import gears as gears_mod
from .errors import CampaignError
from .schema import WIND_SAMPLINGS, Campaign, ParamValue


@dataclass(frozen=True)
class Case:
    id: str
    name: str  # readable: dlc12-v10-s1, grid-fidelity=5, event-shutdown
    group: str  # dlc12, grid or event
    scene: str  # the snapshot .ssp the case runs
    stop_time: float
    transient: float
    step: float | None
    params: dict[str, ParamValue]  # every --param, in the order passed
    analysis_digest: str
    wind_speed: float = math.nan  # DLC 1.2: bin speed, m/s
    seed: int | None = None
    turbulence_intensity: float = math.nan
    probability: float = math.nan  # DLC 1.2: of the bin, shared by its seeds
    hours: float = math.nan  # DLC 1.2: hours over the design life this case stands for
    events: float = math.nan  # events: occurrences over the design life

    def command(self, windrive: str, out: str | None, record: list[str]) -> list[str]:
        """`windrive run` of this case; the series is written to `out` (.csv or .parquet) if given."""
        cmd = [windrive, "run", self.scene, "--stop-time", repr(self.stop_time), "--quiet"]
        if out is not None:
            cmd += ["--out", out]
        if self.step is not None:
            cmd += ["--step", repr(self.step)]
        if record:
            cmd += ["--record", ",".join(record)]
        for name, value in self.params.items():
            cmd += ["--param", f"{name}={param_text(value)}"]
        return cmd


def param_text(value: ParamValue) -> str:
    """A parameter value as `--param` reads it: floats in full precision (repr), booleans lower case."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(value)


def file_digest(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def snapshot_scene(
    scene: Path,
    windrive: str,
    out_dir: Path,
    record: list[str],
    gears: gears_mod.Gears | None = None,
    bearings: bearings_mod.Bearings | None = None,
) -> tuple[str, str]:
    """The scene as an immutable .ssp under out_dir/scenes/ and its digest. The scene is first run for
    one millisecond, recording the campaign's channels: windrive brings its own FMUs in a folder's
    resources/ up to date (and packs them on a fresh clone), and a misspelt channel is one error now
    instead of one per case. With `gears` or `bearings`, `windrive gears` or `windrive bearings` rates
    that probe too, so recorded channels that no longer match what it reads, or a scene that runs
    another gearbox (windrive bearings checks the speed ratio), stop the campaign here rather than fail
    every case. A folder is then zipped with fixed timestamps and sorted names: the same files give the
    same bytes."""
    with tempfile.TemporaryDirectory() as tmp:
        series = f"{tmp}/probe.csv"
        probe = [windrive, "run", str(scene), "--stop-time", "0.001", "--out", series, "--quiet"]
        r = subprocess.run(probe + ["--record", ",".join(record)], capture_output=True, text=True)
        if r.returncode != 0:
            raise CampaignError(f"{scene}: the scene does not run: {r.stderr.strip() or r.returncode}")
        if gears is not None:
            _rate_probe(scene, gears_mod.command(windrive, series, gears, 0.0), section(gears))
        if bearings is not None:
            _rate_probe(scene, bearings_mod.command(windrive, series, bearings, 0.0), section(bearings))
    if scene.is_file():
        return str(scene), file_digest(scene)
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_STORED) as z:  # FMUs are zips already: storing is fastest
        for p in sorted(scene.rglob("*")):
            if p.is_file() and "__pycache__" not in p.parts:
                info = zipfile.ZipInfo(p.relative_to(scene).as_posix(), date_time=(1980, 1, 1, 0, 0, 0))
                info.external_attr = 0o644 << 16
                z.writestr(info, p.read_bytes())
    data = buf.getvalue()
    digest = hashlib.sha256(data).hexdigest()
    target = out_dir / "scenes" / f"{scene.name}-{digest[:12]}.ssp"
    if not target.is_file():
        target.parent.mkdir(parents=True, exist_ok=True)
        tmp = target.with_suffix(".ssp.tmp")
        tmp.write_bytes(data)
        tmp.replace(target)
    return str(target), digest


def section(rated: gears_mod.Gears | bearings_mod.Bearings) -> str:
    """A rating section as an error names it: `[gears] table = 'P', fmu = 'torsional', component = …`."""
    if isinstance(rated, gears_mod.Gears):
        return f"[gears] table = {rated.table!r}, fmu = {rated.fmu!r}, component = {rated.component!r}"
    return f"[bearings] gearbox = {rated.gearbox!r}, component = {rated.component!r}"


def _rate_probe(scene: Path, command: list[str], section: str):
    r = subprocess.run(command, capture_output=True, text=True)
    if r.returncode != 0:
        raise CampaignError(f"{scene}: {section}: windrive {command[1]} cannot rate its series: "
                            f"{r.stderr.strip() or r.returncode}")  # fmt: skip


def windrive_digest(windrive: str) -> str:
    """The master's identity: its version line and its bytes (a rebuild can change results)."""
    try:
        version = subprocess.run([windrive, "--version"], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        raise CampaignError(f"{windrive}: cannot run windrive: {e}") from None
    return hashlib.sha256((version.strip() + file_digest(Path(windrive))).encode()).hexdigest()


def snapshot_windrive(windrive: str, out_dir: Path) -> tuple[str, str]:
    """A copy of the binary under out_dir/bin/ named by its digest, and the digest. The cases run the
    copy: a `cargo build` during the campaign replaces target/release/windrive, and the cases after it
    would run another master than the one their id names. The digest is taken of the copy, so a build
    finishing while it is made cannot pair one binary's name with another's bytes."""
    (out_dir / "bin").mkdir(parents=True, exist_ok=True)
    tmp = out_dir / "bin" / f".windrive.{os.getpid()}.tmp"
    try:
        shutil.copy2(windrive, tmp)
    except OSError as e:
        raise CampaignError(f"{windrive}: cannot copy windrive: {e.strerror}") from None
    digest = windrive_digest(str(tmp))
    target = out_dir / "bin" / f"windrive-{digest[:12]}"
    tmp.replace(target)  # the same bytes if it was there already
    return str(target), digest


def expand(c: Campaign, scenes: dict[Path, tuple[str, str]], windrive_id: str, windrive: str | None = None) -> list[Case]:
    """Every case of the campaign, DLC 1.2 first (bins ascending, then seeds), then the grids (each
    grid's cartesian product in the file's order of axes, the grids in the file's order), then the
    events. `scenes` maps each scene path to its snapshot (path, digest).

    Several grids give the union of their products. A parameter set that two grids both produce is one
    simulation, so it is one case, named by the first grid that produces it; case ids, not names, decide
    what is already done, so resuming is unaffected by which grid names a case. Two different cases with
    one name (axes of different components but the same variable name, or a value "1" beside 1) are an
    error: the name is what the table and the progress lines show."""

    def make(name, group, scene, stop_time, transient, params, **weights) -> Case:
        ssp, digest = scenes[scene]
        params = {**params, **turbulent_windows(params, stop_time - transient)}
        identity = {
            "scene": digest,
            "windrive": windrive_id,
            "stop_time": stop_time,
            "step": c.step,
            "params": sorted([k, type(v).__name__, v] for k, v in params.items()),
        }
        case_id = hashlib.sha256(json.dumps(identity, sort_keys=True).encode()).hexdigest()[:16]
        analysis = hashlib.sha256(f"{c.analysis_digest()} {transient!r}".encode()).hexdigest()[:16]
        return Case(case_id, name, group, ssp, stop_time, transient, c.step, params, analysis, **weights)

    def merge(where: str, *layers: dict) -> dict:
        out: dict = {}
        for layer in layers:
            for k, v in layer.items():
                if k in out:
                    raise CampaignError(
                        f"{c.path}: {where}: parameter {k} is set twice (in params and by the load case)"
                    )
                out[k] = v
        return out

    cases: list[Case] = []
    if c.dlc12 is not None:
        d = c.dlc12
        cl = c.climate
        if windrive is None:
            raise ValueError("expand: a campaign with [dlc12] needs the windrive binary for its wind bins")
        sampling, from_params = dlc12_sampling(c)
        for b in climate_mod.wind_bins(windrive, d, cl):
            ti = d.turbulence_intensity
            if ti is None:
                ti = b.ntm_turbulence_intensity
            for seed in d.seeds:
                own = {
                    f"{d.rotor}.turbulence": "ntm",
                    f"{d.rotor}.wind_speed": b.speed,
                    f"{d.rotor}.seed": seed,
                    f"{d.rotor}.turbulence_intensity": ti,
                    **({} if from_params else {f"{d.rotor}.wind_sampling": sampling}),
                }
                cases.append(
                    make(
                        f"dlc12-v{b.speed:g}-s{seed}",
                        "dlc12",
                        c.scene,
                        c.stop_time,
                        c.transient,
                        merge("dlc12", c.params, d.params, own),
                        wind_speed=b.speed,
                        seed=seed,
                        turbulence_intensity=ti,
                        probability=b.probability / len(d.seeds),
                        hours=b.hours / len(d.seeds),
                    )
                )
    grid_ids: set[str] = set()
    for grid in c.grids:
        axes = list(grid)
        for values in itertools.product(*(grid[a] for a in axes)):
            point = dict(zip(axes, values))
            label = ",".join(f"{a.split('.', 1)[1]}={param_text(v)}" for a, v in point.items())
            case = make(f"grid-{label}", "grid", c.scene, c.stop_time, c.transient, merge("grid", c.params, point))
            if case.id not in grid_ids:  # reached by an earlier grid already: the same simulation
                grid_ids.add(case.id)
                cases.append(case)
    years = c.climate.years if c.climate is not None else 20.0
    for e in c.events:
        cases.append(
            make(
                f"event-{e.name}",
                "event",
                e.scene,
                e.stop_time,
                e.transient,
                merge(f"event {e.name}", c.params, e.params),
                events=e.per_year * years,
            )
        )
    seen: dict[str, str] = {}
    named: dict[str, Case] = {}
    for case in cases:
        if case.id in seen:
            raise CampaignError(f"{c.path}: cases {seen[case.id]} and {case.name} are the same simulation")
        seen[case.id] = case.name
        if case.name in named:
            raise CampaignError(
                f"{c.path}: two different cases are named {case.name} "
                f"({_params_text(named[case.name].params)} and {_params_text(case.params)}): rename an axis or value"
            )
        named[case.name] = case
    return cases


def dlc12_sampling(c: Campaign) -> tuple[str, bool]:
    """The wind sampling a campaign's DLC 1.2 cases run: [dlc12]'s `wind_sampling`, else the rotor's
    parameter in the campaign's params (then True: expand leaves it to them), else blades."""
    d = c.dlc12
    given = {**c.params, **d.params}.get(f"{d.rotor}.wind_sampling")
    if d.wind_sampling is None and given is not None:
        return str(given), True
    return d.wind_sampling or WIND_SAMPLINGS[0], False


def turbulent_windows(params: dict[str, ParamValue], window: float) -> dict[str, ParamValue]:
    """What each turbulent rotor (a component with a `seed`) of a case runs with:

    - its turbulence period the analysed window (unless the campaign gives one), so every window has
      exactly the mean wind its case names, and its σ read over that period (`turbulence_scaling =
      "period"`, unless the campaign gives one), so every window also has exactly the intensity its case
      names, however short (TurbSim's ScaleIEC on a record as long as the window; from 10 minutes on the
      same as IEC's 10-minute σ; src/physics/turbulence.rs, docs/WIND.md);
    - its seed made the case's own: the campaign's seed number mixed with the rotor's wind speed,
      turbulence model and intensity, so seed 1 at 10 m/s shares no phase with seed 1 at 12 m/s or at
      another intensity (the same case draws the same seed on every machine)."""
    out: dict[str, ParamValue] = {}
    for key in [k for k in params if k.endswith(".seed")]:
        rotor = key.removesuffix(".seed")
        if f"{rotor}.turbulence_period" not in params:
            out[f"{rotor}.turbulence_period"] = window
        if f"{rotor}.turbulence_scaling" not in params:
            out[f"{rotor}.turbulence_scaling"] = "period"
        if isinstance(params[key], int) and not isinstance(params[key], bool):  # else windrive names the mistake
            out[key] = case_seed(rotor, params)
    return out


def case_seed(rotor: str, params: dict[str, ParamValue]) -> int:
    """A positive 31-bit seed (the FMU's Integer) from the rotor's seed number and what it blows."""
    what = [params.get(f"{rotor}.{v}") for v in ("seed", "wind_speed", "turbulence", "turbulence_intensity")]
    digest = hashlib.sha256(json.dumps(what).encode()).digest()
    return int.from_bytes(digest[:4], "big") % (2**31 - 1) + 1


def _params_text(params: dict[str, ParamValue]) -> str:
    return " ".join(f"{k}={v!r}" for k, v in params.items())


def scene_paths(c: Campaign) -> list[Path]:
    return list(dict.fromkeys([c.scene, *(e.scene for e in c.events)]))
