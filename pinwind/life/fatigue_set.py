"""A fatigue set: its load cases over a site's wind, and how each is run and rated.

Jørgensen 2014 §3-4: one compliant run per wind bin, its contact-stress
cycles counted and scaled to the bin's hours over the design life (Tables 1-3), Palmgren-Miner
per gear (Table 7), and the same again at each turbulence intensity (Table 8). One load case is
a wind bin × a turbulence level × a seed (`LoadCase`); the set (`FatigueSet`) holds the bins,
levels and seeds, the run values every case shares and the curves its gears are rated with.
It is read from a scenario file (`pinwind.runs.fatigue_set_file`), its cases run and reduced
(`pinwind.runs.case_runner`, `pinwind.life.case_cycles`) and rated
(`pinwind.life.set_damage`).

Cycles are kept, not damage, so that any S-N curve is applied afterwards, and the damage is
linear in the counts: a case's life damage is its counted damage times the time factor
h · 3600 / (T_sim − skip_start) of its bin (Table 2), averaged over the seeds of the bin (each
seed stands for all of the bin's hours), summed over the bins.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pinwind.life.root_stress import RootStress
from pinwind.life.site import WindSite
from pinwind.life.sn_curve import FatigueCurve

if TYPE_CHECKING:
    from pinwind.model.bearing import BearingRating
    from pinwind.model.bearing_life_data import BearingLifeData


@dataclass(frozen=True)
class TurbulenceLevel:
    """One turbulence setting of a fatigue set: a whole life at these intensities.

    Attributes:
        label: how tables name it (``"10%"``, ``"class B"``).
        intensities: σ_u / U of each wind bin [-].
    """

    label: str
    intensities: tuple[float, ...]


@dataclass(frozen=True)
class LoadCase:
    """One simulation of a fatigue set: a wind bin at a turbulence level with a seed.

    Attributes:
        bin: index of the wind bin.
        speed: its mean wind speed [m/s].
        level: index of the turbulence level.
        turbulence: the intensity of this bin at that level [-].
        seed: the Kaimal seed.
    """

    bin: int
    speed: float
    level: int
    turbulence: float
    seed: int

    @property
    def name(self) -> str:
        """The file stem of the case's log and reduction.

        It names the run's inputs only: two levels with the same intensity in a bin share it.
        """
        return f"v{self.speed:05.2f}_ti{self.turbulence:.4f}_s{self.seed}"


@dataclass(frozen=True)
class OpenFastInput:
    """One OpenFAST output per case, one channel of it as a joint torque.

    Attributes:
        files: file name pattern with ``{speed}``, ``{turbulence}`` and ``{seed}`` fields,
            relative to the scenario file.
        joint: the joint the channel drives.
        channel: the OpenFAST channel (``RotTorq`` in kN·m).
        scale: factor to SI (1000 for kN·m).
    """

    files: str
    joint: str
    channel: str = "RotTorq"
    scale: float = 1000.0

    def file(self, case: LoadCase, base: Path) -> Path:
        """The output file of a case."""
        name = Path(self.files.format(speed=case.speed, turbulence=case.turbulence, seed=case.seed))
        return name if name.is_absolute() else base / name


@dataclass(frozen=True)
class FatigueSet:
    """The load cases of a fatigue set and how to run and rate them (SI units).

    Attributes:
        values: the scenario's run values (everything but ``[fatigue]``), keys normalised.
        source: the scenario file, for messages and the logs.
        base: the folder relative file names are relative to.
        site: the wind bins with their hours.
        levels: the turbulence levels, each a life.
        seeds: the Kaimal seeds.
        duration: simulated time per case [s].
        skip_start: start-up left out of the counted history [s].
        sample_rate: samples per second of the stress histories [Hz].
        out: the folder of the case logs and reductions.
        curves: gear → S-N curve of its contact stress (read at the von Mises stress).
        gears: the meshed gears, in the model's order.
        root_curves: gear → S-N curve of its root stress (default: its contact curve).
        iso_curves: gear → ISO 6336-2's σ_Hlim Z_NT, read at the von Mises stress (the
            ``iso 6336`` variant of `pinwind.life.set_damage`).
        iso_root_curves: gear → ISO 6336-3's σ_Flim Y_ST Y_NT, loaded on one flank.
        materials: gear → its material (``pinwind.gears.materials`` key).
        root_stress: gear → its root-stress model.
        wind: ``"disc"`` or ``"point"``.
        hub_height: [m].
        rotor_joint: the joint of the rotor, or None (OpenFAST input).
        rotor_radius: its radius [m], or None.
        mesh_stiffness, mesh_damping: the meshes' compliance if given [N/m], [N·s/m].
        openfast: OpenFAST input instead of rotor and wind, or None.
        bearings: the model's ``<bearing>`` elements: joint → its ISO 281 data (without C:
            not rated), and their rows' by ``bearing_life.row_name`` (``lss.INP-A``).
        roles: gear → ``"sun"``, ``"planet"`` or ``"ring"`` from the model's topology
            (`pinwind.model.gear_roles`); gears of no planetary stage left out.
        bearing_life: the lubricant, cleanliness, C_u and inside (and a row's size) of each
            bearing and row whose modified and reference sums the cases keep, by the names of
            ``bearings`` (``life/life_sums.py``).
        face_load: ``"uniform"`` (each pair's force spread evenly across the face) or
            ``"run"`` (at the run's peak line load, ``mesh_face_load_factor``:
            `pinwind.life.peak_line_load`), for the contact and root stresses.
    """

    values: dict[str, Any]
    source: str
    base: Path
    site: WindSite
    levels: tuple[TurbulenceLevel, ...]
    seeds: tuple[int, ...]
    duration: float
    skip_start: float
    sample_rate: float
    out: Path
    curves: dict[str, FatigueCurve]
    gears: tuple[str, ...]
    wind: str = "disc"
    hub_height: float = 80.0
    rotor_joint: str | None = None
    rotor_radius: float | None = None
    mesh_stiffness: float | None = None
    mesh_damping: float | None = None
    openfast: OpenFastInput | None = None
    root_curves: dict[str, FatigueCurve] = field(default_factory=dict)
    iso_curves: dict[str, FatigueCurve] = field(default_factory=dict)
    iso_root_curves: dict[str, FatigueCurve] = field(default_factory=dict)
    materials: dict[str, str] = field(default_factory=dict)
    root_stress: dict[str, RootStress] = field(default_factory=dict)
    bearings: Mapping[str, BearingRating] = field(default_factory=dict)
    roles: dict[str, str] = field(default_factory=dict)
    bearing_life: Mapping[str, BearingLifeData] = field(default_factory=dict)
    face_load: str = "uniform"

    @property
    def dt(self) -> float:
        """The cases' time step [s] (the scenario's ``dt``)."""
        return float(self.values.get("dt", 1e-3))

    @property
    def counted_seconds(self) -> float:
        """Length of each case's counted history, T_sim − skip_start [s]."""
        return self.duration - self.skip_start

    def cases(self) -> list[LoadCase]:
        """Every case: levels, then bins, then seeds."""
        return [
            LoadCase(bin=b, speed=w.speed, level=k, turbulence=level.intensities[b], seed=seed)
            for k, level in enumerate(self.levels)
            for b, w in enumerate(self.site.bins)
            for seed in self.seeds
        ]

    def log_path(self, case: LoadCase) -> Path:
        """The case's MCAP log."""
        return self.out / f"{case.name}.mcap"

    def cycles_path(self, case: LoadCase) -> Path:
        """The case's reduction (`CaseCycles`)."""
        return self.out / f"{case.name}.npz"

    def case_values(self, case: LoadCase) -> dict[str, Any]:
        """The scenario values of a case's run."""
        dt = self.dt
        values = {
            **self.values,
            "duration": self.duration,
            "keep": max(1, round(1.0 / (self.sample_rate * dt))),
            "out": str(self.log_path(case).resolve()),
            "force": True,
            "no_log": False,
        }
        if self.openfast is not None:
            path = self.openfast.file(case, self.base)
            spec = (
                f'openfast(file="{path}", channel="{self.openfast.channel}", '
                f"scale={self.openfast.scale!r})"
            )
            values["torque"] = {**values.get("torque", {}), self.openfast.joint: spec}
            values.pop("rotor", None)
            values.pop("wind", None)
            return values
        radius = f", rotor_radius={self.rotor_radius!r}" if self.wind == "disc" else ""
        values["wind"] = (
            f"kaimal(mean={case.speed!r}, turbulence_intensity={case.turbulence!r}, "
            f"seed={case.seed}, duration={max(600.0, self.duration)!r}, "
            f"hub_height={self.hub_height!r}{radius})"
        )
        return values

    def case_key(self, case: LoadCase) -> str:
        """What a case's reduction was made from: its run values and how they were read."""
        record: dict[str, Any] = {
            "values": self.case_values(case),
            "skip_start": self.skip_start,
            "mesh_stiffness": self.mesh_stiffness,
            "mesh_damping": self.mesh_damping,
            "reduction": "contact and root cycles of each tooth flank; bearing sums: basic, "
            "modified, reference",
            "materials": self.materials,
            "root_stress": {g: r.describe() for g, r in self.root_stress.items()},
            # The load sums depend on each bearing's type and load factors (not on C).
            "bearings": {
                name: [r.kind, r.exponent, r.e, r.y1, r.x2, r.y2]
                for name, r in sorted(self.bearings.items())
            },
            # Their modified and reference sums on the lubricant and inside (not on C).
            "bearing_life": {name: repr(d) for name, d in sorted(self.bearing_life.items())},
        }
        if self.face_load != "uniform":  # the keys of sets made before it stay the same
            record["face_load"] = self.face_load
        record["values"].pop("out")
        text = json.dumps(record, sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()[:16]
