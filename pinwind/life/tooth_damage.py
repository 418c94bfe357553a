"""Stress history and fatigue damage of every tooth of a gear, from a compliant run.

Jørgensen 2014 (003_83d3049daebcd276.txt) §3.1 counts the stress of one mesh at one chosen
point of the path and spreads it over the teeth with a time factor (Table 3). Here each tooth
gets its own history instead, so damage is per tooth and the worst tooth is found:

- A mesh logs, per sample, the roll position x of its entering tooth pair from gear A's base
  tangency point (``mesh_contact_position``), the force on that pair (``mesh_single_tooth_force``),
  the mesh force F_n (``mesh_normal``) and the pairs in contact (``mesh_pairs``). With two pairs,
  the pair one base pitch p_b ahead, at x + p_b, carries F_n minus the entering pair's force.
- x grows as the gears roll and jumps back by p_b when the next pair enters, so counting the
  jumps numbers the teeth in the order they enter (`entering_teeth`): tooth k + 1 enters after
  tooth k, on either gear of the pair.
- A tooth's history is the stress at its moving contact point while it is in contact, with a
  zero between its passes through the mesh(es); rainflow (`pinwind.life.cycles`) then counts one
  cycle per pass (of the largest stress on the flank that pass) plus the smaller ones within it.
  That rates each pass by the flank's most stressed point, which is conservative where that
  point moves from pass to pass (Jørgensen 2014 follows one fixed point instead).
- Damage is Palmgren-Miner (`pinwind.life.sn_curve`, Jørgensen 2014 eq. 2) of those cycles times
  the plain time factor h · 3600 / T_sim (Table 2): each tooth's own cycles need no division by
  the teeth or multiplication by the meshes (Table 3 does both to spread one mesh's cycles).

The teeth are numbered per mesh from the tooth entering at the first sample (0). A gear in
several meshes (a sun or a planet) has its meshes' numberings joined by ``first_teeth``: the
tooth in each mesh's entering pair at the first sample (it follows from the gears' tooth
phases, `pinwind.model.phasing`, and their angles at that sample; not derived here yet).
Without it each mesh counts from 0, which is right for a gear in one mesh and, for a gear in
several, gives the same cycles but may pair a tooth's passes at one mesh with another tooth's
at the next.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from pinwind.errors import InputError
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.materials import Material
from pinwind.life.contact_stress import contact_stress
from pinwind.life.cycles import Cycles, rainflow_cycles
from pinwind.life.sn_curve import SNCurve, miner_damage

if TYPE_CHECKING:
    from pinwind.dynamics.result import Result
    from pinwind.model.gearbox import Gearbox


def entering_teeth(
    contact_position: npt.ArrayLike, *, base_pitch: float, teeth: int, first_tooth: int = 0
) -> np.ndarray:
    """Which of a gear's teeth is in a mesh's entering pair at each sample, in entering order.

    A jump of x back by about p_b is the next tooth entering (+1), a jump forward by about p_b
    the previous one entering again as the gears turn back (−1). The samples must follow the
    roll closely: x may move less than p_b / 2 between samples (at least two samples per mesh
    period; a stress history needs many more).

    Args:
        contact_position: x, the roll position of the entering pair [m], (n,).
        base_pitch: p_b [m].
        teeth: the gear's tooth count.
        first_tooth: the tooth entering at the first sample.

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
    return (first_tooth + np.concatenate([[0], np.cumsum(entered)])) % teeth


@dataclass(frozen=True)
class ToothContacts:
    """A gear's teeth in contact at one mesh, per sample.

    Attributes:
        tooth: the gear's tooth in the entering pair (`entering_teeth`), (n,).
        entering: stress (or load) on the entering pair, (n,).
        leading: stress (or load) on the pair one base pitch ahead, the tooth before in
            entering order, (n,).
        pairs: tooth pairs in contact, 1 or 2, (n,); ``leading`` counts only where it is 2.
    """

    tooth: np.ndarray
    entering: np.ndarray
    leading: np.ndarray
    pairs: np.ndarray


def tooth_histories(contacts: Sequence[ToothContacts], *, teeth: int) -> list[np.ndarray]:
    """The history of each tooth of a gear over all its meshes, in time order.

    A tooth's history holds its values while it is in contact (entering, then leading) at any
    of the meshes, with a 0 before, between and after its passes: out of contact it is unloaded.

    Args:
        contacts: one per mesh of the gear, all over the same samples.
        teeth: the gear's tooth count.

    Returns:
        ``teeth`` arrays, the history of tooth 0, 1, ...

    Raises:
        InputError: three or more pairs in contact (a contact ratio of 2 or more), which the
            logged series do not resolve.
    """
    tooth_of, sample_of, mesh_of, value_of = [], [], [], []
    for m, c in enumerate(contacts):
        pairs = np.asarray(c.pairs)
        if np.any(pairs > 2):
            raise InputError(
                f"mesh {m} has {int(np.max(pairs))} tooth pairs in contact at times; the logged "
                "series give the forces of the entering pair and, by difference, of one more: "
                "per-tooth histories need a contact ratio below 2"
            )
        samples = np.arange(len(c.tooth))
        two = pairs == 2
        tooth_of += [np.asarray(c.tooth), (np.asarray(c.tooth)[two] - 1) % teeth]
        sample_of += [samples, samples[two]]
        mesh_of += [np.full(samples.size, m), np.full(int(np.sum(two)), m)]
        value_of += [np.asarray(c.entering, dtype=float), np.asarray(c.leading, dtype=float)[two]]
    tooth = np.concatenate(tooth_of).astype(int)
    sample = np.concatenate(sample_of)
    mesh = np.concatenate(mesh_of)
    value = np.concatenate(value_of)
    order = np.lexsort((mesh, sample, tooth))
    tooth, sample, mesh, value = tooth[order], sample[order], mesh[order], value[order]
    histories = []
    for j in range(teeth):
        rows = slice(*np.searchsorted(tooth, [j, j + 1]))
        at, where, v = sample[rows], mesh[rows], value[rows]
        # A pass ends where the tooth skips a sample or moves to another mesh.
        breaks = np.flatnonzero((np.diff(at) > 1) | (np.diff(where) != 0)) + 1
        parts = np.split(v, breaks)
        history = [np.zeros(1)]
        for part in parts:
            history += [part, np.zeros(1)]
        histories.append(np.concatenate(history) if v.size else np.zeros(1))
    return histories


