"""An efficiency map: the gearbox's efficiency over a grid of input torques and speeds.

At each operating point (input torque T on the input joint, input speed n) a short run holds the
output joint at the speed n × ratio (a speed driver; the ratio from the train's kinematics with
its torsional springs undeflected, ``steady_ratio``), starts the train at that speed and takes
the efficiency ``analysis/efficiency.py`` gives over the run's second half (ISO/TR 14179-2's
bearing and mesh losses from the run's loads; no churning). The points run here, on local
processes or on Dask (``runs/executor.py``); the map is written as CSV and drawn as a filled
contour plot.
"""

from __future__ import annotations

import csv
import math
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from pinwind.errors import InvalidLossInput, PinwindWarning
from pinwind.losses.oil import VG_GRADES

#: The columns of the map's CSV, in order.
COLUMNS = (
    "torque_Nm",
    "speed_rpm",
    "input_power_W",
    "bearing_loss_W",
    "mesh_loss_W",
    "efficiency",
)
_RPM = 2.0 * math.pi / 60.0


def check_grade(grade: int, name: str = "lubricant_vg") -> None:
    """Refuse an ISO 3448 viscosity grade that does not exist, listing those that do.

    ``name``: how the user gave the grade (a model attribute or a command-line option), named
    in the message.

    Raises:
        InvalidLossInput: ``grade`` is not a key of ``VG_GRADES``.
    """
    if grade not in VG_GRADES:
        raise InvalidLossInput(
            name,
            grade,
            f"not an ISO 3448 viscosity grade; give one of {', '.join(map(str, VG_GRADES))}",
        )


def steady_ratio(gearbox: Any, output: str, reference: str) -> float:
    """ω_output / ω_reference at steady state: the meshes' kinematics, torsional springs held.

    A spring keeps its joints turning together (a shaft's twist is constant at steady state),
    a spring to the ground holds its joint (``dynamics/ratios.py`` ``train_modes``, as the torque
    balance takes them); the compliant bearings' slides and locks are held.

    Raises:
        UnknownJoint: a name is not a joint of the gearbox.
        InputError: the two joints do not turn together in one mode of the train.
    """
    from pinwind.dynamics.ratios import train_modes
    from pinwind.errors import InputError, UnknownJoint

    for name in (output, reference):
        if name not in gearbox.joint_names:
            raise UnknownJoint(name, "pinwind efficiency", gearbox.joint_names)
    nv = gearbox.model.nv
    springs = np.array([s.twist_row(nv) for s in gearbox.springs]).reshape(-1, nv)
    i, o = gearbox.v_index(reference), gearbox.v_index(output)
    for mode in train_modes(gearbox, (), springs):
        if mode[i] != 0.0 and mode[o] != 0.0:
            return float(mode[o] / mode[i])
    raise InputError(
        f'joints "{reference}" and "{output}" do not turn together (no mode of the train moves '
        "both): give an input and an output of one gear train"
    )


