"""What a design sweep needs from one kind of stage (planetary, parallel): the `StageDesign` base.

The sweep (`pinwind.runs.sweep`) runs every design the same way, whatever its kind:

1. ``design.check(settings)``: geometry findings (`pinwind.gears.checks`), recorded in the row;
2. ``design.urdf(settings)``: the model file (`pinwind.model.builders`), loaded by pinwind;
3. ``design.loads(settings)``: (torques, initial speeds) that put the stage in torque balance;
   a short rigid `simulate` run gives the mesh forces;
4. `pinwind.analysis.rating.rate` (ISO 6336 and AGMA 2001), then ``design.rating_columns``.

A subclass is a frozen dataclass of one candidate design (SI units) that names its table columns:
``IDENTITY`` (what the design is; ``KEY`` of them identify it across runs, so a re-run skips it)
and ``RESULTS`` (forces, stresses and safety factors). Every kind has the columns ``number``,
``stage``, ``centre_distance_mm``, ``module_mm``, ``ratio``, ``face_width_mm``, ``status``,
``reason``, ``findings``, ``agma_SF_min``, ``iso_S_min`` and ``wall_time_s``, which the queries
(Saleh 2017 eq. 41) and plots use.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

from pinwind.errors import InputError
from pinwind.units import rpm_to_rad_s

if TYPE_CHECKING:
    from pinwind.analysis.rating import GearboxRating

#: Columns every row has after its identity columns, before its results.
STATUS_COLUMNS = ("status", "reason", "findings")


@dataclass(frozen=True)
class SweepSettings:
    """How each design is built, loaded, simulated and rated (one set for every design).

    Attributes:
        input_torque: torque on the stage's input [N·m]: the carrier of a planetary stage, the
            wheel's shaft of a parallel stage (wind-turbine gearboxes step the speed up).
        input_speed: speed of the input [rad/s] at the start of the run (dynamic factors).
        pressure_angle: normal pressure angle [rad] (Saleh 2017: 24.5°).
        face_width: face width [m] when ``face_width_factor`` is None (Saleh 2017: 380 mm).
        face_width_factor: k in b = k π m_n (AGMA's 3…5 circular pitches), else None.
        material: gear material key (`gears.materials.MATERIALS`).
        duration: simulated time [s] of each rigid run.
        dt: time step [s].
    """

    input_torque: float = 1e6
    input_speed: float = rpm_to_rad_s(14.2)
    pressure_angle: float = math.radians(24.5)
    face_width: float = 0.38
    face_width_factor: float | None = None
    material: str = "18CrNiMo7-6"
    duration: float = 0.01
    dt: float = 1e-3

    def __post_init__(self) -> None:
        """Refuse settings no design could be rated with, before any row is computed."""
        alpha = math.degrees(self.pressure_angle)
        if not (math.isfinite(alpha) and 0.0 < alpha < 45.0):
            raise InputError(
                f"--pressure-angle is {alpha:g}°; every design would fail: give a pressure "
                "angle in (0, 45)° (20° is the ISO 53 standard; Saleh 2017 uses 24.5°)"
            )
        if not (math.isfinite(self.input_torque) and self.input_torque > 0.0):
            # NaN or inf ran every design to a table of NaN safety factors
            raise InputError(
                f"--torque is {self.input_torque:g} N·m; give the input torque, a finite "
                "positive number"
            )
        if not (math.isfinite(self.input_speed) and self.input_speed >= 0.0):
            raise InputError(
                f"the input speed (--carrier-speed, --input-speed) is "
                f"{self.input_speed * 30 / math.pi:g} rpm; give a finite speed ≥ 0"
            )
        width = self.face_width if self.face_width_factor is None else self.face_width_factor
        if not (math.isfinite(width) and width > 0.0):
            option = "--face-width" if self.face_width_factor is None else "--face-width-factor"
            raise InputError(f"{option} is {width:g}; give a finite positive number")

    def width(self, module: float) -> float:
        """Face width of a design of module ``module`` [m]."""
        if self.face_width_factor is None:
            return self.face_width
        return self.face_width_factor * math.pi * module


class StageDesign(ABC):
    """One candidate design of a stage kind; subclasses are frozen dataclasses (SI units).

    Class attributes:
        kind: the ``stage`` column's value (``"planetary"``, ``"parallel"``).
        IDENTITY: columns that describe the design, in table order (``number`` first).
        KEY: the identity columns that identify a design across runs (face width included).
        RESULTS: columns filled by `rating_columns`.
        PLOTS: (file stem, column, axis label, line at 1) of `pinwind.analysis.sweep_plots`.
    """

    kind: ClassVar[str]
    IDENTITY: ClassVar[tuple[str, ...]]
    KEY: ClassVar[tuple[str, ...]]
    RESULTS: ClassVar[tuple[str, ...]]
    PLOTS: ClassVar[tuple[tuple[str, str, str, bool], ...]]

    number: int
    module: float

    @classmethod
    def columns(cls) -> tuple[str, ...]:
        """Every column of a row of this kind, in order (units in the names)."""
        return (*cls.IDENTITY, *STATUS_COLUMNS, *cls.RESULTS, "wall_time_s")

    @abstractmethod
    def identity(self, settings: SweepSettings) -> dict:
        """Values of the ``IDENTITY`` columns (lengths in mm, angles in degrees)."""

    @abstractmethod
    def check(self, settings: SweepSettings) -> list:
        """Geometry findings (`pinwind.gears.checks.Finding`) of the design."""

    @abstractmethod
    def urdf(self, settings: SweepSettings) -> str:
        """The design's model file (`pinwind.model.builders`)."""

    @abstractmethod
    def loads(self, settings: SweepSettings) -> tuple[dict[str, float], dict[str, float]]:
        """(joint torques [N·m], initial joint speeds [rad/s]) of the run, in torque balance."""

    @staticmethod
    @abstractmethod
    def rating_columns(rating: GearboxRating) -> dict:
        """The ``RESULTS`` columns from a `pinwind.analysis.rating.GearboxRating`."""

    @classmethod
    @abstractmethod
    def from_row(cls, row: dict) -> StageDesign:
        """The design of a table row."""

    @staticmethod
    @abstractmethod
    def describe(row: dict) -> str:
        """One line naming the design of a row (for ``pinwind sweep query``)."""


def length_key(value: float) -> int:
    """A length [m] rounded to the micrometre, to match designs by value."""
    return round(value * 1e6)
