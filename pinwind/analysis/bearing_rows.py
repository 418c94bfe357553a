"""The load of each rolling bearing (row) of a shaft over a run, from the row series.

A shaft runs in several rows at their axial positions (a main shaft in INP-A and INP-B, a planet
in two rows; Nejad et al. 2016 Tables VI and IX). When the rows are its compliant bearing's
springs (``model/bearing_rows.py``), the compiled step holds the shaft in each row and writes
each row's load as it acts in the step (``cpp/bearing_rows.hpp``): for the bearing's radial
slides (x, y along u, w), axial slide z and tilts θ_u, θ_w about u and w, a point a along the
axis moves radially by (x + a θ_w, y − a θ_u) (θ_u u × a k = −a θ_u w, θ_w w × a k = a θ_w u), so
row i carries, on the shaft,

    radial   F_i = −(k_u,i (x + a_i θ_w), k_w,i (y − a_i θ_u)) − (c_u,i (…)˙, c_w,i (…)˙)
    axial    F_i = −k_x,i z − c_x,i ż
    tilt     M_i = −(k_β,i θ_u, k_γ,i θ_w) − (c_β,i θ̇_u, c_γ,i θ̇_w)

(a row with a radial clearance or preload c: each radial part by its two sides' law,
−k [max(δ − c, 0) − max(−δ − c, 0)], its damper while a side touches) at the step's weighted
state, the forces the step used: the rows add up to the bearing's
reaction, Σ F_i its force and Σ (M_i + a_i k × F_i) its tilting moment. For two rows without tilt
stiffness this is the lever rule. Here they are read from the series ``row_force`` and
``row_moment`` (``Result.row``) and given with the row's bearing and position. The frame is the
bearing's axes (u, w radial, k axial: its joint frame's x, y, z for a bearing along z), forces
on the shaft [N], moments [N·m].
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from pinwind.model.bearing_rows import row_name


@dataclass(frozen=True)
class RowLoad:
    """One row's load on the shaft over a run, along its bearing's axes (u, w, k).

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

    The rows that are their bearings' springs (``Gearbox.row_names``, ``Result.row_names``);
    rows that only carry ratings (no stiffness, or an ideal bearing) have no load series.
    """
    out: list[RowLoad] = []
    for bearing, compliant in gearbox.compliant_bearings.items():
        for row in compliant.rows:
            series = result.row(row_name(bearing, row.name))
            out.append(
                RowLoad(
                    name=row.name,
                    bearing=bearing,
                    position=row.position,
                    radial=series.force[:, :2],
                    axial=series.force[:, 2],
                    tilting=series.moment[:, :2],
                )
            )
    return out
