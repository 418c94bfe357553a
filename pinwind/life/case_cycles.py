"""A load case reduced: the rainflow cycles of every tooth flank and root, and bearing sums.

Each case of a fatigue set (`pinwind.life.fatigue_set.LoadCase`) is run with a log in the set's
output folder and, beside it, its reduction (`CaseCycles`, ``.npz``): the rainflow cycles of
every tooth flank of every meshed gear (`pinwind.life.tooth_damage`) from ``skip_start`` on, of
the contact (von Mises) stress and of the root stress of the fillet on the flank's side
(`pinwind.life.root_stress`), and each bearing's ISO 281 load sums
(`pinwind.life.bearing_life.BearingLoadSum`), which the set adds over its bins into each
bearing's L10h over the site's life (`pinwind.life.set_bearing_life`).
"""

from __future__ import annotations

import dataclasses
import json
import math
import zipfile
import zlib
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from pinwind.errors import InputError
from pinwind.life.bearing_life import BearingLoadSum
from pinwind.life.fatigue_set import LoadCase
from pinwind.life.root_stress import RootStress
from pinwind.life.sn_curve import FatigueCurve

if TYPE_CHECKING:
    from pinwind.dynamics.result import Result
    from pinwind.life.tooth_damage import GearTeeth
    from pinwind.model.bearing_life_data import BearingLifeData
    from pinwind.model.gearbox import Gearbox


@dataclass(frozen=True)
class FlankCycles:
    """The rainflow cycles of one flank of every tooth of a gear, in a case's counted history.

    Attributes:
        gear: the gear.
        flank: +1 or −1 (`pinwind.life.tooth_damage.EnteringTeeth.flank`); of a root, the
            loaded flank whose side's fillet it is.
        teeth: the gear's tooth count.
        tooth: the tooth of each cycle, (n,).
        ranges: the stress range of each cycle [Pa], (n,): von Mises contact stress, or the
            root stress σ_F.
        counts: 1 or 0.5 (half cycles), (n,).
        peaks: the largest stress of each tooth [Pa], (teeth,).
    """

    gear: str
    flank: int
    teeth: int
    tooth: np.ndarray
    ranges: np.ndarray
    counts: np.ndarray
    peaks: np.ndarray

    def damage(self, curve: FatigueCurve, *, use_endurance_limit: bool = True) -> np.ndarray:
        """Palmgren-Miner damage of each tooth from these cycles, time factor 1 [-], (teeth,)."""
        life = curve.cycles_to_failure(self.ranges, use_endurance_limit=use_endurance_limit)
        return np.bincount(self.tooth, weights=self.counts / life, minlength=self.teeth)


