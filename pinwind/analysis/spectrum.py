"""Spectra of a Result's series: Welch PSD, its peaks, and the gearbox's mesh and shaft frequencies.

Any series of ``dynamics/series.py`` (per element, a vector per component) has its one-sided
power spectral density estimated by Welch's method (``scipy.signal.welch``: Hann window,
half-overlapping segments, the mean of each segment removed) and its largest peaks listed.
``pinwind spectrum LOG`` reads the series from a log and draws the figure
(``io/log_spectrum.py``); the modes' checks and the Campbell diagram take the same functions.

Amplitude convention: a peak's amplitude is that of the sinusoid A sin(2π f t) carrying the
peak's power, A = √(2 Σ PSD Δf) summed over the peak's bins (the Hann main lobe, ±3 bins at
most, to the local minima), so it does not depend on where the frequency falls between bins;
its frequency is the power-weighted mean of those bins. Units are the series' SI units.

Markers: the mesh frequency of mesh A–B is f_m = z_A |ω_A − ω_line| / 2π, ω_A gear A's absolute
angular speed about its axis and ω_line that of the line through the two gear centres (the
carrier's for a planet mesh, zero for fixed axes): the rate at which teeth of A pass the line
of centres (z_B gives the same). A shaft's order 1 is |ω| / 2π of its body's absolute speed.
Both come from the Pinocchio model at the reference pose (the relations are linear in the joint
speeds, and for gears on fixed or carrier-borne axes the same at every pose), evaluated at the
mean absolute speeds of the window.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin

from pinwind.dynamics import series as schema
from pinwind.dynamics.result import Result
from pinwind.errors import InputError, UnknownElement
from pinwind.model.gearbox import Gearbox

#: Bins on each side of a peak's largest bin that may hold its power (the Hann main lobe is
#: ±2 bins wide; one more keeps the power of a tone between two bins).
PEAK_HALF_WIDTH = 3
#: Peaks weaker than this fraction of the strongest peak's amplitude are not listed.
PEAK_FLOOR = 1e-3
#: Meshes whose frequencies differ by less than this (relative) share one marker.
MESH_GROUPING = 1e-3
#: Harmonics of the mesh frequencies and shaft orders a peak is matched against.
HARMONICS = (1, 2, 3)


@dataclass(frozen=True)
class Peak:
    """A peak of a PSD.

    Attributes:
        frequency: power-weighted frequency of its bins [Hz].
        amplitude: amplitude A of the sinusoid of the same power [series unit].
        near: the mesh or shaft harmonic it sits at (``1× mesh sun_planet1``), else ``""``.
    """

    frequency: float
    amplitude: float
    near: str = ""


@dataclass(frozen=True)
class Spectrum:
    """The Welch PSD of one series of one element (one component of a vector).

    Attributes:
        series: the series' name (``mesh_normal``).
        element: the element (``sun_planet1``), ``""`` for a series per run.
        component: ``x``, ``y`` or ``z`` of a vector series, else ``""``.
        unit: the series' SI unit.
        frequency: bin frequencies [Hz].
        density: one-sided PSD [unit²/Hz].
        peaks: its largest peaks, strongest first.
    """

    series: str
    element: str
    component: str
    unit: str
    frequency: np.ndarray
    density: np.ndarray
    peaks: list[Peak]

    @property
    def label(self) -> str:
        """``sun_planet1``, ``carrier x``: the element and component."""
        return " ".join(p for p in (self.element or self.series, self.component) if p)


@dataclass(frozen=True)
class Marker:
    """A frequency of the gearbox at the window's mean speeds.

    Attributes:
        kind: ``mesh`` (a mesh frequency) or ``shaft`` (a shaft's order 1).
        names: the meshes or the joint that have it.
        frequency: [Hz].
    """

    kind: str
    names: tuple[str, ...]
    frequency: float

    @property
    def label(self) -> str:
        """``mesh sun_planet1, sun_planet2`` or ``shaft carrier``."""
        return f"{self.kind} {', '.join(self.names)}"

    @property
    def short_label(self) -> str:
        """``mesh sun_planet1 and 5 more``: the first name and how many more (figure labels)."""
        more = f" and {len(self.names) - 1} more" if len(self.names) > 1 else ""
        return f"{self.kind} {self.names[0]}{more}"


@dataclass
class SpectrumReport:
    """The spectra of a log's series and the gearbox frequencies they are read against.

    Attributes:
        path: the log.
        spectra: one per series, element and component.
        markers: mesh frequencies and shaft orders (empty when the log's model does not load).
        sample_rate: samples per second of the window [Hz].
        segment: Welch segment length [s].
        span: first and last sample time of the window [s].
        metadata: the run's metadata (for the figure's caption).
        status: how the run ended.
    """

    path: Path
    spectra: list[Spectrum]
    markers: list[Marker]
    sample_rate: float
    segment: float
    span: tuple[float, float]
    metadata: dict[str, Any] = field(default_factory=dict)
    status: str = ""

    @property
    def resolution(self) -> float:
        """Bin spacing Δf = 1 / segment [Hz]."""
        return 1.0 / self.segment

    def as_dict(self) -> dict[str, Any]:
        """Peaks and markers as plain values for JSON (the PSD arrays are left out)."""
        return {
            "log": str(self.path),
            "window_s": list(self.span),
            "sample_rate_Hz": self.sample_rate,
            "segment_s": self.segment,
            "resolution_Hz": self.resolution,
            "amplitude": "A of the sinusoid A sin(2 pi f t) of the peak's power, SI units",
            "spectra": [
                {
                    "series": s.series, "element": s.element, "component": s.component,
                    "unit": s.unit,
                    "peaks": [
                        {"frequency_Hz": p.frequency, "amplitude": p.amplitude, "near": p.near}
                        for p in s.peaks
                    ],
                }
                for s in self.spectra
            ],
            "mesh_frequencies": [
                {"meshes": list(m.names), "frequency_Hz": m.frequency}
                for m in self.markers if m.kind == "mesh"
            ],
            "shaft_frequencies": [
                {"joint": m.names[0], "frequency_Hz": m.frequency}
                for m in self.markers if m.kind == "shaft"
            ],
        }  # fmt: skip


# --- the PSD and its peaks ----------------------------------------------------------------------


def power_spectral_density(
    values: np.ndarray, *, sample_rate: float, segment_samples: int
) -> tuple[np.ndarray, np.ndarray]:
    """(frequency [Hz], one-sided PSD [unit²/Hz]) of evenly sampled values by Welch's method.

    Hann window, segments of ``segment_samples`` overlapping by half, each segment's mean
    removed.
    """
    from scipy import signal  # scipy only here and in the peaks: ``campbell`` does without

    return signal.welch(
        np.asarray(values, dtype=float), fs=sample_rate, window="hann",
        nperseg=segment_samples, noverlap=segment_samples // 2, detrend="constant",
        scaling="density", return_onesided=True,
    )  # fmt: skip


def spectral_peaks(
    frequency: np.ndarray, density: np.ndarray, *, count: int = 10, floor: float = PEAK_FLOOR
) -> list[Peak]:
    """The ``count`` largest peaks of a PSD, strongest first (module docstring: amplitude).

    Peaks below ``floor`` times the strongest amplitude are left out; the zero-frequency bin
    is never a peak.
    """
    from scipy import signal

    if len(frequency) < 3:
        return []
    step = float(frequency[1] - frequency[0])
    found = []
    for k in signal.find_peaks(density)[0]:
        lo = hi = int(k)
        while lo > 1 and k - lo < PEAK_HALF_WIDTH and density[lo - 1] < density[lo]:
            lo -= 1
        while hi < len(density) - 1 and hi - k < PEAK_HALF_WIDTH and density[hi + 1] < density[hi]:
            hi += 1
        power = density[lo : hi + 1]
        total = float(power.sum())
        if total <= 0.0:
            continue
        centre = float(np.sum(frequency[lo : hi + 1] * power) / total)
        found.append(Peak(centre, math.sqrt(2.0 * total * step)))
    found.sort(key=lambda p: -p.amplitude)
    if not found:
        return []
    strongest = found[0].amplitude
    return [p for p in found if p.amplitude >= floor * strongest][:count]


# --- mesh frequencies and shaft orders ----------------------------------------------------------


def _velocity_rows(gearbox: Gearbox) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """Rows r (nv,) with r · v the absolute speed about the axis [rad/s] at the reference pose.

    Returns (per joint: its body's angular speed about the joint axis, per mesh: gear A's
    angular speed relative to the line of centres, about A's axis).
    """
    model = gearbox.model
    data = model.createData()
    q = gearbox.neutral()
    pin.computeJointJacobians(model, data, q)
    frame = pin.LOCAL_WORLD_ALIGNED

    def jacobian(joint_id: int) -> np.ndarray:
        return np.reshape(pin.getJointJacobian(model, data, joint_id, frame), (6, model.nv))

    def axis(joint_id: int, axis_in_joint: np.ndarray) -> np.ndarray:
        return data.oMi[joint_id].rotation @ axis_in_joint

    def centre_rows(gear: Any) -> tuple[np.ndarray, np.ndarray]:
        """(centre in world, rows of its velocity (3, nv))."""
        jid = gear.joint_id
        centre = data.oMi[jid].act(gear.centre_in_joint)
        jac = jacobian(jid)
        lever = centre - data.oMi[jid].translation
        return centre, jac[:3] - pin.skew(lever) @ jac[3:]

    shafts = {}
    # A compliant bearing's slides are no shafts: they move the body, not turn it.
    for name in (n for n in gearbox.joint_names if n not in gearbox.slide_joints):
        jid = model.getJointId(name)
        column = jacobian(jid)[3:, model.joints[jid].idx_v]
        shafts[name] = axis(jid, column / np.linalg.norm(column)) @ jacobian(jid)[3:]
    meshes = {}
    for mesh in gearbox.meshes:
        a, b = mesh.gear_a, mesh.gear_b
        k = axis(a.joint_id, a.axis_in_joint)
        centre_a, rows_a = centre_rows(a)
        centre_b, rows_b = centre_rows(b)
        d = centre_b - centre_a
        d -= (d @ k) * k
        line = k @ pin.skew(d) @ (rows_b - rows_a) / float(d @ d)  # k · (d × ḋ) / |d|²
        meshes[mesh.name] = k @ jacobian(a.joint_id)[3:] - line
    return shafts, meshes


def mesh_roll_speeds(gearbox: Gearbox, speeds: np.ndarray) -> np.ndarray:
    """Gear A's angular speed relative to the line of centres, each mesh [rad/s], (n, meshes).

    Its absolute value times z_A / 2π is the mesh frequency, times r_b,A the speed the contact
    rolls along the line of action. ``speeds``: joint speeds relative to the parent [rad/s],
    (n, joints) in ``gearbox.joint_names`` order (``Result.speed``). At the reference pose's
    rows (module docstring).
    """
    speeds = np.atleast_2d(np.asarray(speeds, dtype=float))
    v = np.zeros((len(speeds), gearbox.model.nv))
    for i, name in enumerate(gearbox.joint_names):
        v[:, gearbox.v_index(name)] = speeds[:, i]
    _, meshes = _velocity_rows(gearbox)
    return np.stack([v @ meshes[mesh.name] for mesh in gearbox.meshes], axis=1)


def gearbox_frequencies(gearbox: Gearbox, speeds: np.ndarray) -> list[Marker]:
    """Mesh frequencies and shaft orders [Hz] at joint speeds (module docstring).

    Args:
        gearbox: the model.
        speeds: joint speeds [rad/s] relative to the parent, (n, joints) in
            ``gearbox.joint_names`` order; each marker is the mean over the n samples of its
            absolute value.
    """
    speeds = np.atleast_2d(np.asarray(speeds, dtype=float))
    v = np.zeros((len(speeds), gearbox.model.nv))
    for i, name in enumerate(gearbox.joint_names):
        v[:, gearbox.v_index(name)] = speeds[:, i]
    shafts, meshes = _velocity_rows(gearbox)
    by_frequency: dict[float, list[str]] = {}
    for mesh in gearbox.meshes:
        teeth = mesh.gear_a.spec.teeth
        f = teeth * float(np.mean(np.abs(v @ meshes[mesh.name]))) / (2.0 * math.pi)
        # one frequency, up to the speed ripple of compliant meshes (a planetary stage's sun
        # and ring meshes)
        same = next((g for g in by_frequency if math.isclose(g, f, rel_tol=MESH_GROUPING)), f)
        by_frequency.setdefault(same, []).append(mesh.name)
    markers = [Marker("mesh", tuple(names), f) for f, names in by_frequency.items()]
    for name in gearbox.joint_names:
        if name in gearbox.locked_joints or name not in shafts:
            continue
        f = float(np.mean(np.abs(v @ shafts[name]))) / (2.0 * math.pi)
        markers.append(Marker("shaft", (name,), f))
    return markers


def nearest_harmonic(frequency: float, markers: Sequence[Marker], tolerance: float) -> str:
    """The marker harmonic (``HARMONICS``) closer than ``tolerance`` [Hz] to a frequency, or ``""``.

    Mesh harmonics before shaft orders; the closest one of a kind (of equals, the first marker's
    lowest harmonic).
    """
    for kind in ("mesh", "shaft"):
        best, label = tolerance, ""
        for m in markers:
            for h in HARMONICS:
                gap = abs(h * m.frequency - frequency)
                if m.kind == kind and m.frequency > 0 and gap < best:
                    best, label = gap, f"{h}× {m.label}"
        if label:
            return label
    return ""


# --- series of a log ----------------------------------------------------------------------------


def parse_series(text: str) -> tuple[schema.Series, str | None]:
    """``NAME[:ELEMENT]`` → (the declared series, the element or None for all).

    Raises:
        InputError: no series has that name, or it is a body pose (not evenly sampled).
    """
    name, _, element = text.partition(":")
    name = name.strip()
    try:
        found = schema.get(name)
    except KeyError:
        names = [s.name for s in schema.schema() if s.per == "sample" and s.name != "time"]
        raise InputError(
            f'unknown series "{name}" in --series; series are: {", ".join(names)} '
            "(docs/series.md), each with :ELEMENT for one joint, mesh or bearing"
        ) from None
    if found.per == "pose" or found.name == "time":
        raise InputError(
            f'series "{name}" has no spectrum here (link poses are logged at the pose rate '
            "only; time is the abscissa); choose a series of docs/series.md"
        )
    return found, element.strip() or None


def series_channel(s: schema.Series) -> str:
    """The log channel that holds a series (joint series ride on ``/joints``)."""
    return s.topic if s.logged else "/joints"


def series_values(
    result: Result, s: schema.Series, element: str | None
) -> list[tuple[str, str, np.ndarray]]:
    """(element, component, values (n,)) of a series, for one element or all of its family.

    Raises:
        UnknownElement: no element of the series' family has that name.
        InputError: an element for a series with one value per run.
    """
    names = result.names(s.family)
    if s.family == "run" and element is not None:
        raise InputError(f'series "{s.name}" has one value per run; drop ":{element}"')
    if s.family == "run":
        picked = [("", getattr(result, s.name))]
    elif element is None:
        picked = [(n, getattr(result, s.name)[:, i]) for i, n in enumerate(names)]
    elif element in names:
        picked = [(element, getattr(result, s.name)[:, names.index(element)])]
    else:
        raise UnknownElement(s.family, element, names)
    out = []
    for name, values in picked:
        if s.components:
            out += [(name, c, values[:, j]) for j, c in enumerate(s.components)]
        else:
            out.append((name, "", values))
    return out
