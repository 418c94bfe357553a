"""Parallel (spur or helical) stages for the design sweep, as Saleh 2017 §5 says.

"The previous systematic procedure can be applied for designing the other parallel axis stages"
(Saleh 2017 §5): the same loop as `sweep_planetary`, for one wheel–pinion pair.

`enumerate_parallel`: for each module m_n and centre distance a, the tooth sum is
Σ = 2 a cos β / m_n. For spur gears (β = 0) Σ must be whole, as the planetary sweep asks of
z_sun + z_planet (no profile shift). For a helical stage the nominal β gives Σ = ⌊2 a cos β/m_n⌋
and the helix angle is then raised to β' = acos(m_n Σ / 2a) so that the pair sits at a exactly
(the usual way to meet a centre distance without profile shift). Every split of Σ into a pinion
z_p and a wheel z_w = Σ − z_p with a speed ratio u = z_w/z_p strictly inside (lo, hi) is kept
when `pinwind.gears.checks.check_pair` finds no error (undercut of the pinion, pointed teeth,
ε_α < 1); designs that only draw warnings are kept with their findings.

Each `ParallelDesign` is built with `model.builders.parallel_urdf`: the wheel on the input shaft
(joint ``input``), the pinion on joint ``stage1_pinion``, mesh ``stage1``. The run applies the
input torque T to the wheel and +T/u to the pinion (the pinion turns the other way, so a load
that resists it is positive): the stage is in torque balance and the tangential force at the
reference circle is T / r_wheel with r_wheel = m_n z_w / (2 cos β).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

from pinwind.analysis.sweep_design import StageDesign, SweepSettings
from pinwind.errors import InputError

if TYPE_CHECKING:
    from pinwind.analysis.rating import GearboxRating

#: Names of the two gears and the mesh in the model of a `ParallelDesign`.
WHEEL, PINION, MESH = "stage1_wheel", "stage1_pinion", "stage1"


@dataclass(frozen=True)
class ParallelDesign(StageDesign):
    """One candidate parallel stage (SI units): a wheel on the input drives a pinion.

    Attributes:
        number: design number, 1… in enumeration order.
        centre_distance: a = m_n (z_wheel + z_pinion) / (2 cos β) [m].
        module: normal module m_n [m].
        wheel, pinion: tooth numbers.
        helix_angle: β [rad] of the wheel (the pinion has −β); 0 for spur gears.
        ratio: u = z_wheel / z_pinion (speed-up from wheel to pinion).
    """

    number: int
    centre_distance: float
    module: float
    wheel: int
    pinion: int
    helix_angle: float
    ratio: float

    kind: ClassVar[str] = "parallel"
    IDENTITY: ClassVar[tuple[str, ...]] = (
        "number", "stage", "centre_distance_mm", "module_mm", "wheel", "pinion", "helix_angle_deg",
        "ratio", "face_width_mm",
    )  # fmt: skip
    KEY: ClassVar[tuple[str, ...]] = (
        "centre_distance_mm", "module_mm", "wheel", "pinion", "helix_angle_deg", "face_width_mm",
    )  # fmt: skip
    RESULTS: ClassVar[tuple[str, ...]] = (
        "normal_force_kN", "tangential_force_kN",
        "agma_contact_stress_MPa", "agma_bending_stress_max_MPa",
        "agma_SF_contact", "agma_SF_bending_wheel", "agma_SF_bending_pinion", "agma_SF_bending_min",
        "agma_SF_min",
        "iso_sigma_H_MPa", "iso_sigma_F_max_MPa",
        "iso_S_H", "iso_S_F_wheel", "iso_S_F_pinion", "iso_S_F_min", "iso_S_min",
        "hertz_p_max_MPa",
    )  # fmt: skip
    PLOTS: ClassVar[tuple[tuple[str, str, str, bool], ...]] = (
        ("centre_distance", "centre_distance_mm", "centre distance [mm]", False),
        ("speed_ratio", "ratio", "speed ratio [-]", False),
        ("contact_sf", "agma_SF_contact", "AGMA S_H wheel/pinion [-]", True),
        ("bending_sf_min", "agma_SF_bending_min", "AGMA S_F, smaller of the two gears [-]", True),
        ("iso_sf_min", "iso_S_min", "ISO 6336 smallest S_H, S_F [-]", True),
    )

    def identity(self, settings: SweepSettings) -> dict:
        """The identity columns of the row (`StageDesign.identity`)."""
        return {
            "number": self.number,
            "stage": self.kind,
            "centre_distance_mm": self.centre_distance * 1e3,
            "module_mm": self.module * 1e3,
            "wheel": self.wheel,
            "pinion": self.pinion,
            "helix_angle_deg": math.degrees(self.helix_angle),
            "ratio": self.ratio,
            "face_width_mm": settings.width(self.module) * 1e3,
        }

    def check(self, settings: SweepSettings) -> list:
        """`gears.checks.check_pair` of pinion and wheel."""
        return _findings(
            self.pinion, self.wheel, self.module, settings.pressure_angle, self.helix_angle,
            face_width=settings.width(self.module),
        )  # fmt: skip

    def urdf(self, settings: SweepSettings) -> str:
        """`model.builders.parallel_urdf` of the pair."""
        from pinwind.model.builders import parallel_urdf

        return parallel_urdf(
            stages=[(self.wheel, self.pinion)], module=self.module,
            pressure_angle=settings.pressure_angle, face_width=settings.width(self.module),
            helix_angle=self.helix_angle, name=f"design{self.number}",
        )  # fmt: skip

    def loads(self, settings: SweepSettings) -> tuple[dict[str, float], dict[str, float]]:
        """Input torque T on the wheel, +T/u on the pinion (module docstring)."""
        torque = settings.input_torque
        return {"input": torque, PINION: torque / self.ratio}, {"input": settings.input_speed}

    @staticmethod
    def rating_columns(rating: GearboxRating) -> dict:
        """The results of the row (`StageDesign.rating_columns`)."""
        (mesh,) = [m for m in rating.meshes if m.mesh == MESH]
        wheel = mesh.pair.names.index(WHEEL)
        pinion = mesh.pair.names.index(PINION)
        out = {
            "normal_force_kN": mesh.normal_force / 1e3,
            "tangential_force_kN": mesh.load.tangential_force / 1e3,
            "agma_contact_stress_MPa": max(mesh.agma.contact_stress) / 1e6,
            "agma_bending_stress_max_MPa": max(mesh.agma.bending_stress) / 1e6,
            "agma_SF_contact": float(min(mesh.agma.S_H)),
            "agma_SF_bending_wheel": float(mesh.agma.S_F[wheel]),
            "agma_SF_bending_pinion": float(mesh.agma.S_F[pinion]),
            "iso_sigma_H_MPa": max(mesh.iso.sigma_H) / 1e6,
            "iso_sigma_F_max_MPa": max(mesh.iso.sigma_F) / 1e6,
            "iso_S_H": float(min(mesh.iso.S_H)),
            "iso_S_F_wheel": float(mesh.iso.S_F[wheel]),
            "iso_S_F_pinion": float(mesh.iso.S_F[pinion]),
            "hertz_p_max_MPa": mesh.hertz_p_max / 1e6,
        }
        bending = (out["agma_SF_bending_wheel"], out["agma_SF_bending_pinion"])
        out["agma_SF_bending_min"] = min(bending)
        out["agma_SF_min"] = min(out["agma_SF_contact"], out["agma_SF_bending_min"])
        out["iso_S_F_min"] = min(out["iso_S_F_wheel"], out["iso_S_F_pinion"])
        out["iso_S_min"] = min(out["iso_S_H"], out["iso_S_F_min"])
        return out

    @classmethod
    def from_row(cls, row: dict) -> ParallelDesign:
        """The design of a table row."""
        return cls(
            number=int(row["number"]),
            centre_distance=float(row["centre_distance_mm"]) * 1e-3,
            module=float(row["module_mm"]) * 1e-3,
            wheel=int(row["wheel"]),
            pinion=int(row["pinion"]),
            helix_angle=math.radians(float(row["helix_angle_deg"])),
            ratio=float(row["ratio"]),
        )

    @staticmethod
    def describe(row: dict) -> str:
        """One line naming the design of a row."""
        beta = float(row["helix_angle_deg"])
        return (
            f"a = {float(row['centre_distance_mm']):g} mm, m = {float(row['module_mm']):g} mm, "
            f"teeth {int(row['wheel'])}/{int(row['pinion'])}"
            + (f", β = {beta:.3f}°" if beta else "")
            + f", u = {float(row['ratio']):.2f}"
        )


#: The most teeth 2a/m of a centre distance and module the sweep enumerates (a wind-turbine
#: stage has a few hundred): 1e30 mm over 15 mm never returned, building every tooth count.
MAX_TEETH = 10_000


def enumerate_parallel(
    centre_distances: Iterable[float],
    modules: Iterable[float],
    *,
    ratio_window: tuple[float, float],
    pressure_angle: float,
    helix_angle: float = 0.0,
) -> list[ParallelDesign]:
    """Every buildable parallel stage, numbered by module, then centre distance, then pinion.

    Args:
        centre_distances: candidate centre distances a [m].
        modules: candidate normal modules m_n [m].
        ratio_window: (lo, hi): keep lo < z_wheel/z_pinion < hi (open, as `enumerate_planetary`).
        pressure_angle: normal pressure angle α_n [rad] (for the undercut and tip checks).
        helix_angle: nominal helix angle β [rad], 0 for spur gears; a helical design's β is
            raised to fit a exactly (module docstring).

    Raises:
        InputError: an empty or reversed window, a non-positive module or centre distance, or
            |β| ≥ 45°.
    """
    lo, hi = ratio_window
    if not lo < hi:
        raise InputError(f"the ratio window {lo}:{hi} is empty; give LOW:HIGH with LOW < HIGH")
    if not 0.0 <= helix_angle < math.pi / 4.0:
        raise InputError(
            f"helix angle {math.degrees(helix_angle):g}°; give 0 ≤ β < 45° (0 for spur gears)"
        )
    designs: list[ParallelDesign] = []
    for module in sorted(set(modules)):
        for a in sorted(set(centre_distances)):
            if module <= 0 or a <= 0:
                raise InputError(f"module {module} m and centre distance {a} m must be positive")
            if 2.0 * a / module > MAX_TEETH:
                raise InputError(
                    f"centre distance {a * 1e3:g} mm over module {module * 1e3:g} mm is "
                    f"2a/m = {2.0 * a / module:.3g} teeth of pinion and wheel, each count of "
                    "which the sweep would build; give a centre distance and modules in mm "
                    f"of at most {MAX_TEETH} teeth (2a/m)"
                )
            total, beta = _tooth_sum(a, module, helix_angle)
            if total is None:
                continue
            for pinion in range(1, total):
                wheel = total - pinion
                ratio = wheel / pinion
                if not lo < ratio < hi:
                    continue
                # No check reads the face width (it only sets the overlap ratio): one circular
                # pitch stands in for the width the settings give later.
                if any(f.severity == "error" for f in _findings(
                    pinion, wheel, module, pressure_angle, beta, face_width=math.pi * module
                )):  # fmt: skip
                    continue
                designs.append(
                    ParallelDesign(
                        number=len(designs) + 1,
                        centre_distance=a,
                        module=module,
                        wheel=wheel,
                        pinion=pinion,
                        helix_angle=beta,
                        ratio=ratio,
                    )
                )
    return designs


def _tooth_sum(a: float, module: float, helix_angle: float) -> tuple[int | None, float]:
    """(Σ, β): the whole tooth sum at centre distance a and the helix angle that fits it."""
    teeth = 2.0 * a * math.cos(helix_angle) / module
    if helix_angle == 0.0:
        total = round(teeth)
        if abs(teeth - total) > 1e-9 * max(teeth, 1.0):
            return None, 0.0
        return total, 0.0
    total = math.floor(teeth + 1e-9)
    if total < 2:
        return None, helix_angle
    return total, math.acos(min(1.0, module * total / (2.0 * a)))


def _findings(
    pinion: int, wheel: int, module: float, pressure_angle: float, beta: float, *, face_width: float
) -> list:
    """`gears.checks.check_pair` of the pinion–wheel pair."""
    from pinwind.gears.checks import check_pair
    from pinwind.gears.gear_pair import GearPair

    return check_pair(
        GearPair(pinion, wheel, module=module, pressure_angle=pressure_angle,
                 face_width=face_width, helix_angle=beta)
    )  # fmt: skip