@dataclass(frozen=True)
class CaseCycles:
    """A case reduced: the cycles of every flank of every gear, and what the run was.

    Attributes:
        case: the case.
        key: `FatigueSet.case_key` of the inputs it was made from.
        counted_seconds: length of the counted history [s].
        wall_time: seconds the case took to run and reduce.
        flanks: the contact-stress cycles of each loaded flank of each gear.
        roots: the root-stress cycles of the fillet of each loaded flank of each gear.
        bearings: each bearing's ISO 281 load sums over the counted history.
        cpu_time: CPU seconds of the process meanwhile, all its threads (the log writer's
            too); over ``wall_time``, the cores the case kept busy (NaN: not recorded).
        thread_time: CPU seconds of the thread that ran the case (the step loop, the
            counting); ``cpu_time`` over it is the cores the case keeps busy on free cores.
        log_sha256: SHA-256 of the case's log as the run wrote it ("": not recorded), so that
            a log changed since (a flipped byte) is found (`case_done`).
    """

    case: LoadCase
    key: str
    counted_seconds: float
    wall_time: float
    flanks: tuple[FlankCycles, ...] = field(default_factory=tuple)
    roots: tuple[FlankCycles, ...] = field(default_factory=tuple)
    bearings: tuple[BearingLoadSum, ...] = field(default_factory=tuple)
    cpu_time: float = math.nan
    thread_time: float = math.nan
    log_sha256: str = ""

    def save(self, path: Path) -> None:
        """Write it as ``.npz`` (written whole under another name, then renamed)."""
        arrays: dict[str, Any] = {}
        for prefix, group in (("", self.flanks), ("root_", self.roots)):
            for i, f in enumerate(group):
                arrays |= {
                    f"{prefix}{i}_tooth": f.tooth,
                    f"{prefix}{i}_ranges": f.ranges,
                    f"{prefix}{i}_counts": f.counts,
                    f"{prefix}{i}_peaks": f.peaks,
                }
        meta = {
            "case": dataclasses.asdict(self.case),
            "key": self.key,
            "counted_seconds": self.counted_seconds,
            "wall_time": self.wall_time,
            "cpu_time": self.cpu_time,
            "thread_time": self.thread_time,
            "log_sha256": self.log_sha256,
            "flanks": [[f.gear, f.flank, f.teeth] for f in self.flanks],
            "roots": [[f.gear, f.flank, f.teeth] for f in self.roots],
            "bearings": [dataclasses.asdict(b) for b in self.bearings],
        }
        partial = path.with_name(path.name + ".partial.npz")
        arrays["meta"] = np.array(json.dumps(meta))
        np.savez_compressed(partial, **arrays)
        partial.replace(path)

    @classmethod
    def load(cls, path: Path, *, with_flanks: bool = True) -> CaseCycles:
        """Read one written by `save`.

        Args:
            with_flanks: read the tooth cycles too (without: ``flanks`` is empty, and only the
                small record of the case and its bearing sums is read).

        Raises:
            InputError: not readable as one.
        """
        try:
            with np.load(path) as data:
                meta = json.loads(str(data["meta"]))
                flanks, roots = (
                    tuple(
                        FlankCycles(
                            gear,
                            flank,
                            teeth,
                            data[f"{prefix}{i}_tooth"],
                            data[f"{prefix}{i}_ranges"],
                            data[f"{prefix}{i}_counts"],
                            data[f"{prefix}{i}_peaks"],
                        )
                        for i, (gear, flank, teeth) in enumerate(
                            meta.get(group, []) if with_flanks else []
                        )
                    )
                    for prefix, group in (("", "flanks"), ("root_", "roots"))
                )
                bearings = tuple(BearingLoadSum(**b) for b in meta.get("bearings", []))
        except (OSError, ValueError, KeyError, TypeError, zipfile.BadZipFile, zlib.error) as err:
            raise InputError(
                f"{path}: not a fatigue case reduction, or a damaged one ({err}); delete it and "
                "run the set again, which computes that case again"
            ) from err
        return cls(
            LoadCase(**meta["case"]),
            meta["key"],
            meta["counted_seconds"],
            meta["wall_time"],
            flanks,
            roots,
            bearings,
            meta.get("cpu_time", math.nan),
            meta.get("thread_time", math.nan),
            meta.get("log_sha256", ""),
        )


def case_cycles(
    result: Result,
    gearbox: Gearbox,
    gears: Iterable[str],
    *,
    materials: Mapping[str, str] | None = None,
    root_stress: Mapping[str, RootStress] | None = None,
    face_load: str = "uniform",
) -> list[FlankCycles]:
    """The rainflow cycles of every flank of every tooth of ``gears`` in a run.

    The histories are those of `pinwind.life.tooth_damage.gear_tooth_damage` (von Mises
    contact stress at the moving contact point, per tooth over all its meshes), or with
    ``root_stress`` (gear → model) its root stress. The whole run is one block of the
    `GearTeeth` counters `CaseReduction` feeds block by block.

    Args:
        materials: gear → material key (default `materials.DEFAULT_MATERIAL`).
        root_stress: count the root stress of each gear with its model instead.
        face_load: ``"uniform"`` or ``"run"`` (`pinwind.life.tooth_damage.GearTeeth`).
    """
    from pinwind.life.tooth_damage import GearTeeth

    counters = [
        GearTeeth(
            gearbox,
            gear,
            materials=materials,
            root_stress=None if root_stress is None else root_stress[gear],
            face_load=face_load,
        )
        for gear in gears
    ]
    for counter in counters:
        counter.add(result)
    return flank_cycles(counters)


