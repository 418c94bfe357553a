"""Rotor performance tables in the text format of NREL's ROSCO toolbox (``Cp_Ct_Cq.*.txt``).

ROSCO (Abbas et al. 2022, "A reference open-source controller for fixed and floating offshore
wind turbines", Wind Energ. Sci. 7, 53–73) writes a rotor's power, thrust and torque coefficients
on a grid of blade pitch [deg] (columns) and tip-speed ratio (rows): comment lines start with
``#``; after the pitch angles, the tip-speed ratios and the wind speed come the C_p rows, the
C_t rows and the C_q rows, one row per tip-speed ratio. ``read_performance`` gives the grid and
the C_p and C_t values, pitch in radians (``loads/rotor.py`` ``performance_tables`` makes them
the rotor's tables).

``NREL5MW_PERFORMANCE`` is ROSCO's table of the NREL 5 MW reference rotor
(``parameter_files/NREL5MW/Cp_Ct_Cq.NREL5MW.txt`` of github.com/NREL/ROSCO at commit c0cde02b,
MIT License, written by the ROSCO toolbox on 2019-10-30), shipped unchanged: 52 pitch angles
from −1° to 24.5° and 24 tip-speed ratios from 3 to 14.5. Its C_p,max at 0° pitch, 0.482 at
λ 7.5, is Jonkman et al. 2009's (0.482 at λ 7.55).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from pinwind.errors import InputError

#: ROSCO's C_p, C_t, C_q table of the NREL 5 MW rotor (module docstring).
NREL5MW_PERFORMANCE = Path(__file__).with_name("data") / "nrel5mw_cp_ct_cq.txt"


@dataclass(frozen=True)
class Performance:
    """A rotor's coefficients on a grid (module docstring).

    Attributes:
        pitch: blade pitch angles [rad], increasing; tsr: tip-speed ratios, increasing.
        cp, ct: power and thrust coefficients, (len(tsr), len(pitch)).
    """

    pitch: tuple[float, ...]
    tsr: tuple[float, ...]
    cp: np.ndarray
    ct: np.ndarray


def read_performance(path: str | os.PathLike) -> Performance:
    """The grid and the C_p and C_t values of a ROSCO performance file (module docstring).

    Raises:
        InputError: a file that cannot be read, or whose numbers do not make the three grids and
            three tables of its pitch angles × tip-speed ratios (naming the file and the counts).
    """
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as err:
        raise InputError(f"{path}: cannot read the rotor performance table: {err}") from err
    rows = []
    for line in text.splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        try:
            rows.append([float(x) for x in line.split()])
        except ValueError as err:
            raise InputError(
                f"{path}: {line[:40]!r} is not a row of numbers; give a ROSCO Cp_Ct_Cq text file"
            ) from err
    if len(rows) < 3:
        raise InputError(
            f"{path}: no pitch, tip-speed-ratio and wind-speed lines; not a ROSCO Cp_Ct_Cq file"
        )
    pitch_deg, tsr = rows[0], rows[1]
    tables = rows[3:]
    if len(tables) < 2 * len(tsr) or any(len(r) != len(pitch_deg) for r in tables):
        raise InputError(
            f"{path}: {len(tables)} table rows of lengths {sorted({len(r) for r in tables})}; a "
            f"ROSCO file with {len(pitch_deg)} pitch angles and {len(tsr)} tip-speed ratios has "
            f"{len(tsr)} rows of {len(pitch_deg)} values per coefficient (C_p, C_t, C_q)"
        )
    n = len(tsr)
    return Performance(
        pitch=tuple(math.radians(p) for p in pitch_deg),
        tsr=tuple(tsr),
        cp=np.array(tables[:n]),
        ct=np.array(tables[n : 2 * n]),
    )
