"""A rolling bearing's frictional moment: Palmgren's M0 + M1 as ISO/TR 14179-2:2001 gives it.

ISO/TR 14179-2:2001 (§ on bearing losses) splits a rolling bearing's frictional moment, after
Palmgren (1959, *Ball and Roller Bearing Engineering*, 3rd ed., ch. on friction), into a
load-independent part M0 from the oil's viscous drag and a load-dependent part M1 [N·mm, with
ν in mm²/s, n in rpm, d_m in mm and P1 in N]:

    M0 = 10⁻⁷ f0 (ν n)^(2/3) d_m³          for ν n ≥ 2000
    M0 = 160·10⁻⁷ f0 d_m³                  for ν n < 2000
    M1 = f1 P1 d_m

f0 depends on the bearing type and the way it is lubricated (oil bath, jet, mist), f1 on the type
and its load, P1 is the load that governs M1 (``friction_load``), d_m = (D + d)/2 the mean
diameter and ν the oil's kinematic viscosity at its operating temperature (``losses/oil.py``).
The power loss is P = M ω.

The two branches of M0 meet at ν n = 2000 only to within 0.8 % (2000^(2/3) = 158.7, not 160):
pinwind takes the larger of the two, ``10⁻⁷ f0 d_m³ max((ν n)^(2/3), 160)``, continuous, which
differs from the standard's only for 2000 < ν n < 2024 (by ≤ 0.8 %). The viscous branch's
form and its 10⁻⁷ are as read in Fernandes's script (below); the low-speed branch (160) was not
found in a text that could be read and cited.

**Factors** (``PALMGREN_FACTORS``), by bearing type, and where each was checked. The formula
(M0 = 10⁻⁷ f0 (ν n)^(2/3) d_m³ [N·mm], ν n ≥ 2000) and the deep-groove ball bearing's range
f0 = 1.5-2 were read in C. Fernandes (University of Porto), figure script
``figures/RB_L3_Palmgren.py`` of the public repository cfernandesFEUP/Machine-Elements-Animations-
Figures (commit 40f90ec, function ``Harris``: "f0 = 1.75 ## 1.5-2", 6206 bearing), which takes the
middle, 1.75. No other row could be checked against a readable text: ISO/TR 14179-2, Palmgren
(1959), Harris & Kotzalas (2007) and the bearing makers' friction tables were not found in a form
that could be read; those rows are the values first written here, unverified (``source``):

| type | f0 | f1 | P1 | checked |
|---|---|---|---|---|
| deep_groove_ball | 1.75 (1.5-2) | 0.0007 | max(3 F_a − 0.1 F_r, F_r) | f0: Fernandes (above) |
| angular_contact_ball | 2.0 | 0.001 | max(0.9 F_a cot α − 0.1 F_r, F_r) | unverified |
| cylindrical_roller | 2.5 | 0.000275 | F_r | unverified |
| tapered_roller | 4.0 | 0.0004 | max(0.8 F_a cot α, F_r) | unverified |
| spherical_roller | 5.0 | 0.0004 | max(0.8 F_a cot α, F_r) | unverified |
| toroidal_roller | 5.0 (as spherical) | 0.0004 (as spherical) | F_r | pinwind's assumption |

(the deep-groove ball bearing's f1 and P1 rule: unverified.)

Fernandes's script takes the ball bearing's load term in another form, M1 = μ f1 F d_m/2 with
μ = 0.002 (F/C0)^(1/2) and f1 = 1.45 (a coefficient that grows with the load), not the constant
f1 here: the form of M1 for ball bearings is not settled by a text read here.
(tapered: pinwind uses the radial roller bearing's rule, 0.8 F_a cot α with the type's ISO 281
contact angle, ``model/bearing.py``.) The toroidal (CARB) roller bearing is not in Palmgren's
tables: pinwind takes the spherical roller bearing's factors (the same barrel-shaped rollers in
a curved raceway), an assumption. A model file may give a bearing's own ``friction_f0`` and
``friction_f1`` (its catalogue's; docs/losses.md), the better values for a real bearing.
SKF's 2018 model (rolling, sliding, seal and drag moments) is not implemented.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pinwind.errors import InvalidLossInput
from pinwind.losses.oil import Lubricant

#: A value or an array of values (speeds, loads), SI units.
Values = float | np.ndarray

__all__ = [
    "LOAD_RULES",
    "LOW_SPEED_PRODUCT",
    "PALMGREN_FACTORS",
    "STICK_SPEED",
    "BearingFriction",
    "PalmgrenFactors",
    "friction_load",
    "load_moment",
    "lubricant_viscosity",
    "no_load_moment",
    "no_load_moment_coefficients",
]

#: ν n [mm²/s · rpm] below which ISO/TR 14179-2's M0 is constant (160^(3/2) ≈ 2024 with the
#: continuous form, module docstring).
LOW_SPEED_PRODUCT = 2000.0
_FLOOR = 160.0  # (ν n)^(2/3) of the low-speed branch
_RPM = 60.0 / (2.0 * math.pi)


@dataclass(frozen=True)
class PalmgrenFactors:
    """Palmgren's friction factors of a bearing type (module docstring).

    Attributes:
        f0: no-load factor [-] (oil bath).
        f1: load factor [-].
        axial: how the axial load enters P1: "none" (P1 = F_r), "ball" (max(3 F_a − 0.1 F_r,
            F_r)), "angular_ball" (max(0.9 F_a cot α − 0.1 F_r, F_r)), "roller"
            (max(0.8 F_a cot α, F_r)).
        contact_angle: α [rad] of the axial rule.
        source: where the factors come from.
    """

    f0: float
    f1: float
    axial: str
    contact_angle: float
    source: str


#: Where a row's factors were read (module docstring).
_FERNANDES = (
    "f0 1.75, the middle of 1.5-2: C. Fernandes (U. Porto), cfernandesFEUP/Machine-Elements-"
    "Animations-Figures, figures/RB_L3_Palmgren.py (commit 40f90ec), after Harris; f1: unverified"
)
_UNVERIFIED = (
    "unverified: no readable text of Palmgren 1959, Harris & Kotzalas 2007 or ISO/TR 14179-2"
)

#: Palmgren's factors by bearing type (``model/bearing.py`` ``BEARING_TYPES``).
PALMGREN_FACTORS: dict[str, PalmgrenFactors] = {
    "deep_groove_ball": PalmgrenFactors(1.75, 0.0007, "ball", 0.0, _FERNANDES),
    "angular_contact_ball": PalmgrenFactors(
        2.0, 0.001, "angular_ball", math.radians(40.0), _UNVERIFIED
    ),
    "cylindrical_roller": PalmgrenFactors(2.5, 0.000275, "none", 0.0, _UNVERIFIED),
    "tapered_roller": PalmgrenFactors(4.0, 0.0004, "roller", math.radians(15.0), _UNVERIFIED),
    "spherical_roller": PalmgrenFactors(5.0, 0.0004, "roller", math.radians(10.0), _UNVERIFIED),
    "toroidal_roller": PalmgrenFactors(
        5.0, 0.0004, "none", 0.0, "spherical roller's factors (pinwind's assumption)"
    ),
}


def _checked(name: str, value: object, low: float = 0.0) -> None:
    array = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(array)) or np.any(array < low):
        raise InvalidLossInput(name, value, f"must be finite and ≥ {low:g}")


def no_load_moment(f0: float, viscosity: float, speed: Values, mean_diameter: float) -> Values:
    """M0 [N·m] at relative speed ``speed`` [rad/s] (either sign; module docstring).

    Args:
        f0: Palmgren's no-load factor [-].
        viscosity: the oil's kinematic viscosity ν at its operating temperature [m²/s].
        speed: the rings' relative speed ω [rad/s], a float or an array.
        mean_diameter: d_m = (D + d)/2 [m].
    """
    _checked("f0", f0)
    _checked("viscosity", viscosity)
    _checked("mean_diameter", mean_diameter)
    nu_n = viscosity * 1e6 * np.abs(speed) * _RPM  # mm²/s · rpm
    moment_nmm = 1e-7 * f0 * np.maximum(np.cbrt(nu_n * nu_n), _FLOOR) * (mean_diameter * 1e3) ** 3
    return moment_nmm * 1e-3


def no_load_moment_coefficients(
    f0: float, viscosity: float, mean_diameter: float
) -> tuple[float, float]:
    """(c0, M0_min): M0 = max(c0 |ω|^(2/3), M0_min) [N·m], ω in rad/s (the compiled step's form).

    c0 = 10⁻⁷ f0 (ν (60/2π))^(2/3) d_m³ and M0_min = 160·10⁻⁷ f0 d_m³, in N·m with ν in
    mm²/s and d_m in mm as ISO/TR 14179-2 writes them (``no_load_moment``).
    """
    d3 = (mean_diameter * 1e3) ** 3
    nu = viscosity * 1e6 * _RPM
    return 1e-10 * f0 * float(np.cbrt(nu * nu)) * d3, 1e-10 * f0 * _FLOOR * d3


def load_moment(f1: float, load: Values, mean_diameter: float) -> Values:
    """M1 = f1 P1 d_m [N·m] (module docstring): P1 [N], d_m [m]; a float or an array."""
    _checked("f1", f1)
    _checked("load", load)
    return f1 * np.asarray(load, dtype=float) * mean_diameter


def friction_load(kind: str, radial: Values, axial: Values) -> Values:
    """P1 [N] of bearing type ``kind`` under radial load F_r and axial load F_a [N].

    The rules of ``PALMGREN_FACTORS`` (module docstring); F_a of either sign.
    """
    factors = PALMGREN_FACTORS[kind]
    f_r = np.abs(np.asarray(radial, dtype=float))
    f_a = np.abs(np.asarray(axial, dtype=float))
    if factors.axial == "ball":
        return np.maximum(3.0 * f_a - 0.1 * f_r, f_r)
    if factors.axial == "angular_ball":
        return np.maximum(0.9 * f_a / math.tan(factors.contact_angle) - 0.1 * f_r, f_r)
    if factors.axial == "roller":
        return np.maximum(0.8 * f_a / math.tan(factors.contact_angle), f_r)
    return f_r


@dataclass(frozen=True)
class BearingFriction:
    """One rolling bearing's friction on its joint (a ``<bearing>`` or one of its ``<row>``).

    Attributes:
        joint: the joint it acts on.
        name: the bearing (the joint's name) or row (``INP-A``).
        kind: its type (a key of ``PALMGREN_FACTORS``).
        f0, f1: Palmgren's factors [-].
        mean_diameter: d_m = (D + d)/2 [m].
        viscosity: the oil's kinematic viscosity at its operating temperature [m²/s].
        load: a fixed P1 in the step [N] (the model's ``friction_load_kN``), or None: P1
            follows the bearing's (or row's) load in the step, lagged one step
            (``cpp/bearing_friction.hpp``).
        row: its column in the row series (``Gearbox.row_names``) when it is a row that is its
            compliant bearing's spring, else None (the bearing's reaction is its load).
    """

    joint: str
    name: str
    kind: str
    f0: float
    f1: float
    mean_diameter: float
    viscosity: float
    load: float | None
    row: int | None = None

    def moment(self, speed: Values, load: Values | None = None) -> Values:
        """M0 + M1 [N·m] ≥ 0 at relative speed ω [rad/s] and load P1 [N] (default ``load``)."""
        p1 = (self.load or 0.0) if load is None else load
        return no_load_moment(self.f0, self.viscosity, speed, self.mean_diameter) + load_moment(
            self.f1, p1, self.mean_diameter
        )


def lubricant_viscosity(
    grade: int, temperature: float, viscosity_100: float | None, viscosity: float | None
) -> float:
    """ν [m²/s]: ``viscosity`` when given outright, else the grade's at ``temperature`` [K]."""
    if viscosity is not None:
        return viscosity
    return Lubricant(grade, temperature, viscosity_100).viscosity()


#: The compiled step's code of each axial rule of ``PalmgrenFactors`` (``cpp/bearing_friction.hpp``
#: ``friction_load``, which restates ``friction_load``; a test checks that the two agree).
LOAD_RULES: dict[str, int] = {"none": 0, "ball": 1, "angular_ball": 2, "roller": 3}


#: ω_s [rad/s] of the step's regularised sign (``cpp/bearing_friction.hpp``): below it the
#: moment grows linearly with the speed, a viscous law c = M/ω_s, so a shaft at rest is not
#: held by a moment it cannot reverse within a step; 0.01 rad/s ≈ 0.1 rpm, far below any
#: drivetrain's working speed.
STICK_SPEED = 0.01
