"""The Campbell diagram: natural frequencies against the input speed, with the excitation orders.

The natural frequencies come from the linearisation at the reference pose
(``modes/linearisation.py``), taken once at the top of the speed range and scaled down to each
speed (G grows with the speed, K_Ω with its square, nothing else changes:
``Linearisation.at_speed_scale``). Where the velocity terms vanish (torsional coordinates, where
they are zero at every speed) the frequencies do not change over the range and are solved once;
where they act (a body spinning while it tilts in a compliant bearing: forward and backward whirl
split apart with speed) they are solved at ``points`` speeds across the range. The excitations
change too: every mesh frequency (teeth of gear A times its speed relative to the line of
centres, ``analysis/spectrum.gearbox_frequencies``) and its harmonics, and every shaft's order 1,
each proportional to the input speed Ω through the train's ratios
(``dynamics/ratios.train_speeds``). A line h·f₁·Ω meets a mode f_n(Ω) where f_n(Ω) = h f₁ Ω: at
Ω* = f_n / (h f₁) for a constant mode, and for one that moves with speed at the root of
f_n(Ω) − h f₁ Ω between two sampled speeds where it changes sign (Brent's method, the n-th lowest
frequency being continuous in Ω). The crossings inside the operating range are the resonances an
IEC 61400-4 check asks about.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from pinwind.analysis.spectrum import gearbox_frequencies
from pinwind.dynamics.drivetrain import Drivetrain
from pinwind.dynamics.normal_modes import REPEATED_TOLERANCE, Mode
from pinwind.dynamics.ratios import train_speeds
from pinwind.errors import InputError, UnknownJoint
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import Gearbox
from pinwind.modes.linearisation import linearise


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
        mode: index of the mode (in ``CampbellDiagram.modes``: by frequency, lowest first).
        frequency: the mode's frequency there [Hz].
        speed: the input speed where they meet [rad/s].
        whirl: the mode's whirl there (``forward``, ``backward`` or ``""``).
        multiplicity: how many modes of one repeated frequency meet the line there (the N − 1
            planet modes of N planets: one crossing, as ``pinwind modes`` lists them as one row).
    """

    excitation: Excitation
    mode: int
    frequency: float
    speed: float
    whirl: str = ""
    multiplicity: int = 1


