"""The paper's published gear damage, transcribed for `scripts/campaign paper` (paper.py): D. Xiang,
L. Jiang, M. You, Y. Shen, "Influence of Quasi-Steady Wind Loads on the Fatigue Damage of Wind Turbine
Gearboxes" (Tsinghua University; docs/SOURCES.md §Paper), Table 6 and Table 7. Embedded here so the
report never reads the paper's text at run time.

Transcribed by hand from the paper's extracted text, where both tables lost their layout; how each was
read is noted beside it. Its own consistency is tested (tests/python/test_campaign_paper.py): Table 6's
18 m/s over 11.5 m/s damage at TI 14 % equals Table 7's (1 + η_18/100) / (1 + η_11.5/100) for the six
gear damages both give, to the tables' rounding.
"""

from __future__ import annotations

import math

# -- Table 6: 1-day tooth bending (Db) and flank pitting (Dp) damage at 11.5 m/s (rated) and 18 m/s,
# turbulence intensity 14 %, in units of 1e-6. Columns per gear as printed: Db, Dp at 11.5 m/s, then Db,
# Dp at 18 m/s. A planet's bending is one value for both flanks (R ≈ −1, §1); its pitting is split into
# the forward flank (against the sun) and the back flank (against the ring): the extracted text gives
# the planet's Db over its forward row, "88.2 / 109" then "113.0 / 136.1", and the back row's Dp alone,
# "0.003 0.003". "-" ("too small to display", footnote a) is None.
#
# Doubt: the 1st-stage ring's Dp at 11.5 m/s reads "0. 2" in the text; taken as 0.2 (the 18 m/s value
# 0.269 over it is 1.35, near the 1.25–1.34 of the other 1st-stage gears).

TABLE6_SPEEDS = (11.5, 18.0)  # m/s
TABLE6_TI_PCT = 14.0
TABLE6_UNIT = 1e-6


# (stage, the paper's gear, damage, our tooth in `windrive gears`, (value at 11.5 m/s, at 18 m/s) × 1e-6)
TABLE6 = (
    ("1st", "sun", "bending", "s1", (1.28, 1.71)),
    ("1st", "sun", "pitting", "s1", (483.0, 603.0)),
    ("1st", "planet", "bending", "p1", (88.2, 113.0)),
    ("1st", "planet-forward", "pitting", "ps1", (109.0, 136.1)),
    ("1st", "planet-back", "pitting", "pr1", (0.003, 0.003)),
    ("1st", "ring", "bending", "r1", (437.6, 548.3)),
    ("1st", "ring", "pitting", "r1", (0.2, 0.269)),
    ("2nd", "sun", "bending", "s2", (0.051, 0.072)),
    ("2nd", "sun", "pitting", "s2", (38.5, 48.42)),
    ("2nd", "planet", "bending", "p2", (77.0, 97.6)),
    ("2nd", "planet-forward", "pitting", "ps2", (7.13, 8.97)),
    ("2nd", "planet-back", "pitting", "pr2", (None, None)),
    ("2nd", "ring", "bending", "r2", (155.7, 193.3)),
    ("2nd", "ring", "pitting", "r2", (None, None)),
    ("3rd", "gear", "bending", "g3", (0.596, 1.023)),
    ("3rd", "gear", "pitting", "g3", (0.010, 0.014)),
    ("3rd", "pinion", "bending", "p3", (9.20, 14.7)),
    ("3rd", "pinion", "pitting", "p3", (0.035, 0.048)),
)

# -- The rating's S-N exponents (windrive gears; not the paper's): below the knee a tooth's damage under its
# stresses scaled by f grows as f^(2m − 1), the paper's second slope, with m from ISO 6336's life-factor
# knots: contact Z_NT 1.6 at 1e5 → 1 at 5e7 (both steels), bending Y_NT 2.5 at 1e3 (case carburised) or at
# 1e4 (the through-hardened rings) → 1 at 3e6. tests/python/test_campaign_paper.py checks them against
# windrive gears on a series whose forces it doubles.
CONTACT_SLOPE = math.log(5e7 / 1e5) / math.log(1.6)
BENDING_SLOPE = math.log(3e6 / 1e3) / math.log(2.5)
RING_BENDING_SLOPE = math.log(3e6 / 1e4) / math.log(2.5)


def damage_exponent(kind: str, gear: str) -> float:
    """k of D ∝ f^k below the knee for `kind` (bending or pitting) of the paper's `gear` (a ring or not)."""
    m = CONTACT_SLOPE if kind != "bending" else RING_BENDING_SLOPE if gear == "ring" else BENDING_SLOPE
    return 2.0 * m - 1.0


# our table's column for each kind of damage: bending is the tooth root, pitting (the paper's Table 7
# says "contacting") the flank
DAMAGE_COLUMN = {"bending": "root_day", "pitting": "flank_day", "contacting": "flank_day"}


# -- Table 7: fatigue damage comparison factor η = (D − D_const,rated) / D_const,rated × 100 % (Eq. 5),
# D_const,rated the damage under steady wind at the rated 11.5 m/s. Columns: bending of r1, r2, p3, then
# contacting of s1, s2, p3. Rows: mean wind speed (m/s) × turbulence intensity (%); TI 0 is steady wind;
# below rated the paper lists 9 m/s at TI 24 % only ("only one row is listed for mean wind speed lower
# than rated for simplicity").
#
# Doubts, kept as printed: at 20 m/s, TI 18 % the r1 bending value is 88.4, where every other row has r1
# bending within 0.7 of s1 contacting (77.7 here; both follow the first stage's torque): probably 78.4
# misprinted. At 16 m/s, steady, r2 bending is 95.5 against s2 contacting 102.8, the only row where r2
# is below s2 by more than 0.6 (elsewhere 0.5 to 4.3 above).

