"""The load of each rolling bearing (row) of a shaft, from the compliant bearing standing for them.

A shaft runs in several rows at their axial positions (a main shaft in INP-A and INP-B, a planet
in two rows; Nejad et al. 2016 Tables VI and IX). The step holds the shaft in one compliant
bearing at the rows' stiffness centre (``model/bearing_rows.py``: k = Σ k_i, k_t = Σ (k_i a_i² +
k_t,i), Σ k_i a_i = 0). Each row's springs see the shaft's displacement at the row: for the
bearing's radial slides (x, y along u, w), axial slide z and tilts θ_u, θ_w about u and w, a point
a along the axis moves radially by (x + a θ_w, y − a θ_u) (u × k = −w, w × k = u), so row i
carries, on the shaft,

    radial   F_i = −k_i (x + a_i θ_w, y − a_i θ_u) − c_i (ẋ + a_i θ̇_w, ẏ − a_i θ̇_u)
    axial    F_i = −k_x,i z − c_x,i ż
    tilt     M_i = −k_t,i (θ_u, θ_w) − c_t,i (θ̇_u, θ̇_w)

with k_i, c_i the mean of the row's two radial values (as the equivalent takes them). The rows'
sums are the equivalent bearing's spring and damper forces: Σ F_i = −k r and Σ a_i × F_i + Σ M_i
is its tilting moment, since Σ k_i a_i = 0. For two rows without tilt stiffness this is the lever
rule. The frame is the bearing's joint frame (u, w radial, k axial), forces on the shaft [N],
moments [N·m].
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from pinwind.errors import InputError

#: Relative size of Σ k_i a_i (over Σ k_i |a_i|) above which rows are not about the joint's
#: stiffness centre, and of the difference between Σ k_i and the bearing's own radial stiffness.
ROWS_TOLERANCE = 1e-9


@dataclass(frozen=True)
class RowLoad:
    """One row's load on the shaft over a run, in its bearing's joint frame.

    Attributes:
        name: the row's name (``INP-A``); bearing: its bearing (joint).
        position: its axial position from the bearing's joint [m].
        radial: force along u and w [N], (n, 2).
        axial: force along the axis [N], (n,).
        tilting: moment of the row's own tilt springs about u and w [N·m], (n, 2).
    """

    name: str
    bearing: str
    position: float
    radial: np.ndarray
    axial: np.ndarray
    tilting: np.ndarray

    @property
    def radial_magnitude(self) -> np.ndarray:
        """|F_radial| [N], (n,)."""
        return np.hypot(self.radial[:, 0], self.radial[:, 1])


def row_loads(result: Any, gearbox: Any) -> list[RowLoad]:
    """Each row's load over the run, bearing by bearing in the model's order (module docstring).

    Rows are named within their bearing: several planets' bearings have rows of one name.

    Raises:
        InputError: a bearing whose rows are not about its joint (Σ k_i a_i ≠ 0) or whose radial
            stiffness is not the rows' sum: the rows do not describe the bearing the run used.
    """
    out: list[RowLoad] = []
    for bearing, rows in gearbox.source.bearing_rows.items():
        compliant = gearbox.compliant_bearings.get(bearing)
        if compliant is None or not rows:
            continue
        _check_rows(bearing, rows, compliant.compliance)
        q, v = _slides(result, gearbox, compliant.v_index)
        for row in rows:
            a = row.position
            k, c = row.radial_stiffness, row.radial_damping
            shift = np.column_stack(
                [q["radial_x"] + a * q["tilt_y"], q["radial_y"] - a * q["tilt_x"]]
            )
            speed = np.column_stack(
                [v["radial_x"] + a * v["tilt_y"], v["radial_y"] - a * v["tilt_x"]]
            )
            k_t = 0.5 * (row.stiffness[3] + row.stiffness[4])
            c_t = 0.5 * (row.damping[3] + row.damping[4])
            tilt = np.column_stack([q["tilt_x"], q["tilt_y"]])
            tilt_speed = np.column_stack([v["tilt_x"], v["tilt_y"]])
            out.append(
                RowLoad(
                    name=row.name,
                    bearing=bearing,
                    position=a,
                    radial=-k * shift - c * speed,
                    axial=-row.stiffness[0] * q["axial"] - row.damping[0] * v["axial"],
                    tilting=-k_t * tilt - c_t * tilt_speed,
                )
            )
    return out


def _slides(result: Any, gearbox: Any, index: dict[str, int]) -> tuple[dict, dict]:
    """The bearing's slide coordinates and speeds over the run, 0 for slides it lacks."""
    n = len(result.time)
    q: dict[str, np.ndarray] = {}
    v: dict[str, np.ndarray] = {}
    model = gearbox.model
    for slide in ("radial_x", "radial_y", "axial", "tilt_x", "tilt_y"):
        if slide not in index:
            q[slide], v[slide] = np.zeros(n), np.zeros(n)
            continue
        joint = next(j for j in range(1, model.njoints) if model.joints[j].idx_v == index[slide])
        q[slide] = result.angle[:, model.joints[joint].idx_q]
        v[slide] = result.speed[:, index[slide]]
    return q, v


def _check_rows(bearing: str, rows: list, compliance: Any) -> None:
    """Refuse rows that do not make up the bearing the run held the shaft in."""
    k = np.array([r.radial_stiffness for r in rows])
    a = np.array([r.position for r in rows])
    moment = float(np.sum(k * a))
    if abs(moment) > ROWS_TOLERANCE * max(float(np.sum(k * np.abs(a))), 1e-300):
        raise InputError(
            f'bearing "{bearing}": its rows are not about its joint: Σ k_i a_i = {moment:.6g} N '
            "(positions from the joint at the rows' stiffness centre make it 0); place the joint "
            "at Σ k_i z_i / Σ k_i (pinwind build stages does)"
        )
    total = float(np.sum(k))
    if abs(total - float(compliance.radial_stiffness)) > ROWS_TOLERANCE * total:
        raise InputError(
            f'bearing "{bearing}": radial_stiffness {compliance.radial_stiffness:.6g} N/m is not '
            f"its rows' sum {total:.6g} N/m; regenerate the model (pinwind build stages) or make "
            "them agree"
        )