@dataclass(frozen=True)
class CampbellDiagram:
    """Natural frequencies and excitation lines over an input-speed range (module docstring).

    Attributes:
        joint: the input joint whose speed Ω the diagram runs over.
        speeds: (lowest, highest) input speed [rad/s].
        modes: the elastic modes (rigid ones left out) at the top of the range, lowest first.
        excitations: the lines.
        crossings: every line meeting a mode inside the range, by speed.
        speed_grid: the input speeds the modes were solved at [rad/s] (the top alone when they
            do not change with speed).
        frequencies: (len(speed_grid), len(modes)) the elastic modes' frequencies at each [Hz].
    """

    joint: str
    speeds: tuple[float, float]
    modes: list[Mode]
    excitations: list[Excitation]
    crossings: list[Crossing]
    speed_grid: np.ndarray
    frequencies: np.ndarray


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
    machine: Gearbox | Drivetrain,
    joint: str,
    speed_range: tuple[float, float],
    *,
    meshes: Mapping[str, str | MeshCompliance] | None = None,
    held: Iterable[str] = (),
    harmonics: int = 3,
    points: int = 101,
) -> CampbellDiagram:
    """The Campbell diagram of ``machine`` for input ``joint`` over ``speed_range`` [rad/s].

    Args:
        machine: a gearbox alone, or the drivetrain a run steps (``dynamics/drivetrain.py``:
            its rotor's inertia, its laws' slopes, taken at the top of the range, its drivers
            held, its loaded flanks); ``linearisation.linearise``'s first argument.
        meshes, held: as ``linearise`` takes them.
        points: speeds sampled across the range when the modes change with speed (≥ 2).

    Raises:
        UnknownJoint: ``joint`` is not a joint of the model.
        InputError: a speed range that is not 0 ≤ low < high, harmonics < 1 or points < 2.
        SpeedOutOfRange: a joint beyond ``linearisation.MAX_SPEED`` at the top of the range, or
            equations whose coefficients change as the train turns (``linearisation.py``).
    """
    gearbox = machine.gearbox if isinstance(machine, Drivetrain) else machine
    if joint not in gearbox.joint_names:
        raise UnknownJoint(joint, "the input joint", gearbox.joint_names)
    low, high = (float(x) for x in speed_range)
    if not (math.isfinite(low) and math.isfinite(high) and 0.0 <= low < high):
        raise InputError(
            f"speed range {low:g} to {high:g} rad/s: give 0 ≤ lowest < highest, e.g. 0:20 rpm"
        )
    if harmonics < 1:
        raise InputError(f"harmonics = {harmonics}: give at least 1")
    if points < 2:
        raise InputError(f"points = {points}: give at least 2 speeds across the range")
    top = linearise(machine, meshes=meshes, held=held, speeds={joint: high})
    found = top.modes()
    modes = [m for m in found if not m.rigid]
    lines = excitation_orders(gearbox, joint, harmonics)
    if not top.speed_terms_act():
        crossings = [
            Crossing(line, i, mode.frequency, mode.frequency / line.per_speed, mode.whirl)
            for line in lines
            for i, mode in enumerate(modes)
            if low <= mode.frequency / line.per_speed <= high
        ]
        crossings = _merge_repeated(crossings)
        grid = np.array([high])
        frequencies = np.array([[m.frequency for m in modes]])
        return CampbellDiagram(joint, (low, high), modes, lines, crossings, grid, frequencies)

    def modes_at(speed: float) -> list[Mode]:
        return top.at_speed_scale(speed / high).modes()

    rigid = len(found) - len(modes)
    grid = np.linspace(low, high, points)
    table = np.array([[m.frequency for m in modes_at(x)] for x in grid])
    crossings = []
    for line in lines:
        for n in range(rigid, table.shape[1]):
            gap = table[:, n] - line.per_speed * grid
            for a in range(points - 1):
                if gap[a] == 0.0 and table[a, n] > 0.0:
                    speed = float(grid[a])
                elif gap[a] * gap[a + 1] < 0.0:
                    speed = _root(modes_at, n, line.per_speed, float(grid[a]), float(grid[a + 1]))
                else:
                    continue
                mode = modes_at(speed)[n]
                crossings.append(Crossing(line, n - rigid, mode.frequency, speed, mode.whirl))
    crossings = _merge_repeated(crossings)
    return CampbellDiagram(joint, (low, high), modes, lines, crossings, grid, table[:, rigid:])


def _merge_repeated(crossings: list[Crossing]) -> list[Crossing]:
    """The crossings by speed, those of one line with modes of a repeated frequency as one.

    Modes whose frequencies agree to ``REPEATED_TOLERANCE`` (``normal_modes.repeated_groups``)
    meet a line at the same speed; the first of them stays, with their count as multiplicity.
    """
    out: list[Crossing] = []
    for c in sorted(crossings, key=lambda c: (c.speed, c.frequency)):
        same = [
            i
            for i, kept in enumerate(out)
            if kept.excitation == c.excitation
            and math.isclose(kept.frequency, c.frequency, rel_tol=REPEATED_TOLERANCE)
            and math.isclose(kept.speed, c.speed, rel_tol=REPEATED_TOLERANCE)
        ]
        if same:
            kept = out[same[0]]
            whirl = kept.whirl if kept.whirl == c.whirl else ""
            out[same[0]] = Crossing(
                kept.excitation, kept.mode, kept.frequency, kept.speed, whirl,
                kept.multiplicity + c.multiplicity,
            )  # fmt: skip
        else:
            out.append(c)
    return out