TABLE7_COLUMNS = (
    ("bending", "r1"),
    ("bending", "r2"),
    ("bending", "p3"),
    ("contacting", "s1"),
    ("contacting", "s2"),
    ("contacting", "p3"),
)

# {wind speed: {TI %: (η of the six columns above, %)}}
TABLE7 = {
    9.0: {
        24.0: (-94.4, -94.8, -99.6, -94.1, -95.9, -98.5),
    },
    11.5: {
        0.0: (0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        9.0: (54.9, 39.2, 30.4, 54.9, 34.9, 31.3),
        12.0: (52.7, 37.0, 51.1, 53.0, 34.0, 45.8),
        14.0: (44.9, 30.9, 27.4, 45.2, 27.2, 30.0),
        16.0: (44.8, 32.4, 31.6, 44.8, 29.4, 29.4),
        18.0: (45.6, 34.0, 18.0, 45.5, 30.1, 16.7),
        21.0: (45.3, 32.8, 44.2, 45.5, 29.1, 38.8),
        24.0: (41.4, 28.6, 31.0, 41.3, 25.1, 28.4),
    },
    14.0: {
        0.0: (97.7, 82.4, 102.2, 97.3, 81.9, 89.0),
        9.0: (86.9, 67.2, 66.3, 86.7, 66.2, 61.3),
        12.0: (83.9, 65.4, 79.0, 83.8, 62.8, 88.4),
        14.0: (81.1, 61.8, 87.0, 81.0, 58.7, 76.1),
        16.0: (79.1, 61.7, 91.9, 78.8, 58.2, 74.2),
        18.0: (77.7, 62.3, 73.1, 77.3, 59.1, 64.5),
        21.0: (78.4, 60.7, 74.3, 78.2, 58.9, 65.7),
        24.0: (72.5, 57.1, 102.0, 72.3, 54.4, 75.3),
    },
    16.0: {
        0.0: (97.1, 95.5, 203.5, 96.4, 102.8, 151.1),
        9.0: (85.0, 66.0, 80.1, 84.7, 63.4, 69.2),
        12.0: (82.7, 64.4, 97.3, 82.7, 62.3, 79.9),
        14.0: (77.9, 59.7, 114.2, 77.7, 57.6, 87.9),
        16.0: (76.2, 56.6, 67.0, 76.2, 53.8, 57.1),
        18.0: (75.4, 58.4, 107.6, 75.1, 55.0, 85.7),
        21.0: (76.9, 56.4, 101.6, 76.6, 54.1, 78.4),
        24.0: (73.3, 55.8, 126.4, 72.6, 53.3, 91.5),
    },
    18.0: {
        0.0: (99.2, 82.9, 143.8, 98.9, 82.3, 115.3),
        9.0: (85.0, 69.3, 107.4, 84.8, 67.9, 83.9),
        12.0: (82.5, 65.6, 80.8, 82.2, 62.1, 65.8),
        14.0: (81.5, 62.5, 104.1, 81.4, 60.1, 78.6),
        16.0: (80.0, 58.2, 99.0, 79.6, 54.7, 77.3),
        18.0: (79.4, 59.3, 105.3, 79.2, 56.9, 81.6),
        21.0: (79.0, 60.7, 125.8, 78.5, 58.7, 97.5),
        24.0: (77.7, 57.6, 195.5, 77.1, 56.7, 135.4),
    },
    20.0: {
        0.0: (100.0, 75.0, 118.3, 99.8, 75.6, 95.0),
        9.0: (84.9, 61.3, 104.5, 84.8, 60.2, 78.1),
        12.0: (79.4, 56.3, 114.8, 79.3, 54.8, 89.8),
        14.0: (78.6, 59.2, 152.1, 78.0, 57.5, 112.9),
        16.0: (78.1, 54.8, 136.2, 77.7, 53.4, 94.7),
        18.0: (88.4, 56.7, 181.2, 77.7, 55.3, 117.5),
        21.0: (78.4, 61.7, 192.3, 77.8, 61.2, 120.0),
        24.0: (79.9, 60.4, 296.8, 79.3, 58.3, 166.0),
    },
}

RATED_SPEED = 11.5  # m/s: D_const,rated is steady wind at this speed (Eq. 5)

# -- Table 8: the gears' sensitivity to the wind in three levels, each a pair of damages of one stage,
# "by comparing their fatigue damage comparison factors" (§2.2.2.2; the rule itself is not given)
TABLE8 = {
    1: (("bending", "p3"), ("contacting", "p3")),
    2: (("bending", "r1"), ("contacting", "s1")),
    3: (("bending", "r2"), ("contacting", "s2")),
}

# -- The grid its text describes (§2.1): mean wind speed 5 to 20 m/s by 2 m/s, turbulence intensity 9 to
# 24 % by 2 % (the text's words; Table 7's rows are another grid)
TEXT_SPEEDS = tuple(5.0 + 2.0 * k for k in range(8))  # 5, 7, ..., 19 (20 is not reached by steps of 2)
TEXT_TI_PCT = tuple(9.0 + 2.0 * k for k in range(8))  # 9, 11, ..., 23
