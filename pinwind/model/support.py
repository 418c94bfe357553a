"""The support structure: the gearbox housing on compliant mounts, the bedplate on tower modes.

By default the housing (the link the ring and the bearings are fixed to, usually the root link)
is the ground. A ``<support housing="...">`` in the model file (docs/model_format.md "Support
structure") makes it a body: ``model/gearbox.py`` puts slides between the ground and the housing,

    ground ─ tower slides (one per tower mode) ─ bedplate ─ mount_x ─ mount_y ─ mount_z
           ─ mount_roll ─ housing

prismatic joints along the tower modes' directions and the housing frame's x, y, z axes, and a
hinge about the shaft axis through the housing frame's origin (the torque arms' roll), each
only where the file gives it. ``dynamics/support_springs.py`` holds each slide with a linear
spring (``cpp/bearing_spring.hpp``'s linear term); its damper is the slide's viscous damping.

A tower mode is a modal mass-spring-damper at the tower top (e.g. OpenFAST ElastoDyn's first
fore-aft and side-side modes): from its frequency f of the tower alone, its modal mass m and
damping ratio ζ,

    k = m (2π f)²,    c = 2 ζ √(k m)

and the bedplate's translation in that direction is its modal coordinate (tower-top mode shape
normalised to 1). The modes' slides are in series, largest modal mass first, each slide's link
carrying the difference to the next mass: the mass matrix of the bedplate is then
diag(m_d + M) exactly, m_d each direction's own modal mass and M what it carries (a slide moves
every link after it). One mode per direction; all axes in the housing's frame at rest.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

#: The tower-mode directions: fore-aft along the shaft axis, vertical against gravity (made
#: normal to the shaft), side-side = vertical × fore-aft.
DIRECTIONS = ("fore_aft", "side_side", "vertical")
#: The mount's axes: the housing frame's x, y, z and the roll about the shaft axis.
MOUNT_AXES = ("x", "y", "z", "roll")


@dataclass(frozen=True)
class TowerMode:
    """One tower mode at the tower top, as a modal mass-spring-damper.

    Attributes:
        direction: one of ``DIRECTIONS``.
        frequency: f of the tower alone [Hz].
        mass: modal mass m [kg].
        damping_ratio: ζ of the tower alone [-].
    """

    direction: str
    frequency: float
    mass: float
    damping_ratio: float = 0.0

    @property
    def stiffness(self) -> float:
        """Stiffness k = m (2π f)² [N/m]."""
        return self.mass * (2.0 * math.pi * self.frequency) ** 2

    @property
    def damping(self) -> float:
        """Damping c = 2 ζ √(k m) [N·s/m]."""
        return 2.0 * self.damping_ratio * math.sqrt(self.stiffness * self.mass)


@dataclass(frozen=True)
class SupportSlide:
    """One slide of the support chain (a prismatic joint or the roll hinge).

    Attributes:
        name: its joint in the Pinocchio model (``support_tower_vertical``, ``support_mount_roll``).
        kind: ``"prismatic"`` or ``"revolute"``.
        axis: unit axis in the housing's frame at rest.
        stiffness: k [N/m or N·m/rad].
        damping: c [N·s/m or N·m·s/rad].
        mass: the mass of its link [kg] (a tower slide's share of the modal masses; else 0).
    """

    name: str
    kind: str
    axis: np.ndarray
    stiffness: float
    damping: float
    mass: float = 0.0


@dataclass(frozen=True)
class Support:
    """The housing's mounts and the bedplate's tower modes, as read from the model file.

    Attributes:
        housing: the housing link.
        shaft_axis: unit shaft axis in the housing's frame (the roll axis, fore-aft).
        mount_stiffness: mount axis (``MOUNT_AXES``) → k [N/m, N·m/rad for roll]; an axis
            not given is rigid.
        mount_damping: mount axis → c [N·s/m, N·m·s/rad for roll].
        tower_modes: the tower modes, at most one per direction.
    """

    housing: str
    shaft_axis: np.ndarray
    mount_stiffness: dict[str, float] = field(default_factory=dict)
    mount_damping: dict[str, float] = field(default_factory=dict)
    tower_modes: tuple[TowerMode, ...] = ()

    def problems(self) -> list[tuple[str, float, str]]:
        """(attribute, value, what is wrong and the fix) for each bad value (empty when fine)."""
        out = []
        values: list[tuple[str, float, str]] = []
        for axis, k in self.mount_stiffness.items():
            values.append((f"stiffness_{axis}", k, "N·m/rad" if axis == "roll" else "N/m"))
        for axis, c in self.mount_damping.items():
            values.append((f"damping_{axis}", c, "N·m·s/rad" if axis == "roll" else "N·s/m"))
        for mode in self.tower_modes:
            values += [
                (f"{mode.direction} frequency_hz", mode.frequency, "Hz"),
                (f"{mode.direction} mass", mode.mass, "kg"),
                (f"{mode.direction} damping_ratio", mode.damping_ratio, ""),
            ]
        for name, value, unit in values:
            positive = name.endswith(("frequency_hz", "mass")) or name.startswith("stiffness")
            if not math.isfinite(value) or value < 0.0 or (positive and value == 0.0):
                bound = "> 0" if positive else "≥ 0"
                out.append(
                    (name, value, f"{name} is {value:g} {unit}; give a finite value {bound}")
                )
        for axis in self.mount_damping:
            if axis not in self.mount_stiffness:
                out.append(
                    (
                        f"damping_{axis}",
                        self.mount_damping[axis],
                        f"damping_{axis} without stiffness_{axis}: the mount is rigid in {axis}; "
                        f"give stiffness_{axis} or remove the damping",
                    )
                )
        return out

    def directions(self, up: np.ndarray) -> dict[str, np.ndarray]:
        """Each tower direction's unit axis in the housing's frame, ``up`` against gravity."""
        fore_aft = self.shaft_axis
        vertical = up - (up @ fore_aft) * fore_aft
        length = np.linalg.norm(vertical)
        # A shaft along gravity has no vertical nor side-side: NaN, refused where a mode needs it
        # (``model/gearbox.py``).
        vertical = vertical / length if length > 0.0 else np.full(3, np.nan)
        return {
            "fore_aft": fore_aft,
            "side_side": np.cross(vertical, fore_aft),
            "vertical": vertical,
        }

    def slides(self, up: np.ndarray) -> list[SupportSlide]:
        """The chain from the ground to the housing (module docstring), ``up`` as ``directions``.

        The tower slides come first, largest modal mass first, each link carrying the
        difference to the next mass (the last the smallest mass), then the mounts' slides.
        """
        axes = self.directions(up)
        modes = sorted(self.tower_modes, key=lambda m: -m.mass)
        out = []
        for i, mode in enumerate(modes):
            after = modes[i + 1].mass if i + 1 < len(modes) else 0.0
            out.append(
                SupportSlide(
                    f"support_tower_{mode.direction}",
                    "prismatic",
                    axes[mode.direction],
                    mode.stiffness,
                    mode.damping,
                    mode.mass - after,
                )
            )
        eye = np.eye(3)
        for i, axis in enumerate(MOUNT_AXES):
            if axis not in self.mount_stiffness:
                continue
            out.append(
                SupportSlide(
                    f"support_mount_{axis}",
                    "revolute" if axis == "roll" else "prismatic",
                    self.shaft_axis if axis == "roll" else eye[i],
                    self.mount_stiffness[axis],
                    self.mount_damping.get(axis, 0.0),
                )
            )
        return out