def _root(
    modes_at: Callable[[float], list[Mode]], n: int, per_speed: float, a: float, b: float
) -> float:
    """The speed in [a, b] where mode n meets the line ``per_speed`` · Ω (Brent's method).

    Mode n is the n-th lowest at each speed (``modes_at``); to 1e-12 relative.
    """
    import scipy.optimize

    def gap(speed: float) -> float:
        return modes_at(speed)[n].frequency - per_speed * speed

    return float(scipy.optimize.brentq(gap, a, b, xtol=1e-12 * b, rtol=1e-12))


#: Colours of the excitation lines, one per source (a mesh or a shaft): matplotlib's tab20
#: without its greys (the modes) and reds (the crossings), dark and light shades apart.
EXCITATION_COLOURS = (
    "#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#bcbd22", "#17becf",
    "#aec7e8", "#ffbb78", "#98df8a", "#c5b0d5", "#c49c94", "#f7b6d2", "#dbdb8d", "#9edae5",
)  # fmt: skip
#: Dash patterns of harmonics 1, 2, 3, ... of one source.
HARMONIC_DASHES = ("-", "--", ":", "-.", (0, (5, 1, 1, 1, 1, 1)), (0, (8, 2)))
#: Line widths of the rounds through the colours, when there are more sources than colours.
ROUND_WIDTHS = (1.3, 2.6, 0.7)


def excitation_styles(excitations: list[Excitation]) -> list[tuple[str, Any, float]]:
    """(colour, dash pattern, line width) of each excitation line, no two lines alike.

    One colour per source (the label without its ``×h``), a dash pattern per harmonic; a
    source past the last colour takes the colours again at another line width.
    """
    sources: dict[str, int] = {}
    out = []
    for line in excitations:
        source = sources.setdefault(line.label.split(" ×")[0], len(sources))
        colours = len(EXCITATION_COLOURS)
        out.append(
            (
                EXCITATION_COLOURS[source % colours],
                HARMONIC_DASHES[(line.harmonic - 1) % len(HARMONIC_DASHES)],
                ROUND_WIDTHS[(source // colours) % len(ROUND_WIDTHS)],
            )
        )
    return out


def write_figure(diagram: CampbellDiagram, out: str) -> None:
    """A PNG of the diagram against the input speed in rpm: modes, excitation rays, crossings.

    Modes are grey, each excitation has its own colour and dash (``excitation_styles``) and
    the crossings are red dots; the legend stands beside the axes, so that it hides no crossing.
    """
    import textwrap

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from pinwind.units import rad_s_to_rpm

    low, high = diagram.speeds
    top = 1.2 * max([m.frequency for m in diagram.modes] or [1.0])
    fig, ax = plt.subplots(figsize=(11, 6), layout="constrained")
    if len(diagram.speed_grid) == 1:
        for mode in diagram.modes:
            ax.axhline(mode.frequency, color="0.45", lw=1.0)
    else:
        ax.plot(rad_s_to_rpm(diagram.speed_grid), diagram.frequencies, color="0.45", lw=1.0)
    ax.plot([], [], color="0.45", lw=1.0, label="natural frequencies")
    x = np.array([low, high])
    for line, (colour, dash, width) in zip(
        diagram.excitations, excitation_styles(diagram.excitations), strict=True
    ):
        label = "\n".join(textwrap.wrap(line.label, 48, subsequent_indent="  "))
        ax.plot(rad_s_to_rpm(x), line.per_speed * x, color=colour, ls=dash, lw=width, label=label)
    crossings = diagram.crossings
    ax.plot(
        [rad_s_to_rpm(c.speed) for c in crossings],
        [c.frequency for c in crossings],
        "o",
        color="crimson",
        ms=5,
        label=f"crossings ({len(crossings)})",
    )
    ax.set_xlim(rad_s_to_rpm(low), rad_s_to_rpm(high))
    ax.set_ylim(0.0, top)
    ax.set_xlabel(f"{diagram.joint} speed [rpm]")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title("Campbell diagram: natural frequencies, excitations, crossings", loc="left")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    fig.savefig(out, dpi=110)
    plt.close(fig)
