"""The Campbell diagram: natural frequencies against the input speed, with the excitation orders.

The natural frequencies come from the linearisation at the reference pose
(``dynamics/linearisation.py``), taken at the top of the speed range: the velocity terms grow with
the speed, so where they vanish there (torsional coordinates, where they are zero at every speed)
the frequencies do not change over the range, and where they act the linearisation refuses the
range (``SpeedOutOfRange``). The excitations do change: every mesh frequency (teeth of gear A
times its speed relative to the line of centres, ``analysis/spectrum.gearbox_frequencies``) and
its harmonics, and every shaft's order 1, each proportional to the input speed Ω through the
train's ratios
(``dynamics/ratios.train_speeds``). A line h·f₁·Ω meets a mode f_n at Ω* = f_n / (h f₁): the
crossings inside the operating range are the resonances an IEC 61400-4 check asks about.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np

from pinwind.analysis.spectrum import gearbox_frequencies
from pinwind.dynamics.linearisation import linearise
from pinwind.dynamics.normal_modes import Mode
from pinwind.dynamics.ratios import train_speeds
from pinwind.errors import InputError, UnknownJoint
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import Gearbox


@dataclass(frozen=True)
class Excitation:
    """An excitation order: frequency = ``per_speed`` · Ω [Hz per rad/s of the input joint].

    Attributes:
        label: ``mesh sun_planet1, sun_planet2`` or ``shaft carrier``, with ``×h`` for harmonic h.
        harmonic: h.
        per_speed: f / Ω [Hz·s/rad].
    """

    label: str
    harmonic: int
    per_speed: float


@dataclass(frozen=True)
class Crossing:
    """An excitation line meeting a natural frequency inside the speed range.

    Attributes:
        excitation: the line.
        mode: index of the mode (in ``CampbellDiagram.modes``).
        frequency: the mode's frequency [Hz].
        speed: the input speed where they meet [rad/s].
    """

    excitation: Excitation
    mode: int
    frequency: float
    speed: float


@dataclass(frozen=True)
class CampbellDiagram:
    """Natural frequencies and excitation lines over an input-speed range (module docstring).

    Attributes:
        joint: the input joint whose speed Ω the diagram runs over.
        speeds: (lowest, highest) input speed [rad/s].
        modes: the elastic modes (rigid ones left out), lowest first.
        excitations: the lines.
        crossings: every line meeting a mode inside the range, by speed.
    """

    joint: str
    speeds: tuple[float, float]
    modes: list[Mode]
    excitations: list[Excitation]
    crossings: list[Crossing]


def excitation_orders(gearbox: Gearbox, joint: str, harmonics: int = 3) -> list[Excitation]:
    """Mesh frequencies (harmonics 1…h) and shaft orders per rad/s of ``joint``'s speed."""
    v = train_speeds(gearbox, {joint: 1.0}, through_springs=True)
    speeds = np.array([[v[gearbox.v_index(n)] for n in gearbox.joint_names]])
    out = []
    for marker in gearbox_frequencies(gearbox, speeds):
        if marker.frequency <= 0.0:
            continue
        orders = range(1, harmonics + 1) if marker.kind == "mesh" else (1,)
        for h in orders:
            label = marker.label + (f" ×{h}" if h > 1 else "")
            out.append(Excitation(label, h, h * marker.frequency))
    return out


def campbell(
    gearbox: Gearbox,
    joint: str,
    speed_range: tuple[float, float],
    *,
    meshes: Mapping[str, str | MeshCompliance] | None = None,
    held: Iterable[str] = (),
    harmonics: int = 3,
) -> CampbellDiagram:
    """The Campbell diagram of ``gearbox`` for input ``joint`` over ``speed_range`` [rad/s].

    Raises:
        UnknownJoint: ``joint`` is not a joint of the model.
        InputError: a speed range that is not 0 ≤ low < high, or harmonics < 1.
        SpeedOutOfRange: a joint beyond ``linearisation.MAX_SPEED`` at the top of the range, or
            velocity terms that act there (module docstring).
    """
    if joint not in gearbox.joint_names:
        raise UnknownJoint(joint, "the input joint", gearbox.joint_names)
    low, high = (float(x) for x in speed_range)
    if not (math.isfinite(low) and math.isfinite(high) and 0.0 <= low < high):
        raise InputError(
            f"speed range {low:g} to {high:g} rad/s: give 0 ≤ lowest < highest, e.g. 0:20 rpm"
        )
    if harmonics < 1:
        raise InputError(f"harmonics = {harmonics}: give at least 1")
    top = linearise(gearbox, meshes=meshes, held=held, speeds={joint: high})
    modes = [m for m in top.modes() if not m.rigid]
    lines = excitation_orders(gearbox, joint, harmonics)
    crossings = [
        Crossing(line, i, mode.frequency, mode.frequency / line.per_speed)
        for line in lines
        for i, mode in enumerate(modes)
        if low <= mode.frequency / line.per_speed <= high
    ]
    crossings.sort(key=lambda c: c.speed)
    return CampbellDiagram(joint, (low, high), modes, lines, crossings)


def write_figure(
    diagram: CampbellDiagram, out: str, *, speed_unit: float = 1.0, unit: str = "rad/s"
) -> None:
    """A PNG of the diagram: modes as horizontal lines, excitations as rays, crossings marked.

    Args:
        speed_unit: input speed per rad/s in the axis's unit (e.g. 60/2π for rpm).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    low, high = diagram.speeds
    top = 1.2 * max([m.frequency for m in diagram.modes] or [1.0])
    fig, ax = plt.subplots(figsize=(9, 6))
    for mode in diagram.modes:
        ax.axhline(mode.frequency, color="0.4", lw=1.0)
    x = np.array([low, high])
    for line in diagram.excitations:
        ax.plot(x * speed_unit, line.per_speed * x, lw=1.0, label=line.label)
    for c in diagram.crossings:
        ax.plot(c.speed * speed_unit, c.frequency, "o", color="crimson", ms=5)
    ax.set_xlim(low * speed_unit, high * speed_unit)
    ax.set_ylim(0.0, top)
    ax.set_xlabel(f"{diagram.joint} speed [{unit}]")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title("Campbell diagram: natural frequencies (grey), excitations, crossings (red)")
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
