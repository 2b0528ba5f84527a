"""The wind climate's DLC 1.2 bins, asked of `windrive climate` (src/analysis/fatigue/operating_hours.rs):
the simulated speeds are cut_in, cut_in + w, cut_in + 2w, … (w = bin_width); bin j covers
[v_j − w/2, v_j + w/2] clipped to [cut_in, cut_out], so the bins tile cut-in to cut-out exactly. Each bin
comes with its probability, its hours in the design life and the IEC normal turbulence model's intensity
for the campaign's turbulence class. Asked of the binary rather than computed here, so the campaign's
weights and `windrive life`'s hours are one computation.
"""

from __future__ import annotations

import json
import subprocess
from dataclasses import dataclass

from .errors import CampaignError
from .schema import Climate, Dlc12


@dataclass(frozen=True)
class WindBin:
    speed: float  # simulated mean hub-height wind speed, m/s
    lo: float
    hi: float
    probability: float  # of the hub-height wind lying in [lo, hi]
    hours: float  # in the climate's design life
    ntm_turbulence_intensity: float  # IEC NTM at `speed` for the [dlc12] turbulence class (A without one)


def wind_bins(windrive: str, d: Dlc12, climate: Climate) -> list[WindBin]:
    command = [
        windrive, "climate", "--weibull", f"{climate.k!r},{climate.a!r}", "--cut-in", repr(d.cut_in),
        "--cut-out", repr(d.cut_out), "--bin-width", repr(d.bin_width), "--years", repr(climate.years),
        "--class", d.turbulence_class or "A", "--json",
    ]  # fmt: skip
    r = subprocess.run(command, capture_output=True, text=True)
    if r.returncode != 0:
        raise CampaignError(f"windrive climate: {r.stderr.strip() or r.returncode}")
    return [WindBin(**b) for b in json.loads(r.stdout)]
