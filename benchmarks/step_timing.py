"""The cost of one step of a run: the timing the step benchmarks share.

A benchmark compares two variants of a model (rigid and compliant meshes, with and without
friction, one line and slices) by timing the same run of each, interleaved, in one process.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable
from typing import Any

import pinwind
from pinwind.errors import PinwindWarning

#: (input joint, its torque [N·m], output joint, its held speed [rad/s])
Case = tuple[str, float, str, float]


def seconds_per_step(
    gearbox: Any,
    case: Case,
    *,
    steps: int,
    dt: float,
    meshes: dict[str, Any],
    clock: Callable[[], float] = time.perf_counter,
) -> float:
    """The clock's seconds per step of a run: torque on the input joint, the output held at its
    speed, the meshes as given, nothing kept but the last sample, no statistics or progress."""
    joint_in, torque, joint_out, speed = case
    started = clock()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        pinwind.simulate(
            gearbox,
            duration=steps * dt,
            dt=dt,
            torques={joint_in: torque},
            speeds={joint_out: speed},
            meshes=meshes,
            keep="last",
            statistics=False,
            progress=False,
        )
    return (clock() - started) / steps
