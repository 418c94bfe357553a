"""Stress history and fatigue damage of every tooth of a gear, from a compliant run.

Jørgensen 2014 §3.1 counts the stress of one mesh at one chosen
point of the path and spreads it over the teeth with a time factor (Table 3). Here each tooth
gets its own history instead, so damage is per tooth and the worst tooth is found:

- A mesh logs, per sample, the roll position x of its entering tooth pair from gear A's base
  tangency point (``mesh_contact_position``), the force on that pair (``mesh_single_tooth_force``),
  the mesh force F_n (``mesh_normal``) and the pairs in contact (``mesh_pairs``). With two pairs,
  the pair one base pitch p_b ahead, at x + p_b, carries F_n minus the entering pair's force.
- x grows as the gears roll and jumps back by p_b when the next pair enters, so counting the
  jumps follows the teeth as they enter (`entering_teeth`), on either gear of the pair.
- A tooth's history is the stress at its moving contact point while it is in contact, with a
  zero between its passes through the mesh(es); rainflow (`pinwind.life.cycles`) then counts one
  cycle per pass (of the largest stress on the flank that pass) plus the smaller ones within it.
  That rates each pass by the flank's most stressed point, which is conservative where that
  point moves from pass to pass (Jørgensen 2014 follows one fixed point instead).
- Damage is Palmgren-Miner (`pinwind.life.sn_curve`, Jørgensen 2014 eq. 2) of those cycles times
  the plain time factor h · 3600 / T_sim (Table 2): each tooth's own cycles need no division by
  the teeth or multiplication by the meshes (Table 3 does both to spread one mesh's cycles).

A helical mesh with an overlap ratio ε_β ≥ 1 (the NREL 5 MW stage 3, ε_β = 1.42) is rated as
ISO 6336 rates it (`HelicalContacts`): its contact lines sweep the face, the load per unit
length of line stays near the mesh force's share F_n cos β_b/(b ε_α) whichever pairs are in
contact, so every tooth in contact meets the stress of the mesh force
(`contact_stress.helical_contact_stress`, `root_stress.RootStress.mesh_stress`), and each pass
of a tooth through the mesh is one cycle, of the largest such stress during the pass: the
teeth in contact are the entering one and the ``mesh_pairs`` − 1 ahead of it, one base pitch
apart, and each point of the flank (each section of the root) is loaded once per pass, by the
force of the moment the contact line crosses it; the pass's largest is its most loaded point,
as for a spur pair.

Teeth carry the gear's own numbers (`mesh_teeth`): tooth j has its centre line at the gear's
tooth phase + 2πj/z about its axis (`pinwind.model.phasing`), so a sun's passes at its three
planets join into one history per physical tooth. The tooth in each mesh's entering pair at
the first sample (and wherever the mesh changes flank) follows from the joint angles there: it
is the tooth whose centre line lies nearest the contact point (less than half a pitch away, as
a flank is); the jumps of x count on from it, in the sense the gear turns as the contact rolls
forward. Each flank of a tooth is its own surface and is rated apart (`gear_tooth_damage`).

A run may be counted block by block as it runs (`GearTeeth`, a fatigue case's reduction): the
teeth are numbered on from the block before (the roll position and tooth at its last sample),
a pass that runs past a block's end goes on in the next (a helical pass's largest value is
held until the pass ends), and each tooth flank's history is rainflow-counted as it comes
(`pinwind.life.cycles.CycleStream`, holding only the points not yet closed); the whole run is
one block.

The force of a pair is spread evenly across the face width (ISO's K_Hβ = K_Fβ = 1), or with
``face_load="run"`` rated at the run's peak line load (`pinwind.life.peak_line_load`): each
sample's force times K_Hβ(t) of the mesh (``mesh_face_load_factor``) for the contact stress,
times K_Hβ(t)^N_F for the root (ISO 6336-1 K_Fβ), on both pairs of a spur mesh (the entering
pair's force and F_n minus it) and on the mesh force of a helical one (ISO 6336-2 applies
K_Hβ to a helical mesh's force the same way). The run must have cut the mesh into slices.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from pinwind.dynamics.compliant import overlap_span
from pinwind.dynamics.mesh import MeshSet
from pinwind.errors import InputError
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.hertz import VON_MISES_RATIO
from pinwind.gears.materials import Material
from pinwind.life.contact_stress import contact_stress, helical_contact_stress
from pinwind.life.cycles import Cycles, CycleStream, rainflow_cycles
from pinwind.life.peak_line_load import FACE_LOADS, require_sliced, run_force_factor
from pinwind.life.root_stress import RootStress
from pinwind.life.sn_curve import FatigueCurve, miner_damage
from pinwind.model.phasing import zero_direction

if TYPE_CHECKING:
    from pinwind.dynamics.result import Result
    from pinwind.model.gearbox import Gear, Gearbox


def entering_teeth(
    contact_position: npt.ArrayLike,
    *,
    base_pitch: float,
    teeth: int,
    first_tooth: int = 0,
    direction: int = 1,
) -> np.ndarray:
    """Which of a gear's teeth is in a mesh's entering pair at each sample.

    A jump of x back by about p_b is the next tooth entering, a jump forward by about p_b the
    previous one entering again as the gears turn back. The samples must follow the roll
    closely: x may move less than p_b / 2 between samples (at least two samples per mesh
    period; a stress history needs many more).

    Args:
        contact_position: x, the roll position of the entering pair [m], (n,).
        base_pitch: p_b [m].
        teeth: the gear's tooth count.
        first_tooth: the tooth entering at the first sample.
        direction: +1 when the next tooth to enter has the next number, −1 when the previous.

    Returns:
        The tooth index in [0, teeth) at each sample, (n,).

    Raises:
        InputError: x not finite (a rigid mesh without a path of contact), or bad numbers.
    """
    x = np.asarray(contact_position, dtype=float)
    if x.ndim != 1 or not np.all(np.isfinite(x)):
        raise InputError(
            "the contact position must be one finite series; a mesh whose gear data give no "
            "path of contact logs NaN: fix its teeth, module or profile shifts"
        )
    if not base_pitch > 0.0 or teeth < 1:
        raise InputError(
            f"the base pitch ({base_pitch!r} m) and tooth count ({teeth}) must be positive"
        )
    step = np.diff(x)
    entered = (step < -0.5 * base_pitch).astype(int) - (step > 0.5 * base_pitch).astype(int)
    return (first_tooth + direction * np.concatenate([[0], np.cumsum(entered)])) % teeth


@dataclass(frozen=True)
class ToothContacts:
    """A gear's teeth in contact at one mesh, per sample.

    Attributes:
        tooth: the gear's tooth in the entering pair (`entering_teeth`), (n,).
        leading_tooth: its tooth in the pair one base pitch ahead, the one that entered before,
            (n,).
        entering: stress (or load) on the entering pair, (n,).
        leading: stress (or load) on the pair ahead, (n,).
        pairs: tooth pairs in contact, 1 or 2, (n,); ``leading`` counts only where it is 2.
    """

    tooth: np.ndarray
    leading_tooth: np.ndarray
    entering: np.ndarray
    leading: np.ndarray
    pairs: np.ndarray

    #: Each sample of a pass is kept (the pair's load rises and falls within it).
    peak_per_pass = False

    def loads(self, mesh: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(tooth, sample, value) of every tooth in contact at every sample; ``mesh`` its index.

        Raises:
            InputError: three or more pairs in contact (a contact ratio of 2 or more), which
                the logged series do not resolve.
        """
        pairs = np.asarray(self.pairs)
        if np.any(pairs > 2):
            raise InputError(
                f"mesh {mesh} has {int(np.max(pairs))} tooth pairs in contact at times; the "
                "logged series give the forces of the entering pair and, by difference, of one "
                "more: per-tooth histories of a spur pair need a contact ratio below 2"
            )
        samples = np.arange(len(self.tooth))
        two = pairs == 2
        return (
            np.concatenate([np.asarray(self.tooth), np.asarray(self.leading_tooth)[two]]),
            np.concatenate([samples, samples[two]]),
            np.concatenate(
                [np.asarray(self.entering, dtype=float), np.asarray(self.leading, dtype=float)[two]]
            ),
        )

    def unloaded_where(self, off: np.ndarray) -> ToothContacts:
        """The same contacts with no load at the samples ``off`` (another flank's)."""
        return dataclasses.replace(
            self,
            entering=np.where(off, 0.0, self.entering),
            leading=np.where(off, 0.0, self.leading),
        )


