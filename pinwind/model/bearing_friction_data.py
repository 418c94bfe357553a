"""A rolling bearing's friction model in a model file: which model, its coefficients and load.

A ``<bearing>`` or one of its ``<row>`` elements may give (docs/losses.md "Model file"):

    friction_model="iso_tr_14179_2"   the friction model (a key of ``FRICTION_MODELS``);
                                      "none" (the default): no friction moment
    friction_f0="3"                   Palmgren's no-load factor f0 (default: the type's,
                                      ``losses/bearing_friction.py`` ``PALMGREN_FACTORS``)
    friction_f1="0.0004"              Palmgren's load factor f1 (default: the type's)
    friction_load_kN="120"            a fixed load P1 of the load-dependent moment M1 = f1 P1 d_m
                                      [kN] (default: none, P1 follows the bearing's or row's
                                      load in the step, docs/losses.md)

The oil and the size (its mean diameter d_m = (D + d)/2) are the bearing's life attributes
(``lubricant_vg``, ``temperature_C``, ``viscosity_100C_cSt``, ``viscosity_cSt``, ``size_mm``;
``model/bearing_life_data.py``). A ``<row>`` takes what its ``<bearing>`` gives and may change
any of it. ``friction_data`` reads and checks the attributes; ``losses/bearing_friction.py``
computes the moments and ``dynamics/element_specs.py`` puts them in the step.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass

from pinwind.errors import InvalidBearingFriction

#: The friction models a model file may name: "none", or ISO/TR 14179-2:2001's bearing losses
#: (Palmgren's M0 + M1; ``losses/bearing_friction.py``).
FRICTION_MODELS: tuple[str, ...] = ("none", "iso_tr_14179_2")

#: The attributes ``friction_data`` reads (on ``<bearing>`` and ``<row>``).
FRICTION_ATTRIBUTES: tuple[str, ...] = (
    "friction_model",
    "friction_f0",
    "friction_f1",
    "friction_load_kN",
)


@dataclass(frozen=True)
class BearingFrictionData:
    """A bearing's friction model, in SI units.

    Attributes:
        model: a key of ``FRICTION_MODELS``.
        f0: Palmgren's no-load factor [-], or None: the bearing type's.
        f1: Palmgren's load factor [-], or None: the bearing type's.
        load: a fixed load P1 of M1 = f1 P1 d_m [N], or None: P1 follows the load in the step.
    """

    model: str = "none"
    f0: float | None = None
    f1: float | None = None
    load: float | None = None

    @property
    def active(self) -> bool:
        """A friction moment acts (the model is not "none")."""
        return self.model != "none"


def friction_data(
    attrs: Mapping[str, str],
    *,
    where: str,
    path: str,
    inherited: BearingFrictionData | None = None,
) -> BearingFrictionData:
    """The friction data an element's attributes give, over those it inherits (module docstring).

    Args:
        attrs: the element's attributes (others are ignored).
        where: the element, for messages (``<bearing joint="lss">``).
        path: the model file, for messages.
        inherited: its ``<bearing>``'s data (a ``<row>``), or None: no friction.

    Raises:
        InvalidBearingFriction: a model name that is not one of ``FRICTION_MODELS``, a factor or
            load that is not a finite number ≥ 0.
    """
    base = inherited or BearingFrictionData()
    given = {k: v.strip() for k, v in attrs.items() if k in FRICTION_ATTRIBUTES}
    out: dict[str, object] = {}
    if "friction_model" in given:
        name = given["friction_model"]
        if name not in FRICTION_MODELS:
            raise InvalidBearingFriction(
                where,
                "friction_model",
                name,
                f'friction_model="{name}" is not a friction model pinwind knows; give one of '
                f"{', '.join(FRICTION_MODELS)}",
                path=path,
            )
        out["model"] = name
    for attr, field, scale in (
        ("friction_f0", "f0", 1.0),
        ("friction_f1", "f1", 1.0),
        ("friction_load_kN", "load", 1e3),
    ):
        if attr not in given:
            continue
        try:
            value = float(given[attr])
        except ValueError:
            value = math.nan
        if not (math.isfinite(value) and value >= 0.0):
            raise InvalidBearingFriction(
                where,
                attr,
                given[attr],
                f'{attr}="{given[attr]}" must be a finite number ≥ 0',
                path=path,
            )
        out[field] = value * scale
    return dataclasses.replace(base, **out)  # type: ignore[arg-type]
