"""Load spectra over a site's design life, from the case logs of a fatigue set (IEC 61400-4).

Each case's counted history (from ``skip_start`` on) gives every turning shaft's LDD and LRD
(`load_spectrum.shaft_spectra`) on torque bins common to the whole level; a case stands for its
wind bin's h hours divided among the bin's seeds, so its time and revolutions count
h · 3600 / (T · seeds) times, T the seconds of its counted history. Added over the bins, the LDD
of a level sums to the site's operating hours and its LRD to Σ_b h_b · 3600 · n̄_b, n̄_b the bin's
mean |ω| / 2π. The shafts' torques are the ones `load_spectrum.shaft_torque` takes.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from pinwind.life.load_spectrum import DEFAULT_BINS, LoadSpectrum, load_spectrum, shaft_torque

if TYPE_CHECKING:
    from pinwind.life.fatigue_set import FatigueSet


def set_load_spectra(
    fatigue: FatigueSet, level: int, *, bins: int = DEFAULT_BINS
) -> list[LoadSpectrum]:
    """Every turning shaft's LDD and LRD over the site's life at turbulence level ``level``.

    Args:
        fatigue: the set, its cases run (their logs in ``fatigue.out``).
        level: index of the turbulence level.
        bins: equal torque bins from the level's least to its largest torque, per shaft.

    Returns:
        One spectrum per turning shaft, in joint order: time [s] and revolutions over the life.

    Raises:
        InputError: a case's log is missing (run the fatigue set first).
    """
    from pinwind.errors import InputError
    from pinwind.io.log_reader import read_log
    from pinwind.model.gearbox import load
    from pinwind.runs.scenario import build

    first = fatigue.cases()[0]
    scenario = build(fatigue.case_values(first), source=fatigue.source, base=fatigue.base)
    gearbox = load(scenario.model_path())
    histories: dict[str, list[tuple[np.ndarray, np.ndarray, np.ndarray, float]]] = {}
    sources: dict[str, str] = {}
    for case in fatigue.cases():
        if case.level != level:
            continue
        path = fatigue.log_path(case)
        if not path.is_file():
            raise InputError(f"{path}: case {case.name} has not run; run the fatigue set first")
        result = read_log(path)
        counted = result.time >= fatigue.skip_start
        time = result.time[counted]
        # The case's history stands for its share of the bin's hours.
        factor = fatigue.site.bins[case.bin].hours * 3600.0 / len(fatigue.seeds)
        factor /= time[-1] - time[0]
        for i, joint in enumerate(result.joint_names):
            if joint in gearbox.locked_joints:
                continue
            torque, sources[joint] = shaft_torque(result, gearbox, joint)
            histories.setdefault(joint, []).append(
                (torque[counted], result.speed[counted, i], time, factor)
            )
    spectra = []
    for joint, cases in histories.items():
        low = min(float(np.min(torque)) for torque, *_ in cases)
        high = max(float(np.max(torque)) for torque, *_ in cases)
        edges = np.linspace(low, high if high > low else low + 1.0, bins + 1)
        durations, turns = np.zeros(bins), np.zeros(bins)
        for torque, speed, time, factor in cases:
            one = load_spectrum(torque, speed, time, bins=edges.tolist(), joint=joint)
            durations += factor * one.time
            turns += factor * one.revolutions
        spectra.append(LoadSpectrum(joint, sources[joint], edges, durations, turns))
    return spectra


def write_load_spectra_csv(spectra: list[LoadSpectrum], path: Path) -> Path:
    """The spectra as CSV: one row per shaft and torque bin.

    Columns: the joint, where its torque comes from, the bin's torque range [N·m], its time [h]
    (LDD) and revolutions (LRD) over the life.
    """
    import csv

    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as out:
        rows = csv.writer(out)
        rows.writerow(
            ["joint", "torque_source", "torque_from_N_m", "torque_to_N_m", "time_h", "revolutions"]
        )
        for spectrum in spectra:
            for k in range(len(spectrum.time)):
                rows.writerow(
                    [
                        spectrum.joint,
                        spectrum.source,
                        repr(float(spectrum.edges[k])),
                        repr(float(spectrum.edges[k + 1])),
                        repr(float(spectrum.time[k] / 3600.0)),
                        repr(float(spectrum.revolutions[k])),
                    ]
                )
    return path
