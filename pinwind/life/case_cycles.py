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
import shutil
import tempfile
import weakref
import zipfile
import zlib
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any, Protocol

import numpy as np

from pinwind.errors import InputError
from pinwind.life.bearing_life import BearingLoadSum
from pinwind.life.fatigue_set import LoadCase
from pinwind.life.root_stress import RootStress
from pinwind.life.sn_curve import FatigueCurve

if TYPE_CHECKING:
    from pinwind.dynamics.result import Result
    from pinwind.life.cycles import Cycles
    from pinwind.life.tooth_damage import GearTeeth
    from pinwind.model.bearing_life_data import BearingLifeData
    from pinwind.model.gearbox import Gearbox


class _Flank(Protocol):
    """What the saved record names of a flank (`CaseCycles.save`)."""

    @property
    def gear(self) -> str: ...
    @property
    def flank(self) -> int: ...
    @property
    def teeth(self) -> int: ...


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
        partial = path.with_name(path.name + ".partial.npz")
        arrays["meta"] = np.array(json.dumps(self._meta(self.flanks, self.roots)))
        np.savez_compressed(partial, **arrays)
        partial.replace(path)

    def _meta(self, flanks: Iterable[_Flank], roots: Iterable[_Flank]) -> dict[str, Any]:
        """The record saved beside the arrays (``meta``), of these flanks and roots."""
        return {
            "case": dataclasses.asdict(self.case),
            "key": self.key,
            "counted_seconds": self.counted_seconds,
            "wall_time": self.wall_time,
            "cpu_time": self.cpu_time,
            "thread_time": self.thread_time,
            "log_sha256": self.log_sha256,
            "flanks": [[f.gear, f.flank, f.teeth] for f in flanks],
            "roots": [[f.gear, f.flank, f.teeth] for f in roots],
            "bearings": [dataclasses.asdict(b) for b in self.bearings],
        }

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


def saved_flanks(path: Path, group: str = "flanks") -> Iterator[FlankCycles]:
    """The flanks (``"flanks"``) or roots (``"roots"``) of a case `CaseCycles.save` wrote.

    Read one at a time as they are asked for, so that a case's cycles are not in memory at
    once (`CaseCycles.load` reads them all).

    Raises:
        InputError: not readable as one.
    """
    try:
        with np.load(path) as data:
            prefix = "" if group == "flanks" else "root_"
            for i, (gear, flank, teeth) in enumerate(json.loads(str(data["meta"])).get(group, [])):
                yield FlankCycles(
                    gear,
                    flank,
                    teeth,
                    data[f"{prefix}{i}_tooth"],
                    data[f"{prefix}{i}_ranges"],
                    data[f"{prefix}{i}_counts"],
                    data[f"{prefix}{i}_peaks"],
                )
    except (OSError, ValueError, KeyError, TypeError, zipfile.BadZipFile, zlib.error) as err:
        raise InputError(
            f"{path}: not a fatigue case reduction, or a damaged one ({err}); delete it and "
            "run the set again, which computes that case again"
        ) from err


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
    what `case_cycles` and `life_sums.run_load_sums` give of the blocks joined. Each tooth
    flank's history is rainflow-counted as it comes (`pinwind.life.cycles.CycleStream`) and
    its cycles appended to a file of its own, in a folder of its own under the system's
    temporary folder, as they close; `save` writes the case's ``.npz`` from those files a
    tooth at a time. A bearing row with a clearance or a preload keeps its samples in a file
    of that folder until the end (``life_sums.HistoryStream``). So the memory held is the
    counters' residues and the sums, whatever the case's length (``pinwind.runs.kept_blocks``
    feeds it during the run). The folder goes with `save`, `reduced`, `close` or the
    reduction itself.

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
        self.folder = Path(tempfile.mkdtemp(prefix="pinwind-case-cycles-"))
        self._remove = weakref.finalize(self, shutil.rmtree, self.folder, ignore_errors=True)
        self._files = {
            kind: [_ToothFiles(self.folder / f"{kind}{i}") for i in range(len(gears))]
            for kind in ("contact", "root")
        }
        self.contact = [
            GearTeeth(
                gearbox,
                g,
                materials=materials,
                face_load=face_load,
                cycles_to=self._files["contact"][i].append,
            )
            for i, g in enumerate(gears)
        ]
        self.root = [
            GearTeeth(
                gearbox,
                g,
                materials=materials,
                root_stress=root_stress[g],
                face_load=face_load,
                cycles_to=self._files["root"][i].append,
            )
            for i, g in enumerate(gears)
        ]
        self.bearings = RunLoadSums(gearbox, life=bearing_life, folder=self.folder)

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

    def _flanks(self, kind: str) -> list[_FlankFiles]:
        """The flanks of each gear counted, the most damaged (at unit curve) first.

        As `flank_cycles` orders them; the histories end here.
        """
        counters = self.contact if kind == "contact" else self.root
        out: list[_FlankFiles] = []
        for counter, files in zip(counters, self._files[kind], strict=True):
            flanks = [
                _FlankFiles(counter.gear, side, counter.teeth, files, peaks)
                for side, peaks in counter.end().items()
            ]
            out += sorted(flanks, key=lambda f: -f.worst_at_unit_curve())
        return out

    def reduced(
        self,
    ) -> tuple[tuple[FlankCycles, ...], tuple[FlankCycles, ...], tuple[BearingLoadSum, ...]]:
        """(flanks, roots, bearings) of `CaseCycles` over the blocks given, in memory.

        No block may follow, nor another call: the cycles' files are read and removed. A
        case's `save` writes the same without holding them.
        """
        try:
            return (
                tuple(f.cycles() for f in self._flanks("contact")),
                tuple(f.cycles() for f in self._flanks("root")),
                tuple(self.bearings.sums()),
            )
        finally:
            self.close()

    def save(self, path: Path, record: CaseCycles) -> None:
        """Write the case's ``.npz`` as `CaseCycles.save` writes it, from the cycles' files.

        ``record`` gives the case, key, times and log digest (its flanks, roots and bearings
        are not read: the reduction's are written). Each array is written into the file a
        tooth's cycles at a time (no more in memory), with `CaseCycles.save`'s names, format
        and compression, so that `CaseCycles.load` reads it as the same case. No block may
        follow, nor another call: the cycles' files are removed.
        """
        try:
            flanks, roots = self._flanks("contact"), self._flanks("root")
            whole = dataclasses.replace(
                record, flanks=(), roots=(), bearings=tuple(self.bearings.sums())
            )
            partial = path.with_name(path.name + ".partial.npz")
            with zipfile.ZipFile(partial, mode="w", compression=zipfile.ZIP_DEFLATED) as npz:
                for prefix, group in (("", flanks), ("root_", roots)):
                    for i, f in enumerate(group):
                        for name, dtype, size, parts in f.arrays():
                            with npz.open(f"{prefix}{i}_{name}.npy", "w", force_zip64=True) as out:
                                _write_npy(out, dtype, size, parts)
                with npz.open("meta.npy", "w", force_zip64=True) as out:
                    meta = np.array(json.dumps(whole._meta(flanks, roots)))
                    np.lib.format.write_array(out, meta, allow_pickle=False)
            partial.replace(path)
        finally:
            self.close()

    def close(self) -> None:
        """Remove the cycles' files (done by `save`, `reduced`, or when it is let go)."""
        self._remove()


