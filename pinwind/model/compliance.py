"""How a compliant gear mesh's force follows its deflection: the data of one mesh, SI units.

A mesh is rigid (a constraint row, ``dynamics/mesh.py``) unless it has a ``MeshCompliance``;
then it is a spring-damper along the line of action (``dynamics/compliant.py``,
IFToMM 2018 eqs. 2-6, Jørgensen 2014 eqs. 14-19). The model file sets
it per mesh (docs/model_format.md), and ``simulate(..., meshes=...)`` or ``pinwind simulate
--mesh NAME=compliant`` per run.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pinwind.losses.mesh_friction import LUBRICANT_FACTORS
from pinwind.losses.oil import VG_GRADES, Lubricant

#: Damping ratio of the mesh mode used when a compliant mesh gives neither damping nor a ratio.
DEFAULT_DAMPING_RATIO = 0.05

#: Laws of the flanks' μ besides a constant: ``"iso14179"``, ISO/TR 14179-2's μ_mz at the
#: operating point (``losses/mesh_friction.py`` ``mean_friction_coefficient``).
FRICTION_LAWS = ("iso14179",)

#: How the mesh stiffness varies as the teeth roll.
STIFFNESS_VARIATIONS = ("path", "constant")

#: ``slices`` that asks for the rule's N (`pinwind.gears.face_load.slice_count`).
AUTO_SLICES = "auto"


@dataclass(frozen=True)
class MeshCompliance:
    """The spring-damper of a compliant mesh: F_n = k(x) δ + c δ̇ on the flank in contact, ≥ 0.

    Attributes:
        stiffness: single-pair stiffness c′·b [N/m] (ISO 6336-1 c′ times the face width b),
            along the transverse line of action (helical gears too: F_n and δ are transverse);
            None: ISO 6336-1 method B from the gear data (``gears/mesh_stiffness.py``).
        variation: ``"path"``: the mesh stiffness is the sum over the tooth pairs in contact as
            they roll along the path of contact (spur: c′b with one pair, 1.75 c′b with two;
            helical: in proportion to the total contact-line length, ``gears/mesh_stiffness.py``
            ``contact_line_pair_stiffness``; mean ISO's c_γα b either way); ``"constant"``: the
            mean mesh stiffness c_γα b throughout.
        mean_stiffness: the mean mesh stiffness c_γα·b [N/m] (ISO 6336-1's mean over a mesh
            period, along the transverse line of action), given instead of ``stiffness``: the
            single-pair c′·b is then c_γα·b / (0.75 ε_α + 0.25), so that the constant stiffness
            and the mean of the ``path`` variation are the value given.
        pair_stiffness: stiffness of one tooth pair along the path of contact, as (positions
            from the path start A [m], stiffness [N/m]), e.g. a FEM curve as in
            Jørgensen 2014 Fig. 8; replaces ``stiffness`` and ``variation``.
        damping: c [N·s/m]; None: from ``damping_ratio``.
        damping_ratio: ζ of the mesh mode, c = 2 ζ √(k m_eq) with m_eq the effective mass
            along the line of action; used when ``damping`` is None.
        backlash: normal backlash along the line of action [m] (≥ 0): no force inside the gap.
        slices: N, the contact line cut into N equal slices across the face width, each with
            k(x)/N, c/N and its own contact, loaded by the gears' relative tilt, the lead
            modifications and profile relief; a helical mesh's slices follow its inclined
            contact lines (``dynamics/compliant.py`` ``slice_tables``, ``helical_slices``); 1:
            one contact line. ``"auto"``: the run takes `pinwind.gears.face_load.slice_count`'s
            N for the mesh's expected misalignment (``dynamics/compliant.py`` ``auto_slices``)
            and records it here, with ``slice_rule``.
        slice_rule: (F_β [m], δ_m [m]) the rule took where N came from ``slices="auto"``;
            None otherwise.
        friction_coefficient: μ of the tooth flanks [-], in [0, 1): each pair in contact takes
            μ F_n along its line against its sliding (``cpp/flank_friction.hpp``; F_n = F_bt /
            cos β_b, a helical pair's friction integrated along its inclined contact line);
            0: frictionless flanks. Or ``"iso14179"`` (``FRICTION_LAWS``): the step takes
            ISO/TR 14179-2's μ_mz at each step from the flank's force, the sum velocity at the
            pitch point (from the gears' spins), the reduced radius of curvature, the oil's
            dynamic viscosity (``oil``), the flanks' roughness (``roughness``) and X_L
            (``base_oil``), at most 0.2 (``losses/mesh_friction.py``).
        oil: the gear oil at its temperature, for ``"iso14179"`` (``losses.oil.Lubricant``).
        roughness: Ra = (Ra1 + Ra2)/2 of the flanks [m], for ``"iso14179"``.
        base_oil: the oil's base, for X_L of ``"iso14179"`` (a key of
            ``losses.mesh_friction.LUBRICANT_FACTORS``; mineral: X_L = 1).
    """

    stiffness: float | None = None
    variation: str = "path"
    pair_stiffness: tuple[np.ndarray, np.ndarray] | None = None
    damping: float | None = None
    damping_ratio: float = DEFAULT_DAMPING_RATIO
    backlash: float = 0.0
    mean_stiffness: float | None = None
    slices: int | str = 1
    friction_coefficient: float | str = 0.0
    oil: Lubricant | None = None
    roughness: float | None = None
    base_oil: str = "mineral"
    slice_rule: tuple[float, float] | None = None

    @property
    def slice_number(self) -> int:
        """N as a whole number, once a run has resolved ``slices="auto"`` (``auto_slices``)."""
        if isinstance(self.slices, str):
            raise AssertionError(
                'slices="auto" is not resolved yet; dynamics.compliant.auto_slices resolves it'
            )
        return int(self.slices)

    @property
    def friction_law(self) -> str:
        """``"constant"`` (μ a number) or the name of the law of μ (``FRICTION_LAWS``)."""
        mu = self.friction_coefficient
        return mu if isinstance(mu, str) else "constant"

    @property
    def has_friction(self) -> bool:
        """The flanks rub: a μ > 0 or a law of μ."""
        mu = self.friction_coefficient
        return isinstance(mu, str) or mu > 0.0

    def problems(self) -> list[str]:
        """What is physically wrong with these values, each with the fix (empty when fine)."""
        out = []
        if self.stiffness is not None and not (
            math.isfinite(self.stiffness) and self.stiffness > 0.0
        ):
            out.append(f"stiffness is {self.stiffness:g} N/m; give a positive value (c′·b)")
        if self.mean_stiffness is not None:
            if not (math.isfinite(self.mean_stiffness) and self.mean_stiffness > 0.0):
                out.append(
                    f"mean stiffness is {self.mean_stiffness:g} N/m; give a positive value (c_γα·b)"
                )
            given = [
                n
                for n, v in (("stiffness", self.stiffness), ("pair_stiffness", self.pair_stiffness))
                if v is not None
            ]
            if given:
                out.append(
                    f"mean_stiffness (c_γα·b) and {' and '.join(given)} both give the stiffness; "
                    "keep one"
                )
        if self.variation not in STIFFNESS_VARIATIONS:
            out.append(
                f'stiffness variation "{self.variation}" is unknown; use one of '
                + ", ".join(STIFFNESS_VARIATIONS)
            )
        if self.damping is not None and not (math.isfinite(self.damping) and self.damping >= 0):
            out.append(f"damping is {self.damping:g} N·s/m; it must be ≥ 0")
        if not (math.isfinite(self.damping_ratio) and 0.0 <= self.damping_ratio < 1.0):
            out.append(f"damping ratio is {self.damping_ratio:g}; it must lie in [0, 1)")
        if self.slices != AUTO_SLICES and not (
            isinstance(self.slices, int | np.integer) and self.slices >= 1
        ):
            out.append(
                f"slices is {self.slices!r}; give a whole number ≥ 1 (1: one contact line) or "
                f'"{AUTO_SLICES}" (the rule\'s N for the expected misalignment)'
            )
        out += self._friction_problems()
        if not (math.isfinite(self.backlash) and self.backlash >= 0.0):
            out.append(f"backlash is {self.backlash * 1e3:g} mm; it must be ≥ 0")
        if self.pair_stiffness is not None:
            s, k = (np.asarray(a, dtype=float) for a in self.pair_stiffness)
            if s.ndim != 1 or s.shape != k.shape or s.size < 1:
                out.append("pair stiffness table needs as many positions as stiffness values")
            elif not (np.all(np.isfinite(s)) and np.all(np.isfinite(k))):
                out.append("pair stiffness table has non-finite values")
            elif np.any(np.diff(s) < 0.0):
                out.append("pair stiffness positions must increase along the path")
            elif np.any(k <= 0.0):
                out.append(f"pair stiffness values must be positive; smallest {k.min():g} N/m")
        return out

    def _friction_problems(self) -> list[str]:
        """What is wrong with the flanks' friction: μ, or its law and that law's data."""
        mu = self.friction_coefficient
        if isinstance(mu, str):
            if mu not in FRICTION_LAWS:
                return [
                    f'friction_coefficient "{mu}" is not a law pinwind knows; give a number μ in '
                    f"[0, 1) or one of: {', '.join(FRICTION_LAWS)}"
                ]
            out = []
            if self.oil is None:
                out.append(
                    f'friction_coefficient "{mu}" needs the oil: give lubricant_vg and '
                    "temperature_C (model file) or oil=Lubricant(grade, temperature_K)"
                )
            elif self.oil.grade not in VG_GRADES:
                out.append(
                    f"oil grade VG {self.oil.grade} is not an ISO 3448 grade; give one of "
                    + ", ".join(str(g) for g in VG_GRADES)
                )
            ra = self.roughness
            if ra is None or not (math.isfinite(ra) and ra > 0.0):
                got = "missing" if ra is None else f"{ra * 1e6:g} µm"
                out.append(
                    f'friction_coefficient "{mu}" needs the flanks\' roughness Ra = (Ra1 + Ra2)/2 '
                    f"> 0 ({got}): give roughness_um (model file) or roughness [m]"
                )
            if self.base_oil not in LUBRICANT_FACTORS:
                out.append(
                    f'base_oil "{self.base_oil}" is unknown; give one of '
                    + ", ".join(LUBRICANT_FACTORS)
                )
            return out
        if not (isinstance(mu, int | float | np.floating) and math.isfinite(mu) and 0 <= mu < 1):
            return [
                f"friction_coefficient is {mu!r}; give μ in [0, 1) (steel on steel, lubricated: "
                '0.03 to 0.1; 0 for frictionless flanks) or "iso14179"'
            ]
        return []
