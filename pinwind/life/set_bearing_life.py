"""Bearing life over a site's design life, from the cases of a fatigue set (ISO 281).

Each case keeps its bearings' load sums over its counted history (`BearingLoadSum`: Σ P_i^p n_i,
Σ n_i, and the seconds they took). A case stands for its wind bin's h hours divided among the
bin's seeds, so its sums count h · 3600 / (T · seeds) times, T the seconds of its history; added
over the bins they give each bearing's revolutions over the life, Σ_b h_b · 60 · n̄_b (n̄_b the
bin's mean speed [rpm]), and its equivalent load by the revolution-weighted rule over the bins

    P_eq = (Σ_b P_b^p R_b / Σ_b R_b)^(1/p),    R_b = the revolutions of bin b,

so that L10 = (C / P_eq)^p [10⁶ rev] and L10h = L10 · 10⁶ / (Σ_b R_b / Σ_b h_b) [h of
operation]. The sums of one turbulence level are one life; the lives are given per level.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pinwind.life.bearing_life import BearingLife, BearingLoadSum, life_of_load_sum
from pinwind.life.case_cycles import CaseCycles

if TYPE_CHECKING:
    from pinwind.life.fatigue_set import FatigueSet


def set_bearing_lives(fatigue: FatigueSet) -> list[list[BearingLife]]:
    """Each bearing's ISO 281 life over the site's life, per turbulence level.

    Returns:
        level index → the bearings in the model's order → its life (``duration`` the operating
        seconds of the site's bins; not rated when the model gives it no C).

    Raises:
        InputError: a case has no reduction (run the cases first: `case_runner.run_cases`).
    """
    from pinwind.errors import InputError

    site = fatigue.site
    sums: list[dict[str, BearingLoadSum]] = [{} for _ in fatigue.levels]
    for case in fatigue.cases():
        path = fatigue.cycles_path(case)
        if not path.is_file():
            raise InputError(f"{path}: case {case.name} has not run; run the fatigue set first")
        reduced = CaseCycles.load(path, with_flanks=False)
        level = sums[case.level]
        # The case's history stands for its share of the bin's hours.
        hours = site.bins[case.bin].hours / len(fatigue.seeds)
        for load_sum in reduced.bearings:
            if load_sum.seconds <= 0.0:  # a history of one sample stands for nothing
                continue
            scaled = load_sum.times(hours * 3600.0 / load_sum.seconds)
            previous = level.get(load_sum.joint)
            level[load_sum.joint] = scaled if previous is None else previous.plus(scaled)
    return [
        [life_of_load_sum(fatigue.bearings.get(joint), total) for joint, total in level.items()]
        for level in sums
    ]


def set_skidding(fatigue: FatigueSet, level: int) -> dict[str, list[float]]:
    """Each bearing's share of its wind bins' time turning below its minimum load (skidding).

    Per bin of the site, the bin's cases at turbulence level ``level`` added (their seconds
    below the minimum load over their seconds, ``life/skidding.py``); NaN for a bearing without
    a rating C, or a bin without a history.

    Raises:
        InputError: a case has no reduction (run the cases first).
    """
    import math

    from pinwind.errors import InputError

    bins = len(fatigue.site.bins)
    below: dict[str, list[float]] = {}
    seconds: dict[str, list[float]] = {}
    for case in fatigue.cases():
        if case.level != level:
            continue
        path = fatigue.cycles_path(case)
        if not path.is_file():
            raise InputError(f"{path}: case {case.name} has not run; run the fatigue set first")
        for load_sum in CaseCycles.load(path, with_flanks=False).bearings:
            below.setdefault(load_sum.joint, [0.0] * bins)[case.bin] += (
                load_sum.seconds_below_minimum
            )
            seconds.setdefault(load_sum.joint, [0.0] * bins)[case.bin] += load_sum.seconds
    return {
        joint: [b / s if s > 0.0 else math.nan for b, s in zip(shares, seconds[joint], strict=True)]
        for joint, shares in below.items()
    }