class _ToothFiles:
    """The cycles of each tooth flank of a gear, one file each.

    (range [Pa], count) pairs as native float64, appended as they close, in the order counted.
    """

    def __init__(self, stem: Path) -> None:
        self.stem = stem

    def path(self, side: int, tooth: int) -> Path:
        """The file of a tooth of flank ``side``."""
        return self.stem.with_name(f"{self.stem.name}_{side:+d}_{tooth}.f8")

    def append(self, side: int, tooth: int, cycles: Cycles) -> None:
        """Appends cycles just closed (`GearTeeth` ``cycles_to``)."""
        with self.path(side, tooth).open("ab") as f:
            np.column_stack((cycles.ranges, cycles.counts)).tofile(f)

    def read(self, side: int, tooth: int) -> tuple[np.ndarray, np.ndarray]:
        """(ranges, counts) of a tooth of flank ``side``, in the order counted."""
        path = self.path(side, tooth)
        pairs = np.fromfile(path, dtype=float) if path.exists() else np.zeros(0)
        return pairs[0::2].copy(), pairs[1::2].copy()

    def size(self, side: int, tooth: int) -> int:
        """Cycles of a tooth of flank ``side``."""
        path = self.path(side, tooth)
        return path.stat().st_size // 16 if path.exists() else 0


@dataclass(frozen=True)
class _FlankFiles:
    """One flank of a gear whose cycles are in files (`_ToothFiles`), with its tooth peaks."""

    gear: str
    flank: int
    teeth: int
    files: _ToothFiles
    peaks: np.ndarray

    def worst_at_unit_curve(self) -> float:
        """The largest tooth damage at the unit curve, as `flank_cycles` orders flanks."""
        from pinwind.life.cycles import Cycles
        from pinwind.life.sn_curve import SNCurve, miner_damage

        unit = SNCurve(reference_stress=1.0, slope_exponent=1.0)
        damage = []
        for j in range(self.teeth):  # as `tooth_damage.cycles_damage` at time factor 1
            ranges, counts = self.files.read(self.flank, j)
            damage.append(miner_damage(Cycles(ranges, ranges, counts).scaled(1.0), unit))
        return float(np.max(np.array(damage)))

    def arrays(self) -> Iterator[tuple[str, np.dtype, int, Iterator[np.ndarray]]]:
        """Each array `CaseCycles.save` writes of a flank, in its order.

        (name, dtype, length, its parts in order).
        """
        sizes = [self.files.size(self.flank, j) for j in range(self.teeth)]
        n = sum(sizes)
        teeth = range(self.teeth)
        yield "tooth", np.dtype(np.int32), n, (np.full(k, j, np.int32) for j, k in enumerate(sizes))
        yield "ranges", np.dtype(float), n, (self.files.read(self.flank, j)[0] for j in teeth)
        yield "counts", np.dtype(float), n, (self.files.read(self.flank, j)[1] for j in teeth)
        yield "peaks", self.peaks.dtype, self.peaks.size, iter([self.peaks])

    def cycles(self) -> FlankCycles:
        """The flank's cycles in memory."""
        parts = {name: list(chunks) for name, _, _, chunks in self.arrays()}
        tooth, ranges, counts = (
            np.concatenate(parts[k]) for k in ("tooth", "ranges", "counts")
        )  # fmt: skip
        return FlankCycles(self.gear, self.flank, self.teeth, tooth, ranges, counts, self.peaks)


def _write_npy(out: IO[bytes], dtype: np.dtype, size: int, parts: Iterable[np.ndarray]) -> None:
    """A one-dimensional ``.npy`` of ``size`` values written part by part.

    NumPy's format 1.0, as ``np.save`` writes an array of that size.
    """
    header = {"descr": np.lib.format.dtype_to_descr(dtype), "fortran_order": False,
              "shape": (size,)}  # fmt: skip
    np.lib.format.write_array_header_1_0(out, header)
    written = 0
    for part in parts:
        out.write(np.ascontiguousarray(part, dtype=dtype).tobytes())
        written += part.size
    if written != size:  # the files changed under it
        raise InputError(f"wrote {written} values of an array of {size}; run the case again")
