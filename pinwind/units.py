"""Unit conversions at the edges: pinwind is SI inside (rad/s for speeds).

Speeds come in and go out in rpm at the edges (command line, scenario files, tables, plots);
``rpm_to_rad_s`` and ``rad_s_to_rpm`` are the one conversion, for numbers and arrays alike.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, TypeVar

if TYPE_CHECKING:  # numpy only in annotations: the command line reads these without numpy
    import numpy as np

#: One revolution per minute in rad/s: 2π/60.
RAD_S_PER_RPM = 2.0 * math.pi / 60.0

Speed = TypeVar("Speed", float, "np.ndarray")


def rpm_to_rad_s(speed_rpm: Speed) -> Speed:
    """A speed in rad/s from one in revolutions per minute (ω = 2π n/60)."""
    return speed_rpm * RAD_S_PER_RPM


def rad_s_to_rpm(speed: Speed) -> Speed:
    """A speed in revolutions per minute from one in rad/s (n = 60 ω/2π)."""
    return speed / RAD_S_PER_RPM


#: rpm per rad/s, 60/2π: plots multiply by it, as they always have (bit for bit).
RPM_PER_RAD_S = 60.0 / (2.0 * math.pi)
#: Display units that are a thousand SI units.
_KILO = ("kN", "kN·m", "kW", "kJ", "kN/m")


def to_display(values: np.ndarray, unit: str) -> np.ndarray:
    """SI values in a plot's display unit.

    kN, kN·m, kW, kJ, kN/m: ÷ 1000; µm: × 1e6; rpm: × 60/2π; deg: × 180/π; any other unit:
    the values.
    """
    if unit in _KILO:
        return values / 1e3
    if unit == "µm":
        return values * 1e6
    if unit == "rpm":
        return values * RPM_PER_RAD_S
    if unit == "deg":
        return values * (180.0 / math.pi)
    return values