def point_efficiency(
    item: tuple[float, float],
    *,
    model: str,
    input_joint: str,
    output_joint: str,
    ratio: float,
    duration: float,
    dt: float,
    grade: int,
    temperature: float,
    roughness: float,
) -> dict[str, Any]:
    """One point of the map: a row of ``COLUMNS`` (module docstring); runs on a worker.

    The pinwind warnings of its run (a step too coarse, ...) come back under ``"warnings"``
    (a worker's warnings do not reach the caller), for the caller to show.

    Args:
        item: (input torque T [N·m], input speed n [rpm]).
        model: the model file.
        input_joint, output_joint: where the torque acts and the speed driver holds.
        ratio: ω_output / ω_input [-].
        duration, dt: the run [s].
        grade: ISO VG grade of the gear oil; temperature: the oil's [K].
        roughness: the flanks' Ra [m].
    """
    import pinwind
    from pinwind.analysis.efficiency import efficiency
    from pinwind.losses.oil import Lubricant

    torque, speed_rpm = item
    omega = speed_rpm * _RPM
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", PinwindWarning)
        gearbox = pinwind.load(model)
        res = pinwind.simulate(
            gearbox, duration=duration, dt=dt, torques={input_joint: torque},
            speeds={output_joint: omega * ratio}, initial_speeds={input_joint: omega},
        )  # fmt: skip
    e = efficiency(res, gearbox, oil=Lubricant(grade, temperature), roughness=roughness)
    keep = e.time >= 0.5 * duration
    bearings = sum((c.power for c in e.components if c.kind == "bearing"), np.zeros(len(keep)))
    meshes = sum((c.power for c in e.components if c.kind == "mesh"), np.zeros(len(keep)))
    power = float(np.mean(e.input_power[keep]))
    loss_b, loss_m = float(np.mean(bearings[keep])), float(np.mean(meshes[keep]))
    notes = sorted({str(w.message) for w in caught if issubclass(w.category, PinwindWarning)})
    return {
        "warnings": notes,  # not a column: the caller shows them
        "torque_Nm": torque,
        "speed_rpm": speed_rpm,
        "input_power_W": power,
        "bearing_loss_W": loss_b,
        "mesh_loss_W": loss_m,
        "efficiency": 1.0 - (loss_b + loss_m) / power if power > 0.0 else math.nan,
    }


def efficiency_map(
    model: str,
    *,
    input_joint: str,
    output_joint: str,
    torques: Sequence[float],
    speeds_rpm: Sequence[float],
    duration: float,
    dt: float,
    grade: int = 320,
    temperature: float = 343.15,
    roughness: float = 0.5e-6,
    workers: int = 1,
    scheduler: Any = None,
) -> tuple[list[dict[str, Any]], str]:
    """Every point of the grid torques × speeds (module docstring), sorted, and the backend.

    Raises:
        InvalidLossInput: a viscosity grade that does not exist.
        UnknownJoint, InputError: joints the model lacks, or that do not turn together
            (``steady_ratio``).
    """
    import pinwind
    from pinwind.runs.executor import run_tasks

    check_grade(grade)
    ratio = steady_ratio(pinwind.load(model), output_joint, input_joint)
    items = [(float(t), float(n)) for t in torques for n in speeds_rpm]
    rows: list[dict[str, Any]] = []
    backend = run_tasks(
        point_efficiency, items, accept=rows.append, workers=workers, scheduler=scheduler,
        model=str(model), input_joint=input_joint, output_joint=output_joint, ratio=ratio,
        duration=duration, dt=dt, grade=grade, temperature=temperature, roughness=roughness,
    )  # fmt: skip
    rows.sort(key=lambda r: (r["torque_Nm"], r["speed_rpm"]))
    return rows, backend


def write_csv(rows: list[dict[str, Any]], path: Path) -> None:
    """The map as CSV (``COLUMNS``), one row per point."""
    with open(path, "w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows)


def draw(rows: list[dict[str, Any]], path: Path, *, title: str) -> None:
    """The map as a filled contour of η [%] over input speed [rpm] and torque [kN·m] (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    torques = sorted({r["torque_Nm"] for r in rows})
    speeds = sorted({r["speed_rpm"] for r in rows})
    eta = np.full((len(torques), len(speeds)), np.nan)
    for r in rows:
        eta[torques.index(r["torque_Nm"]), speeds.index(r["speed_rpm"])] = 100 * r["efficiency"]
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    try:
        if len(torques) > 1 and len(speeds) > 1:
            filled = ax.contourf(speeds, np.asarray(torques) / 1e3, eta, levels=12)
            fig.colorbar(filled, ax=ax, label="efficiency η [%]")
        else:
            ax.plot(speeds if len(speeds) > 1 else np.asarray(torques) / 1e3, eta.ravel(), "o-")
        ax.set_xlabel("input speed [rpm]")
        ax.set_ylabel("input torque [kN·m]")
        ax.set_title(title)
        fig.savefig(path, dpi=120)
    finally:
        plt.close(fig)