@dataclass(frozen=True)
class HelicalContacts:
    """A gear's teeth in contact at a helical mesh (ε_β ≥ 1), per sample (module docstring).

    Every tooth in contact meets the same stress, the mesh force's; each pass of a tooth
    counts once, at the largest stress during it.

    Attributes:
        tooth: the gear's tooth in the entering pair (`entering_teeth`), (n,).
        leading_tooth: its tooth one base pitch ahead, (n,); the k-th ahead is k steps further.
        stress: the stress of the mesh force (or the load), (n,).
        pairs: tooth pairs in contact, (n,): the entering one and ``pairs`` − 1 ahead of it.
        teeth: the gear's tooth count.
    """

    tooth: np.ndarray
    leading_tooth: np.ndarray
    stress: np.ndarray
    pairs: np.ndarray
    teeth: int

    #: A pass counts once, at its largest stress.
    peak_per_pass = True

    def loads(self, mesh: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(tooth, sample, value) of every tooth in contact at every sample (``mesh`` unused)."""
        tooth = np.asarray(self.tooth)
        step = tooth - np.asarray(self.leading_tooth)  # ±1 (mod z): the next tooth ahead
        pairs = np.asarray(self.pairs)
        samples = np.arange(tooth.size)
        stress = np.asarray(self.stress, dtype=float)
        ahead = range(max(int(np.max(pairs, initial=1)), 1))
        rows = [pairs > k for k in ahead]
        return (
            np.concatenate(
                [(tooth - k * step)[r] % self.teeth for k, r in zip(ahead, rows, strict=True)]
            ),
            np.concatenate([samples[r] for r in rows]),
            np.concatenate([stress[r] for r in rows]),
        )

    def unloaded_where(self, off: np.ndarray) -> HelicalContacts:
        """The same contacts with no load at the samples ``off`` (another flank's)."""
        return dataclasses.replace(self, stress=np.where(off, 0.0, self.stress))


def tooth_histories(
    contacts: Sequence[ToothContacts | HelicalContacts], *, teeth: int
) -> list[np.ndarray]:
    """The history of each tooth of a gear over all its meshes, in time order.

    A tooth's history holds its values while it is in contact (entering, then leading) at any
    of the meshes, with a 0 before, between and after its passes: out of contact it is unloaded.
    A pass through a helical mesh (`HelicalContacts`) keeps one value, its largest. The whole
    history is one block of `ToothPasses`.

    Args:
        contacts: one per mesh of the gear, all over the same samples.
        teeth: the gear's tooth count.

    Returns:
        ``teeth`` arrays, the history of tooth 0, 1, ...

    Raises:
        InputError: three or more pairs in contact at a spur mesh (a contact ratio of 2 or
            more), which the logged series do not resolve.
    """
    parts: list[list[np.ndarray]] = [[] for _ in range(teeth)]
    passes = ToothPasses(teeth, lambda j, values: parts[j].append(values))
    passes.add(contacts)
    passes.close()
    return [np.concatenate(p) for p in parts]


class ToothPasses:
    """Each tooth's history of a gear over all its meshes, built block by block.

    The history is `tooth_histories`'s; the blocks are consecutive runs of samples, each given
    as the contacts of every mesh over them (`add`). Each block's part of every tooth's history
    goes to ``sink(tooth, values)`` as soon as it is known: a pass that runs on past a block's
    end continues in the next block (no 0 between), and a helical pass's one value, its
    largest, is given once the pass has ended. `close` gives the end (the last helical passes
    and the final 0). The parts given to one tooth, joined, are its history over all the blocks.

    Args:
        teeth: the gear's tooth count.
        sink: receives (tooth, the next values of its history).
    """

    def __init__(self, teeth: int, sink: Callable[[int, np.ndarray], None]) -> None:
        self.teeth = teeth
        self._sink = sink
        self._offset = 0  # samples in the blocks before
        self._last_sample = np.full(teeth, -2)  # each tooth's last sample in contact ...
        self._last_mesh = np.full(teeth, -1)  # ... and its mesh there
        self._touched = np.zeros(teeth, dtype=bool)
        self._open = np.full(teeth, np.nan)  # the largest value of an unfinished helical pass
        self._closed = False
        for j in range(teeth):
            sink(j, np.zeros(1))  # a history starts unloaded

    def add(self, contacts: Sequence[ToothContacts | HelicalContacts]) -> None:
        """The next block: the gear's contacts at each of its meshes, all over its samples.

        Raises:
            InputError: three or more pairs in contact at a spur mesh (`ToothContacts.loads`).
        """
        if not contacts:
            return
        tooth_of, sample_of, mesh_of, value_of, peak_of = [], [], [], [], []
        for m, c in enumerate(contacts):
            tooth_m, sample_m, value_m = c.loads(m)
            tooth_of.append(tooth_m)
            sample_of.append(sample_m + self._offset)
            mesh_of.append(np.full(tooth_m.size, m))
            value_of.append(value_m)
            peak_of.append(np.full(tooth_m.size, c.peak_per_pass))
        tooth = np.concatenate(tooth_of).astype(int)
        sample = np.concatenate(sample_of)
        mesh = np.concatenate(mesh_of)
        value = np.concatenate(value_of)
        peak = np.concatenate(peak_of)
        order = np.lexsort((mesh, sample, tooth))
        tooth, sample, mesh, value, peak = (
            tooth[order], sample[order], mesh[order], value[order], peak[order]
        )  # fmt: skip
        bounds = np.searchsorted(tooth, np.arange(self.teeth + 1))
        for j in range(self.teeth):
            rows = slice(int(bounds[j]), int(bounds[j + 1]))
            at, where, v, pk = sample[rows], mesh[rows], value[rows], peak[rows]
            if not at.size:
                continue
            # A pass ends where the tooth skips a sample or moves to another mesh: a 0 between
            # passes (one insert for all of them, not a list of parts: a tooth has thousands).
            breaks = np.flatnonzero((np.diff(at) > 1) | (np.diff(where) != 0)) + 1
            if np.any(pk):
                v, breaks = _pass_peaks(v, breaks, pk)
            parts = []
            held = self._open[j]
            if (
                self._touched[j]
                and at[0] == self._last_sample[j] + 1
                and where[0] == self._last_mesh[j]
            ):  # the pass of the block before goes on
                if not np.isnan(held):  # a helical one: its largest over both blocks
                    v = v.copy()
                    v[0] = max(held, v[0])
            else:
                if not np.isnan(held):
                    parts.append(np.array([held]))
                if self._touched[j]:
                    parts.append(np.zeros(1))
            if pk[-1]:  # a helical pass until the block's end: held until it ends
                self._open[j] = v[-1]
                v = v[:-1]
            else:
                self._open[j] = np.nan
            parts.append(np.insert(v, breaks, 0.0))
            self._sink(j, np.concatenate(parts))
            self._touched[j] = True
            self._last_sample[j], self._last_mesh[j] = at[-1], where[-1]
        self._offset += len(contacts[0].tooth)

    def close(self) -> None:
        """The end of the histories: the helical passes still held, and a 0 after the last pass."""
        if self._closed:
            return
        self._closed = True
        for j in range(self.teeth):
            end = [] if np.isnan(self._open[j]) else [self._open[j]]
            if self._touched[j]:
                end.append(0.0)
            if end:
                self._sink(j, np.array(end))


def _pass_peaks(
    values: np.ndarray, breaks: np.ndarray, peak: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """(values, breaks) with each pass whose samples are ``peak`` cut to its largest value.

    ``breaks`` are the indices where passes start (but the first); a pass lies in one mesh, so
    ``peak`` is the same over it.
    """
    starts = np.concatenate(([0], breaks)).astype(int)
    lengths = np.diff(np.append(starts, values.size))
    largest = np.maximum.reduceat(values, starts)
    first = np.zeros(values.size, dtype=bool)
    first[starts] = True
    kept = np.where(peak, np.repeat(largest, lengths), values)[~peak | first]
    new_lengths = np.where(peak[starts], 1, lengths)
    return kept, np.cumsum(new_lengths)[:-1]


@dataclass(frozen=True)
class ToothDamage:
    """Fatigue damage of each tooth of a gear.

    Attributes:
        gear: the gear's name.
        damage: Palmgren-Miner damage of each tooth over the hours the time factor stands for
            [-], (teeth,).
        cycles: rainflow cycles of each tooth's simulated history, before the time factor.
        peak_stress: largest stress of each tooth in the simulated history [Pa], (teeth,).
        flank: the teeth's flank rated: +1 the one facing the gear's positive turn, −1 the
            other (`EnteringTeeth.flank`), 0 when not told.
    """

    gear: str
    damage: np.ndarray
    cycles: tuple[Cycles, ...]
    peak_stress: np.ndarray
    flank: int = 0

    @property
    def cycle_counts(self) -> np.ndarray:
        """Cycles of each tooth in the simulated history, half cycles 0.5, (teeth,)."""
        return np.array([c.total for c in self.cycles])

    @property
    def worst_tooth(self) -> int:
        """Index of the tooth with the largest damage (the first of equals)."""
        return int(np.argmax(self.damage))

    @property
    def worst(self) -> float:
        """The largest damage of any tooth [-]."""
        return float(np.max(self.damage))


def histories_damage(
    histories: Sequence[np.ndarray],
    *,
    gear: str,
    curve: FatigueCurve,
    time_factor: float,
    use_endurance_limit: bool = True,
    flank: int = 0,
) -> ToothDamage:
    """Rainflow and Palmgren-Miner damage of each tooth's stress history.

    Args:
        histories: stress history of each tooth [Pa] (`tooth_histories`).
        gear: the gear's name, for the record.
        curve: the S-N curve, read at the cycle ranges.
        time_factor: life seconds per simulated second, h · 3600 / T_sim (`site.time_factor`).
        use_endurance_limit: False to count cycles below the endurance limit too.
        flank: the flank the histories are of, for the record (`ToothDamage.flank`).
    """
    counted = tuple(rainflow_cycles(history) for history in histories)
    peaks = [float(np.max(history)) for history in histories]
    return cycles_damage(
        counted,
        peaks,
        gear=gear,
        curve=curve,
        time_factor=time_factor,
        use_endurance_limit=use_endurance_limit,
        flank=flank,
    )


def cycles_damage(
    counted: Sequence[Cycles],
    peaks: Sequence[float],
    *,
    gear: str,
    curve: FatigueCurve,
    time_factor: float,
    use_endurance_limit: bool = True,
    flank: int = 0,
) -> ToothDamage:
    """Palmgren-Miner damage of each tooth from its rainflow cycles (`histories_damage`).

    Args:
        counted: the rainflow cycles of each tooth's stress history [Pa].
        peaks: the largest stress of each tooth's history [Pa].
        gear: the gear's name, for the record.
        curve: the S-N curve, read at the cycle ranges.
        time_factor: life seconds per simulated second (`histories_damage`).
        use_endurance_limit: False to count cycles below the endurance limit too.
        flank: the flank the cycles are of, for the record (`ToothDamage.flank`).
    """
    damage = [
        miner_damage(c.scaled(time_factor), curve, use_endurance_limit=use_endurance_limit)
        for c in counted
    ]
    return ToothDamage(gear, np.array(damage), tuple(counted), np.array(peaks, dtype=float), flank)


@dataclass(frozen=True)
class EnteringTeeth:
    """A gear's tooth in a mesh's entering pair, per sample.

    Attributes:
        tooth: its number, in [0, z) (module docstring), (n,).
        leading_tooth: the gear's tooth in the pair one base pitch ahead, which entered before
            it, (n,).
        flank: the flank of it in contact: +1 the one facing the gear's positive turn, −1 the
            other, (n,). A sun's or a ring's meshes all load one flank of its teeth; a planet's
            sun and ring meshes load opposite flanks.
    """

    tooth: np.ndarray
    leading_tooth: np.ndarray
    flank: np.ndarray


def mesh_teeth(result: Result, gearbox: Gearbox, mesh: str, gear: str) -> EnteringTeeth:
    """The tooth of ``gear`` in the entering pair of ``mesh`` at each sample, by its number.

    Tooth j has its centre line at the gear's tooth phase + 2πj/z about its axis (module
    docstring). Where the mesh changes flank the teeth are found again from the joint angles.

    Args:
        result: the run, with the joint angles of its samples (a Result of ``simulate``).
        gearbox: its model.
        mesh: the mesh's name.
        gear: one of the mesh's gears.

    Raises:
        InputError: the gear is not in the mesh, the mesh has no path of contact, or a
            sample where the teeth are found has no joint angles.
        UnknownElement: no mesh of that name.
    """
    i = [m.name for m in gearbox.meshes].index(gearbox.mesh(mesh).name)
    return _mesh_teeth(result, gearbox, i, _mesh_gear(gearbox, i, gear), None)[0]


def _mesh_gear(gearbox: Gearbox, index: int, gear: str) -> Gear:
    """The gear ``gear`` of mesh ``index``, whose teeth can be tracked.

    Raises:
        InputError: the gear is not in the mesh, or the mesh has no path of contact.
    """
    spec = gearbox.meshes[index]
    if gear not in (spec.gear_a.name, spec.gear_b.name):
        raise InputError(
            f'gear "{gear}" is not in mesh "{spec.name}"; its gears are {spec.gear_a.name} and '
            f"{spec.gear_b.name}"
        )
    if spec.path is None:
        raise InputError(
            f'mesh "{spec.name}" has no path of contact (its gear data give none), so its teeth '
            "cannot be tracked; fix its teeth, module or profile shifts"
        )
    return spec.gear_a if spec.gear_a.name == gear else spec.gear_b


@dataclass(frozen=True)
class _Roll:
    """A gear's entering tooth at a mesh at the last sample of a block, for the next block.

    Attributes:
        position: the roll position x there [m].
        tooth, direction, side: the entering tooth, `entering_teeth`'s direction, the flank.
        flank: the mesh's loaded flank there (``mesh_flank``).
        time: the sample's time [s]; speed: its joint speeds [rad/s], (joints,).
    """

    position: float
    tooth: int
    direction: int
    side: int
    flank: float
    time: float
    speed: np.ndarray


def _mesh_teeth(
    result: Result, gearbox: Gearbox, index: int, wheel: Gear, before: _Roll | None
) -> tuple[EnteringTeeth, _Roll | None]:
    """`mesh_teeth` of mesh ``index`` over a block of samples, and where the block ends.

    ``before``: where the block before ended (None: the first block), whose teeth it numbers
    on, unless the mesh changes flank at the block's first sample (then found anew, as within
    a block).
    """
    spec = gearbox.meshes[index]
    _mesh_gear(gearbox, index, wheel.name)  # a mesh without a path of contact is refused
    pitch = spec.path.base_pitch if spec.path is not None else math.nan
    _check_samples_follow_the_roll(result, gearbox, index, before)
    position = result.mesh_contact_position[:, index]
    loaded = result.mesh_flank[:, index]
    samples, teeth = len(position), wheel.spec.teeth
    tooth = np.empty(samples, dtype=int)
    leading = np.empty(samples, dtype=int)
    flank = np.empty(samples, dtype=int)
    if not samples:
        return EnteringTeeth(tooth, leading, flank), before
    cuts = [0, *(np.flatnonzero(np.diff(loaded) != 0) + 1).tolist(), samples]
    direction = 1
    for start, stop in zip(cuts[:-1], cuts[1:], strict=True):
        x = position[start:stop]
        if start == 0 and before is not None and loaded[0] - before.flank == 0:
            first, direction, side = before.tooth, before.direction, before.side
            x = np.concatenate(([before.position], x))  # the jump from the block before
        else:
            first, direction, side = _entering_tooth(result, gearbox, index, wheel, start)
        numbered = entering_teeth(
            x,
            base_pitch=pitch,
            teeth=teeth,
            first_tooth=first,
            direction=direction,
        )
        tooth[start:stop] = numbered[x.size - (stop - start) :]
        leading[start:stop] = (tooth[start:stop] - direction) % teeth
        flank[start:stop] = side
    end = _Roll(
        float(position[-1]), int(tooth[-1]), direction, int(flank[-1]), float(loaded[-1]),
        float(result.time[-1]), np.array(result.speed[-1], dtype=float),
    )  # fmt: skip
    return EnteringTeeth(tooth, leading, flank), end


def _check_samples_follow_the_roll(
    result: Result, gearbox: Gearbox, index: int, before: _Roll | None = None
) -> None:
    """Refuses samples too far apart to tell which tooth enters (`entering_teeth`).

    Between two samples the contact rolls |ω_A − ω_line| r_b,A Δt along the line of action
    (`pinwind.analysis.spectrum.mesh_roll_speeds`, the faster of the two samples' speeds);
    from half a base pitch on, a tooth entering cannot be told from the previous one coming
    back, and the tooth histories would silently mix teeth. ``before``: the last sample of the
    block before, checked with the first of this one.

    Raises:
        InputError: the roll between two samples reaches half a base pitch, with the time,
            the speed and the sample rate that would follow it.
    """
    from pinwind.analysis.spectrum import mesh_roll_speeds

    mesh = gearbox.meshes[index]
    time, speed = np.asarray(result.time), np.asarray(result.speed)
    if before is not None:
        time = np.concatenate(([before.time], time))
        speed = np.concatenate((before.speed[None, :], speed))
    if mesh.path is None or len(time) < 2:
        return
    omega = np.abs(mesh_roll_speeds(gearbox, speed)[:, index])
    faster = np.maximum(omega[1:], omega[:-1])
    roll = faster * abs(mesh.base_radius_a) * np.diff(time)
    worst = int(np.argmax(roll))
    pitch = mesh.path.base_pitch
    if roll[worst] >= 0.5 * pitch:
        rate = 2.0 * faster[worst] * abs(mesh.base_radius_a) / pitch
        raise InputError(
            f'mesh "{mesh.name}": between samples at t = {time[worst]:.6g} s its teeth '
            f"roll {roll[worst] / pitch:.2f} base pitches (gear {mesh.gear_a.name} at "
            f"{faster[worst] * 30.0 / math.pi:.4g} rpm relative to the line of centres); the "
            "tooth histories need less than half a base pitch per sample: record at least "
            f"{math.ceil(rate):d} Hz there (a higher sample_rate or log rate)"
        )


def _entering_tooth(
    result: Result, gearbox: Gearbox, index: int, gear: Gear, sample: int
) -> tuple[int, int, int]:
    """(tooth, `entering_teeth` direction, flank) of the gear entering mesh ``index`` at ``sample``.

    The contact lies on the line of action n of the loaded flank, x from gear A's tangency point
    T_A (the foot of A's centre on that line) towards the pitch point P. The tooth is the one
    whose centre line is nearest it, and the contact lies on its flank facing the gear's
    positive turn when it is ahead of that centre line. As the contact rolls forward (along
    T_A → P) the gear turns with the sign of k · ((C − O) × d) (an involute's contact moves
    along the line as fast as its flank does); the tooth behind then comes next.

    A helical mesh logs x in the mid-face section, where the tooth phases lie, Δ/2 behind the
    front face section (`pinwind.dynamics.compliant.overlap_span`, Δ = ε_β p_bt). There the
    entering pair may not touch yet: x may lie before A, on the involute extended beyond the
    tip, which can cross the tooth's centre line, and the flank would be misjudged (the 5 MW
    stage-3 pinion's came out +1 or −1 by the sample). The contact is taken in the front face
    instead, at x + Δ/2, where the entering pair always touches, and its angle turned back by
    the tooth's twist from the mid-face to the front face, Δ/(2 r_b) in the sense the gear
    turns as the contact moves forward.
    """
    model = gearbox.model
    angles = result.angle[sample]
    if not np.all(np.isfinite(angles)):
        raise InputError(
            f"sample {sample} has no joint angles (a log keeps them only with its poses), so "
            "the teeth cannot be numbered; use the Result of the run"
        )
    q = gearbox.neutral()
    for name, angle in zip(result.joint_names, angles, strict=True):
        q[model.joints[model.getJointId(name)].idx_q] = angle
    meshes, data = _pose_tools(gearbox)
    pin.computeJointJacobiansTimeVariation(model, data, q, np.zeros(model.nv))
    rows = meshes.evaluate(model, data)
    flank = float(result.mesh_flank[sample, index])
    line = meshes.line_of_action(rows, np.full(meshes.count, flank))[index]
    pitch_point = rows.pitch_point[index]
    mesh = gearbox.meshes[index]
    centre_a = data.oMi[mesh.gear_a.joint_id].act(mesh.gear_a.centre_in_joint)
    foot = pitch_point - float((pitch_point - centre_a) @ line) * line
    forward = (pitch_point - foot) / np.linalg.norm(pitch_point - foot)
    half_span = 0.5 * overlap_span(mesh)  # 0 for a spur mesh
    contact = foot + (float(result.mesh_contact_position[sample, index]) + half_span) * forward
    placement = data.oMi[gear.joint_id]
    centre = placement.act(gear.centre_in_joint)
    arm = placement.rotation.T @ (contact - centre)
    zero = zero_direction(gear.axis_in_joint)
    angle = math.atan2(float(gear.axis_in_joint @ np.cross(zero, arm)), float(zero @ arm))
    axis = placement.rotation @ gear.axis_in_joint
    turns = float(axis @ np.cross(contact - centre, forward))
    radius = mesh.base_radius_a if gear.name == mesh.gear_a.name else mesh.base_radius_b
    twist = math.copysign(half_span / radius, turns)
    teeth = gear.spec.teeth
    pitches = (angle - twist - gearbox.tooth_phases[gear.name]) * teeth / (2.0 * math.pi)
    nearest = round(pitches)
    return nearest % teeth, -1 if turns > 0.0 else 1, 1 if pitches > nearest else -1


#: The last gearbox's mesh rows and Pinocchio data (`_pose_tools`): a run counted block by
#: block finds its teeth from the angles hundreds of times per block, and a new Data and
#: MeshSet each time cost half the counting's time and the memory pages to touch again.
_POSE_TOOLS: dict[str, tuple[Gearbox, MeshSet, pin.Data] | None] = {"last": None}


def _pose_tools(gearbox: Gearbox) -> tuple[MeshSet, pin.Data]:
    """The mesh rows and a Pinocchio Data of ``gearbox`` (those of the last call, if its)."""
    held = _POSE_TOOLS["last"]
    if held is None or held[0] is not gearbox:
        held = (gearbox, MeshSet(gearbox), gearbox.model.createData())
        _POSE_TOOLS["last"] = held
    return held[1], held[2]


def gear_tooth_damage(
    result: Result,
    gearbox: Gearbox,
    gear: str,
    *,
    curve: FatigueCurve,
    time_factor: float,
    materials: Mapping[str, Material | str] | None = None,
    use_endurance_limit: bool = True,
    root_stress: RootStress | None = None,
    face_load: str = "uniform",
) -> tuple[ToothDamage, ...]:
    """Contact- or root-stress damage of every tooth of a gear over all its meshes in a run.

    The contact stress is σ_vM ≈ 0.65 p_max of the Hertz pressure at the moving contact point
    (`pinwind.life.contact_stress`, Jørgensen 2014 eqs. 20-22); of a helical gear 0.65 σ_H of
    the mesh force (`contact_stress.helical_contact_stress`, ISO 6336-2), the same equivalent
    so that the set's curves, read at the von Mises stress, apply to both. Each flank of the
    teeth is its own surface: a planet's sun mesh and ring mesh load opposite flanks and are
    rated apart (Jørgensen 2014 §3.1 joins them into one 60 s history). With ``root_stress``
    the stress is instead that of the root fillet on the loaded flank's side
    (`pinwind.life.root_stress`), each fillet rated apart as each flank is.

    Args:
        result: the run (every sample of it).
        gearbox: its model.
        gear: the gear's name.
        curve: S-N curve of the gear's flanks (e.g. `sn_curve.jorgensen_2014_curve`).
        time_factor: life seconds per simulated second, h · 3600 / T_sim (`site.time_factor`).
        materials: gear name → material (default `materials.DEFAULT_MATERIAL`).
        use_endurance_limit: False to count cycles below the endurance limit too.
        root_stress: rate the tooth root with this model instead of the flank's contact.
        face_load: ``"uniform"`` (the force spread evenly across the face) or ``"run"`` (at
            the run's peak line load, module docstring).

    Returns:
        The damage of each flank (or its root fillet) in contact during the run, the most
        damaged first.

    Raises:
        InputError: no mesh has the gear, or as `mesh_teeth`; a spur mesh with a contact ratio
            of 2 or more; a helical mesh with ε_β < 1 (`contact_stress.require_full_overlap`)
            or a root-stress table on one; an unknown ``face_load``.
        FactorNotInRun: ``face_load="run"`` and a mesh of the gear not cut into slices.
    """
    counter = GearTeeth(
        gearbox, gear, materials=materials, root_stress=root_stress, face_load=face_load
    )
    counter.add(result)
    return counter.damage(
        curve=curve, time_factor=time_factor, use_endurance_limit=use_endurance_limit
    )


class GearTeeth:
    """The tooth histories of a gear over all its meshes, fed block by block and counted.

    Each block is a Result of consecutive samples of a run, continuing the block before
    (`add`); the teeth are numbered on across blocks (`mesh_teeth`), the passes joined
    (`ToothPasses`), and each tooth flank's history is counted as it comes
    (`pinwind.life.cycles.CycleStream`, which holds only the points not yet closed): its cycles
    are held here for `damage` (`gear_tooth_damage` of the blocks joined; the whole run is one
    block), or handed to ``cycles_to(flank, tooth, cycles)`` as they close, so that nothing
    held grows with the run. Each flank is built from the first block, whichever flanks the
    blocks load, so that its passes are those of the whole history.

    Args:
        gearbox: the model of the run.
        gear: the gear's name.
        materials: gear name → material (default `materials.DEFAULT_MATERIAL`).
        root_stress: rate the tooth root with this model instead of the flank's contact.
        face_load: ``"uniform"`` or ``"run"`` (`gear_tooth_damage`).
        cycles_to: receives (flank, tooth, the cycles just closed) instead of holding them;
            `end` gives the last.

    Raises:
        InputError: no mesh has the gear, or a mesh of it has no path of contact; an unknown
            ``face_load``.
    """

    def __init__(
        self,
        gearbox: Gearbox,
        gear: str,
        *,
        materials: Mapping[str, Material | str] | None = None,
        root_stress: RootStress | None = None,
        face_load: str = "uniform",
        cycles_to: Callable[[int, int, Cycles], None] | None = None,
    ) -> None:
        if face_load not in FACE_LOADS:
            raise InputError(
                f'face_load = "{face_load}"; choose "uniform" (the force spread evenly across '
                'the face) or "run" (at the run\'s peak line load)'
            )
        chosen = dict(materials or {})
        self.gearbox, self.gear, self.root_stress = gearbox, gear, root_stress
        self.face_load = face_load
        self._meshes: list[tuple[int, Gear, GearPair]] = []
        for i, mesh in enumerate(gearbox.meshes):
            if gear in (mesh.gear_a.name, mesh.gear_b.name):
                pair = GearPair.from_gears(mesh.gear_a.spec, mesh.gear_b.spec, dict(chosen))
                self._meshes.append((i, _mesh_gear(gearbox, i, gear), pair))
        if not self._meshes:
            names = sorted({g.name for m in gearbox.meshes for g in (m.gear_a, m.gear_b)})
            raise InputError(f'no mesh has a gear "{gear}"; meshed gears are: {", ".join(names)}')
        self.teeth = self._meshes[-1][1].spec.teeth
        self._rolls: dict[int, _Roll | None] = {i: None for i, _, _ in self._meshes}
        self._streams = {side: [CycleStream() for _ in range(self.teeth)] for side in (1, -1)}
        self._parts: dict[int, list[list[Cycles]]] = {
            side: [[] for _ in range(self.teeth)] for side in (1, -1)
        }
        self._cycles_to = cycles_to if cycles_to is not None else self._keep
        self._passes = {side: ToothPasses(self.teeth, self._sink(side)) for side in (1, -1)}
        self._loaded = {1: False, -1: False}
        self._peaks: dict[int, np.ndarray] = {}

    def _keep(self, side: int, tooth: int, cycles: Cycles) -> None:
        """Holds the cycles in memory (no ``cycles_to``), for `damage`."""
        self._parts[side][tooth].append(cycles)

    def _sink(self, side: int) -> Callable[[int, np.ndarray], None]:
        """Where `ToothPasses` puts the next values of a tooth's history of flank ``side``."""
        streams = self._streams[side]

        def add(tooth: int, values: np.ndarray) -> None:
            closed = streams[tooth].add(values)
            if closed.ranges.size:
                self._cycles_to(side, tooth, closed)

        return add

    def check_run(self, result: Result) -> None:
        """Refuse a run whose meshes of the gear lack what ``face_load`` needs (its metadata).

        Raises:
            FactorNotInRun: ``face_load="run"`` and a mesh of the gear not cut into slices.
        """
        if self.face_load != "run":
            return
        for i, _, _ in self._meshes:
            require_sliced(result, self.gearbox.meshes[i].name)

    def add(self, result: Result) -> None:
        """The next samples of the run (a Result of the series the teeth need, `CASE_SERIES`).

        Raises:
            InputError: as `gear_tooth_damage`.
        """
        if not len(result):
            return
        contacts: list[tuple[ToothContacts | HelicalContacts, np.ndarray]] = []
        for i, wheel, pair in self._meshes:
            teeth, self._rolls[i] = _mesh_teeth(result, self.gearbox, i, wheel, self._rolls[i])
            gear_a = self.gearbox.meshes[i].gear_a.name
            factor = None
            if self.face_load == "run":
                stress = "contact" if self.root_stress is None else "root"
                factor = run_force_factor(result, i, pair, stress=stress)
            stressed = _contacts(
                result, i, pair, self.gear, teeth, self.root_stress, gear_a, factor
            )
            contacts.append((stressed, teeth.flank))
        for side in (1, -1):
            self._loaded[side] |= any(bool(np.any(flank == side)) for _, flank in contacts)
            # Samples on the other flank leave this one unloaded.
            self._passes[side].add([c.unloaded_where(flank != side) for c, flank in contacts])

    def end(self) -> dict[int, np.ndarray]:
        """The histories end (`ToothPasses.close`): each loaded flank's tooth peaks.

        Peaks [Pa], (teeth,), by flank. No block may follow. The last cycles of each tooth
        flank go where the others went (``cycles_to``), and its counter is let go; a second
        call gives the same peaks.
        """
        for side in (1, -1):
            self._passes[side].close()
            if not self._loaded[side] or side in self._peaks:
                continue
            streams = self._streams[side]
            peaks = []
            for j in range(self.teeth):
                last = streams[j].end()
                if last.ranges.size:
                    self._cycles_to(side, j, last)
                peaks.append(streams[j].largest)
                streams[j] = CycleStream()  # its residue let go
            self._peaks[side] = np.array(peaks, dtype=float)
        return dict(self._peaks)

    def damage(
        self, *, curve: FatigueCurve, time_factor: float, use_endurance_limit: bool = True
    ) -> tuple[ToothDamage, ...]:
        """The damage of each flank loaded in the blocks so far, the most damaged first.

        The histories end here (`end`): no block may follow. Each tooth flank's cycles are
        counted as its history comes (`pinwind.life.cycles.CycleStream`) and held here (not
        with ``cycles_to``, which holds them instead).

        Raises:
            InputError: the cycles went to ``cycles_to``.
        """
        if self._cycles_to != self._keep:
            raise InputError(
                f"gear {self.gear}: its cycles went to cycles_to, not held for damage; rate them "
                "where they went (CaseReduction.save), or count without cycles_to"
            )
        rated = []
        for side, peaks in self.end().items():
            cycles = []
            for parts in self._parts[side]:
                if len(parts) != 1:  # joined once, then held as one
                    parts[:] = [_joined(parts)]
                cycles.append(parts[0])
            rated.append(
                cycles_damage(
                    cycles,
                    list(peaks),
                    gear=self.gear,
                    curve=curve,
                    time_factor=time_factor,
                    use_endurance_limit=use_endurance_limit,
                    flank=side,
                )
            )
        return tuple(sorted(rated, key=lambda d: -d.worst))


def _joined(parts: Sequence[Cycles]) -> Cycles:
    """Cycles given in parts, in order, as one."""
    return Cycles(
        ranges=np.concatenate([np.zeros(0), *(c.ranges for c in parts)]),
        means=np.concatenate([np.zeros(0), *(c.means for c in parts)]),
        counts=np.concatenate([np.zeros(0), *(c.counts for c in parts)]),
    )


def _contacts(
    result: Result,
    index: int,
    pair: GearPair,
    gear: str,
    teeth: EnteringTeeth,
    root_stress: RootStress | None,
    gear_a: str,
    factor: np.ndarray | None = None,
) -> ToothContacts | HelicalContacts:
    """The teeth of ``gear`` at mesh ``index`` and their stresses, contact or root.

    ``gear_a``: the mesh's gear A (the root stress of its side or of gear B's); ``factor``:
    the force factor of the peak line load per sample (`peak_line_load.force_factor`), or
    None for the force spread evenly.
    """
    if pair.helix_angle != 0.0:
        return _helical_contacts(result, index, pair, gear, teeth, root_stress, factor)
    position = result.mesh_contact_position[:, index]
    single = np.abs(result.mesh_single_tooth_force[:, index])
    normal = np.abs(result.mesh_normal[:, index])
    ahead = position + pair.path.base_pitch
    if factor is not None:
        single, normal = single * factor, normal * factor  # so normal − single is scaled too
    if root_stress is None:
        entering = contact_stress(pair, force=single, position=position).von_mises
        leading = contact_stress(pair, force=normal - single, position=ahead).von_mises
    else:
        side = 1 if gear == gear_a else 2
        entering = root_stress.stress(pair, side, force=single, position=position)
        leading = root_stress.stress(pair, side, force=normal - single, position=ahead)
    return ToothContacts(
        tooth=teeth.tooth,
        leading_tooth=teeth.leading_tooth,
        entering=np.nan_to_num(entering),
        leading=np.nan_to_num(leading),
        pairs=result.mesh_pairs[:, index],
    )


def _helical_contacts(
    result: Result,
    index: int,
    pair: GearPair,
    gear: str,
    teeth: EnteringTeeth,
    root_stress: RootStress | None,
    factor: np.ndarray | None = None,
) -> HelicalContacts:
    """The teeth of ``gear`` at helical mesh ``index`` with the stress of the mesh force.

    ``factor``: as `_contacts`, on the mesh force.
    """
    force = np.abs(result.mesh_normal[:, index])
    if factor is not None:
        force = force * factor
    normal = pair.flank_normal_force(force)
    if root_stress is None:
        stress = VON_MISES_RATIO * helical_contact_stress(pair, force=normal)
    else:
        side = 1 if gear == pair.names[0] else 2
        stress = root_stress.mesh_stress(pair, side, force=normal)
    return HelicalContacts(
        tooth=teeth.tooth,
        leading_tooth=teeth.leading_tooth,
        stress=np.nan_to_num(stress),
        pairs=np.asarray(result.mesh_pairs[:, index]).astype(int),
        teeth=pair.teeth_1 if gear == pair.names[0] else pair.teeth_2,
    )
