"""``pinwind spectrum LOG``: Welch spectra of a log's series, their peaks and their figure.

Reads a window of the log's series (``io/log_reader.py``) and the model it records
(``io/panels.model_of_log``), and hands the samples to the spectral analysis
(``analysis/spectrum.py``: Welch PSD, peaks and their amplitude convention, the gearbox's mesh
and shaft frequencies); the figure draws the PSDs with those frequencies marked.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from pinwind.analysis.spectrum import (
    HARMONICS,
    Peak,
    Spectrum,
    SpectrumReport,
    gearbox_frequencies,
    nearest_harmonic,
    parse_series,
    power_spectral_density,
    series_channel,
    series_values,
    spectral_peaks,
)
from pinwind.dynamics import series as schema
from pinwind.errors import InputError
from pinwind.io.figure_layout import caption_below
from pinwind.io.figures import caption
from pinwind.io.log_reader import LogReader
from pinwind.io.panels import model_of_log

#: Fewest samples a Welch segment may have.
MIN_SEGMENT_SAMPLES = 16
#: Segments in the window when the segment length is not given (half-overlapping: 7 averages).
DEFAULT_SEGMENTS = 4


def sample_rate_of(time: np.ndarray, path: str | os.PathLike) -> float:
    """Samples per second of evenly spaced times [Hz].

    Raises:
        InputError: fewer than two samples, or a gap (a damaged log lost samples).
    """
    if len(time) < 2:
        raise InputError(f"{path}: {len(time)} sample(s) in the window; a spectrum needs more")
    steps = np.diff(time)
    step = float(np.median(steps))
    uneven = np.flatnonzero(np.abs(steps - step) > 1e-6 * step)
    if len(uneven):
        k = int(uneven[0])
        raise InputError(
            f"{path}: the samples are not evenly spaced (a step of {steps[k]:.6g} s after "
            f"t = {time[k]:.6g} s, {step:.6g} s elsewhere); choose a window without the gap "
            "with --from/--to"
        )
    return 1.0 / step


def spectrum_of_log(
    path: str | os.PathLike,
    *,
    series: Sequence[str] = (),
    start: float | None = None,
    stop: float | None = None,
    segment: float | None = None,
    peaks: int = 10,
) -> SpectrumReport:
    """Welch spectra and peaks of series of a log, with the gearbox's frequencies.

    Args:
        path: the log.
        series: ``NAME[:ELEMENT]`` each (``mesh_normal:sun_planet1``, ``bearing_force``);
            default the mesh normal forces (the joint speeds in a model without meshes).
        start, stop: time window [s] (inclusive; open ends when None).
        segment: Welch segment length [s]; default a quarter of the window.
        peaks: peaks listed per spectrum.

    Raises:
        LogError: the log cannot be read.
        InputError: an unknown series, a segment that is not positive or longer than the
            window or shorter than ``MIN_SEGMENT_SAMPLES`` samples, uneven samples.
        UnknownElement: an element the series' family does not have.
    """
    if segment is not None and not 0.0 < segment < math.inf:
        # inf passed the check and overflowed the sample count (OverflowError)
        raise InputError(f"--segment {segment} s; give a positive segment length [s]")
    if peaks < 1:
        raise InputError(f"--peaks {peaks}; give at least one")
    with LogReader(path) as reader:
        gearbox, _ = model_of_log(reader)
        wanted = list(series)
        if not wanted:
            has_meshes = reader.metadata.get("pinwind.model", {}).get("mesh_names")
            wanted = ["mesh_normal" if has_meshes else "speed"]
        chosen = [parse_series(text) for text in wanted]
        channels = sorted({"/joints", *(series_channel(s) for s, _ in chosen)})
        result = reader.read(start=start, stop=stop, channels=channels)
    rate = sample_rate_of(result.time, path)
    window = float(result.time[-1] - result.time[0])
    length = segment if segment is not None else window / DEFAULT_SEGMENTS
    samples = int(round(length * rate))
    if samples > len(result) or samples < MIN_SEGMENT_SAMPLES:
        raise InputError(
            f"{path}: a segment of {length:.6g} s is {samples} samples at {rate:.6g} Hz, but "
            f"the window has {len(result)} samples ({window:.6g} s) and a segment needs "
            f"{MIN_SEGMENT_SAMPLES} to {len(result)}; give --segment between "
            f"{MIN_SEGMENT_SAMPLES / rate:.3g} and {window:.6g} s, or a longer log"
        )
    markers = gearbox_frequencies(gearbox, result.speed) if gearbox is not None else []
    spectra = []
    for s, element in chosen:
        if s.family != "run" and not result.names(s.family):
            families = [f for f in schema.NAMES_OF if result.names(f)]
            raise InputError(
                f"{path}: --series {s.name}: the run has no {s.family}, so the log has no "
                f"values of it (it was simulated without one); give a series of a kind of "
                f"element the run has: {', '.join(families)} (docs/series.md)"
            )
        for name, component, values in series_values(result, s, element):
            if not np.all(np.isfinite(values)):
                raise InputError(
                    f'{path}: series "{s.name}" of "{name}" has NaN or infinite samples (the '
                    "log was written before the series was declared, or the run diverged)"
                )
            freq, density = power_spectral_density(
                values, sample_rate=rate, segment_samples=samples
            )
            found = spectral_peaks(freq, density, count=peaks)
            tolerance = 1.5 * rate / samples
            found = [
                Peak(p.frequency, p.amplitude, nearest_harmonic(p.frequency, markers, tolerance))
                for p in found
            ]
            unit = result.unit(s, result.names(s.family).index(name) if name else 0)
            spectra.append(Spectrum(s.name, name, component, unit, freq, density, found))
    return SpectrumReport(
        Path(path), spectra, markers, rate, samples / rate,
        (float(result.time[0]), float(result.time[-1])), dict(result.metadata), result.status,
    )  # fmt: skip


# --- the figure ---------------------------------------------------------------------------------


def write_figure(report: SpectrumReport, out: str | os.PathLike, *, dpi: int = 110) -> Path:
    """A PNG (or SVG, PDF by suffix) of the PSDs, one panel per series, markers drawn.

    Mesh frequencies are solid vertical lines (their 2nd and 3rd harmonics dashed), shaft
    orders dotted; the caption gives the log's provenance (``io/figures.caption``).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(dict.fromkeys(s.series for s in report.spectra))
    rows = len(names)
    fig, axes = plt.subplots(
        rows, 1, figsize=(10, 1.2 + 3.0 * rows), sharex=True, squeeze=False, layout="constrained"
    )
    nyquist = report.sample_rate / 2.0
    for ax, name in zip(axes[:, 0], names, strict=True):
        shown = [s for s in report.spectra if s.series == name]
        ax.set_yscale("log")
        for s in shown:
            if np.any(s.density[1:] > 0.0):
                ax.plot(s.frequency[1:], s.density[1:], linewidth=1.0, label=s.label)
            else:  # zero at every frequency (a spur mesh's axial force): no line on a log axis
                ax.plot([], [], linewidth=1.0, label=f"{s.label} (0: no line on the log axis)")
        labelled: list[float] = []  # a label closer than 1.5 % of the axis to another is left out
        for m in sorted(report.markers, key=lambda m: m.kind):  # mesh labels first
            for h in HARMONICS if m.kind == "mesh" else (1,):
                f = h * m.frequency
                if not 0.0 < f < nyquist:
                    continue
                style = ":" if m.kind == "shaft" else ("-" if h == 1 else "--")
                colour = "0.45" if m.kind == "shaft" else "tab:red"
                ax.axvline(f, color=colour, linestyle=style, linewidth=0.8, alpha=0.7)
                if any(abs(f - x) < 0.015 * nyquist for x in labelled):
                    continue
                labelled.append(f)
                ax.text(f, 0.98, f" {h}× {m.short_label}",
                        transform=ax.get_xaxis_transform(), rotation=90, fontsize=6,
                        va="top", ha="left", color=colour)  # fmt: skip
        # a joint series of revolute joints and slides has two units (rad/s and m/s)
        unit = ", ".join(f"{u}²/Hz" for u in dict.fromkeys(sp.unit for sp in shown))
        ax.set_title(f"{name}: Welch PSD [{unit}]", fontsize=9, loc="left")
        ax.set_ylabel(f"[{unit}]", fontsize=8)
        ax.grid(True, linewidth=0.3, which="both")
        ax.tick_params(labelsize=7)
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, frameon=False)
    axes[-1, 0].set_xlabel("frequency [Hz]")
    axes[-1, 0].set_xlim(0.0, nyquist)
    fig.suptitle(
        f"{report.metadata.get('model_name', '')}: spectra (segment {report.segment:.4g} s, "
        f"Δf = {report.resolution:.4g} Hz)", fontsize=11, x=0.02, ha="left",
    )  # fmt: skip
    caption_below(
        fig, caption(report.metadata, report.status, report.path, report.span, None, None)
    )
    path = Path(out)
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path
