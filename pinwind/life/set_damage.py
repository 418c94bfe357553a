"""Damage over the design life per gear, per wind bin and per turbulence level, from a fatigue set.

Jørgensen 2014 Tables 7-8. The cycles of each case
(`pinwind.life.case_cycles.CaseCycles`, counted in T = T_sim − skip_start seconds) stand for
the h hours of the case's wind bin: its damage counts h · 3600 / T times (Table 2), divided
among the bin's seeds (each seed is one sample of the same hours). Each tooth flank has its own
sum over the bins; a gear's damage is that of its worst tooth flank, and its damage per bin is
that flank's, so that the bins add up to the total (Table 7's rows). Jørgensen 2014 instead rates
one point of the path of one mesh and spreads it over the teeth (Table 3): its numbers are a
mean tooth's at that point, ours the worst tooth's at its most stressed point.

The damage is computed for each S-N variant (`VARIANTS`): ``"limit"`` (the set's curve as
given, cycles below the endurance limit do nothing), ``"no limit"`` (its sloped line extended to
zero stress) and ``"iso 6336"`` (ISO 6336's own curves of each gear's material, σ_Hlim Z_NT and
σ_Flim Y_ST Y_NT, with the standard's falling line beyond the knee, `pinwind.life.sn_curve`),
for the contact (von Mises) stress and for the root stress of each fillet. An ISO root curve of
a gear whose teeth a case loads on both flanks (a planet) is taken at 0.7 of its strength
(reversed bending, ISO 6336-5). Memory is flat in the number of cases: one case's cycles are
read at a time.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np

from pinwind.life.case_cycles import CaseCycles, FlankCycles, saved_flanks
from pinwind.life.fatigue_set import FatigueSet
from pinwind.life.sn_curve import REVERSED_BENDING_FACTOR, FatigueCurve, IsoLifeCurve

#: Edges of the cycle-range histogram kept per case and gear, for the figures [Pa].
RANGE_EDGES = np.linspace(0.0, 2000e6, 201)
#: The S-N variants the damage is computed for: name → what it is.
VARIANTS = {
    "limit": "the set's S-N curve with its endurance limit",
    "no limit": "the set's S-N curve without an endurance limit",
    "iso 6336": "ISO 6336-2 Z_NT / ISO 6336-3 Y_NT curves of the gear's material, 0.85 at 1e10",
}
#: The stresses rated: name → what it is.
LOCATIONS = {
    "contact": "von Mises contact stress σ_vM = 0.65 p_max at the moving contact point",
    "root": "root stress σ_F of the fillet on the loaded flank's side",
}

#: Jørgensen 2014 Table 7: damage per wind bin (6, 8, ..., 20 m/s) at TI = 10 %, and the sum.
JORGENSEN_2014_TABLE_7 = {
    "sun": ((0.0, 0.0, 0.0, 0.0, 0.2185, 0.3727, 0.0869, 0.0132), 0.69),
    "planet": ((0.0, 0.0, 0.0, 0.0, 0.0416, 0.0710, 0.0166, 0.0025), 0.13),
    "ring": ((0.0, 0.0, 0.0, 0.0116, 0.0177, 0.0125, 0.0028, 0.0004), 0.05),
}
#: The paper the tables, figures and messages compare with, named as its readers know it
#: (docs/references.md: Jørgensen et al. 2014).
PAPER = "Jørgensen 2014"
#: Jørgensen 2014 Table 8: total damage at turbulence intensities 8, 10, ..., 20 %.
JORGENSEN_2014_TABLE_8 = {
    "turbulence": (0.08, 0.10, 0.12, 0.14, 0.16, 0.18, 0.20),
    "sun": (0.65, 0.69, 0.75, 0.85, 1.10, 1.60, 2.00),
    "planet": (0.12, 0.13, 0.14, 0.16, 0.21, 0.30, 0.38),
    "ring": (0.05, 0.05, 0.05, 0.05, 0.07, 0.10, 0.11),
}


@dataclass(frozen=True)
class GearDamage:
    """A gear's damage over the design life at one turbulence level, one S-N variant.

    Attributes:
        gear: the gear.
        per_bin: damage of its worst tooth flank in each wind bin [-], (bins,).
        total: that flank's damage over all bins [-] (the sum of ``per_bin``).
        tooth: the worst tooth's number.
        flank: its flank (+1, −1).
        peak_stress: largest stress of any of its teeth in the cases [Pa] (von Mises contact
            stress, or root stress).
    """

    gear: str
    per_bin: np.ndarray
    total: float
    tooth: int
    flank: int
    peak_stress: float


@dataclass(frozen=True)
class SetDamage:
    """The damage of a fatigue set.

    Attributes:
        speeds: the wind bins' speeds [m/s], (bins,).
        hours: their hours [h], (bins,).
        levels: the turbulence levels' labels.
        intensities: each level's mean turbulence intensity over the bins [-].
        gears: the rated gears.
        damage: variant → level index → gear → `GearDamage` of the contact stress.
        range_cycles: level index → bin → gear → cycles per tooth over the bin's hours in each
            stress-range bin of `RANGE_EDGES` [-], (len(RANGE_EDGES) − 1,).
        root_damage: as ``damage``, of the root stress.
        roles: gear → its role in its planetary stage (`FatigueSet.roles`, from topology).
    """

    speeds: np.ndarray
    hours: np.ndarray
    levels: tuple[str, ...]
    intensities: tuple[float, ...]
    gears: tuple[str, ...]
    damage: dict[str, list[dict[str, GearDamage]]]
    range_cycles: list[list[dict[str, np.ndarray]]]
    root_damage: dict[str, list[dict[str, GearDamage]]] = field(default_factory=dict)
    roles: dict[str, str] = field(default_factory=dict)

    def by_kind(
        self, variant: str, level: int, *, location: str = "contact"
    ) -> dict[str, tuple[np.ndarray, float]]:
        """(per bin, total) for each gear kind: the planets' mean as Jørgensen 2014's "planet*".

        Gears that are no sun, planet or ring keep their own names.

        Args:
            location: ``"contact"`` (`damage`) or ``"root"`` (`root_damage`).
        """
        table = self.damage if location == "contact" else self.root_damage
        groups: dict[str, list[GearDamage]] = defaultdict(list)
        for gear, d in table[variant][level].items():
            groups[self.roles.get(gear, gear)].append(d)
        return {
            kind: (np.mean([d.per_bin for d in ds], axis=0), float(np.mean([d.total for d in ds])))
            for kind, ds in groups.items()
        }


def _curve(
    fatigue: FatigueSet, gear: str, variant: str, location: str, both_flanks: bool
) -> tuple[FatigueCurve, bool]:
    """(curve, whether its endurance limit applies) of a gear in a variant and location."""
    if variant == "iso 6336":
        curves = fatigue.iso_curves if location == "contact" else fatigue.iso_root_curves
        limited = False
    else:
        curves = fatigue.curves if location == "contact" else fatigue.root_curves
        limited = variant == "limit"
    curve = curves.get(gear) or fatigue.curves[gear]
    if location == "root" and both_flanks and isinstance(curve, IsoLifeCurve):
        curve = curve.scaled(REVERSED_BENDING_FACTOR)
    return curve, limited


def set_damage(fatigue: FatigueSet) -> SetDamage:
    """The damage of every gear over the design life, from the cases' reductions.

    Raises:
        InputError: a case has no reduction (run the cases first: `case_runner.run_cases`).
    """
    from pinwind.errors import InputError

    site = fatigue.site
    bins, levels = len(site.bins), len(fatigue.levels)
    # location → variant → level → (gear, flank) → (bins, teeth) damage
    sums: dict[str, dict[str, list[dict[tuple[str, int], np.ndarray]]]] = {
        where: {v: [{} for _ in range(levels)] for v in VARIANTS} for where in LOCATIONS
    }
    peaks: dict[str, list[dict[str, float]]] = {
        where: [defaultdict(float) for _ in range(levels)] for where in LOCATIONS
    }
    ranges: list[list[defaultdict[str, np.ndarray]]] = [
        [defaultdict(lambda: np.zeros(RANGE_EDGES.size - 1)) for _ in range(bins)]
        for _ in range(levels)
    ]
    teeth: dict[str, int] = {}
    for case in fatigue.cases():
        path = fatigue.cycles_path(case)
        if not path.is_file():
            raise InputError(f"{path}: case {case.name} has not run; run the fatigue set first")
        # The record first, then one flank's cycles at a time: a case's cycles grow with its
        # length, and are never all in memory.
        reduced = CaseCycles.load(path, with_flanks=False)
        factor = site.bins[case.bin].hours * 3600.0 / reduced.counted_seconds / len(fatigue.seeds)
        for location, group in (("contact", "flanks"), ("root", "roots")):
            loaded = _loaded_flanks(saved_flanks(path, group))
            for flank in saved_flanks(path, group):
                teeth[flank.gear] = flank.teeth
                for variant in VARIANTS:
                    curve, limited = _curve(
                        fatigue, flank.gear, variant, location, loaded[flank.gear] == {1, -1}
                    )
                    per_flank = sums[location][variant][case.level]
                    key = (flank.gear, flank.flank)
                    if key not in per_flank:
                        per_flank[key] = np.zeros((bins, flank.teeth))
                    per_flank[key][case.bin] += factor * flank.damage(
                        curve, use_endurance_limit=limited
                    )
                peaks[location][case.level][flank.gear] = max(
                    peaks[location][case.level][flank.gear],
                    float(np.max(flank.peaks, initial=0.0)),
                )
                if location == "contact":
                    counted, _ = np.histogram(flank.ranges, RANGE_EDGES, weights=flank.counts)
                    ranges[case.level][case.bin][flank.gear] += factor * counted / flank.teeth
    damage = {
        where: _worst_flanks(fatigue, sums[where], peaks[where], levels) for where in LOCATIONS
    }
    return SetDamage(
        speeds=site.speeds,
        hours=site.hours,
        levels=tuple(level.label for level in fatigue.levels),
        intensities=tuple(float(np.mean(level.intensities)) for level in fatigue.levels),
        gears=tuple(g for g in fatigue.gears if g in teeth),
        damage=damage["contact"],
        range_cycles=[[dict(b) for b in level] for level in ranges],
        root_damage=damage["root"],
        roles=dict(fatigue.roles),
    )


def _loaded_flanks(group: Iterable[FlankCycles]) -> dict[str, set[int]]:
    """Gear → the flanks a case loads (with any cycle)."""
    loaded: dict[str, set[int]] = defaultdict(set)
    for flank in group:
        if flank.counts.size:
            loaded[flank.gear].add(flank.flank)
    return loaded


def _worst_flanks(
    fatigue: FatigueSet,
    sums: dict[str, list[dict[tuple[str, int], np.ndarray]]],
    peaks: list[dict[str, float]],
    levels: int,
) -> dict[str, list[dict[str, GearDamage]]]:
    """Variant → level → gear → the damage of its worst tooth flank."""
    damage: dict[str, list[dict[str, GearDamage]]] = {}
    for variant in VARIANTS:
        damage[variant] = []
        for level in range(levels):
            gears = {}
            for gear in fatigue.gears:
                flanks = {k: v for k, v in sums[variant][level].items() if k[0] == gear}
                if not flanks:
                    continue
                (_, side), table = max(flanks.items(), key=lambda kv: float(kv[1].sum(0).max()))
                tooth = int(np.argmax(table.sum(axis=0)))
                gears[gear] = GearDamage(
                    gear,
                    table[:, tooth],
                    float(table[:, tooth].sum()),
                    tooth,
                    side,
                    peaks[level][gear],
                )
            damage[variant].append(gears)
    return damage
