"""A fatigue set's damage from the cases' cycles, by hand (``life/set_damage.py``).

The damage of a set is checked against Palmgren-Miner by hand on cycles written here: with
N(s) = N0 (s0 / s)^m, a cycle of range s counts (s / s0)^m / N0, times the bin's
h · 3600 / T_counted.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
from numpy.testing import assert_allclose

from pinwind.life.case_cycles import CaseCycles, FlankCycles
from pinwind.life.set_damage import set_damage
from pinwind.runs.fatigue_set_file import load_fatigue_set
from tests.conftest import fatigue_toml


def write_cycles(fset, case, tooth, ranges_mpa, counts, counted_seconds):
    """A case reduction for the sun (20 teeth, one flank) with these cycles."""
    flank = FlankCycles(
        gear="sun",
        flank=1,
        teeth=20,
        tooth=np.asarray(tooth),
        ranges=np.asarray(ranges_mpa, dtype=float) * 1e6,
        counts=np.asarray(counts, dtype=float),
        peaks=np.zeros(20),
    )
    fset.out.mkdir(parents=True, exist_ok=True)
    CaseCycles(case, fset.case_key(case), counted_seconds, 0.0, (flank,)).save(
        fset.cycles_path(case)
    )


def test_two_case_set_damage_is_the_sum_of_the_cases_miner_sums_by_hand(tmp_path):
    fset = load_fatigue_set(fatigue_toml(tmp_path))
    low, high = fset.cases()  # 10 m/s (1000 h), 16 m/s (250 h)
    write_cycles(fset, low, [4, 4, 7], [500, 300, 800], [1.0, 0.5, 1.0], 2.0)
    write_cycles(fset, high, [4, 7], [600, 900], [2.0, 1.0], 4.0)
    damage = set_damage(fset).damage["no limit"][0]["sun"]
    # tooth 4: (0.5³ + 0.5·0.3³)·1000·3600/2 + 2·0.6³·250·3600/4
    tooth_4 = (0.5**3 + 0.5 * 0.3**3) * 1000 * 1800 + 2 * 0.6**3 * 250 * 900
    # tooth 7: 0.8³·1000·3600/2 + 0.9³·250·3600/4
    tooth_7 = 0.8**3 * 1000 * 1800 + 0.9**3 * 250 * 900
    assert damage.tooth == (4 if tooth_4 > tooth_7 else 7)
    assert_allclose(damage.total, max(tooth_4, tooth_7), rtol=1e-12)
    worst = (0.5**3 + 0.5 * 0.3**3, 2 * 0.6**3) if tooth_4 > tooth_7 else (0.8**3, 0.9**3)
    assert_allclose(damage.per_bin, [worst[0] * 1000 * 1800, worst[1] * 250 * 900], rtol=1e-12)


def test_cycles_below_the_endurance_limit_do_no_damage_in_a_set(tmp_path):
    fset = load_fatigue_set(fatigue_toml(tmp_path))
    limited = {g: dataclasses.replace(c, endurance_limit=850e6) for g, c in fset.curves.items()}
    fset = dataclasses.replace(fset, curves=limited)
    low, high = fset.cases()
    write_cycles(fset, low, [1], [840], [1.0], 1.0)
    write_cycles(fset, high, [1], [860], [1.0], 1.0)
    damage = set_damage(fset).damage["limit"][0]["sun"]
    assert_allclose(damage.per_bin, [0.0, 0.86**3 * 250 * 3600], rtol=1e-12)


def flank(gear, side, teeth, tooth, ranges_mpa, counts):
    """Cycles of one flank (or its root fillet) of a gear."""
    return FlankCycles(
        gear=gear,
        flank=side,
        teeth=teeth,
        tooth=np.asarray(tooth),
        ranges=np.asarray(ranges_mpa, dtype=float) * 1e6,
        counts=np.asarray(counts, dtype=float),
        peaks=np.zeros(teeth),
    )


def iso_toml(tmp_path: Path, sn_curve: str) -> Path:
    """The two-bin set with another ``[fatigue.sn_curve]`` table."""
    path = fatigue_toml(tmp_path)
    text = path.read_text()
    start = text.index("[fatigue.sn_curve]")
    path.write_text(text[:start] + "[fatigue.sn_curve]\n" + sn_curve)
    return path


def contact_life(z_nt: float) -> float:
    return 5e7 * z_nt ** (-math.log(500.0) / math.log(1.6))


def root_life(y_nt: float) -> float:
    return 3e6 * y_nt ** (-math.log(3000.0) / math.log(2.5))


def test_iso_variant_damage_of_contact_and_root_cycles_by_hand(tmp_path):
    """One 16 m/s case (250 h, 4 s counted): a sun contact cycle at Z_NT = 1.3, a sun root
    cycle at Y_NT = 1.5 on one flank, and a planet root cycle at 1.5 · 0.7 σ_FE on each flank."""
    fset = load_fatigue_set(fatigue_toml(tmp_path))
    low, high = fset.cases()
    fset.out.mkdir(parents=True, exist_ok=True)
    CaseCycles(low, fset.case_key(low), 2.0, 0.0).save(fset.cycles_path(low))
    contact = (flank("sun", 1, 20, [2], [0.65 * 1.3 * 1500], [1.0]),)
    roots = (
        flank("sun", 1, 20, [2], [1500], [1.0]),
        flank("planet1", 1, 35, [5], [0.7 * 1.5 * 1000], [1.0]),
        flank("planet1", -1, 35, [5], [0.7 * 1.5 * 1000], [1.0]),
    )
    CaseCycles(high, fset.case_key(high), 4.0, 0.0, contact, roots).save(fset.cycles_path(high))
    damage = set_damage(fset)
    time_factor = 250 * 3600 / 4.0
    sun = damage.damage["iso 6336"][0]["sun"]
    assert_allclose(sun.per_bin, [0.0, time_factor / contact_life(1.3)], rtol=1e-9)
    root = damage.root_damage["iso 6336"][0]
    assert_allclose(root["sun"].total, time_factor / root_life(1.5), rtol=1e-9)
    assert_allclose(root["planet1"].total, time_factor / root_life(1.5), rtol=1e-9)
    assert root["sun"].tooth == 2 and root["planet1"].tooth == 5
    # The set's own curve (N = (1000 MPa / s)³) rates the root cycles as it rates the contact.
    assert_allclose(
        damage.root_damage["no limit"][0]["sun"].total, 1.5**3 * time_factor, rtol=1e-12
    )
