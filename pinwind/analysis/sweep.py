"""Design sweep of a planetary stage (000_3b7c4a8fe52a6eee.txt §5, Table 5, eq. 41).

1. `enumerate_planetary`: every buildable stage for the given centre distances and modules:
   whole tooth numbers with z_sun + z_planet = 2 a/m, z_ring = z_sun + 2 z_planet (no profile
   shift, 000 §4.1), equally spaced planets ((z_sun + z_ring)/N whole) and a speed ratio
   i = 1 + z_ring/z_sun strictly inside the window (lo, hi). Designs given in ``include`` (the
   paper's preliminary 24/48/120 at 15 mm, i = 6 exactly, on the window's edge) are added and
   numbered first in their (module, centre distance) group, as Table 5 numbers #38 before #39.
2. `evaluate`: build each design with `model.builder.planetary_urdf`, run a short rigid
   simulation under the carrier torque (sun loaded with −T/i, so the stage is in torque
   balance), rate every mesh (`analysis.rating.rate`, ISO 6336 and AGMA 2001) and record a row.
   A design that fails to build, simulate or rate is a row with ``status = "failed"`` and the
   reason; geometry findings (`gears.checks.check_planetary`) are listed in ``findings``.
3. `run_sweep`: all local cores (processes) or a Dask cluster, a progress bar, rows written to
   a checkpoint as they finish; a re-run skips the designs already in the output or checkpoint.
   The rows do not depend on the backend: each design is computed on its own, the same way.

Why the window is open: with the paper's inputs every (a, m) group that assembles has a design
at i = 6 exactly (z_sun = (z_sun + z_planet)/3) and two have one at 6.4 (480 mm with 5 and
10 mm); Table 5 lists none of them but the preliminary design. So Table 5 is (6, 6.4) open plus
the preliminary design; `TABLE_5_INCLUDE` holds it.
"""

from __future__ import annotations

import json
import math
import time
import traceback
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path

from pinwind.errors import InputError

#: Below this many designs a default sweep runs in this process (see `run_sweep`).
SERIAL_BELOW = 256
#: The preliminary design of 000 (Table 2): (sun, planet, ring, module [m]).
TABLE_5_INCLUDE = ((24, 48, 120, 0.015),)


@dataclass(frozen=True)
class PlanetaryDesign:
    """One candidate planetary stage (SI units).

    Attributes:
        number: design number, 1… in enumeration order (Table 5's "#").
        centre_distance: a = m (z_sun + z_planet)/2 [m].
        module: m [m].
        sun, planet, ring: tooth numbers.
        planets: number of planets.
        ratio: i = 1 + z_ring/z_sun (carrier to sun, ring fixed).
        included: added by ``include`` rather than found in the window.
    """

    number: int
    centre_distance: float
    module: float
    sun: int
    planet: int
    ring: int
    planets: int
    ratio: float
    included: bool = False


def enumerate_planetary(
    centre_distances: Iterable[float],
    modules: Iterable[float],
    *,
    ratio_window: tuple[float, float],
    planets: int = 3,
    include: Iterable[tuple[int, int, int, float]] = (),
) -> list[PlanetaryDesign]:
    """Every buildable design, numbered by module, then centre distance, then sun teeth.

    Args:
        centre_distances: candidate centre distances a [m].
        modules: candidate modules m [m].
        ratio_window: (lo, hi): keep lo < i < hi (open, see the module docstring).
        planets: number of planets N.
        include: extra designs (sun, planet, ring, module [m]) kept whatever their ratio; they
            must still be buildable (ring = sun + 2 planet, equal spacing).

    Raises:
        InputError: an empty or reversed window, a non-positive value, or an ``include`` that
            cannot be built.
    """
    lo, hi = ratio_window
    if not lo < hi:
        raise InputError(f"the ratio window {lo}:{hi} is empty; give LOW:HIGH with LOW < HIGH")
    if planets < 1:
        raise InputError(f"planets = {planets}; give at least one planet")
    extra: dict[tuple[float, float], list[tuple[int, int, int]]] = {}
    for sun, planet, ring, module in include:
        if ring != sun + 2 * planet or (sun + ring) % planets:
            raise InputError(
                f"included design {sun}/{planet}/{ring} cannot be built: the ring needs "
                f"sun + 2·planet = {sun + 2 * planet} teeth and (sun + ring)/{planets} must be "
                "whole"
            )
        a = module * (sun + planet) / 2.0
        extra.setdefault((_key(module), _key(a)), []).append((sun, planet, ring))
    designs: list[PlanetaryDesign] = []
    for module in sorted(set(modules)):
        for a in sorted(set(centre_distances)):
            if module <= 0 or a <= 0:
                raise InputError(f"module {module} m and centre distance {a} m must be positive")
            group = []
            for sun, planet, ring in extra.get((_key(module), _key(a)), []):
                group.append((sun, planet, ring, True))
            teeth = 2.0 * a / module
            total = round(teeth)
            if abs(teeth - total) < 1e-9 * max(teeth, 1.0):
                for sun in range(1, total):
                    planet = total - sun
                    ring = sun + 2 * planet
                    ratio = 1.0 + ring / sun
                    if (sun + ring) % planets or not lo < ratio < hi:
                        continue
                    if any(g[0] == sun for g in group):
                        continue
                    group.append((sun, planet, ring, False))
            for sun, planet, ring, included in group:
                designs.append(
                    PlanetaryDesign(
                        number=len(designs) + 1,
                        centre_distance=a,
                        module=module,
                        sun=sun,
                        planet=planet,
                        ring=ring,
                        planets=planets,
                        ratio=1.0 + ring / sun,
                        included=included,
                    )
                )
    return designs


