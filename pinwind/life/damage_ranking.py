"""Every gear and bearing of a fatigue set ranked by the damage of its design life.

Nejad et al. 2016 (§6, the "vulnerability map") rank the gears' teeth and the bearings of the
5 MW reference gearbox by their 20-year damage, to say where a failure is most likely to start.
Here one list holds, for one turbulence level of a fatigue set and one S-N variant
(`pinwind.life.set_damage.VARIANTS`):

- each gear's contact (flank) damage: its worst tooth flank's Palmgren–Miner sum of the von
  Mises contact stress (`GearDamage.total`);
- each gear's root damage: the same of its fillet's root stress;
- each rated bearing's (or row's) ISO 281 life consumption: the revolutions of the design life
  over its L10 at P_eq (`BearingLife.life_consumed`), the Miner sum of bearing fatigue at 10 %
  failure probability.

All three are fractions of a life (1: the life is used up) but of different curves and
probabilities: the ranking says which item comes first under this set's assumptions, not a
probability of failure.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pinwind.life.bearing_life import BearingLife
from pinwind.life.set_damage import SetDamage

#: The kinds of ranked items, with what their damage is.
KINDS = {
    "flank": "contact (pitting) damage of the worst tooth flank",
    "root": "root (bending) damage of the worst tooth fillet",
    "bearing": "ISO 281 life consumption, revolutions / L10",
}


@dataclass(frozen=True)
class RankedItem:
    """One gear's flank or root, or one bearing, with its damage over the design life.

    Attributes:
        name: the gear, or the bearing (``BEARING.ROW`` for a row).
        kind: ``"flank"``, ``"root"`` or ``"bearing"`` (`KINDS`).
        damage: its damage (or life consumption) over the design life [-].
        detail: what the number comes from, for a table (peak stress, P_eq and C).
    """

    name: str
    kind: str
    damage: float
    detail: str


def damage_ranking(
    damage: SetDamage,
    lives: list[list[BearingLife]],
    *,
    variant: str = "iso 6336",
    level: int = 0,
) -> list[RankedItem]:
    """Every gear (flank and root) and every rated bearing, the most damaged first.

    Args:
        damage: the set's gear damage (`set_damage`).
        lives: the set's bearing lives per level (`set_bearing_lives`); bearings without a
            rating are left out.
        variant: the S-N variant of the gears (`set_damage.VARIANTS`).
        level: the turbulence level's index.
    """
    items = []
    for kind, table in (("flank", damage.damage), ("root", damage.root_damage)):
        for gear, rated in table[variant][level].items():
            items.append(
                RankedItem(
                    gear,
                    kind,
                    rated.total,
                    f"tooth {rated.tooth} flank {rated.flank:+d}, peak "
                    f"{rated.peak_stress / 1e6:.0f} MPa",
                )
            )
    for life in lives[level]:
        if life.rated and life.rating is not None and life.rating.dynamic_load_rating:
            items.append(
                RankedItem(
                    life.joint,
                    "bearing",
                    life.life_consumed,
                    f"P_eq {life.equivalent_load / 1e3:.0f} kN, "
                    f"C {life.rating.dynamic_load_rating / 1e3:.0f} kN, "
                    f"{life.mean_speed_rpm:.1f} rpm",
                )
            )
    # NaN last, then the largest damage first; names break ties so that the order is stable.
    return sorted(items, key=lambda i: (math.isnan(i.damage), -_finite(i.damage), i.kind, i.name))


def _finite(value: float) -> float:
    return 0.0 if math.isnan(value) else value
