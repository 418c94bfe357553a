"""Planetary stages for the design sweep (Saleh 2017 §5, Table 5, eq. 41).

`enumerate_planetary`: every buildable stage for the given centre distances and modules: whole
tooth numbers with z_sun + z_planet = 2 a/m, z_ring = z_sun + 2 z_planet (no profile shift,
Saleh 2017 §4.1), equally spaced planets ((z_sun + z_ring)/N whole) and a speed ratio
i = 1 + z_ring/z_sun strictly inside the window (lo, hi). Designs given in ``include`` (the
paper's preliminary 24/48/120 at 15 mm, i = 6 exactly, on the window's edge) are added and
numbered first in their (module, centre distance) group, as Table 5 numbers #38 before #39.

Each `PlanetaryDesign` is built with `model.builders.planetary_urdf` and run with the carrier
torque in and the sun loaded with −T/i, so the stage is in torque balance (`StageDesign`).

Why the window is open: with the paper's inputs every (a, m) group that assembles has a design
at i = 6 exactly (z_sun = (z_sun + z_planet)/3) and two have one at 6.4 (480 mm with 5 and
10 mm); Table 5 lists none of them but the preliminary design. So Table 5 is (6, 6.4) open plus
the preliminary design; `TABLE_5_INCLUDE` holds it.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

from pinwind.analysis.sweep_design import StageDesign, SweepSettings, length_key
from pinwind.errors import InputError
from pinwind.model.gear_roles import gear_roles, planetary_gears

if TYPE_CHECKING:
    from pinwind.analysis.rating import GearboxRating

#: The preliminary design of Saleh 2017 (Table 2): (sun, planet, ring, module [m]).
TABLE_5_INCLUDE = ((24, 48, 120, 0.015),)


@dataclass(frozen=True)
class PlanetaryDesign(StageDesign):
    """One candidate planetary stage (SI units), ring fixed, carrier in, sun out.

    Attributes:
        number: design number, 1… in enumeration order (Table 5's "#").
        centre_distance: a = m (z_sun + z_planet)/2 [m].
        module: m [m].
        sun, planet, ring: tooth numbers.
        planets: number of planets.
        ratio: i = 1 + z_ring/z_sun (carrier to sun, ring fixed).
        included: added by ``include`` rather than found in the window.
    """

    number: int
    centre_distance: float
    module: float
    sun: int
    planet: int
    ring: int
    planets: int
    ratio: float
    included: bool = False

    kind: ClassVar[str] = "planetary"
    IDENTITY: ClassVar[tuple[str, ...]] = (
        "number", "stage", "centre_distance_mm", "module_mm", "sun", "planet", "ring", "planets",
        "ratio", "face_width_mm", "included",
    )  # fmt: skip
    KEY: ClassVar[tuple[str, ...]] = (
        "centre_distance_mm", "module_mm", "sun", "planet", "ring", "planets", "face_width_mm",
    )  # fmt: skip
    RESULTS: ClassVar[tuple[str, ...]] = (
        "sun_planet_normal_force_kN", "sun_planet_tangential_force_kN",
        "planet_ring_normal_force_kN",
        "agma_contact_stress_sun_planet_MPa", "agma_contact_stress_planet_ring_MPa",
        "agma_bending_stress_max_MPa",
        "agma_SF_contact_sun_planet", "agma_SF_contact_planet_ring", "agma_SF_bending_min",
        "agma_SF_bending_sun", "agma_SF_bending_planet", "agma_SF_bending_ring", "agma_SF_min",
        "iso_sigma_H_sun_planet_MPa", "iso_sigma_H_planet_ring_MPa", "iso_sigma_F_max_MPa",
        "iso_S_H_sun_planet", "iso_S_H_planet_ring", "iso_S_F_min", "iso_S_min",
        "hertz_p_max_sun_planet_MPa", "hertz_p_max_planet_ring_MPa",
    )  # fmt: skip
    PLOTS: ClassVar[tuple[tuple[str, str, str, bool], ...]] = (
        ("fig14_centre_distance", "centre_distance_mm", "centre distance [mm]", False),
        ("fig15_speed_ratio", "ratio", "speed ratio [-]", False),
        ("fig16_contact_sf_sun_planet", "agma_SF_contact_sun_planet", "AGMA S_H sun/planet [-]",
         True),
        ("fig17_contact_sf_planet_ring", "agma_SF_contact_planet_ring", "AGMA S_H planet/ring [-]",
         True),
        ("fig18_bending_sf_min", "agma_SF_bending_min", "AGMA S_F, smallest of all gears [-]",
         True),
        ("fig19_iso_sf_min", "iso_S_min", "ISO 6336 smallest S_H, S_F [-]", True),
    )  # fmt: skip

    def identity(self, settings: SweepSettings) -> dict:
        """The identity columns of the row (`StageDesign.identity`)."""
        return {
            "number": self.number,
            "stage": self.kind,
            "centre_distance_mm": self.centre_distance * 1e3,
            "module_mm": self.module * 1e3,
            "sun": self.sun,
            "planet": self.planet,
            "ring": self.ring,
            "planets": self.planets,
            "ratio": self.ratio,
            "face_width_mm": settings.width(self.module) * 1e3,
            "included": self.included,
        }

    def check(self, settings: SweepSettings) -> list:
        """`gears.checks.check_planetary` of the stage."""
        from pinwind.gears.checks import check_planetary

        return check_planetary(
            sun=self.sun, planet=self.planet, ring=self.ring, planets=self.planets,
            module=self.module, pressure_angle=settings.pressure_angle,
            face_width=settings.width(self.module),
        )  # fmt: skip

    def urdf(self, settings: SweepSettings) -> str:
        """`model.builders.planetary_urdf` of the stage."""
        from pinwind.model.builders import planetary_urdf

        return planetary_urdf(
            sun=self.sun, planet=self.planet, ring=self.ring, planets=self.planets,
            module=self.module, pressure_angle=settings.pressure_angle,
            face_width=settings.width(self.module), name=f"design{self.number}",
        )  # fmt: skip

    def loads(self, settings: SweepSettings) -> tuple[dict[str, float], dict[str, float]]:
        """Carrier torque T in, sun loaded with −T/i (sun and carrier turn the same way)."""
        torques = {"carrier": settings.input_torque, "sun": -settings.input_torque / self.ratio}
        return torques, {"carrier": settings.input_speed}

    @staticmethod
    def rating_columns(rating: GearboxRating) -> dict:
        """The results of the row (`StageDesign.rating_columns`)."""
        return _rating_columns(rating)

    @classmethod
    def from_row(cls, row: dict) -> PlanetaryDesign:
        """The design of a table row."""
        return cls(
            number=int(row["number"]),
            centre_distance=float(row["centre_distance_mm"]) * 1e-3,
            module=float(row["module_mm"]) * 1e-3,
            sun=int(row["sun"]),
            planet=int(row["planet"]),
            ring=int(row["ring"]),
            planets=int(row["planets"]),
            ratio=float(row["ratio"]),
            included=bool(row["included"]),
        )

    @staticmethod
    def describe(row: dict) -> str:
        """One line naming the design of a row."""
        return (
            f"a = {float(row['centre_distance_mm']):g} mm, m = {float(row['module_mm']):g} mm, "
            f"teeth {int(row['sun'])}/{int(row['planet'])}/{int(row['ring'])}, "
            f"i = {float(row['ratio']):.2f}"
        )


#: The most teeth 2a/m of a centre distance and module the sweep enumerates (a wind-turbine
#: stage has a few hundred): 1e30 mm over 15 mm never returned, building every tooth count.
MAX_TEETH = 10_000


def enumerate_planetary(
    centre_distances: Iterable[float],
    modules: Iterable[float],
    *,
    ratio_window: tuple[float, float],
    planets: int = 3,
    include: Iterable[tuple[int, int, int, float]] = (),
) -> list[PlanetaryDesign]:
    """Every buildable design, numbered by module, then centre distance, then sun teeth.

    Args:
        centre_distances: candidate centre distances a [m].
        modules: candidate modules m [m].
        ratio_window: (lo, hi): keep lo < i < hi (open, see the module docstring).
        planets: number of planets N.
        include: extra designs (sun, planet, ring, module [m]) kept whatever their ratio; they
            must still be buildable (ring = sun + 2 planet, equal spacing).

    Raises:
        InputError: an empty or reversed window, a non-positive value, or an ``include`` that
            cannot be built.
    """
    lo, hi = ratio_window
    if not lo < hi:
        raise InputError(f"the ratio window {lo}:{hi} is empty; give LOW:HIGH with LOW < HIGH")
    if planets < 1:
        raise InputError(f"planets = {planets}; give at least one planet")
    extra: dict[tuple[float, float], list[tuple[int, int, int]]] = {}
    for sun, planet, ring, module in include:
        if ring != sun + 2 * planet or (sun + ring) % planets:
            raise InputError(
                f"included design {sun}/{planet}/{ring} cannot be built: the ring needs "
                f"sun + 2·planet = {sun + 2 * planet} teeth and (sun + ring)/{planets} must be "
                "whole"
            )
        a = module * (sun + planet) / 2.0
        extra.setdefault((length_key(module), length_key(a)), []).append((sun, planet, ring))
    designs: list[PlanetaryDesign] = []
    for module in sorted(set(modules)):
        for a in sorted(set(centre_distances)):
            if module <= 0 or a <= 0:
                raise InputError(f"module {module} m and centre distance {a} m must be positive")
            if 2.0 * a / module > MAX_TEETH:
                raise InputError(
                    f"centre distance {a * 1e3:g} mm over module {module * 1e3:g} mm is "
                    f"2a/m = {2.0 * a / module:.3g} teeth of sun and planet, each count of "
                    "which the sweep would build; give a centre distance and modules in mm "
                    f"of at most {MAX_TEETH} teeth (2a/m)"
                )
            group = []
            for sun, planet, ring in extra.get((length_key(module), length_key(a)), []):
                group.append((sun, planet, ring, True))
            teeth = 2.0 * a / module
            total = round(teeth)
            if abs(teeth - total) < 1e-9 * max(teeth, 1.0):
                for sun in range(1, total):
                    planet = total - sun
                    ring = sun + 2 * planet
                    ratio = 1.0 + ring / sun
                    if (sun + ring) % planets or not lo < ratio < hi:
                        continue
                    if any(g[0] == sun for g in group):
                        continue
                    group.append((sun, planet, ring, False))
            for sun, planet, ring, included in group:
                designs.append(
                    PlanetaryDesign(
                        number=len(designs) + 1,
                        centre_distance=a,
                        module=module,
                        sun=sun,
                        planet=planet,
                        ring=ring,
                        planets=planets,
                        ratio=1.0 + ring / sun,
                        included=included,
                    )
                )
    return designs


def _rating_columns(rating: GearboxRating) -> dict:
    internal: dict[str, bool] = {}
    for m in rating.meshes:
        internal |= dict(zip(m.pair.names, (m.pair.internal_1, m.pair.internal_2), strict=True))
    pairs = [m.pair.names for m in rating.meshes]
    roles = gear_roles(planetary_gears(internal, pairs))  # from the topology, not the names
    sp = [m for m in rating.meshes if {roles.get(g) for g in m.pair.names} == {"sun", "planet"}]
    pr = [m for m in rating.meshes if "ring" in {roles.get(g) for g in m.pair.names}]
    gears = rating.gears
    planets = [g for name, g in gears.items() if roles.get(name) == "planet"]
    (sun,) = (g for name, g in gears.items() if roles.get(name) == "sun")
    (ring,) = (g for name, g in gears.items() if roles.get(name) == "ring")

    def low(items: Iterable[float]) -> float:
        return float(min(items))

    out = {
        "sun_planet_normal_force_kN": max(m.normal_force for m in sp) / 1e3,
        "sun_planet_tangential_force_kN": max(m.load.tangential_force for m in sp) / 1e3,
        "planet_ring_normal_force_kN": max(m.normal_force for m in pr) / 1e3,
        "agma_contact_stress_sun_planet_MPa": max(max(m.agma.contact_stress) for m in sp) / 1e6,
        "agma_contact_stress_planet_ring_MPa": max(max(m.agma.contact_stress) for m in pr) / 1e6,
        "agma_bending_stress_max_MPa": max(max(m.agma.bending_stress) for m in rating.meshes) / 1e6,
        "agma_SF_contact_sun_planet": low(s for m in sp for s in m.agma.S_H),
        "agma_SF_contact_planet_ring": low(s for m in pr for s in m.agma.S_H),
        "agma_SF_bending_min": low(s for m in rating.meshes for s in m.agma.S_F),
        "agma_SF_bending_sun": sun.S_F_agma,
        "agma_SF_bending_planet": low(g.S_F_agma for g in planets),
        "agma_SF_bending_ring": ring.S_F_agma,
        "iso_sigma_H_sun_planet_MPa": max(max(m.iso.sigma_H) for m in sp) / 1e6,
        "iso_sigma_H_planet_ring_MPa": max(max(m.iso.sigma_H) for m in pr) / 1e6,
        "iso_sigma_F_max_MPa": max(max(m.iso.sigma_F) for m in rating.meshes) / 1e6,
        "iso_S_H_sun_planet": low(s for m in sp for s in m.iso.S_H),
        "iso_S_H_planet_ring": low(s for m in pr for s in m.iso.S_H),
        "iso_S_F_min": low(s for m in rating.meshes for s in m.iso.S_F),
        "hertz_p_max_sun_planet_MPa": max(m.hertz_p_max for m in sp) / 1e6,
        "hertz_p_max_planet_ring_MPa": max(m.hertz_p_max for m in pr) / 1e6,
    }
    out["agma_SF_min"] = min(
        out["agma_SF_contact_sun_planet"], out["agma_SF_contact_planet_ring"],
        out["agma_SF_bending_min"],
    )  # fmt: skip
    out["iso_S_min"] = min(
        out["iso_S_H_sun_planet"], out["iso_S_H_planet_ring"], out["iso_S_F_min"]
    )
    return out
