"""Statistics of a run and the printed summary of ``pinwind simulate``.

``statistics`` gives min, max, mean, RMS and final value of a series (the columns of
002_bb0c67d52fe8a188.txt Tables 4-1/4-2). ``summary_tables`` lays them out for the terminal, in
engineering units (rpm, kN, kN·m).
"""

from __future__ import annotations

import math

import numpy as np
from rich.markup import escape
from rich.table import Table

from pinwind.dynamics.result import Result

RAD_PER_S_TO_RPM = 60.0 / (2.0 * math.pi)


def statistics(values: np.ndarray) -> dict[str, float]:
    """min, max, mean, RMS and final value of a 1-D series (empty series give NaN)."""
    values = np.asarray(values, dtype=float)
    if values.size == 0:
        return {k: math.nan for k in ("min", "max", "mean", "rms", "final")}
    return {
        "min": float(values.min()),
        "max": float(values.max()),
        "mean": float(values.mean()),
        "rms": float(np.sqrt(np.mean(values**2))),
        "final": float(values[-1]),
    }


def _input_joint(res: Result) -> str | None:
    for key in ("speeds", "torques"):
        names = list(res.metadata.get(key, {}))
        if names:
            return names[0]
    return None


def summary_tables(res: Result) -> list[Table]:
    """Tables of joint speeds and ratios, mesh forces and bearing reactions."""
    tables = []
    ref = _input_joint(res)
    ref_speed = res.joint(ref).speed[-1] if ref else 0.0

    joints = Table(title=f"Bearings: speeds at t = {res.time[-1]:.4g} s")
    for col in ("joint", "speed [rpm]", f"ratio to {ref or '-'}", "torque [kN·m]"):
        joints.add_column(escape(col), justify="right" if col != "joint" else "left")
    locked = set(res.metadata.get("locked_joints", []))
    for name in res.joint_names:
        js = res.joint(name)
        speed = js.speed[-1]
        ratio = speed / ref_speed if abs(ref_speed) > 1e-12 else math.nan
        if name in locked:
            ratio_text = "0 (fixed)"  # held by a row: its speed is rounding noise
        else:
            ratio_text = f"{ratio:.6g}" if math.isfinite(ratio) else "-"
        joints.add_row(
            name,
            f"{speed * RAD_PER_S_TO_RPM:.4f}",
            ratio_text,
            f"{js.torque[-1] / 1e3:.4f}",
        )
    tables.append(joints)

    if res.mesh_names:
        meshes = Table(
            title=escape("Gear meshes: tooth forces [kN] (final; min / max / RMS of normal)")
        )
        for col in (
            "mesh",
            "normal",
            "tangential",
            "radial",
            "flank",
            "min",
            "max",
            "RMS",
            "TE [µm]",
        ):
            meshes.add_column(escape(col), justify="right" if col != "mesh" else "left")
        for name in res.mesh_names:
            ms = res.mesh(name)
            s = statistics(ms.normal)
            meshes.add_row(
                name,
                f"{ms.normal[-1] / 1e3:.4f}",
                f"{ms.tangential[-1] / 1e3:.4f}",
                f"{ms.radial[-1] / 1e3:.4f}",
                f"{int(ms.flank[-1]):+d}",
                f"{s['min'] / 1e3:.4f}",
                f"{s['max'] / 1e3:.4f}",
                f"{s['rms'] / 1e3:.4f}",
                f"{np.max(np.abs(ms.transmission_error)) * 1e6:.2e}",
            )
        tables.append(meshes)

    bearings = Table(
        title="Bearing reactions on the child body, world frame, kN and kN·m "
        "(final; min / max / RMS of |F|)"
    )
    for col in (
        "bearing",
        "Fx [kN]",
        "Fy [kN]",
        "Fz [kN]",
        "|F| min",
        "|F| max",
        "|F| RMS",
        "|M| [kN·m]",
    ):
        bearings.add_column(escape(col), justify="right" if col != "bearing" else "left")
    for name in res.bearing_names:
        b = res.bearing(name)
        magnitude = np.linalg.norm(b.force, axis=1)
        s = statistics(magnitude)
        fx, fy, fz = b.force[-1] / 1e3
        bearings.add_row(
            name,
            f"{fx:.4f}",
            f"{fy:.4f}",
            f"{fz:.4f}",
            f"{s['min'] / 1e3:.4f}",
            f"{s['max'] / 1e3:.4f}",
            f"{s['rms'] / 1e3:.4f}",
            f"{np.linalg.norm(b.moment[-1]) / 1e3:.4f}",
        )
    tables.append(bearings)
    return tables
