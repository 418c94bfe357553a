"""A channel of an OpenFAST output file (``.out`` text, ``.outb`` binary) as a time signal.

The file is read with openfast-io (``openfast_io.FAST_output_reader``, NREL's reader shipped with
OpenFAST), so every format OpenFAST writes is read as OpenFAST reads it. OpenFAST's channels are
in its own units (``RotTorq`` and ``GenTq`` in kN·m, ``RotSpeed`` and ``GenSpeed`` in rpm,
``Wind1VelX`` in m/s): ``scale`` turns them into the SI unit of what the channel drives
(``scale=1000`` for kN·m → N·m). ``si_factor`` reads that factor from a channel's unit, for
readers that take the unit from the file (the hub loads, ``loads/hub_loads.py``).
"""

from __future__ import annotations

import hashlib
import math
from pathlib import Path
from typing import Any

import numpy as np

from pinwind.errors import InputError
from pinwind.loads.signals import Scaled, Table


def read_output(path: str | Path) -> tuple[np.ndarray, list[str], list[str]]:
    """(data, channel names, units) of an OpenFAST output file; column 0 is ``Time``.

    Raises:
        InputError: the file is missing, openfast-io cannot read it, or it has no data rows.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such OpenFAST output file")
    from openfast_io.FAST_output_reader import load_ascii_output, load_binary_output

    try:
        if path.suffix.lower() == ".outb":
            data, info, _ = load_binary_output(str(path))
        else:
            data, info = load_ascii_output(str(path))
    except Exception as err:  # the reader raises bare Exceptions, ValueErrors, struct.errors
        raise InputError(
            f"{path}: openfast-io cannot read it as an OpenFAST output file ({err})"
        ) from err
    names = list(info["attribute_names"])
    units = list(info["attribute_units"])
    if not names or len(units) != len(names):
        # openfast-io reads a header cut before its unit line as channels without units.
        what = (
            "no line of channel names"
            if not names
            else f"channels {', '.join(names)} and {len(units)} units"
        )
        raise InputError(
            f"{path}: the file ends inside its OpenFAST header ({what}), so it holds no "
            "samples: it was cut short (OpenFAST stopped, or a copy broke off); give the whole "
            "output file"
        )
    # openfast-io gives a 1-D array for a file of one data row, and an empty one without rows
    table = np.asarray(data, dtype=float).reshape(-1, len(names))
    if not len(table):
        raise InputError(
            f"{path}: the OpenFAST output has its header (channels {', '.join(names)}) but no "
            "data rows, as when OpenFAST stopped before its first output; give a file with at "
            "least two rows of samples"
        )
    return table, names, units


#: SI value of one unit as OpenFAST writes units in its output headers (the parentheses
#: stripped): forces, moments, angles, speeds. OpenFAST writes "kN-m" and "kN·m" alike.
_SI_PER_UNIT: dict[str, float] = {
    "N": 1.0,
    "kN": 1e3,
    "MN": 1e6,
    "N-m": 1.0,
    "Nm": 1.0,
    "N·m": 1.0,
    "kN-m": 1e3,
    "kNm": 1e3,
    "kN·m": 1e3,
    "MN-m": 1e6,
    "MNm": 1e6,
    "MN·m": 1e6,
    "rad": 1.0,
    "deg": math.pi / 180.0,
    "rad/s": 1.0,
    "rpm": 2.0 * math.pi / 60.0,
    "deg/s": math.pi / 180.0,
    "s": 1.0,
    "m": 1.0,
    "m/s": 1.0,
}


def si_factor(unit: str, *, where: str) -> float:
    """SI value of one ``unit`` of an OpenFAST header ("(kN-m)" → 1000, "(deg)" → π/180).

    Raises:
        InputError: a unit pinwind cannot turn into SI (naming ``where``, the unit and the
            known units), so that no channel is read in a unit it was not written in.
    """
    name = unit.strip().removeprefix("(").removesuffix(")").strip()
    if name not in _SI_PER_UNIT:
        raise InputError(
            f'{where}: unit "{unit}" is not one pinwind converts to SI; known units: '
            f"{', '.join(_SI_PER_UNIT)}"
        )
    return _SI_PER_UNIT[name]


def read_channel(path: str | Path, channel: str, *, scale: float = 1.0) -> Scaled:
    """Channel ``channel`` of an OpenFAST output file, times ``scale``, as a signal.

    Raises:
        InputError: unknown channel (the message lists the file's channels), or rows the
            ``Table`` refuses (naming the file and row).
    """
    path = Path(path)
    data, names, units = read_output(path)
    if channel not in names[1:]:
        raise InputError(f'{path}: no channel "{channel}"; channels are: {", ".join(names[1:])}')
    column = names.index(channel)
    unit = units[column] if column < len(units) else ""
    spec = {"type": "openfast", "file": str(path), "channel": channel, "scale": scale,
            "sha256": hashlib.sha256(path.read_bytes()).hexdigest()}  # fmt: skip
    # Data rows follow the header: row numbers in messages are data rows, 1-based.
    table = Table(data[:, 0], data[:, column], source=f"{path} channel {channel} [{unit}]")
    return _Channel(table, scale, spec)


class _Channel(Scaled):
    """A scaled table whose spec is the ``openfast(...)`` call that reads it."""

    _spec: dict[str, Any]

    def __init__(self, table: Table, scale: float, spec: dict):
        object.__setattr__(self, "signal", table)
        object.__setattr__(self, "factor", float(scale))
        object.__setattr__(self, "_spec", spec)

    @property
    def table(self) -> Table:
        """The channel's values before scaling."""
        return self.signal  # type: ignore[return-value]

    def spec(self) -> dict:
        """``{"type": "openfast", "file": ..., "channel": ..., "scale": ...}``."""
        return dict(self._spec)

    @property
    def description(self) -> str:
        """The file, channel and scale."""
        return f"openfast(file={self._spec['file']!r}, channel={self._spec['channel']!r}, " + (
            f"scale={self.factor!r})"
        )
