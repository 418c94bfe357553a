"""The rotor's load on the drivetrain: six components (forces and moments) at a point of a body.

A wind turbine's rotor loads its main shaft with a thrust, two shear forces, the torque and two
bending moments; the NREL Gearbox Reliability Collaborative found these non-torque loads to
change planet-bearing loads by up to 46 % (Keller et al. 2018). Aero-elastic codes give them in
two frames that share the shaft axis x (IEC 61400-13 as used by FAST/OpenFAST ElastoDyn; Jonkman
and Buhl 2005, FAST User's Guide, "shaft" and "azimuth" coordinate systems):

- ``fixed`` (OpenFAST's shaft system xs, ys, zs, channels ``…s``): x along the shaft, positive
  downwind (from the rotor into the gearbox); z perpendicular to x in the vertical plane,
  pointing up; y = z × x. It tilts with the shaft but does not turn with it.
- ``rotating`` (OpenFAST's azimuth system xa, ya, za, channels ``…a``): the fixed frame turned
  by the rotor azimuth ψ about x, the two coinciding at ψ = 0 (blade 1 up). A vector given in
  it is, in the fixed frame (a rotation about x by ψ)::

      v_ys = cos ψ v_ya − sin ψ v_za,      v_zs = sin ψ v_ya + cos ψ v_za,      v_xs = v_xa

Thrust and torque lie on the axis, the same in both frames. ``HubLoad.in_fixed_frame`` is the one
implementation of that turn; an OpenFAST output's rotating channels are turned with the azimuth
the file logs (``hub_load_from_openfast``), so the load is the one the aero-elastic run saw.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from enum import StrEnum
from pathlib import Path
from typing import Any

import numpy as np

from pinwind.errors import InputError, NonFiniteInput
from pinwind.loads.openfast import read_output, si_factor
from pinwind.loads.signals import Constant, Signal, Table

#: The six components, in order: forces [N] along x, y, z, then moments [N·m] about them.
COMPONENTS = ("force_x", "force_y", "force_z", "moment_x", "moment_y", "moment_z")


class HubFrame(StrEnum):
    """The frame a hub load's components are given in (the module's docstring)."""

    FIXED = "fixed"
    ROTATING = "rotating"

    @classmethod
    def named(cls, name: str, *, where: str) -> HubFrame:
        """The frame called ``name``.

        Raises:
            InputError: a name that is not a frame, naming ``where`` and the known frames.
        """
        try:
            return cls(name)
        except ValueError:
            known = ", ".join(f'"{frame.value}"' for frame in cls)
            raise InputError(
                f'{where}: frame "{name}" is not one of {known} (fixed: the shaft frame that does '
                "not turn; rotating: turned by the rotor azimuth)"
            ) from None


ComponentSignal = float | Signal | Callable[[float], float]


@dataclass(frozen=True)
class HubLoad:
    """Six load components on ``body`` at ``point``, in ``frame``.

    Attributes:
        body: the body (URDF link) the load acts on, e.g. the main shaft.
        components: (F_x, F_y, F_z [N], M_x, M_y, M_z [N·m]) along the frame's axes, each a
            number, a ``Signal`` or a function of time t [s]: F_x is the thrust, M_x the torque.
        frame: the frame of the components.
        point: where the force acts, in the body's frame [m] (the rotor centre on the shaft).
        up: the direction of the hub's z in the model's world frame, or None: against the
            model's gravity. With x on the shaft axis (the body's joint axis as the model gives
            it), y = z × x; ``up`` need not be normal to the axis (its normal part is used).
    """

    body: str
    components: tuple[ComponentSignal, ...]
    frame: HubFrame = HubFrame.FIXED
    point: Sequence[float] = (0.0, 0.0, 0.0)
    up: Sequence[float] | None = None

    def __post_init__(self) -> None:
        where = f'hub load on "{self.body}"'
        if len(self.components) != 6:
            raise InputError(
                f"{where}: {len(self.components)} components given; give six: "
                f"{', '.join(COMPONENTS)}"
            )
        for name, vector in (("point", self.point), ("up", self.up)):
            if vector is not None and (
                len(vector) != 3 or not all(math.isfinite(float(x)) for x in vector)
            ):
                raise NonFiniteInput(f"{where}: {name} {vector} must be three finite numbers")
            if vector is not None:  # any sequence given: kept as a tuple of floats
                object.__setattr__(self, name, tuple(float(x) for x in vector))
        if not isinstance(self.frame, HubFrame):
            object.__setattr__(self, "frame", HubFrame.named(str(self.frame), where=where))

    def values(self, t: np.ndarray, *, check: bool = True) -> np.ndarray:
        """The components at times t [s] in the load's own frame, shape (len(t), 6).

        Raises:
            NonFiniteInput: with ``check``, a component that is not finite, naming it and the
                time (a run checks its inputs itself, step by step, to keep what came before).
        """
        t = np.atleast_1d(np.asarray(t, dtype=float))
        out = np.empty((len(t), 6))
        for i, signal in enumerate(self.components):
            if isinstance(signal, Signal):
                out[:, i] = signal.values(t)
            elif callable(signal):
                out[:, i] = [float(signal(float(ti))) for ti in t]
            else:
                out[:, i] = float(signal)
        bad = np.argwhere(~np.isfinite(out)) if check else np.zeros((0, 2))
        if bad.size:
            row, column = (int(x) for x in bad[0])
            raise NonFiniteInput(
                f'hub load on "{self.body}": {COMPONENTS[column]} is {out[row, column]} at '
                f"t = {t[row]:g} s; give finite values"
            )
        return out

    def describe(self) -> dict[str, Any]:
        """The load as plain values for a log: body, frame, point, up and each component."""
        return {
            "body": self.body,
            "frame": self.frame.value,
            "point": list(self.point),
            "up": None if self.up is None else list(self.up),
            "components": {
                name: _describe(signal)
                for name, signal in zip(COMPONENTS, self.components, strict=True)
            },
        }

    def in_fixed_frame(self, t: np.ndarray, azimuth: np.ndarray | float) -> np.ndarray:
        """The components at times t [s] in the fixed frame, shape (len(t), 6).

        Args:
            t: times [s].
            azimuth: the rotor azimuth ψ [rad] at those times (ignored for a fixed-frame load).
        """
        values = self.values(t)
        if self.frame is HubFrame.ROTATING:
            values = rotating_to_fixed(values, azimuth)
        return values


def rotating_to_fixed(components: np.ndarray, azimuth: np.ndarray | float) -> np.ndarray:
    """Six components (rows of F_x, F_y, F_z, M_x, M_y, M_z) from the rotating frame to the fixed.

    The rotation about the shaft axis x by the azimuth ψ [rad] (the module's docstring).
    """
    components = np.atleast_2d(np.asarray(components, dtype=float))
    psi = np.broadcast_to(np.asarray(azimuth, dtype=float), components.shape[:1])
    c, s = np.cos(psi), np.sin(psi)
    out = components.copy()
    for y, z in ((1, 2), (4, 5)):
        out[:, y] = c * components[:, y] - s * components[:, z]
        out[:, z] = s * components[:, y] + c * components[:, z]
    return out


#: ElastoDyn's output channels of the low-speed shaft loads (Jonkman and Buhl 2005; OpenFAST
#: OutListParameters), by component, each with the names the same quantity may be written
#: under: the first one a file has is read. Thrust and torque are on the axis, one name for both
#: frames; the shear forces are constant along the shaft and the bending moments are at the
#: shaft's tip (the rotor centre), which is where ``point`` should be.
OPENFAST_CHANNELS: dict[HubFrame, tuple[tuple[str, ...], ...]] = {
    HubFrame.FIXED: (
        ("RotThrust", "LSShftFxs", "LSShftFxa", "LSSGagFxs", "LSSGagFxa"),
        ("LSShftFys",),
        ("LSShftFzs",),
        ("RotTorq", "LSShftMxs", "LSShftMxa", "LSShftTq", "LSSGagMxs", "LSSGagMxa"),
        ("LSSTipMys",),
        ("LSSTipMzs",),
    ),
    HubFrame.ROTATING: (
        ("RotThrust", "LSShftFxa", "LSShftFxs", "LSSGagFxa", "LSSGagFxs"),
        ("LSShftFya",),
        ("LSShftFza",),
        ("RotTorq", "LSShftMxa", "LSShftMxs", "LSShftTq", "LSSGagMxa", "LSSGagMxs"),
        ("LSSTipMya",),
        ("LSSTipMza",),
    ),
}
#: The rotor azimuth's channel names (ElastoDyn: "Azimuth", or the shaft's tip position).
AZIMUTH_CHANNELS = ("Azimuth", "LSSTipPxa", "LSSGagPxa")


def hub_load_from_openfast(
    path: str | Path,
    body: str,
    *,
    frame: HubFrame | str = HubFrame.FIXED,
    point: Sequence[float] = (0.0, 0.0, 0.0),
    up: Sequence[float] | None = None,
) -> HubLoad:
    """The six shaft loads of an OpenFAST output file as a fixed-frame ``HubLoad`` on ``body``.

    Each channel is read in the unit its header gives (``(kN)``, ``(kN-m)``, ``(deg)``) and
    turned into SI. ``frame="rotating"`` reads the ``…a`` channels and turns them into the fixed
    frame with the file's own azimuth, sample by sample, so the load does not depend on how the
    model's shaft angle is counted.

    Raises:
        InputError: a missing channel (the message lists the file's channels and the names
            tried), an unknown frame, or a unit pinwind cannot convert.
    """
    path = Path(path)
    frame = HubFrame.named(str(frame), where=str(path))
    data, names, units = read_output(path)

    def column(name: str) -> np.ndarray:
        """The channel in SI, from the unit its header gives."""
        i = names.index(name)
        return data[:, i] * si_factor(units[i], where=f"{path} channel {name}")

    chosen = [_first_present(names, options, path) for options in OPENFAST_CHANNELS[frame]]
    components = np.column_stack([column(name) for name in chosen])
    if frame is HubFrame.ROTATING:
        components = rotating_to_fixed(
            components, column(_first_present(names, AZIMUTH_CHANNELS, path))
        )
    time = column(names[0])
    tables = tuple(
        Table(time, components[:, i], source=f"{path} {COMPONENTS[i]} ({frame.value} channels)")
        for i in range(6)
    )
    return HubLoad(body, tables, HubFrame.FIXED, tuple(point), None if up is None else tuple(up))


def constant_hub_load(
    body: str,
    components: Sequence[float],
    *,
    frame: HubFrame | str = HubFrame.FIXED,
    point: Sequence[float] = (0.0, 0.0, 0.0),
    up: Sequence[float] | None = None,
) -> HubLoad:
    """A steady hub load: six numbers (N and N·m) along the frame's axes."""
    return HubLoad(
        body,
        tuple(Constant(float(value)) for value in components),
        HubFrame.named(str(frame), where=f'hub load on "{body}"'),
        tuple(point),
        None if up is None else tuple(up),
    )


def _first_present(names: list[str], options: tuple[str, ...], path: Path) -> str:
    """The first of ``options`` that the file has."""
    for option in options:
        if option in names[1:]:
            return option
    raise InputError(
        f"{path}: none of the channels {', '.join(options)} is in the file, which has: "
        f"{', '.join(names[1:])}; add one to ElastoDyn's OutList"
    )


def _describe(signal: ComponentSignal) -> Any:
    """A component for a log: its number, its signal's spec, or a function's name."""
    if isinstance(signal, Signal):
        return signal.spec()
    if callable(signal):
        return getattr(signal, "__name__", repr(signal))
    return float(signal)