def _key(value: float) -> float:
    """A length rounded to the micrometre, to match designs by value."""
    return round(value * 1e6)


@dataclass(frozen=True)
class SweepSettings:
    """How each design is built, loaded, simulated and rated (one set for every design).

    Attributes:
        carrier_torque: input torque on the carrier [N·m].
        carrier_speed: carrier speed [rad/s] (initial speed of the run; for dynamic factors).
        pressure_angle: normal pressure angle [rad] (000: 24.5°).
        face_width: face width [m] when ``face_width_factor`` is None (000: 380 mm).
        face_width_factor: k in b = k π m (AGMA's 3…5 circular pitches), else None.
        material: gear material key (`gears.materials.MATERIALS`).
        duration: simulated time [s] of each rigid run.
        dt: time step [s].
    """

    carrier_torque: float = 1e6
    carrier_speed: float = 14.2 * math.pi / 30.0
    pressure_angle: float = math.radians(24.5)
    face_width: float = 0.38
    face_width_factor: float | None = None
    material: str = "18CrNiMo7-6"
    duration: float = 0.01
    dt: float = 1e-3

    def width(self, module: float) -> float:
        """Face width of a design of module ``module`` [m]."""
        if self.face_width_factor is None:
            return self.face_width
        return self.face_width_factor * math.pi * module


#: Columns of a sweep row, in order (units in the names).
COLUMNS = (
    "number", "centre_distance_mm", "module_mm", "sun", "planet", "ring", "planets", "ratio",
    "face_width_mm", "included", "status", "reason", "findings",
    "sun_planet_normal_force_kN", "sun_planet_tangential_force_kN", "planet_ring_normal_force_kN",
    "agma_contact_stress_sun_planet_MPa", "agma_contact_stress_planet_ring_MPa",
    "agma_bending_stress_max_MPa",
    "agma_SF_contact_sun_planet", "agma_SF_contact_planet_ring", "agma_SF_bending_min",
    "agma_SF_bending_sun", "agma_SF_bending_planet", "agma_SF_bending_ring", "agma_SF_min",
    "iso_sigma_H_sun_planet_MPa", "iso_sigma_H_planet_ring_MPa", "iso_sigma_F_max_MPa",
    "iso_S_H_sun_planet", "iso_S_H_planet_ring", "iso_S_F_min", "iso_S_min",
    "hertz_p_max_sun_planet_MPa", "hertz_p_max_planet_ring_MPa",
    "wall_time_s",
)  # fmt: skip


