"""A compliant or floating bearing: how a bearing lets its body move in it, SI units.

An ideal bearing (the default) is a revolute joint: the body only turns. A ``<bearing>`` with
``radial_stiffness`` (or ``floating="true"``) in the model file (docs/model_format.md "Compliant
bearings") lets the body translate in the bearing: ``model/gearbox.py`` puts massless slides
between the housing and the revolute joint, which keeps its name and every series,

    parent ─ radial_x ─ radial_y [─ axial] [─ tilt_x ─ tilt_y] ─ the bearing's revolute joint

(prismatic joints along two radial axes u, w of the joint frame and along its axis k, and
hinges about u and w through the bearing centre), and ``dynamics/bearing_springs.py`` holds the
slides with the bearing's springs and radial damper (``cpp/bearing_spring.hpp``) and its axial
and tilt dampers (the slides' own viscous damping):

    radial  F = −k max(|r| − c, 0) r/|r| − c_r ṙ        r the displacement in (u, w) [m]
            (the damper in contact, |r| > c, only)
            or, ``law="roller_sum"``, Harris's sum over the rolling elements
            F = −Σ_j K_n max(r·e_j − c, 0)ⁿ e_j − c_r ṙ       (``model/roller_sum.py``)
    axial   F = −k_a z − c_a ż,      tilt  M = −k_t θ − c_t θ̇   (θ about u and about w)

A floating bearing has radial slides without spring or damper: its body (a floating sun) is
centred by its meshes alone.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pinwind.model.roller_sum import CONTACT_EXPONENTS, RollerSum

#: The slides a compliant bearing may have: name suffix → what it carries.
SLIDES = ("radial_x", "radial_y", "axial", "tilt_x", "tilt_y")
#: The radial laws (``law=`` in the model file; ``cpp/bearing_spring.hpp`` BearingLaw).
RADIAL_LAWS = ("linear", "roller_sum")


@dataclass(frozen=True)
class BearingCompliance:
    """The stiffness and damping of a compliant bearing, or a floating one.

    Attributes:
        radial_stiffness: k [N/m] of the radial law (0 for a floating bearing).
        radial_damping: c_r [N·s/m] on each radial slide.
        clearance: radial clearance c [m]: no radial force while |r| < c.
        axial_stiffness: k_a [N/m], or None: axially rigid (no axial slide).
        axial_damping: c_a [N·s/m].
        tilt_stiffness: k_t [N·m/rad] about each radial axis, or None: rigid in tilt.
        tilt_damping: c_t [N·m·s/rad].
        floating: the radial slides are free (no spring, no damper): a floating member.
        law: the radial law, one of ``RADIAL_LAWS``: ``"linear"`` (k) or ``"roller_sum"``
            (``rollers``, ``contact_stiffness``, ``load_exponent``).
        rollers: Z, the rolling elements of a roller sum.
        contact_stiffness: K_n [N/mⁿ] of one rolling element's contact (roller sum).
        load_exponent: n of the elements' load-deflection law Q = K_n δⁿ (roller sum;
            ``CONTACT_EXPONENTS``: 10/9 line contact, 3/2 point contact).
        radial_axis: the direction of the first radial axis u in the joint frame (its part
            normal to the bearing axis), or None: the joint frame's x (its y when the axis lies
            along x). A planet's bearing points it away from its carrier's axis, so that its
            rows' K_y acts radially on every planet alike.
    """

    radial_stiffness: float = 0.0
    radial_damping: float = 0.0
    clearance: float = 0.0
    axial_stiffness: float | None = None
    axial_damping: float = 0.0
    tilt_stiffness: float | None = None
    tilt_damping: float = 0.0
    floating: bool = False
    law: str = "linear"
    rollers: int = 0
    contact_stiffness: float = 0.0
    load_exponent: float = CONTACT_EXPONENTS["line"]
    radial_axis: tuple[float, float, float] | None = None

    @property
    def slides(self) -> tuple[str, ...]:
        """The slides this bearing has, in the order of the joint chain (``SLIDES``)."""
        out = ["radial_x", "radial_y"]
        if self.axial_stiffness is not None:
            out.append("axial")
        if self.tilt_stiffness is not None:
            out += ["tilt_x", "tilt_y"]
        return tuple(out)

    def radial_force(self, displacement: np.ndarray) -> np.ndarray:
        """The radial law's force on the body [N] at displacements r (..., 2) [m], joint frame."""
        r = np.asarray(displacement, dtype=float)
        if self.law == "roller_sum":
            return self.roller_sum.force(r)
        if self.clearance == 0.0:
            return -self.radial_stiffness * r  # the scale below is then exactly 1 (or r is 0)
        radius = np.hypot(r[..., 0], r[..., 1])
        over = np.maximum(radius - self.clearance, 0.0)
        scale = np.divide(over, radius, out=np.zeros_like(radius), where=radius > 0.0)
        return -self.radial_stiffness * scale[..., None] * r

    def radial_tangent(self, displacement: np.ndarray) -> np.ndarray:
        """K = −∂F/∂r [N/m], (2, 2), of the radial law at one displacement r (2,) [m].

        The linear law's is k I wherever it is (its clearance taken up: a loaded bearing).
        """
        if self.law == "roller_sum":
            return self.roller_sum.tangent(displacement)
        return self.radial_stiffness * np.eye(2)

    def static_deflection(self, load: np.ndarray) -> np.ndarray:
        """The radial displacement r (2,) [m] at which the bearing carries ``load`` (2,) [N]."""
        if self.law == "roller_sum":
            return self.roller_sum.static_deflection(load)
        if self.radial_stiffness == 0.0:
            return np.zeros(2)
        load = np.asarray(load, dtype=float)
        norm = float(np.linalg.norm(load))
        if norm == 0.0:
            return np.zeros(2)
        return load / norm * (self.clearance + norm / self.radial_stiffness)

    @property
    def roller_sum(self) -> RollerSum:
        """The roller-sum law of this bearing's parameters (``law="roller_sum"``)."""
        return RollerSum(self.rollers, self.contact_stiffness, self.load_exponent, self.clearance)

    def stiffness(self, slide: str) -> float:
        """Stiffness of a slide's spring [N/m or N·m/rad] (0 on a floating radial slide)."""
        if slide.startswith("radial"):
            return self.radial_stiffness
        if slide == "axial":
            return self.axial_stiffness or 0.0
        return self.tilt_stiffness or 0.0

    def damping(self, slide: str) -> float:
        """Viscous damping of a slide [N·s/m or N·m·s/rad]."""
        if slide.startswith("radial"):
            return self.radial_damping
        return self.axial_damping if slide == "axial" else self.tilt_damping

    def problems(self) -> list[tuple[str, float, str]]:
        """(attribute, value, what is wrong and the fix) for each bad value (empty when fine)."""
        out = []
        values = {
            "radial_stiffness": (self.radial_stiffness, "N/m"),
            "radial_damping": (self.radial_damping, "N·s/m"),
            "radial_clearance_mm": (self.clearance * 1e3, "mm"),
            "axial_stiffness": (self.axial_stiffness, "N/m"),
            "axial_damping": (self.axial_damping, "N·s/m"),
            "tilt_stiffness": (self.tilt_stiffness, "N·m/rad"),
            "tilt_damping": (self.tilt_damping, "N·m·s/rad"),
        }
        for name, (value, unit) in values.items():
            if value is not None and not (math.isfinite(value) and value >= 0.0):
                out.append((name, value, f"{name} is {value:g} {unit}; give a finite value ≥ 0"))
        if self.law == "roller_sum":
            return out + self._roller_sum_problems()
        if not self.floating and not out and self.radial_stiffness <= 0.0:
            out.append(
                (
                    "radial_stiffness",
                    self.radial_stiffness,
                    "radial_stiffness is 0 N/m: the body would be free in its bearing; give a "
                    'positive stiffness, or floating="true" for a member its meshes centre',
                )
            )
        if self.floating and (self.radial_stiffness or self.radial_damping or self.clearance):
            out.append(
                (
                    "floating",
                    1.0,
                    "a floating bearing has no radial stiffness, damping or clearance; remove "
                    'them or floating="true"',
                )
            )
        return out

    def _roller_sum_problems(self) -> list[tuple[str, float, str]]:
        out = []
        if not self.rollers >= 1:
            out.append(
                (
                    "rollers",
                    float(self.rollers),
                    f"rollers is {self.rollers}: a roller sum needs at least one rolling element",
                )
            )
        if not (math.isfinite(self.contact_stiffness) and self.contact_stiffness > 0.0):
            out.append(
                (
                    "contact_stiffness",
                    self.contact_stiffness,
                    f"contact_stiffness is {self.contact_stiffness:g} N/m^n; give a finite "
                    "value > 0 (one rolling element's K_n)",
                )
            )
        if self.radial_stiffness or self.floating:
            out.append(
                (
                    "radial_stiffness" if self.radial_stiffness else "floating",
                    self.radial_stiffness or 1.0,
                    'law="roller_sum" takes its stiffness from rollers and contact_stiffness; '
                    'remove radial_stiffness and floating, or law="roller_sum"',
                )
            )
        return out
