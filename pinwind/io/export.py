"""Logs as tables: one column per series, for pandas, polars, Excel and MATLAB (``pinwind export``).

Columns are named ``group/element/quantity_unit`` with SI units spelled out (``N_m`` for N·m,
``rad_s`` for rad/s), vector components before the unit, and the time first. A slide's joint
columns (a prismatic joint of a compliant bearing or the support) are in its own units:
``joint/sun_radial_x/angle_m``, ``speed_m_s``, ``acceleration_m_s2``, ``torque_N``.

    time_s, joint/sun/speed_rad_s, mesh/sun_planet1/normal_N, mesh/sun_planet1/force_on_b_x_N,
    bearing/carrier/moment_local_z_N_m, body/carrier/quaternion_w, energy/kinetic_J,
    generator/sun/torque_N_m, rotor/carrier/power_W, rotor/carrier/tip_speed_ratio, ...

Parquet keeps every float64 bit for bit; CSV writes 17 significant digits, which read back to the
same float64. A log is exported a block of samples at a time, so its size does not matter. The
table is written under a temporary name next to it and renamed at the end, so a failed export
(missing folder, full disk, unreadable log) leaves no partial file to block the retry.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import BinaryIO

import numpy as np

from pinwind.dynamics import series
from pinwind.dynamics.result import Result
from pinwind.errors import ExportFailed, InputError, LogExists

FORMATS = ("parquet", "csv")


def columns(res: Result, fields: Iterable[str] | None = None) -> Iterator[tuple[str, np.ndarray]]:
    """(name, (n,) float64 values) of every column of a Result: time, then ``fields``' series.

    The columns are those of the schema (``dynamics/series.py``), in its order, then the
    energy ledger.

    Args:
        res: the samples.
        fields: Result arrays to include (``energy`` for the energy ledger); default all.
    """
    names = [s.name for s in series.schema() if s.name != "time"]
    wanted = set(names + ["energy"] if fields is None else fields)
    yield "time_s", res.time
    for s in series.schema():
        if s.name == "time" or s.name not in wanted:
            continue
        # a row per sample, as every column: NaN at the samples without a pose (pose rate)
        values = res.pose_at_samples(s.name) if s.per == "pose" else getattr(res, s.name)
        if s.family == "run":
            unit = s.column_unit()
            yield f"run/{s.quantity}{'_' + unit if unit else ''}", values
            continue
        for i, element in enumerate(res.names(s.family)):
            # a slide's joint series are in m, m/s, m/s², N (``Series.unit_for``)
            unit = s.column_unit(res.kind_of(s.family, i))
            suffix = f"_{unit}" if unit else ""
            if not s.components:
                yield f"{s.family}/{element}/{s.quantity}{suffix}", values[:, i]
            else:
                for k, axis in enumerate(s.components):
                    yield f"{s.family}/{element}/{s.quantity}_{axis}{suffix}", values[:, i, k]
    if "energy" in wanted:
        for term, values in res.energy.items():
            yield f"energy/{term}_J", values


def _fields(topics: Iterable[str]) -> list[str]:
    from pinwind.io.log_channels import CHANNELS

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
        channels: topics to export (``pinwind.io.log_channels.CHANNELS``); default all.
        overwrite: replace an existing ``out``.
        block: samples read and written at a time.
        progress: gets (simulated time read, of the window) [s] before each block is written
            (``LogReader.blocks``).

    Returns:
        (rows, columns) written.

    Raises:
        InputError: unknown format; LogExists: ``out`` exists and ``overwrite`` is false.
        LogError: the log cannot be read.
        ExportFailed: ``out`` cannot be written (naming it and the system's reason).
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
    # A hidden name in the same folder: the rename at the end is atomic on one file system.
    part = out.with_name(f".{out.name}.{os.getpid()}.part")
    write = _write_parquet if format == "parquet" else _write_csv
    try:
        with LogReader(path) as log, open(part, "wb") as f:
            blocks = log.blocks(block, start=start, stop=stop, channels=channels, progress=progress)
            written = write(blocks, f)
        os.replace(part, out)
    except BaseException as err:
        with contextlib.suppress(OSError):  # the folder may not exist: there is no part then
            part.unlink(missing_ok=True)
        if isinstance(err, OSError):
            raise ExportFailed(str(out), err.strerror or str(err)) from err
        raise
    return written


def _block_columns(res: Result) -> list[tuple[str, np.ndarray]]:
    return list(columns(res, _fields(res.metadata["log"]["channels"])))


def _write_parquet(blocks: Iterator[Result], out: BinaryIO) -> tuple[int, int]:
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


def _write_csv(blocks: Iterator[Result], out: BinaryIO) -> tuple[int, int]:
    rows = 0
    names: list[str] = []
    for res in blocks:
        table = _block_columns(res)
        if not names:
            names = [name for name, _ in table]
            out.write((",".join(names) + "\n").encode("utf-8"))
        if len(res):
            values = np.column_stack([v for _, v in table])
            np.savetxt(out, values, fmt="%.17g", delimiter=",", encoding="utf-8")
        rows += len(res)
    return rows, len(names)
