"""Logs as tables: one column per series, for pandas, polars, Excel and MATLAB (``pinwind export``).

Columns are named ``group/element/quantity_unit`` with SI units spelled out (``N_m`` for N·m,
``rad_s`` for rad/s), vector components before the unit, and the time first:

    time_s, joint/sun/speed_rad_s, mesh/sun_planet1/normal_N, mesh/sun_planet1/force_on_b_x_N,
    bearing/carrier/moment_local_z_N_m, body/carrier/quaternion_w, energy/kinetic_J,
    generator/sun/torque_N_m, rotor/carrier/power_W, rotor/carrier/tip_speed_ratio, ...

Parquet keeps every float64 bit for bit; CSV writes 17 significant digits, which read back to the
same float64. A log is exported a block of samples at a time, so its size does not matter.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path

import numpy as np

from pinwind.dynamics.result import POSE_ARRAYS, Result
from pinwind.errors import InputError, LogExists

#: Result array → (group, quantity, unit in the name); components x y z (w) go before the unit.
COLUMNS: dict[str, tuple[str, str, str]] = {
    "angle": ("joint", "angle", "rad"),
    "speed": ("joint", "speed", "rad_s"),
    "acceleration": ("joint", "acceleration", "rad_s2"),
    "torque": ("joint", "torque", "N_m"),
    "mesh_normal": ("mesh", "normal", "N"),
    "mesh_tangential": ("mesh", "tangential", "N"),
    "mesh_radial": ("mesh", "radial", "N"),
    "mesh_axial": ("mesh", "axial", "N"),
    "mesh_flank": ("mesh", "flank", ""),
    "transmission_error": ("mesh", "transmission_error", "m"),
    "mesh_force_on_b": ("mesh", "force_on_b", "N"),
    "pitch_point": ("mesh", "pitch_point", "m"),
    "bearing_force": ("bearing", "force", "N"),
    "bearing_moment": ("bearing", "moment", "N_m"),
    "bearing_force_local": ("bearing", "force_local", "N"),
    "bearing_moment_local": ("bearing", "moment_local", "N_m"),
    "body_position": ("body", "position", "m"),
    "body_quaternion": ("body", "quaternion", ""),
    "constraint_residual": ("run", "constraint_residual", "m_s_or_rad_s"),
    "generator_torque": ("generator", "torque", "N_m"),
    "rotor_torque": ("rotor", "torque", "N_m"),
    "rotor_power": ("rotor", "power", "W"),
    "rotor_tip_speed_ratio": ("rotor", "tip_speed_ratio", ""),
    "rotor_power_coefficient": ("rotor", "power_coefficient", ""),
    "rotor_wind_speed": ("rotor", "wind_speed", "m_s"),
}

FORMATS = ("parquet", "csv")

_ELEMENTS = {"joint": "joint_names", "mesh": "mesh_names", "bearing": "bearing_names"}
_ELEMENTS["body"] = "body_names"
_ELEMENTS.update(generator="generator_names", rotor="rotor_names")


def columns(res: Result, fields: Iterable[str] | None = None) -> Iterator[tuple[str, np.ndarray]]:
    """(name, (n,) float64 values) of every column of a Result: time, then ``fields``' series.

    Args:
        res: the samples.
        fields: Result arrays to include (``energy`` for the energy ledger); default all.
    """
    fields = list(COLUMNS) + ["energy"] if fields is None else list(fields)
    yield "time_s", res.time
    for name in (*COLUMNS, "energy"):
        if name not in fields:
            continue
        if name == "energy":
            for term, values in res.energy.items():
                yield f"energy/{term}_J", values
            continue
        group, quantity, unit = COLUMNS[name]
        # a row per sample, as every column: NaN at the samples without a pose (pose rate)
        values = res.pose_at_samples(name) if name in POSE_ARRAYS else getattr(res, name)
        suffix = f"_{unit}" if unit else ""
        if group == "run":
            yield f"run/{quantity}{suffix}", values
            continue
        for i, element in enumerate(getattr(res, _ELEMENTS[group])):
            if values.ndim == 2:
                yield f"{group}/{element}/{quantity}{suffix}", values[:, i]
            else:
                for k, axis in enumerate("xyzw"[: values.shape[2]]):
                    yield f"{group}/{element}/{quantity}_{axis}{suffix}", values[:, i, k]


def _fields(topics: Iterable[str]) -> list[str]:
    from pinwind.io.log_reader import CHANNELS

    return [f for topic in topics for f in CHANNELS[topic] if f != "time"]


def export_log(
    path: str | os.PathLike,
    out: str | os.PathLike,
    *,
    format: str | None = None,
    start: float | None = None,
    stop: float | None = None,
    channels: Iterable[str] | str | None = None,
    overwrite: bool = False,
    block: int = 20_000,
    progress: Callable[[float, float], None] | None = None,
) -> tuple[int, int]:
    """Write a log's samples (start ≤ t ≤ stop [s], ``channels``) to a Parquet or CSV file.

    Args:
        path: the log.
        out: the table to write.
        format: ``parquet`` or ``csv``; default from the suffix of ``out``.
        start, stop: time window [s] (open ends when None).
        channels: topics to export (``pinwind.io.log_reader.CHANNELS``); default all.
        overwrite: replace an existing ``out``.
        block: samples read and written at a time.
        progress: gets (simulated time read, of the window) [s] before each block is written
            (``LogReader.blocks``).

    Returns:
        (rows, columns) written.

    Raises:
        InputError: unknown format; LogExists: ``out`` exists and ``overwrite`` is false.
        LogError: the log cannot be read.
    """
    from pinwind.io.log_reader import LogReader

    out = Path(out)
    format = (format or out.suffix.lstrip(".")).lower()
    if format not in FORMATS:
        raise InputError(
            f'export format "{format}" is not one of {", ".join(FORMATS)}; give --format or '
            "an output file ending in .parquet or .csv"
        )
    if out.exists() and not overwrite:
        raise LogExists(str(out))
    with LogReader(path) as log:
        blocks = log.blocks(block, start=start, stop=stop, channels=channels, progress=progress)
        write = _write_parquet if format == "parquet" else _write_csv
        return write(blocks, out)


def _block_columns(res: Result) -> list[tuple[str, np.ndarray]]:
    return list(columns(res, _fields(res.metadata["log"]["channels"])))


def _write_parquet(blocks: Iterator[Result], out: Path) -> tuple[int, int]:
    import pyarrow as pa
    import pyarrow.parquet as pq

    rows = 0
    writer = None
    names: list[str] = []
    try:
        for res in blocks:
            table = _block_columns(res)
            names = [name for name, _ in table]
            batch = pa.table({name: pa.array(values, pa.float64()) for name, values in table})
            if writer is None:
                writer = pq.ParquetWriter(out, batch.schema)
            writer.write_table(batch)
            rows += len(res)
    finally:
        if writer is not None:
            writer.close()
    return rows, len(names)


def _write_csv(blocks: Iterator[Result], out: Path) -> tuple[int, int]:
    rows = 0
    names: list[str] = []
    with open(out, "w", encoding="utf-8", newline="") as f:
        for res in blocks:
            table = _block_columns(res)
            if not names:
                names = [name for name, _ in table]
                f.write(",".join(names) + "\n")
            if len(res):
                values = np.column_stack([v for _, v in table])
                np.savetxt(f, values, fmt="%.17g", delimiter=",")
            rows += len(res)
    return rows, len(names)