def evaluate(design: PlanetaryDesign, settings: SweepSettings) -> dict:
    """Build, simulate and rate one design; a failure is a row with its reason.

    Runs in a worker process or on a Dask worker: it imports what it needs and returns plain
    values only.
    """
    start = time.perf_counter()
    row: dict = {c: math.nan for c in COLUMNS}
    row.update(
        number=design.number,
        centre_distance_mm=design.centre_distance * 1e3,
        module_mm=design.module * 1e3,
        sun=design.sun,
        planet=design.planet,
        ring=design.ring,
        planets=design.planets,
        ratio=design.ratio,
        face_width_mm=settings.width(design.module) * 1e3,
        included=design.included,
        status="ok",
        reason="",
        findings="",
    )
    stage = "building"
    try:
        import warnings

        from pinwind.analysis.rating import rate
        from pinwind.dynamics.simulate import simulate
        from pinwind.gears.checks import check_planetary
        from pinwind.model.builder import planetary_urdf
        from pinwind.model.gearbox import loads

        findings = check_planetary(
            sun=design.sun, planet=design.planet, ring=design.ring, planets=design.planets,
            module=design.module, pressure_angle=settings.pressure_angle,
        )  # fmt: skip
        row["findings"] = "; ".join(f"{f.severity}: {f.message}" for f in findings)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            text = planetary_urdf(
                sun=design.sun, planet=design.planet, ring=design.ring, planets=design.planets,
                module=design.module, pressure_angle=settings.pressure_angle,
                face_width=settings.width(design.module), name=f"design{design.number}",
            )  # fmt: skip
            gearbox = loads(text, f"design #{design.number}")
            stage = "simulating"
            result = simulate(
                gearbox, duration=settings.duration, dt=settings.dt,
                torques={"carrier": settings.carrier_torque,
                         "sun": -settings.carrier_torque / design.ratio},
                initial_speeds={"carrier": settings.carrier_speed},
            )  # fmt: skip
        stage = "rating"
        rating = rate(gearbox, result, materials={g: settings.material for g in gearbox.gears})
    except Exception as err:  # noqa: BLE001 (a design's failure is data, not a crash)
        row["status"] = "failed"
        detail = str(err) or type(err).__name__
        if not isinstance(err, pinwind_error_types()):
            detail = f"{type(err).__name__}: {detail} ({traceback.format_exc(limit=1).strip()})"
        row["reason"] = f"{stage}: {detail}"
        row["wall_time_s"] = time.perf_counter() - start
        return row
    row.update(_rating_columns(rating))
    row["wall_time_s"] = time.perf_counter() - start
    return row


def evaluate_batch(designs: Sequence[PlanetaryDesign], settings: SweepSettings) -> list[dict]:
    """`evaluate` on each design of a batch (one worker task)."""
    return [evaluate(d, settings) for d in designs]


def pinwind_error_types() -> tuple[type, ...]:
    """Error types whose message is enough on its own."""
    from pinwind.errors import PinwindError

    return (PinwindError,)


def _rating_columns(rating) -> dict:
    sp = [m for m in rating.meshes if m.mesh.startswith("sun_planet")]
    pr = [m for m in rating.meshes if m.mesh.endswith("_ring")]
    gears = rating.gears
    planets = [g for name, g in gears.items() if name.startswith("planet")]

    def low(items):
        return float(min(items))

    out = {
        "sun_planet_normal_force_kN": max(m.normal_force for m in sp) / 1e3,
        "sun_planet_tangential_force_kN": max(m.load.tangential_force for m in sp) / 1e3,
        "planet_ring_normal_force_kN": max(m.normal_force for m in pr) / 1e3,
        "agma_contact_stress_sun_planet_MPa": max(max(m.agma.contact_stress) for m in sp) / 1e6,
        "agma_contact_stress_planet_ring_MPa": max(max(m.agma.contact_stress) for m in pr) / 1e6,
        "agma_bending_stress_max_MPa": max(max(m.agma.bending_stress) for m in rating.meshes) / 1e6,
        "agma_SF_contact_sun_planet": low(s for m in sp for s in m.agma.S_H),
        "agma_SF_contact_planet_ring": low(s for m in pr for s in m.agma.S_H),
        "agma_SF_bending_min": low(s for m in rating.meshes for s in m.agma.S_F),
        "agma_SF_bending_sun": gears["sun"].S_F_agma,
        "agma_SF_bending_planet": low(g.S_F_agma for g in planets),
        "agma_SF_bending_ring": gears["ring"].S_F_agma,
        "iso_sigma_H_sun_planet_MPa": max(max(m.iso.sigma_H) for m in sp) / 1e6,
        "iso_sigma_H_planet_ring_MPa": max(max(m.iso.sigma_H) for m in pr) / 1e6,
        "iso_sigma_F_max_MPa": max(max(m.iso.sigma_F) for m in rating.meshes) / 1e6,
        "iso_S_H_sun_planet": low(s for m in sp for s in m.iso.S_H),
        "iso_S_H_planet_ring": low(s for m in pr for s in m.iso.S_H),
        "iso_S_F_min": low(s for m in rating.meshes for s in m.iso.S_F),
        "hertz_p_max_sun_planet_MPa": max(m.hertz_p_max for m in sp) / 1e6,
        "hertz_p_max_planet_ring_MPa": max(m.hertz_p_max for m in pr) / 1e6,
    }
    out["agma_SF_min"] = min(
        out["agma_SF_contact_sun_planet"], out["agma_SF_contact_planet_ring"],
        out["agma_SF_bending_min"],
    )  # fmt: skip
    out["iso_S_min"] = min(
        out["iso_S_H_sun_planet"], out["iso_S_H_planet_ring"], out["iso_S_F_min"]
    )
    return out