def flank_cycles(counters: Iterable[GearTeeth]) -> list[FlankCycles]:
    """The cycles of every flank of each gear counted, the most damaged (at unit curve) first.

    The histories end here (`GearTeeth.damage`).
    """
    from pinwind.life.sn_curve import SNCurve

    # The curve is not used: only the counted cycles are kept.
    unit = SNCurve(reference_stress=1.0, slope_exponent=1.0)
    out = []
    for counter in counters:
        for rated in counter.damage(curve=unit, time_factor=1.0):
            tooth = np.concatenate(
                [np.full(c.ranges.size, j, dtype=np.int32) for j, c in enumerate(rated.cycles)]
            )
            out.append(
                FlankCycles(
                    gear=counter.gear,
                    flank=rated.flank,
                    teeth=len(rated.cycles),
                    tooth=tooth,
                    ranges=np.concatenate([c.ranges for c in rated.cycles]),
                    counts=np.concatenate([c.counts for c in rated.cycles]),
                    peaks=rated.peak_stress,
                )
            )
    return out


class CaseReduction:
    """A case's run reduced block by block as it runs: tooth cycles and bearing load sums.

    Each block (`add`, a Result of `CASE_SERIES` of consecutive kept samples, the first from
    the case's ``skip_start`` on) goes to a `GearTeeth` counter per gear, of the contact and of
    the root stress, and to the bearings' and rows' `life_sums.RunLoadSums`; `reduced` gives
    what `case_cycles` and `life_sums.run_load_sums` give of the blocks joined. Only each tooth
    flank's reversals and the sums are held, so a case's memory does not grow with its length
    but by its reversals (``pinwind.runs.kept_blocks`` feeds it during the run).

    Args:
        gearbox: the model the case runs.
        gears: the gears whose teeth are counted.
        materials: gear → material key (default `materials.DEFAULT_MATERIAL`).
        root_stress: gear → its root-stress model.
        bearing_life: each bearing's and row's life data by its rated name (None: the model's).
        face_load: ``"uniform"`` or ``"run"`` (`pinwind.life.tooth_damage.GearTeeth`): the
            run's peak line load needs ``mesh_face_load_factor`` in the blocks.
    """

    def __init__(
        self,
        gearbox: Gearbox,
        gears: Iterable[str],
        *,
        materials: Mapping[str, str] | None,
        root_stress: Mapping[str, RootStress],
        bearing_life: Mapping[str, BearingLifeData] | None = None,
        face_load: str = "uniform",
    ) -> None:
        from pinwind.life.life_sums import RunLoadSums
        from pinwind.life.tooth_damage import GearTeeth

        gears = list(gears)
        self.contact = [
            GearTeeth(gearbox, g, materials=materials, face_load=face_load) for g in gears
        ]
        self.root = [
            GearTeeth(
                gearbox, g, materials=materials, root_stress=root_stress[g], face_load=face_load
            )
            for g in gears
        ]
        self.bearings = RunLoadSums(gearbox, life=bearing_life)

    def begin(self, result: Result) -> None:
        """Refuse a run the tooth counters cannot read, before it steps (its metadata).

        Raises:
            FactorNotInRun: ``face_load="run"`` and a mesh of a counted gear not cut into
                slices (`GearTeeth.check_run`).
        """
        for counter in self.contact:
            counter.check_run(result)

    def add(self, block: Result) -> None:
        """The next kept samples of the case (`CASE_SERIES`)."""
        for counter in (*self.contact, *self.root):
            counter.add(block)
        self.bearings.add(block)

    def reduced(
        self,
    ) -> tuple[tuple[FlankCycles, ...], tuple[FlankCycles, ...], tuple[BearingLoadSum, ...]]:
        """(flanks, roots, bearings) of `CaseCycles` over the blocks given.

        No block may follow, nor another call: each gear's counter is let go once its cycles
        are out, so that the memory holds the cycles and the reversals not yet counted, not
        both.
        """
        return (
            tuple(flank_cycles(_let_go(self.contact))),
            tuple(flank_cycles(_let_go(self.root))),
            tuple(self.bearings.sums()),
        )


def _let_go(counters: list[GearTeeth]) -> Iterator[GearTeeth]:
    """The counters in order, each taken out of the list as it is given."""
    while counters:
        yield counters.pop(0)
