"""The friction of each rolling bearing of a gearbox, as the step and the efficiency take it.

``bearing_frictions`` reads the model file's friction model of each ``<bearing>`` and ``<row>``
(``model/bearing_friction_data.py``) with its type, size and oil (``model/bearing_life_data.py``)
and gives Palmgren's factors and the oil's viscosity at temperature for each
(``losses/bearing_friction.py``); ``dynamics/element_specs.py`` puts them in the step and
``analysis/efficiency.py`` estimates the losses after a run from them.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from pinwind.errors import InvalidBearingFriction
from pinwind.losses.bearing_friction import PALMGREN_FACTORS, BearingFriction, lubricant_viscosity
from pinwind.model.bearing_rows import row_name

if TYPE_CHECKING:
    from pinwind.model.gearbox import Gearbox

__all__ = ["bearing_frictions"]


def bearing_frictions(gearbox: Gearbox) -> list[BearingFriction]:
    """Every rolling bearing with a friction model in ``gearbox``'s model, in file order.

    A ``<bearing>`` with ``<row>`` elements gives one per row with friction (the row's type,
    size and oil), one without gives one for itself (its ``type``, ``size_mm`` and oil).

    Raises:
        InvalidBearingFriction: a bearing with friction but no ``type`` or no ``size_mm``.
    """
    source = gearbox.source
    out = []
    row_columns = {name: i for i, name in enumerate(gearbox.row_names)}
    for joint, friction in source.bearing_friction.items():
        rows = source.bearing_rows.get(joint, [])
        where = f'<bearing joint="{joint}">'
        parts: list[tuple[str, str | None, tuple[float, float, float] | None, Any, Any]] = []
        if rows:
            for row, data in zip(rows, source.row_friction[joint], strict=True):
                life = row.life or source.bearing_life[joint]
                parts.append((row.name, row.kind, row.size or life.size, life, data))
        else:
            rating = source.bearings.get(joint)
            life = source.bearing_life[joint]
            parts.append((joint, rating.kind if rating else None, life.size, life, friction))
        for name, kind, size, life, data in parts:
            if not data.active:
                continue
            at = where if name == joint else f'{where} <row name="{name}">'
            if kind is None or kind not in PALMGREN_FACTORS:
                raise InvalidBearingFriction(
                    at, "type", kind, f"friction_model needs the bearing's type; give one of "
                    f"{', '.join(PALMGREN_FACTORS)}", path=source.path,
                )  # fmt: skip
            if size is None:
                raise InvalidBearingFriction(
                    at, "size_mm", None, "friction_model needs the bearing's size (its mean "
                    'diameter d_m = (D + d)/2): give size_mm="D d B"', path=source.path,
                )  # fmt: skip
            factors = PALMGREN_FACTORS[kind]
            out.append(
                BearingFriction(
                    joint=joint,
                    name=name,
                    kind=kind,
                    f0=factors.f0 if data.f0 is None else data.f0,
                    f1=factors.f1 if data.f1 is None else data.f1,
                    mean_diameter=0.5 * (size[0] + size[1]),
                    viscosity=lubricant_viscosity(
                        life.grade, life.temperature, life.viscosity_100, life.viscosity
                    ),
                    load=data.load,
                    row=row_columns.get(row_name(joint, name)) if name != joint else None,
                )
            )
    return out