# --- running many designs -----------------------------------------------------------------------


@dataclass
class SweepRun:
    """Rows of a sweep and how they were obtained.

    Attributes:
        rows: one dict per design (`COLUMNS`), ordered by design number.
        computed: how many designs were computed in this call (the rest were reused).
        wall_time: seconds for this call.
        backend: ``"serial"``, ``"processes (N)"`` or ``"dask (ADDRESS)"``.
    """

    rows: list[dict] = field(default_factory=list)
    computed: int = 0
    wall_time: float = 0.0
    backend: str = ""


def design_key(row_or_design) -> tuple:
    """What identifies a design across runs: geometry and planets (lengths in µm)."""
    if isinstance(row_or_design, PlanetaryDesign):
        d = row_or_design
        return (_key(d.centre_distance), _key(d.module), d.sun, d.planet, d.ring, d.planets)
    r = row_or_design
    return (
        round(float(r["centre_distance_mm"]) * 1e3),
        round(float(r["module_mm"]) * 1e3),
        int(r["sun"]),
        int(r["planet"]),
        int(r["ring"]),
        int(r["planets"]),
    )


def run_sweep(
    designs: Sequence[PlanetaryDesign],
    settings: SweepSettings,
    *,
    workers: int | None = None,
    scheduler: str | object | None = None,
    checkpoint: Path | None = None,
    done: Iterable[dict] = (),
    progress: Callable[[int, int], None] | None = None,
) -> SweepRun:
    """Evaluate designs on local processes or a Dask cluster; skip those already ``done``.

    Args:
        designs: from `enumerate_planetary`.
        settings: one set of settings for every design.
        workers: local worker processes (default: all cores, except that fewer than
            `SERIAL_BELOW` designs run in this process: starting the pool and importing pinwind
            in each worker takes about a second, 200 designs' worth; 1 always runs here).
        scheduler: a Dask scheduler address (``tcp://host:8786``) or a ``distributed.Client``;
            overrides ``workers``.
        checkpoint: JSON-lines file; each finished row is appended as soon as it arrives.
        done: rows of an earlier run; designs with the same `design_key` (and face width) are
            not recomputed, and their rows are kept.
        progress: called as progress(finished, total) after each design.
    """
    import os

    start = time.perf_counter()
    previous = {}
    for row in done:
        previous[design_key(row)] = row
    rows: dict[int, dict] = {}
    todo = []
    for d in designs:
        old = previous.get(design_key(d))
        if old is not None and math.isclose(
            float(old["face_width_mm"]), settings.width(d.module) * 1e3, rel_tol=1e-9
        ):
            rows[d.number] = {**old, "number": d.number}
        else:
            todo.append(d)
    total, finished = len(designs), len(rows)
    if progress:
        progress(finished, total)
    sink = checkpoint.open("a", encoding="utf-8") if checkpoint is not None else None

    def accept(row: dict) -> None:
        nonlocal finished
        rows[int(row["number"])] = row
        finished += 1
        if sink is not None:
            sink.write(json.dumps(row) + "\n")
            sink.flush()
        if progress:
            progress(finished, total)

    try:
        if scheduler is not None:
            backend = _run_dask(todo, settings, scheduler, accept)
        else:
            n = workers or (1 if len(todo) < SERIAL_BELOW else os.cpu_count() or 1)
            backend = _run_local(todo, settings, n, accept)
    finally:
        if sink is not None:
            sink.close()
    ordered = [rows[k] for k in sorted(rows)]
    return SweepRun(ordered, len(todo), time.perf_counter() - start, backend)


