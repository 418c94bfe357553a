"""Sun, planet and ring gears found from a train's topology, never from their names.

A planetary stage is an internal gear (the ring) and what meshes round it: the planets are the
bodies whose gears mesh with the ring (every gear of such a body is a planet gear, so both gears
of a stepped planet are), the suns the gears on other bodies that mesh with the planets. A gear
named ``a`` or ``wheel3`` is a sun when it sits there; a gear named ``sun`` that meshes with no
planet has no role. Life (per-kind S-N curves, materials, tables), the design sweeps (sun/planet
and planet/ring columns) and the modes (the stage's central members) read the roles here.
"""

from __future__ import annotations

from collections.abc import Hashable, Iterable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from pinwind.model.gearbox import Gearbox

#: The roles a gear of a planetary stage has, in the order tables list them.
ROLES = ("sun", "planet", "ring")


@dataclass(frozen=True)
class PlanetaryGears:
    """The gears of one planetary stage by their place in it.

    Attributes:
        ring: the internal gear.
        planets: the gears of the bodies that mesh with the ring, in the train's order.
        suns: the gears on other bodies that mesh with the planets, in the train's order.
    """

    ring: str
    planets: tuple[str, ...]
    suns: tuple[str, ...]


def planetary_gears(
    internal: Mapping[str, bool],
    pairs: Iterable[tuple[str, str]],
    body: Mapping[str, Hashable] | None = None,
) -> list[PlanetaryGears]:
    """The planetary stages of a train, one per internal gear that other gears mesh with.

    Args:
        internal: every gear → whether it is internal, in the train's order.
        pairs: the meshes as pairs of gear names.
        body: gear → the body that carries it (default: each gear its own body); gears of one
            body share its place (a stepped planet).
    """
    carrier = dict(body) if body is not None else {g: g for g in internal}
    partners: dict[str, set[str]] = {g: set() for g in internal}
    for a, b in pairs:
        partners[a].add(b)
        partners[b].add(a)
    stages = []
    for ring, is_internal in internal.items():
        if not is_internal:
            continue
        bodies = {carrier[g] for g in partners[ring]} - {carrier[ring]}
        if not bodies:
            continue
        planets = tuple(g for g in internal if carrier[g] in bodies)
        taken = bodies | {carrier[ring]}
        meshed = {s for p in planets for s in partners[p]}
        suns = tuple(g for g in internal if g in meshed and carrier[g] not in taken)
        stages.append(PlanetaryGears(ring, planets, suns))
    return stages


def gearbox_planetary_gears(gearbox: Gearbox) -> list[PlanetaryGears]:
    """`planetary_gears` of a model: its gears, meshes and the joints that carry the gears."""
    return planetary_gears(
        {name: g.spec.internal for name, g in gearbox.gears.items()},
        ((m.gear_a.name, m.gear_b.name) for m in gearbox.meshes),
        {name: g.joint_id for name, g in gearbox.gears.items()},
    )


def gear_roles(stages: Iterable[PlanetaryGears]) -> dict[str, str]:
    """Gear → ``"sun"``, ``"planet"`` or ``"ring"`` over ``stages``; gears of no stage left out."""
    roles: dict[str, str] = {}
    for stage in stages:
        roles |= {g: "sun" for g in stage.suns}
        roles |= {g: "planet" for g in stage.planets}
        roles[stage.ring] = "ring"
    return roles
