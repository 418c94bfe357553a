"""Natural modes against the peaks of a free vibration's spectrum.

The modes (``modes/linearisation.py``: M, K, C at the reference pose, the rigid rows) are the
frequencies a train rings at when let go. This check lets it go and listens:

1. the modes chosen (the non-rigid ones, within ``band``, the lowest ``count``) give a start
   q₀ = Σ_i w_i φ_i, each mode with the same energy (w_i = A / ω_i, φ_i mass-normalised), A such
   that the largest coordinate is ``amplitude`` [m or rad]; the loads F = K q₀ hold it there
   at t = 0 (the run's static start) and are gone after the first step, so the train rings in
   those modes only (F has no part along a rigid mode, so the train does not turn as a whole);
2. the run's speed of the joint that carries most of a mode's kinetic energy gives its spectrum
   (``analysis/spectrum.py``: one Hann-windowed segment over the run, the peak frequency the
   power-weighted mean of its bins);
3. each mode's damped frequency f √(1 − ζ²) must have a peak within ``rtol``.

The step's frequency error, −(ω dt)²/12 for ρ∞ = 1, is kept below a tenth of ``rtol`` by the
default dt, and the default duration holds 2 / rtol periods of the lowest mode (a bin of rtol/2
of it). Modes closer than a bin merge into one peak between them; a mode on a mesh whose
stiffness varies along its path, or with backlash, rings with the nonlinearity's harmonics
too: check a model with ``stiffness_variation="constant"`` meshes without backlash, or give a
tolerance that allows for it.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Iterable, Mapping
from typing import Any

import numpy as np

from pinwind.analysis.spectrum import power_spectral_density, spectral_peaks
from pinwind.dynamics.normal_modes import Mode
from pinwind.errors import InputError, PinwindWarning
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import Gearbox
from pinwind.modes.linearisation import linearise
from pinwind.testing.figure import CheckFigure

#: Default largest coordinate of the start [m or rad]: a µm-scale deflection.
AMPLITUDE = 1e-6


def chosen_modes(
    gearbox: Gearbox,
    *,
    meshes: Mapping[str, str | MeshCompliance] | None = None,
    held: Iterable[str] = (),
    band: tuple[float, float] | None = None,
    count: int | None = None,
) -> list[Mode]:
    """The non-rigid modes of ``linearise(gearbox)`` within ``band`` [Hz], the lowest ``count``."""
    modes = [m for m in linearise(gearbox, meshes=meshes, held=held).modes() if not m.rigid]
    if band is not None:
        modes = [m for m in modes if band[0] <= m.frequency <= band[1]]
    return modes[:count] if count is not None else modes


def damped_frequency(mode: Mode) -> float:
    """The frequency f √(1 − ζ²) a mode rings at [Hz] (0 when over-damped)."""
    zeta = min(abs(mode.damping_ratio), 1.0)
    return mode.frequency * math.sqrt(1.0 - zeta**2)


def _released(value: float) -> Callable[[float], float]:
    """A load that holds the start at t = 0 and is gone after it [N·m or N]."""
    return lambda t: value if t <= 0.0 else 0.0


def modes_in_spectrum(
    gearbox: Gearbox,
    *,
    meshes: Mapping[str, str | MeshCompliance] | None = None,
    held: Iterable[str] = (),
    band: tuple[float, float] | None = None,
    count: int | None = None,
    duration: float | None = None,
    dt: float | None = None,
    amplitude: float = AMPLITUDE,
    rtol: float = 0.01,
    seed: int = 0,
) -> CheckFigure:
    """Each chosen mode rings at its frequency in a free vibration (module docstring).

    Args:
        gearbox: the model.
        meshes: mesh name (or ``"all"``) → ``"rigid"``, ``"compliant"`` or a
            ``MeshCompliance``, for the modes and the run alike.
        held: joints held at rest in both (speed drivers at 0).
        band: (lowest, highest) frequency of the modes to check [Hz]; default all.
        count: check the lowest ``count`` of them; default all.
        duration: the run [s]; default 2 / (rtol f_lowest).
        dt: the step [s]; default √(1.2 rtol) / (2π f_highest), a frequency error of rtol/10.
        amplitude: the start's largest coordinate [m or rad].
        rtol: the largest relative distance from a mode to its peak [-].
        seed: seeds the modes' phases (the sign of each w_i).

    Returns:
        The figure: the largest |f_peak − f_mode| / f_mode over the modes.

    Raises:
        CheckFailed: beyond ``rtol``, naming the mode, the joint listened to and the peaks.
        InputError: no mode to check.
    """
    from pinwind.runs.run import simulate  # the run with its observers, as pinwind.simulate

    held = list(held)
    modes = chosen_modes(gearbox, meshes=meshes, held=held, band=band, count=count)
    if not modes:
        raise InputError(
            "no natural mode to check: the linearised train has none that is not rigid"
            + (f" in the band {band[0]:g}-{band[1]:g} Hz" if band else "")
        )
    lin = linearise(gearbox, meshes=meshes, held=held)
    lowest = min(damped_frequency(m) for m in modes)
    highest = max(m.frequency for m in modes)
    if dt is None:
        dt = math.sqrt(1.2 * rtol) / (2.0 * math.pi * highest)
    if duration is None:
        duration = 2.0 / (rtol * lowest)
    duration = math.ceil(duration / dt - 1e-9) * dt  # whole steps
    rng = np.random.default_rng(seed)
    start = sum(rng.choice([-1.0, 1.0]) * m.shape / (2.0 * math.pi * m.frequency) for m in modes)
    start = np.asarray(start, dtype=float)
    start *= amplitude / float(np.abs(start).max())
    load = np.asarray(lin.stiffness) @ start
    still = {*gearbox.locked_joints, *held}
    torques: dict[str, Any] = {
        name: _released(float(load[gearbox.v_index(name)]))
        for name in gearbox.joint_names
        if name not in still and load[gearbox.v_index(name)] != 0.0
    }
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)  # the step's advice on a short run
        result = simulate(
            gearbox,
            duration=duration,
            dt=dt,
            torques=torques,
            speeds={name: 0.0 for name in held},
            meshes=meshes,
            keep="all",
        )
    late = result.time > dt  # after the release
    worst, detail = 0.0, ""
    for n, mode in enumerate(modes):
        joint = max(mode.kinetic_share, key=lambda j: mode.kinetic_share[j])
        speed = result.joint(joint).speed[late]
        frequency, density = power_spectral_density(
            speed, sample_rate=1.0 / dt, segment_samples=len(speed)
        )
        peaks = spectral_peaks(frequency, density, count=20, floor=1e-6)
        target = damped_frequency(mode)
        if peaks:
            nearest = min(peaks, key=lambda p: abs(p.frequency - target))
            error = abs(nearest.frequency - target) / target
            found = f"{nearest.frequency:.6g} Hz"
        else:
            error, found = float("inf"), "no peak"
        if not error <= worst:
            worst = error
            detail = (
                f"mode {n + 1} at {target:.6g} Hz (ζ {mode.damping_ratio:.3g}) in the speed of "
                f'"{joint}": nearest peak {found}; peaks at '
                + ", ".join(f"{p.frequency:.5g}" for p in sorted(peaks, key=lambda p: p.frequency))
                + " Hz"
            )
    return CheckFigure(
        "modes_in_spectrum",
        "each mode's damped frequency against the nearest peak of a free vibration's spectrum",
        worst,
        rtol,
        f"{detail}; {len(modes)} modes, a run of {duration:.4g} s at dt {dt:.3g} s",
    ).enforced()