def _run_local(todo, settings, n: int, accept) -> str:
    if n <= 1 or len(todo) <= 1:
        for d in todo:
            accept(evaluate(d, settings))
        return "serial"
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor, as_completed

    # "spawn" keeps the workers free of the parent's threads (rerun, dask) and their locks.
    # Batches of a few designs per task: each design takes milliseconds, so one task per design
    # would spend its time in inter-process traffic; small batches keep the progress bar live.
    size = max(1, min(16, len(todo) // (8 * n)))
    batches = [todo[i : i + size] for i in range(0, len(todo), size)]
    with ProcessPoolExecutor(max_workers=n, mp_context=mp.get_context("spawn")) as pool:
        futures = [pool.submit(evaluate_batch, batch, settings) for batch in batches]
        try:
            for future in as_completed(futures):
                for row in future.result():
                    accept(row)
        except BaseException:
            for future in futures:
                future.cancel()
            raise
    return f"processes ({n})"


def _run_dask(todo, settings, scheduler, accept) -> str:
    try:
        from distributed import Client, as_completed
    except ImportError as err:  # pragma: no cover - distributed is a dependency
        raise InputError("--scheduler needs dask.distributed: pip install distributed") from err
    own = not isinstance(scheduler, Client)
    client = Client(scheduler) if own else scheduler
    try:
        futures = client.map(evaluate, todo, settings=settings, pure=False)
        for future in as_completed(futures):
            accept(future.result())
    finally:
        if own:
            client.close()
    return f"dask ({client.scheduler.address if client.scheduler else scheduler})"


# --- tables -------------------------------------------------------------------------------------


def write_table(rows: Sequence[dict], path: Path) -> Path:
    """Write rows as CSV, or Parquet when the suffix is ``.parquet``."""
    import pyarrow as pa

    table = pa.Table.from_pylist([{c: r.get(c) for c in COLUMNS} for r in rows])
    path = Path(path)
    if path.suffix == ".parquet":
        import pyarrow.parquet as pq

        pq.write_table(table, path)
    else:
        import pyarrow.csv as pc

        pc.write_csv(table, path)
    return path


def read_table(path: Path) -> list[dict]:
    """Rows of a table written by `write_table` (CSV or Parquet)."""
    path = Path(path)
    if not path.exists():
        raise InputError(f"{path}: no such sweep table; run pinwind sweep planetary first")
    if path.suffix == ".parquet":
        import pyarrow.parquet as pq

        table = pq.read_table(path)
    else:
        import pyarrow.csv as pc

        table = pc.read_csv(path)
    rows = table.to_pylist()
    for row in rows:
        for k in ("reason", "findings"):
            if row.get(k) is None:
                row[k] = ""
    return rows


def read_checkpoint(path: Path) -> list[dict]:
    """Rows of a checkpoint (JSON lines); a torn last line is ignored."""
    rows = []
    if not Path(path).exists():
        return rows
    for line in Path(path).read_text(encoding="utf-8").splitlines():
        try:
            rows.append(json.loads(line))
        except json.JSONDecodeError:
            continue
    return rows


# --- eq. 41: picking designs ----------------------------------------------------------------------


def query(
    rows: Iterable[dict],
    *,
    centre_distance: float | None = None,
    ratio: float | None = None,
    ratio_tolerance: float = 0.05,
    module: float | None = None,
    min_sf: float | None = None,
    sf_column: str = "agma_SF_min",
    minimise: str | None = None,
) -> list[dict]:
    """Designs that satisfy every given criterion (000 eq. 41: a ∪ i ∪ m ∪ SF).

    Args:
        rows: sweep rows.
        centre_distance: required centre distance [m] (matched to the micrometre).
        ratio: required speed ratio, matched within ``ratio_tolerance`` (the paper's 6.3 picks
            6.32 and not 6.15).
        module: required module [m].
        min_sf: smallest acceptable safety factor: ``row[sf_column] > min_sf`` (the paper's
            "SF > 1"); failed designs never pass.
        sf_column: which safety factor (default the smallest AGMA one of the design).
        minimise: a column to minimise (``"centre_distance_mm"``, ``"module_mm"``, ...); only
            the designs at its smallest value are returned.
    """
    keep = []
    for row in rows:
        if row.get("status") != "ok":
            continue
        if centre_distance is not None and round(float(row["centre_distance_mm"]) * 1e3) != round(
            centre_distance * 1e6
        ):
            continue
        if module is not None and round(float(row["module_mm"]) * 1e3) != round(module * 1e6):
            continue
        if ratio is not None and abs(float(row["ratio"]) - ratio) > ratio_tolerance:
            continue
        if min_sf is not None and not float(row[sf_column]) > min_sf:
            continue
        keep.append(row)
    if minimise and keep:
        if minimise not in keep[0]:
            raise InputError(f'--minimise "{minimise}": not a column; columns are {COLUMNS}')
        best = min(float(r[minimise]) for r in keep)
        keep = [r for r in keep if float(r[minimise]) == best]
    return keep


def design_from_row(row: dict) -> PlanetaryDesign:
    """The design of a row."""
    return PlanetaryDesign(
        number=int(row["number"]),
        centre_distance=float(row["centre_distance_mm"]) * 1e-3,
        module=float(row["module_mm"]) * 1e-3,
        sun=int(row["sun"]),
        planet=int(row["planet"]),
        ring=int(row["ring"]),
        planets=int(row["planets"]),
        ratio=float(row["ratio"]),
        included=bool(row["included"]),
    )


def settings_dict(settings: SweepSettings) -> dict:
    """Settings as plain values (for messages and metadata)."""
    return asdict(settings)
