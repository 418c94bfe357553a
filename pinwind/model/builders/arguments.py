"""Checks of the builders' arguments: each returns the value in SI or raises ``InvalidGearTrain``.

The messages name the argument, its value and what is expected, so that a wrong call is fixed
from the message alone (degrees given for radians, an unknown body in ``inertias``, ...).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from pinwind.errors import InvalidGearTrain
from pinwind.model.builders.gear_bodies import MassProperties


def teeth_count(name: str, value: object) -> int:
    """A tooth (or planet) count: a positive whole number."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value <= 0:
        raise InvalidGearTrain(f"{name} = {value!r}; a tooth count must be a positive whole number")
    return int(value)


def positive(name: str, value: float, unit: str) -> float:
    """A positive finite number, in ``unit`` (named in the message)."""
    if not (isinstance(value, (int, float, np.floating)) and math.isfinite(value) and value > 0):
        raise InvalidGearTrain(f"{name} = {value!r} {unit}; it must be a positive finite number")
    return float(value)


def pressure_angle_rad(value: float) -> float:
    """A pressure angle in (0, 45°) [rad]; a value in degrees is refused with the fix."""
    value = positive("pressure_angle", value, "rad")
    if value >= math.pi / 4:
        raise InvalidGearTrain(
            f"pressure_angle = {value:g} rad ({math.degrees(value):g}°) must lie in (0, 45°); the "
            f"builder takes radians: did you mean math.radians({value:g})?"
        )
    return value


def mass_properties(key: str, props: Sequence[float]) -> MassProperties:
    """(mass [kg], Ixx = Iyy [kg·m²], Izz [kg·m²]) of a real body: positive, Izz ≤ Ixx + Iyy."""
    if len(props) != 3:
        raise InvalidGearTrain(
            f'inertias["{key}"] = {props!r}; give (mass [kg], Ixx = Iyy [kg·m²], Izz [kg·m²])'
        )
    mass, ixx, izz = (float(v) for v in props)
    if not all(math.isfinite(v) and v > 0 for v in (mass, ixx, izz)):
        raise InvalidGearTrain(
            f'inertias["{key}"] = ({mass:g}, {ixx:g}, {izz:g}); mass and moments must be positive'
        )
    if izz > 2.0 * ixx:
        raise InvalidGearTrain(
            f'inertias["{key}"]: Izz = {izz:g} kg·m² exceeds Ixx + Iyy = {2 * ixx:g} kg·m² '
            "(triangle inequality); no real body has these moments"
        )
    return mass, ixx, izz


def inertia_table(
    inertias: Mapping[str, Sequence[float]] | None, allowed: Sequence[str]
) -> dict[str, MassProperties]:
    """The ``inertias`` argument checked: known bodies only, each a real body."""
    table = dict(inertias or {})
    unknown = sorted(set(table) - set(allowed))
    if unknown:
        raise InvalidGearTrain(
            f"inertias has unknown bodies {unknown}; known bodies are: {', '.join(allowed)}"
        )
    return {key: mass_properties(key, value) for key, value in table.items()}


def per_stage(
    name: str, value: float | Sequence[float] | None, default: float, n: int
) -> list[float]:
    """One length [m] per parallel stage: ``default`` for None, one value for all, or n values."""
    if value is None:
        return [default] * n
    if isinstance(value, (int, float)):
        return [positive(name, value, "m")] * n
    values = list(value)
    if len(values) != n:
        raise InvalidGearTrain(f"{name} has {len(values)} values for {n} parallel stages")
    return [positive(f"{name}[{k}]", v, "m") for k, v in enumerate(values)]


def helix_angles(name: str, value: float | Sequence[float], n: int) -> list[float]:
    """One helix angle [rad] per parallel stage: one value for all, or n values, |β| < 45°."""
    if isinstance(value, (int, float)):
        betas = [float(value)] * n
    else:
        betas = [float(b) for b in value]
        if len(betas) != n:
            raise InvalidGearTrain(f"{name} has {len(betas)} values for {n} stages")
    for beta in betas:
        if not (math.isfinite(beta) and abs(beta) < math.pi / 4.0):
            raise InvalidGearTrain(
                f"{name} = {math.degrees(beta):g}°; give |β| < 45° (0 for spur gears)"
            )
    return betas
