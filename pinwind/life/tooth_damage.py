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
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
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
from pinwind.life.cycles import Cycles, rainflow_cycles
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
    A pass through a helical mesh (`HelicalContacts`) keeps one value, its largest.

    Args:
        contacts: one per mesh of the gear, all over the same samples.
        teeth: the gear's tooth count.

    Returns:
        ``teeth`` arrays, the history of tooth 0, 1, ...

    Raises:
        InputError: three or more pairs in contact at a spur mesh (a contact ratio of 2 or
            more), which the logged series do not resolve.
    """
    tooth_of, sample_of, mesh_of, value_of, peak_of = [], [], [], [], []
    for m, c in enumerate(contacts):
        tooth_m, sample_m, value_m = c.loads(m)
        tooth_of.append(tooth_m)
        sample_of.append(sample_m)
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
    histories = []
    for j in range(teeth):
        rows = slice(*np.searchsorted(tooth, [j, j + 1]))
        at, where, v = sample[rows], mesh[rows], value[rows]
        # A pass ends where the tooth skips a sample or moves to another mesh: a 0 between
        # passes (one insert for all of them, not a list of parts: a tooth has thousands).
        breaks = np.flatnonzero((np.diff(at) > 1) | (np.diff(where) != 0)) + 1
        if np.any(peak[rows]):
            v, breaks = _pass_peaks(v, breaks, peak[rows])
        passes = np.insert(v, breaks, 0.0)
        histories.append(np.concatenate(([0.0], passes, [0.0])) if v.size else np.zeros(1))
    return histories


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
    damage = [
        miner_damage(c.scaled(time_factor), curve, use_endurance_limit=use_endurance_limit)
        for c in counted
    ]
    peaks = [float(np.max(history)) for history in histories]
    return ToothDamage(gear, np.array(damage), counted, np.array(peaks), flank)


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
    spec = gearbox.meshes[i]
    if gear not in (spec.gear_a.name, spec.gear_b.name):
        raise InputError(
            f'gear "{gear}" is not in mesh "{mesh}"; its gears are {spec.gear_a.name} and '
            f"{spec.gear_b.name}"
        )
    if spec.path is None:
        raise InputError(
            f'mesh "{mesh}" has no path of contact (its gear data give none), so its teeth '
            "cannot be tracked; fix its teeth, module or profile shifts"
        )
    wheel = spec.gear_a if spec.gear_a.name == gear else spec.gear_b
    _check_samples_follow_the_roll(result, gearbox, i)
    position = result.mesh_contact_position[:, i]
    loaded = result.mesh_flank[:, i]
    tooth = np.empty(len(position), dtype=int)
    leading = np.empty(len(position), dtype=int)
    flank = np.empty(len(position), dtype=int)
    cuts = [0, *(np.flatnonzero(np.diff(loaded) != 0) + 1).tolist(), len(position)]
    for start, stop in zip(cuts[:-1], cuts[1:], strict=True):
        first, direction, side = _entering_tooth(result, gearbox, i, wheel, start)
        tooth[start:stop] = entering_teeth(
            position[start:stop],
            base_pitch=spec.path.base_pitch,
            teeth=wheel.spec.teeth,
            first_tooth=first,
            direction=direction,
        )
        leading[start:stop] = (tooth[start:stop] - direction) % wheel.spec.teeth
        flank[start:stop] = side
    return EnteringTeeth(tooth, leading, flank)


def _check_samples_follow_the_roll(result: Result, gearbox: Gearbox, index: int) -> None:
    """Refuses samples too far apart to tell which tooth enters (`entering_teeth`).

    Between two samples the contact rolls |ω_A − ω_line| r_b,A Δt along the line of action
    (`pinwind.analysis.spectrum.mesh_roll_speeds`, the faster of the two samples' speeds);
    from half a base pitch on, a tooth entering cannot be told from the previous one coming
    back, and the tooth histories would silently mix teeth.

    Raises:
        InputError: the roll between two samples reaches half a base pitch, with the time,
            the speed and the sample rate that would follow it.
    """
    from pinwind.analysis.spectrum import mesh_roll_speeds

    mesh = gearbox.meshes[index]
    if mesh.path is None or len(result.time) < 2:
        return
    omega = np.abs(mesh_roll_speeds(gearbox, result.speed)[:, index])
    faster = np.maximum(omega[1:], omega[:-1])
    roll = faster * abs(mesh.base_radius_a) * np.diff(result.time)
    worst = int(np.argmax(roll))
    pitch = mesh.path.base_pitch
    if roll[worst] >= 0.5 * pitch:
        rate = 2.0 * faster[worst] * abs(mesh.base_radius_a) / pitch
        raise InputError(
            f'mesh "{mesh.name}": between samples at t = {result.time[worst]:.6g} s its teeth '
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
    data = model.createData()
    pin.computeJointJacobiansTimeVariation(model, data, q, np.zeros(model.nv))
    meshes = MeshSet(gearbox)
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

    Returns:
        The damage of each flank (or its root fillet) in contact during the run, the most
        damaged first.

    Raises:
        InputError: no mesh has the gear, or as `mesh_teeth`; a spur mesh with a contact ratio
            of 2 or more; a helical mesh with ε_β < 1 (`contact_stress.require_full_overlap`)
            or a root-stress table on one.
    """
    chosen = dict(materials or {})
    contacts: list[tuple[ToothContacts | HelicalContacts, np.ndarray]] = []
    teeth = 0
    for i, mesh in enumerate(gearbox.meshes):
        if gear not in (mesh.gear_a.name, mesh.gear_b.name):
            continue
        entering_teeth_of = mesh_teeth(result, gearbox, mesh.name, gear)
        teeth = (mesh.gear_a if mesh.gear_a.name == gear else mesh.gear_b).spec.teeth
        pair = GearPair.from_gears(mesh.gear_a.spec, mesh.gear_b.spec, dict(chosen))
        if pair.helix_angle != 0.0:
            contacts.append(
                (
                    _helical_contacts(result, i, pair, gear, entering_teeth_of, root_stress),
                    entering_teeth_of.flank,
                )
            )
            continue
        position = result.mesh_contact_position[:, i]
        single = np.abs(result.mesh_single_tooth_force[:, i])
        normal = np.abs(result.mesh_normal[:, i])
        ahead = position + pair.path.base_pitch
        if root_stress is None:
            entering = contact_stress(pair, force=single, position=position).von_mises
            leading = contact_stress(pair, force=normal - single, position=ahead).von_mises
        else:
            side = 1 if gear == mesh.gear_a.name else 2
            entering = root_stress.stress(pair, side, force=single, position=position)
            leading = root_stress.stress(pair, side, force=normal - single, position=ahead)
        contact = ToothContacts(
            tooth=entering_teeth_of.tooth,
            leading_tooth=entering_teeth_of.leading_tooth,
            entering=np.nan_to_num(entering),
            leading=np.nan_to_num(leading),
            pairs=result.mesh_pairs[:, i],
        )
        contacts.append((contact, entering_teeth_of.flank))
    if not contacts:
        names = sorted({g.name for m in gearbox.meshes for g in (m.gear_a, m.gear_b)})
        raise InputError(f'no mesh has a gear "{gear}"; meshed gears are: {", ".join(names)}')
    rated = []
    for side in (1, -1):
        if not any(np.any(flank == side) for _, flank in contacts):
            continue
        # Samples on the other flank leave this one unloaded.
        on_side = [c.unloaded_where(flank != side) for c, flank in contacts]
        rated.append(
            histories_damage(
                tooth_histories(on_side, teeth=teeth),
                gear=gear,
                curve=curve,
                time_factor=time_factor,
                use_endurance_limit=use_endurance_limit,
                flank=side,
            )
        )
    return tuple(sorted(rated, key=lambda d: -d.worst))


def _helical_contacts(
    result: Result,
    index: int,
    pair: GearPair,
    gear: str,
    teeth: EnteringTeeth,
    root_stress: RootStress | None,
) -> HelicalContacts:
    """The teeth of ``gear`` at helical mesh ``index`` with the stress of the mesh force."""
    normal = pair.flank_normal_force(np.abs(result.mesh_normal[:, index]))
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
