"""Load spectra of the shafts: load duration (LDD) and load revolution (LRD) distributions.

IEC 61400-4 §7.2 asks for the time (LDD) and the revolutions (LRD) a shaft spends at each torque
level, the input of ISO 6336-6's damage sums. From a run, each sample k stands for the
trapezoid-rule share w_k of the time (half a step at both ends), so the LDD sums to the
duration and the LRD, weighted by |ω_k| w_k / 2π, to ∫|ω| dt / 2π over the run.

Which torque a shaft carries (``shaft_torque``):

- a joint that carries gears: the torque the teeth of one of its gears put on it about the joint
  axis, from the mesh forces (T = −s F_n r_b on gear A of a mesh, its reaction on gear B; ``s``
  the loaded flank, docs/model_format.md). The run's ``torque`` series is the torque from
  *outside* the train only (0 on an intermediate shaft, and 0 at a constant speed driven against
  a generator, docs/series.md), so the mesh forces are what a shaft inside the train
  transmits. A shaft with several gears (a parallel-stage wheel on the sun shaft, a compound
  planet) transmits the torque of one gear to the other: the gear whose torque has the larger
  RMS is taken; a simple planet, whose two meshes balance, carries about none;
- a joint without gears (a carrier, a shaft half joined by a torsional spring): the ``torque``
  series, the torque that enters the train there.

Joint speeds are relative to the parent body (a planet's to the carrier), as the revolutions of
its bearing and teeth are.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pinocchio as pin

from pinwind.dynamics.result import Result
from pinwind.errors import InputError, NonFiniteInput
from pinwind.life.bearing_life import sample_weights
from pinwind.model.gearbox import Gearbox

#: Torque levels of a spectrum when none are given: equal bins from the least to the largest.
DEFAULT_BINS = 50


@dataclass(frozen=True)
class LoadSpectrum:
    """A shaft's LDD and LRD: time and revolutions in each torque bin.

    Attributes:
        joint: the shaft's joint.
        source: where its torque was taken (``gear sun`` or ``external torque``).
        edges: torque bin edges [N·m], (bins + 1,), increasing; a bin holds lo ≤ T < hi (the
            last one lo ≤ T ≤ hi).
        time: time at each torque level [s], (bins,) (the LDD).
        revolutions: revolutions at each torque level [rev], (bins,) (the LRD).
    """

    joint: str
    source: str
    edges: np.ndarray
    time: np.ndarray
    revolutions: np.ndarray

    @property
    def levels(self) -> np.ndarray:
        """Torque at the middle of each bin [N·m]."""
        return 0.5 * (self.edges[:-1] + self.edges[1:])

    def as_dict(self) -> dict[str, Any]:
        """Plain values for JSON (SI: N·m, s, revolutions)."""
        return {
            "joint": self.joint,
            "source": self.source,
            "edges_N_m": self.edges.tolist(),
            "time_s": self.time.tolist(),
            "revolutions": self.revolutions.tolist(),
        }


def load_spectrum(
    torque: np.ndarray,
    speed: np.ndarray,
    time: np.ndarray,
    *,
    bins: int | Sequence[float] = DEFAULT_BINS,
    joint: str = "",
    source: str = "",
) -> LoadSpectrum:
    """LDD and LRD of one torque history.

    Args:
        torque: torque T_k [N·m], (n,).
        speed: shaft speed ω_k [rad/s], (n,) (its sign does not count).
        time: sample times [s], (n,), increasing.
        bins: a number of equal bins from min T to max T, or the bin edges [N·m] (increasing;
            they must hold every sample, so that the spectra sum to the run).
        joint: the shaft, for the record.
        source: where its torque comes from, for the record.

    Raises:
        NonFiniteInput: a torque or speed is NaN or infinite (a series the log does not hold).
        InputError: fewer than two samples, or edges that are not increasing or miss samples.
    """
    torque, speed = np.asarray(torque, dtype=float), np.asarray(speed, dtype=float)
    time = np.asarray(time, dtype=float)
    what = f'shaft "{joint}"' if joint else "the shaft"
    if len(time) < 2:
        raise InputError(f"{what}: a load spectrum needs at least two samples, got {len(time)}")
    if not (np.all(np.isfinite(torque)) and np.all(np.isfinite(speed))):
        raise NonFiniteInput(
            f"{what}: its torque or speed is NaN or infinite (a series the log does not hold?)"
        )
    low, high = float(torque.min()), float(torque.max())
    if isinstance(bins, int):
        if bins < 1:
            raise InputError(f"{what}: {bins} torque bins; give at least one")
        if high - low <= 1e-9 * max(abs(low), abs(high), 1.0):
            # constant to rounding (a steady sun, 1e6/6 N·m ± 2 ulps): numpy cannot cut so
            # narrow a span into finite bins; its bins for a constant, the value ± 0.5 N·m
            edges = np.histogram_bin_edges([0.5 * (low + high)], bins=bins)
        else:
            edges = np.histogram_bin_edges(torque, bins=bins)
    else:
        edges = np.asarray(bins, dtype=float)
        if edges.ndim != 1 or len(edges) < 2 or np.any(np.diff(edges) <= 0.0):
            raise InputError(f"{what}: torque bin edges {edges.tolist()} must increase")
        if low < edges[0] or high > edges[-1]:
            raise InputError(
                f"{what}: its torque spans {low:.6g} to {high:.6g} N·m, beyond the bins "
                f"{edges[0]:.6g} to {edges[-1]:.6g} N·m; widen the bins so that they hold the run"
            )
    weights = sample_weights(time)
    durations, _ = np.histogram(torque, bins=edges, weights=weights)
    turns, _ = np.histogram(torque, bins=edges, weights=weights * np.abs(speed) / (2 * math.pi))
    return LoadSpectrum(joint, source, edges, durations, turns)


def gear_torque(result: Result, gearbox: Gearbox, gear: str) -> np.ndarray:
    """Torque the teeth of ``gear`` take from all its meshes, about its axis [N·m], (n,).

    On gear A of a mesh T_A = −F r_w,A with F = (F_n,front − F_n,back) cos α_w the tangential
    force of the front flank less that of the back (both push in double-flank contact) and r_w
    the working pitch radius; on gear B T_B = F c_B (k_A · k_B), c_B = −r_w,B for an
    external pair and +r_w,B with an internal gear, k the gear axes in world (docs/model_format.md
    "Mesh sign convention").

    Raises:
        InputError: no gear has that name.
    """
    if gear not in gearbox.gears:
        raise InputError(f'no gear named "{gear}"; gears are: {", ".join(gearbox.gears)}')
    model = gearbox.model
    data = model.createData()
    pin.forwardKinematics(model, data, gearbox.neutral())

    def axis_in_world(name: str) -> np.ndarray:
        g = gearbox.gears[name]
        return data.oMi[g.joint_id].rotation @ g.axis_in_joint

    total = np.zeros(len(result))
    for i, mesh in enumerate(gearbox.meshes):
        # F_t on the front flank less on the back (both push in double-flank contact) [N]
        push = (result.mesh_normal_front[:, i] - result.mesh_normal_back[:, i]) * math.cos(
            mesh.working_pressure_angle
        )
        if mesh.gear_a.name == gear:
            total -= push * mesh.working_radius_a
        elif mesh.gear_b.name == gear:
            internal = mesh.gear_a.spec.internal or mesh.gear_b.spec.internal
            lever = mesh.working_radius_b if internal else -mesh.working_radius_b
            alignment = float(axis_in_world(mesh.gear_a.name) @ axis_in_world(gear))
            total += push * lever * np.sign(alignment)
    return total


def shaft_torque(result: Result, gearbox: Gearbox, joint: str) -> tuple[np.ndarray, str]:
    """The torque a shaft transmits [N·m], (n,), and where it is taken (module docstring).

    Raises:
        InputError: the joint is not a bearing of the run.
    """
    if joint not in result.joint_names:
        raise InputError(f'no joint named "{joint}"; joints are: {", ".join(result.joint_names)}')
    joint_id = gearbox.model.getJointId(joint)
    gears = [name for name, g in gearbox.gears.items() if g.joint_id == joint_id]
    if not gears:
        return result.torque[:, result.joint_names.index(joint)], "external torque"
    torques = {name: gear_torque(result, gearbox, name) for name in gears}
    name = max(gears, key=lambda g: float(np.sqrt(np.mean(torques[g] ** 2))))
    return torques[name], f"gear {name}"


def shaft_spectra(
    result: Result, gearbox: Gearbox, *, bins: int | Sequence[float] = DEFAULT_BINS
) -> list[LoadSpectrum]:
    """LDD and LRD of every turning shaft of a run (locked mounts left out), in joint order."""
    spectra = []
    for i, joint in enumerate(result.joint_names):
        if joint in gearbox.locked_joints:
            continue
        torque, source = shaft_torque(result, gearbox, joint)
        spectra.append(
            load_spectrum(
                torque, result.speed[:, i], result.time, bins=bins, joint=joint, source=source
            )
        )
    return spectra