@dataclass(frozen=True)
class ToothDamage:
    """Fatigue damage of each tooth of a gear.

    Attributes:
        gear: the gear's name.
        damage: Palmgren-Miner damage of each tooth over the hours the time factor stands for
            [-], (teeth,).
        cycles: rainflow cycles of each tooth's simulated history, before the time factor.
        peak_stress: largest stress of each tooth in the simulated history [Pa], (teeth,).
    """

    gear: str
    damage: np.ndarray
    cycles: tuple[Cycles, ...]
    peak_stress: np.ndarray

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
    curve: SNCurve,
    time_factor: float,
    use_endurance_limit: bool = True,
) -> ToothDamage:
    """Rainflow and Palmgren-Miner damage of each tooth's stress history.

    Args:
        histories: stress history of each tooth [Pa] (`tooth_histories`).
        gear: the gear's name, for the record.
        curve: the S-N curve, read at the cycle ranges.
        time_factor: life seconds per simulated second, h · 3600 / T_sim (`site.time_factor`).
        use_endurance_limit: False to count cycles below the endurance limit too.
    """
    counted = tuple(rainflow_cycles(history) for history in histories)
    damage = [
        miner_damage(c.scaled(time_factor), curve, use_endurance_limit=use_endurance_limit)
        for c in counted
    ]
    peaks = [float(np.max(history)) for history in histories]
    return ToothDamage(gear, np.array(damage), counted, np.array(peaks))


def gear_tooth_damage(
    result: Result,
    gearbox: Gearbox,
    gear: str,
    *,
    curve: SNCurve,
    time_factor: float,
    materials: Mapping[str, Material | str] | None = None,
    first_teeth: Mapping[str, int] | None = None,
    use_endurance_limit: bool = True,
) -> ToothDamage:
    """Contact-stress damage of every tooth of a gear over all its meshes in a compliant run.

    The stress is σ_vM ≈ 0.65 p_max of the Hertz pressure at the moving contact point
    (`pinwind.life.contact_stress`, Jørgensen 2014 eqs. 20-22), the S-N curve's stress.

    Args:
        result: the run (every sample of it, each mesh rolling on one flank).
        gearbox: its model.
        gear: the gear's name.
        curve: S-N curve of the gear's flanks (e.g. `sn_curve.jorgensen_2014_curve`).
        time_factor: life seconds per simulated second, h · 3600 / T_sim (`site.time_factor`).
        materials: gear name → material (default `materials.DEFAULT_MATERIAL`).
        first_teeth: mesh name → the gear's tooth in that mesh's entering pair at the first
            sample (module docstring); 0 for a mesh not given.
        use_endurance_limit: False to count cycles below the endurance limit too.

    Raises:
        InputError: no mesh has the gear, a mesh without a path of contact, a mesh that
            changes flank during the run, or a contact ratio of 2 or more.
    """
    chosen = dict(materials or {})
    starts = dict(first_teeth or {})
    contacts, teeth = [], 0
    for i, mesh in enumerate(gearbox.meshes):
        if gear not in (mesh.gear_a.name, mesh.gear_b.name):
            continue
        if mesh.path is None:
            raise InputError(
                f'mesh "{mesh.name}" has no path of contact (its gear data give none), so its '
                "teeth cannot be tracked; fix its teeth, module or profile shifts"
            )
        flank = result.mesh_flank[:, i]
        if np.any(flank != flank[0]):
            k = int(np.flatnonzero(flank != flank[0])[0])
            raise InputError(
                f'mesh "{mesh.name}" changes flank at t = {result.time[k]:.6g} s; tooth tracking '
                "follows one flank: take the samples on one flank (Result.take)"
            )
        spec = mesh.gear_a.spec if mesh.gear_a.name == gear else mesh.gear_b.spec
        teeth = spec.teeth
        pair = GearPair.from_gears(mesh.gear_a.spec, mesh.gear_b.spec, dict(chosen))
        position = result.mesh_contact_position[:, i]
        single = np.abs(result.mesh_single_tooth_force[:, i])
        normal = np.abs(result.mesh_normal[:, i])
        base_pitch = mesh.path.base_pitch
        entering = contact_stress(pair, force=single, position=position).von_mises
        leading = contact_stress(pair, force=normal - single, position=position + base_pitch)
        contacts.append(
            ToothContacts(
                tooth=entering_teeth(
                    position,
                    base_pitch=base_pitch,
                    teeth=teeth,
                    first_tooth=starts.get(mesh.name, 0),
                ),
                entering=np.nan_to_num(entering),
                leading=np.nan_to_num(leading.von_mises),
                pairs=result.mesh_pairs[:, i],
            )
        )
    if not contacts:
        names = sorted({g.name for m in gearbox.meshes for g in (m.gear_a, m.gear_b)})
        raise InputError(f'no mesh has a gear "{gear}"; meshed gears are: {", ".join(names)}')
    return histories_damage(
        tooth_histories(contacts, teeth=teeth),
        gear=gear,
        curve=curve,
        time_factor=time_factor,
        use_endurance_limit=use_endurance_limit,
    )
