"""A fatigue set: load cases over a site's wind, simulated, reduced to tooth cycles, and damage.

Jørgensen 2014 (003_83d3049daebcd276.txt) §3-4: one compliant run per wind bin, its contact-stress
cycles counted and scaled to the bin's hours over the design life (Tables 1-3), Palmgren-Miner
per gear (Table 7), and the same again at each turbulence intensity (Table 8). Here a fatigue
set is read from a scenario file (``load_fatigue_set``): the run keys of any scenario
(``pinwind.scenario``: model, dt, rotor, generator, ...) plus a ``[fatigue]`` table::

    [fatigue]
    out = "dtu500_fatigue"              # folder of the case logs (relative to the file)
    duration = 30.0                     # simulated seconds per case [s]
    skip_start = 2.0                    # start-up left out of the counted history [s]
    sample_rate = 10000.0               # samples per second the histories are read at [Hz]
    seeds = [1]                         # Kaimal seeds: one case per seed
    turbulence = [0.08, 0.10]           # intensities (each one life), or "B", or ["A", "B"]
    wind = "disc"                       # "disc": rotor-averaged Kaimal wind; "point": hub point
    hub_height = 36.0                   # [m], sets the Kaimal length scale
    mesh_stiffness = 3.5e9              # single-pair stiffness [N/m] of every mesh (optional)
    mesh_damping = 40e3                 # [N·s/m] (optional)

    [fatigue.site]                      # given hours ...
    speeds = [6, 8, 10]                 # [m/s]
    hours = [45418, 31900, 16320]       # [h] over the design life
    # ... or a Weibull site: scale = 6.62, shape = 2.19, edges = [5, 7, 9, 11],
    #     design_life_years = 20, availability = 1, cut_in = ..., cut_out = ...

    [fatigue.sn_curve]                  # preset = "jorgensen2014" (eq. 23, Table 5 per gear) or
    s0_mpa = 28900                      # s0 [MPa], m, n0 and the endurance limit [MPa]: one
    m = 3.4                             # value or one per gear ({ sun = 800, ring = 550 })
    endurance_limit_mpa = 800           # or preset = "iso6336" (or "iso6336_pitting_permitted"):
                                        # ISO 6336's curves of each gear's material, σ_Hlim and
                                        # σ_Flim from it or sigma_h_lim_mpa, sigma_f_lim_mpa

    [fatigue.materials]                 # gear materials (pinwind.gears.materials keys): E and ν
    ring = "42CrMo4"                    # of the contact, the ISO curves; per gear or kind
                                        # (default 18CrNiMo7-6)

    [fatigue.root_stress]               # root stress per unit force from FEM, per gear or kind
    sun = { position_mm = [30, 40, 50], mpa_per_kn = [0.5, 0.6, 0.7] }   # (or fraction = [...]
                                        # of the active flank); gears not named: ISO 6336-3

    [fatigue.openfast]                  # instead of rotor and wind: one OpenFAST output per
    files = "runs/v{speed:g}_ti{turbulence:g}_s{seed}.outb"   # case, its channel on a joint
    joint = "carrier"
    channel = "RotTorq"
    scale = 1000.0

    [fatigue.quick]                     # what --quick changes (any [fatigue] key, and dt)
    duration = 1.5

One load case is a wind bin × a turbulence level × a seed (`LoadCase`). Each case is run like
any scenario (its values are in its log, which ``pinwind run --from-log`` repeats), with a log
in the output folder and, beside it, its reduction (`CaseCycles`, ``.npz``): the rainflow cycles
of every tooth flank of every meshed gear (`pinwind.life.tooth_damage`) from ``skip_start`` on,
of the contact (von Mises) stress and of the root stress of the fillet on the flank's side
(`pinwind.life.root_stress`), and each bearing's ISO 281 load sums
(`pinwind.life.bearing_life.BearingLoadSum`), which the set adds over its bins into each
bearing's L10h over the site's life (`pinwind.life.set_bearing_life`).
A rerun computes only the cases whose log is missing or incomplete or whose reduction is missing
or was made from other inputs. Cycles are kept, not damage, so that any S-N curve is applied
afterwards, and the damage is linear in the counts: a case's life damage is its counted
damage times the time factor h · 3600 / (T_sim − skip_start) of its bin (Table 2), averaged over
the seeds of the bin (each seed stands for all of the bin's hours), summed over the bins.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import time
import zipfile
import zlib
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from pinwind.errors import InputError, PinwindError
from pinwind.gears.hertz import VON_MISES_RATIO
from pinwind.gears.materials import DEFAULT_MATERIAL, MATERIALS
from pinwind.io.folders import folder_problem
from pinwind.known_names import unknown_message, unknown_name
from pinwind.life.bearing_life import BearingLoadSum, bearing_load_sums
from pinwind.life.root_stress import ISO_ROOT_STRESS, RootStress, table_root_stress
from pinwind.life.site import (
    TURBULENCE_CLASSES,
    WindSite,
    bin_turbulence,
    site_from_hours,
    weibull_site,
)
from pinwind.life.sn_curve import (
    FatigueCurve,
    SNCurve,
    iso6336_contact_curve,
    iso6336_root_curve,
    jorgensen_2014_curve,
)
from pinwind.model.gear_roles import ROLES, gear_roles, gearbox_planetary_gears
from pinwind.scenario import ScenarioError, build, key_line, read_toml

if TYPE_CHECKING:
    from pinwind.dynamics.result import Result
    from pinwind.model.bearing import BearingRating
    from pinwind.model.gearbox import Gearbox

#: The keys of the ``[fatigue]`` table, with what they are.
FATIGUE_KEYS: dict[str, str] = {
    "out": "folder of the case logs",
    "duration": "simulated seconds per case [s]",
    "skip_start": "start-up left out of the counted history [s]",
    "sample_rate": "samples per second the stress histories are read at [Hz]",
    "seeds": "Kaimal seeds, one case each",
    "turbulence": "turbulence intensities, or IEC 61400-1 classes",
    "wind": '"disc" (rotor-averaged) or "point" (hub point) Kaimal wind',
    "hub_height": "hub height [m]",
    "mesh_stiffness": "single-pair mesh stiffness [N/m]",
    "mesh_damping": "mesh damping [N·s/m]",
    "site": "wind bins: speeds and hours, or a Weibull distribution",
    "sn_curve": "S-N curve: a preset or s0_mpa, m, n0, endurance_limit_mpa",
    "materials": "gear materials (pinwind.gears.materials), one or per gear or kind",
    "root_stress": "root stress tables per gear or kind (default: ISO 6336-3 method B)",
    "openfast": "one OpenFAST output per case instead of rotor and wind",
    "quick": "what --quick changes",
}
#: The keys of ``[fatigue.quick]``: the scenario's ``dt`` and any ``[fatigue]`` key.
QUICK_KEYS = ("dt", *(k for k in FATIGUE_KEYS if k != "quick"))
#: The keys of ``[fatigue.site]``: the given hours, or a Weibull site (`pinwind.life.site`).
SITE_HOURS_KEYS = ("speeds", "hours")
SITE_WEIBULL_KEYS = (
    "scale",
    "shape",
    "edges",
    "design_life_years",
    "availability",
    "cut_in",
    "cut_out",
)
#: The keys of ``[fatigue.sn_curve]``: one curve, or a preset with ISO 6336's strengths.
SN_CURVE_KEYS = ("s0_mpa", "m", "n0", "endurance_limit_mpa")
SN_PRESET_KEYS = ("preset", "sigma_h_lim_mpa", "sigma_f_lim_mpa")
#: The keys of ``[fatigue.openfast]`` (`OpenFastInput`) and of a root-stress table.
OPENFAST_KEYS = ("files", "joint", "channel", "scale")
ROOT_STRESS_KEYS = ("position_mm", "fraction", "mpa_per_kn")
#: A rate is a whole number of steps when within this relative distance of one [-].
_WHOLE = 1e-6
#: S-N curve presets: Jørgensen 2014 eq. 23 and Table 5 per gear kind (for contact and root, as
#: 003 applies it), or ISO 6336-2 and -3's life-factor curves of each gear's material.
SN_PRESETS = ("jorgensen2014", "iso6336", "iso6336_pitting_permitted")
#: Gear kinds the presets and per-kind tables know: each gear's role in its planetary stage,
#: found from the model's topology (`pinwind.model.gear_roles`), never from its name.
GEAR_KINDS = ROLES
#: Edges of the cycle-range histogram kept per case and gear, for the figures [Pa].
RANGE_EDGES = np.linspace(0.0, 2000e6, 201)


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
            ``iso 6336`` variant of `pinwind.life.life_damage`).
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
            not rated).
        roles: gear → ``"sun"``, ``"planet"`` or ``"ring"`` from the model's topology
            (`pinwind.model.gear_roles`); gears of no planetary stage left out.
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

    def gear_kind(self, gear: str) -> str | None:
        """``"sun"``, ``"planet"`` or ``"ring"``: the gear's role in its stage, else None."""
        return self.roles.get(gear)

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
            "reduction": "contact and root cycles of each tooth flank",
            "materials": self.materials,
            "root_stress": {g: r.describe() for g, r in self.root_stress.items()},
            # The load sums depend on each bearing's type and load factors (not on C).
            "bearings": {
                name: [r.kind, r.exponent, r.e, r.y1, r.x2, r.y2]
                for name, r in sorted(self.bearings.items())
            },
        }
        record["values"].pop("out")
        text = json.dumps(record, sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()[:16]


# --- reading a fatigue set -----------------------------------------------------------------------


def load_fatigue_set(path: str | Path, *, quick: bool = False) -> FatigueSet:
    """Read and check a fatigue set from a scenario file (module docstring).

    Args:
        path: the TOML file.
        quick: apply its ``[fatigue.quick]`` table (a short version), and write the cases into
            the output folder with ``_quick`` appended.

    Raises:
        ScenarioError: anything wrong, naming the file, the key and its line: a missing model
            or OpenFAST file, a bin without hours, an S-N curve with m ≤ 0 or a negative
            endurance limit, a turbulence intensity ≤ 0, an unknown key, ...
    """
    path = Path(path)
    text, values = read_toml(path)
    return _SetReader(path, text, values, quick).fatigue_set()


class _SetReader:
    """Reads a fatigue set; each error names the key at fault and its line."""

    def __init__(self, path: Path, text: str, values: dict[str, Any], quick: bool):
        self.path, self.text, self.quick = path, text, quick
        self.values = {k.replace("-", "_"): v for k, v in values.items()}
        #: The meshed gears, once the model is read: the names of per-gear tables.
        self.gear_names: tuple[str, ...] = ()
        #: Gear → its role in its planetary stage, from the model's topology.
        self.roles: dict[str, str] = {}

    def fail(self, key: tuple[str, ...], message: str) -> ScenarioError:
        return ScenarioError(str(self.path), ".".join(key), key_line(self.text, key), message)

    def known(self, key: tuple[str, ...], given: Iterable[str], known: Iterable[str]) -> None:
        """Refuse a key of the table ``key`` that is not one of ``known``, naming the nearest."""
        names = tuple(known)
        unknown = unknown_name(given, names)
        if unknown is not None:
            raise self.fail(key + (unknown,), unknown_message(unknown, names))

    def fatigue_set(self) -> FatigueSet:
        table = self.values.pop("fatigue", None)
        if not isinstance(table, Mapping):
            raise self.fail(
                ("fatigue",),
                "a fatigue set needs a [fatigue] table (module "
                "pinwind.life.load_cases says its keys)",
            )
        settings = {k.replace("-", "_"): v for k, v in table.items()}
        self.known(("fatigue",), settings, FATIGUE_KEYS)
        quick = settings.pop("quick", None)
        if quick is not None and not isinstance(quick, Mapping):
            raise self.fail(("fatigue", "quick"), "must be a table of [fatigue] keys")
        quick = {k.replace("-", "_"): v for k, v in (quick or {}).items()}
        self.known(("fatigue", "quick"), quick, QUICK_KEYS)
        if self.quick:
            if not quick:
                raise self.fail(
                    ("fatigue", "quick"),
                    "--quick runs the set with the values of its [fatigue.quick] table, but the "
                    "file has none, so it would run the whole set; add one (e.g. [fatigue.quick] "
                    "with duration = 1.5), or leave out --quick",
                )
            for key, value in quick.items():
                if key == "dt":
                    self.values["dt"] = value
                else:
                    settings[key] = value
        gearbox = self.gearbox()
        gears = tuple(dict.fromkeys(g.name for m in gearbox.meshes for g in (m.gear_a, m.gear_b)))
        self.gear_names = gears
        self.roles = gear_roles(gearbox_planetary_gears(gearbox))
        site = self.site(settings.get("site"))
        levels = self.levels(settings.get("turbulence", 0.1), site)
        seeds = self.seeds(settings.get("seeds", [1]))
        duration = self.number(("fatigue", "duration"), settings.get("duration", 30.0), 0.0)
        skip = self.number(("fatigue", "skip_start"), settings.get("skip_start", 0.0), None)
        if not 0.0 <= skip < duration:
            raise self.fail(
                ("fatigue", "skip_start"),
                f"is {skip:g} s; give 0 ≤ skip_start < duration ({duration:g} s)",
            )
        rate = self.number(("fatigue", "sample_rate"), settings.get("sample_rate", 1e4), 0.0)
        self.check_sample_rate(rate, self.number(("dt",), self.values.get("dt", 1e-3), 0.0))
        wind = settings.get("wind", "disc")
        if wind not in ("disc", "point"):
            raise self.fail(("fatigue", "wind"), f'is {wind!r}; give "disc" or "point"')
        hub = self.number(("fatigue", "hub_height"), settings.get("hub_height", 80.0), 0.0)
        stiffness = damping = None
        if "mesh_stiffness" in settings:
            stiffness = self.number(("fatigue", "mesh_stiffness"), settings["mesh_stiffness"], 0.0)
        if "mesh_damping" in settings:
            damping = self.number(("fatigue", "mesh_damping"), settings["mesh_damping"], None)
            if damping < 0.0:
                raise self.fail(("fatigue", "mesh_damping"), "must be ≥ 0 N·s/m")
        openfast = self.openfast(settings.get("openfast"))
        out = Path(str(settings.get("out", self.path.stem)))
        out = (out if out.is_absolute() else self.path.parent / out).resolve()
        if self.quick:
            out = out.with_name(out.name + "_quick")
        problem = folder_problem(out)
        if problem is not None:
            raise self.fail(
                ("fatigue", "out"),
                f"{out}: {problem}; the set writes its case logs and reductions into the folder "
                "out names: give a folder that is not a file's name, or move the file",
            )
        meshes = self.values.setdefault("mesh", {"all": "compliant"})
        if any(kind != "compliant" for kind in meshes.values()):
            raise self.fail(
                ("mesh",),
                "a fatigue set needs compliant meshes (the tooth forces "
                'come from the mesh deflections): mesh = { all = "compliant" }',
            )
        rotor_joint = rotor_radius = None
        if openfast is None:
            rotor_joint, rotor_radius = self.rotor()
        materials = self.materials(settings.get("materials", DEFAULT_MATERIAL), gears)
        curves = self.curves(settings.get("sn_curve", {}), gears, materials)
        fatigue = FatigueSet(
            values=self.values,
            source=str(self.path),
            base=self.path.parent,
            site=site,
            levels=levels,
            seeds=seeds,
            duration=duration,
            skip_start=skip,
            sample_rate=rate,
            out=out,
            curves=curves.contact,
            gears=gears,
            wind=wind,
            hub_height=hub,
            rotor_joint=rotor_joint,
            rotor_radius=rotor_radius,
            mesh_stiffness=stiffness,
            mesh_damping=damping,
            openfast=openfast,
            root_curves=curves.root,
            iso_curves=curves.iso_contact,
            iso_root_curves=curves.iso_root,
            materials=materials,
            root_stress=self.root_stress(settings.get("root_stress", {}), gears),
            bearings=dict(gearbox.source.bearings),
            roles=self.roles,
        )
        for case in fatigue.cases():  # every case's run values build (and files exist)
            if openfast is not None and not openfast.file(case, fatigue.base).is_file():
                raise self.fail(
                    ("fatigue", "openfast", "files"),
                    f"{openfast.file(case, fatigue.base)} (case {case.name}) does not exist",
                )
        if fatigue.cases():
            build(
                fatigue.case_values(fatigue.cases()[0]),
                source=str(self.path),
                base=self.path.parent,
                text=self.text,
            )
        return fatigue

    def check_sample_rate(self, rate: float, dt: float) -> None:
        """Refuse a ``sample_rate`` [Hz] above the step rate 1/dt or not a whole number of steps.

        The histories are every k-th step, k = 1 / (sample_rate · dt) rounded: 3000 Hz at
        dt = 20 µs would be read at 1 / (17 · 20 µs) = 2941 Hz, 100 kHz at 50 kHz.
        """
        key = ("fatigue", "sample_rate")
        steps = 1.0 / (rate * dt)
        if steps < 1.0 - _WHOLE:
            raise self.fail(
                key,
                f"sample_rate = {rate:g} Hz is above the step rate 1/dt = {1.0 / dt:g} Hz "
                f"(dt = {dt:g} s): the histories cannot be read more often than the run steps; "
                f"give a sample_rate of at most {1.0 / dt:g} Hz, or a smaller dt",
            )
        if abs(steps - round(steps)) > _WHOLE * steps:
            below, above = (1.0 / (n * dt) for n in (math.ceil(steps), math.floor(steps)))
            raise self.fail(
                key,
                f"sample_rate = {rate:g} Hz is not a whole number of steps at dt = {dt:g} s "
                f"(1 / (sample_rate · dt) = {steps:.4g}), so the histories would be read at "
                f"{1.0 / (round(steps) * dt):.6g} Hz; give a sample_rate that divides "
                f"1/dt = {1.0 / dt:g} Hz, e.g. {below:.6g} or {above:.6g} Hz",
            )

    def gearbox(self) -> Gearbox:
        """The model, loaded (its file must exist)."""
        from pinwind.model.gearbox import load

        if "model" not in self.values:
            raise self.fail(("model",), "missing; give the gearbox model file")
        model = Path(str(self.values["model"]))
        model = model if model.is_absolute() else self.path.parent / model
        if not model.is_file():
            raise self.fail(("model",), f"{model} does not exist")
        # Absolute, so that a case's inputs (`FatigueSet.case_key`) do not depend on the folder
        # the scenario file is read from.
        self.values["model"] = str(model.resolve())
        return load(model)

    def number(self, key: tuple[str, ...], value: Any, above: float | None) -> float:
        """A finite number, > ``above`` when given."""
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.fail(key, f"is {value!r}; give a number")
        if not math.isfinite(value) or (above is not None and not value > above):
            raise self.fail(
                key,
                f"is {value!r}; give a finite number"
                + (f" above {above:g}" if above is not None else ""),
            )
        return float(value)

    def site(self, table: Any) -> WindSite:
        """The wind bins: given hours, or a Weibull distribution."""
        key = ("fatigue", "site")
        if not isinstance(table, Mapping):
            raise self.fail(
                key,
                "missing: give [fatigue.site] with speeds and hours, or scale, "
                "shape and edges (Weibull)",
            )
        table = {k.replace("-", "_"): v for k, v in table.items()}
        self.known(key, table, SITE_HOURS_KEYS + SITE_WEIBULL_KEYS)
        try:
            if "hours" in table or "speeds" in table:
                if set(table) != {"speeds", "hours"}:
                    raise self.fail(key, "give speeds and hours (one per bin), nothing else")
                return site_from_hours(speeds=table["speeds"], hours=table["hours"])
            if not {"scale", "shape", "edges"} <= set(table) or not set(table) <= set(
                SITE_WEIBULL_KEYS
            ):
                raise self.fail(
                    key,
                    "give speeds and hours, or scale, shape and edges (and "
                    "design_life_years, availability, cut_in, cut_out)",
                )
            return weibull_site(**table)
        except ScenarioError:
            raise
        except (PinwindError, TypeError, ValueError) as err:
            raise self.fail(key, str(err)) from err

    def levels(self, given: Any, site: WindSite) -> tuple[TurbulenceLevel, ...]:
        """The turbulence levels: intensities (one life each) or IEC 61400-1 classes."""
        key = ("fatigue", "turbulence")
        items = given if isinstance(given, list) else [given]
        if not items:
            raise self.fail(key, "is empty; give at least one intensity or class")
        levels = []
        for item in items:
            if isinstance(item, str):
                if item not in TURBULENCE_CLASSES:
                    raise self.fail(
                        key,
                        f"class {item!r} is unknown; classes are: " + ", ".join(TURBULENCE_CLASSES),
                    )
                label = f"class {item}"
            elif isinstance(item, bool) or not isinstance(item, int | float):
                raise self.fail(key, f"{item!r}: give intensities (0.1 for 10 %) or classes")
            else:
                label = f"{100 * item:g}%"
            try:
                intensities = bin_turbulence(site.speeds, item)
            except PinwindError as err:
                raise self.fail(key, str(err)) from err
            levels.append(TurbulenceLevel(label, tuple(float(v or 0.0) for v in intensities)))
        return tuple(levels)

    def seeds(self, given: Any) -> tuple[int, ...]:
        """Whole numbers ≥ 0, at least one."""
        items = given if isinstance(given, list) else [given]
        if not items or any(isinstance(s, bool) or not isinstance(s, int) or s < 0 for s in items):
            raise self.fail(("fatigue", "seeds"), f"is {given!r}; give whole numbers ≥ 0")
        return tuple(items)

    def openfast(self, table: Any) -> OpenFastInput | None:
        """OpenFAST input, if given."""
        if table is None:
            return None
        key = ("fatigue", "openfast")
        if not isinstance(table, Mapping) or not {"files", "joint"} <= set(table):
            raise self.fail(key, "give files (a name pattern) and joint (and channel, scale)")
        self.known(key, table, OPENFAST_KEYS)
        try:
            return OpenFastInput(**table)
        except TypeError as err:
            raise self.fail(key, "keys are: files, joint, channel, scale") from err

    def rotor(self) -> tuple[str, float]:
        """The rotor's joint and radius: the scenario must have one rotor."""
        rotors = self.values.get("rotor", {})
        if len(rotors) != 1:
            raise self.fail(
                ("rotor",),
                "a fatigue set in Kaimal wind needs one [rotor.JOINT] "
                "(or [fatigue.openfast] instead)",
            )
        scenario = build(
            {**self.values, "wind": 10.0},
            source=str(self.path),
            base=self.path.parent,
            text=self.text,
        )
        ((joint, rotor),) = scenario.rotors.items()
        return joint, rotor.radius

    def per_gear(self, key: tuple[str, ...], value: Any, gear: str) -> Any:
        """``value``, or its entry for ``gear`` (or its kind) when it is a table."""
        if not isinstance(value, Mapping):
            return value
        self.known(key, value, self.gear_names + GEAR_KINDS)
        kind = self.roles.get(gear)
        chosen = value.get(gear, value.get(kind, None) if kind else None)
        if chosen is None:
            raise self.fail(
                key, f'no value for "{gear}"; give one per gear (or per kind: sun, planet, ring)'
            )
        return chosen

    def materials(self, given: Any, gears: tuple[str, ...]) -> dict[str, str]:
        """Each gear's material key: one for all, or per gear or kind (default for the rest)."""
        key = ("fatigue", "materials")
        if isinstance(given, Mapping):
            self.known(key, given, gears + GEAR_KINDS)
        out = {}
        for gear in gears:
            kind = self.roles.get(gear)
            name = given
            if isinstance(given, Mapping):
                name = given.get(gear, given.get(kind, DEFAULT_MATERIAL) if kind else None)
                name = DEFAULT_MATERIAL if name is None else name
            if name not in MATERIALS:
                raise self.fail(
                    key, f'"{name}" ({gear}) is unknown; materials are: ' + ", ".join(MATERIALS)
                )
            out[gear] = str(name)
        return out

    def root_stress(self, table: Any, gears: tuple[str, ...]) -> dict[str, RootStress]:
        """Each gear's root-stress model: its table (by gear or kind), else ISO 6336-3."""
        key = ("fatigue", "root_stress")
        if not isinstance(table, Mapping):
            raise self.fail(key, "must be a table of gears (or kinds) → tables")
        self.known(key, table, gears + GEAR_KINDS)
        out: dict[str, RootStress] = {}
        for gear in gears:
            kind = self.roles.get(gear)
            spec = table.get(gear, table.get(kind) if kind else None)
            if spec is None:
                out[gear] = ISO_ROOT_STRESS
                continue
            name = gear if gear in table else str(kind)
            if not isinstance(spec, Mapping):
                raise self.fail(
                    key + (name,), "give position_mm (or fraction) and mpa_per_kn, as lists"
                )
            self.known(key + (name,), spec, ROOT_STRESS_KEYS)
            try:
                out[gear] = table_root_stress(**spec)
            except (PinwindError, TypeError, ValueError) as err:
                raise self.fail(key + (name,), str(err)) from err
        return out

    def curves(self, table: Any, gears: tuple[str, ...], materials: dict[str, str]) -> SetCurves:
        """Each gear's S-N curves: a preset, or one curve with endurance limits per gear."""
        key = ("fatigue", "sn_curve")
        if not isinstance(table, Mapping):
            raise self.fail(key, "must be a table: preset, or s0_mpa, m, n0, endurance_limit_mpa")
        table = {k.replace("-", "_"): v for k, v in table.items()}
        self.known(key, table, SN_CURVE_KEYS + SN_PRESET_KEYS)
        iso_keys = set(SN_PRESET_KEYS)
        preset = table.get("preset", SN_PRESETS[0] if not table else None)
        permitted = preset == "iso6336_pitting_permitted"
        try:
            iso_contact: dict[str, FatigueCurve] = {
                g: iso6336_contact_curve(
                    materials[g],
                    pitting_permitted=permitted,
                    sigma_H_lim=self.strength(table, "sigma_h_lim_mpa", g),
                ).scaled(VON_MISES_RATIO)
                for g in gears
            }
            iso_root: dict[str, FatigueCurve] = {
                g: iso6336_root_curve(
                    materials[g], sigma_F_lim=self.strength(table, "sigma_f_lim_mpa", g)
                )
                for g in gears
            }
        except InputError as err:
            raise self.fail(key, str(err)) from err
        if preset is not None and preset.startswith("iso6336"):
            if preset not in SN_PRESETS or not set(table) <= iso_keys:
                raise self.fail(
                    key + ("preset",),
                    f"is {preset!r}; presets are: {', '.join(SN_PRESETS)} (an ISO one with "
                    "sigma_h_lim_mpa, sigma_f_lim_mpa)",
                )
            return SetCurves(iso_contact, iso_root, iso_contact, iso_root)
        if "preset" in table or not table:
            if preset not in SN_PRESETS or len(table) > 1:
                raise self.fail(
                    key + ("preset",),
                    f"is {preset!r}; presets are: "
                    + ", ".join(SN_PRESETS)
                    + " (jorgensen2014 alone in the table)",
                )
            out: dict[str, FatigueCurve] = {}
            for gear in gears:
                kind = self.roles.get(gear)
                if kind is None:
                    raise self.fail(
                        key,
                        f'the preset rates sun, planet and ring gears; "{gear}" '
                        "is none of them: give s0_mpa, m and endurance_limit_mpa",
                    )
                out[gear] = jorgensen_2014_curve(kind)
            return SetCurves(out, dict(out), iso_contact, iso_root)
        allowed = {"s0_mpa", "m", "n0", "endurance_limit_mpa"}
        if not {"s0_mpa", "m"} <= set(table) or not set(table) <= allowed:
            raise self.fail(key, "give s0_mpa and m (and n0, endurance_limit_mpa), or a preset")
        limits = table.get("endurance_limit_mpa", 0.0)
        out = {}
        for gear in gears:
            limit = self.per_gear(key + ("endurance_limit_mpa",), limits, gear)
            try:
                out[gear] = SNCurve(
                    reference_stress=float(table["s0_mpa"]) * 1e6,
                    slope_exponent=float(table["m"]),
                    reference_cycles=float(table.get("n0", 1.0)),
                    endurance_limit=float(limit) * 1e6,
                )
            except (PinwindError, TypeError, ValueError) as err:
                raise self.fail(key, str(err)) from err
        return SetCurves(out, dict(out), iso_contact, iso_root)

    def strength(self, table: Mapping[str, Any], name: str, gear: str) -> float | None:
        """An ISO strength key [MPa] of the S-N table for a gear, in Pa; None if not given."""
        if name not in table:
            return None
        value = self.per_gear(("fatigue", "sn_curve", name), table[name], gear)
        return self.number(("fatigue", "sn_curve", name), value, 0.0) * 1e6


@dataclass(frozen=True)
class SetCurves:
    """The S-N curves of a fatigue set's gears (`FatigueSet`): gear → curve of each kind."""

    contact: dict[str, FatigueCurve]
    root: dict[str, FatigueCurve]
    iso_contact: dict[str, FatigueCurve]
    iso_root: dict[str, FatigueCurve]


# --- one case ------------------------------------------------------------------------------------


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
) -> list[FlankCycles]:
    """The rainflow cycles of every flank of every tooth of ``gears`` in a run.

    The histories are those of `pinwind.life.tooth_damage.gear_tooth_damage` (von Mises
    contact stress at the moving contact point, per tooth over all its meshes), or with
    ``root_stress`` (gear → model) its root stress.

    Args:
        materials: gear → material key (default `materials.DEFAULT_MATERIAL`).
        root_stress: count the root stress of each gear with its model instead.
    """
    from pinwind.life.sn_curve import SNCurve
    from pinwind.life.tooth_damage import gear_tooth_damage

    # The curve is not used: only the counted cycles are kept.
    unit = SNCurve(reference_stress=1.0, slope_exponent=1.0)
    out = []
    for gear in gears:
        rated_flanks = gear_tooth_damage(
            result,
            gearbox,
            gear,
            curve=unit,
            time_factor=1.0,
            materials=materials,
            root_stress=None if root_stress is None else root_stress[gear],
        )
        for rated in rated_flanks:
            tooth = np.concatenate(
                [np.full(c.ranges.size, j, dtype=np.int32) for j, c in enumerate(rated.cycles)]
            )
            out.append(
                FlankCycles(
                    gear=gear,
                    flank=rated.flank,
                    teeth=len(rated.cycles),
                    tooth=tooth,
                    ranges=np.concatenate([c.ranges for c in rated.cycles]),
                    counts=np.concatenate([c.counts for c in rated.cycles]),
                    peaks=rated.peak_stress,
                )
            )
    return out


def run_case(case: LoadCase, fatigue: FatigueSet) -> CaseCycles:
    """Simulate one case with its log and reduce it (a worker's task).

    The reduction is its tooth cycles and its bearings' load sums, both from ``skip_start`` on.

    Runs in this process, a local worker or a Dask worker (whose output folder must be the
    one the caller reads: a shared file system).
    """
    import warnings

    from pinwind.model.compliance import MeshCompliance
    from pinwind.model.gearbox import load
    from pinwind.scenario import run

    start, cpu, own = time.perf_counter(), time.process_time(), time.thread_time()
    scenario = build(fatigue.case_values(case), source=fatigue.source, base=fatigue.base)
    if fatigue.mesh_stiffness is not None or fatigue.mesh_damping is not None:
        compliance = MeshCompliance(stiffness=fatigue.mesh_stiffness, damping=fatigue.mesh_damping)
        meshes: dict[str, Any] = {"all": compliance}
        scenario = dataclasses.replace(scenario, meshes=meshes)
    gearbox = load(scenario.model_path())
    fatigue.out.mkdir(parents=True, exist_ok=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        # No run statistics: the case counts its kept samples, and folding every step into
        # min, max and RMS (for a summary; not logged) would take a thread beside the loop.
        result = run(
            scenario,
            gearbox=gearbox,
            progress=False,
            command=f"pinwind fatigue {fatigue.source} (case {case.name})",
            statistics=False,
        )
    first = int(np.searchsorted(result.time, fatigue.skip_start - 1e-12))
    counted = result.rows(first, len(result))
    flanks = case_cycles(counted, gearbox, fatigue.gears, materials=fatigue.materials)
    roots = case_cycles(
        counted,
        gearbox,
        fatigue.gears,
        materials=fatigue.materials,
        root_stress={g: fatigue.root_stress.get(g, ISO_ROOT_STRESS) for g in fatigue.gears},
    )
    bearings = bearing_load_sums(counted, gearbox)
    log_sha256 = file_sha256(fatigue.log_path(case))
    return CaseCycles(
        case,
        fatigue.case_key(case),
        fatigue.counted_seconds,
        time.perf_counter() - start,
        tuple(flanks),
        tuple(roots),
        tuple(bearings),
        time.process_time() - cpu,
        time.thread_time() - own,
        log_sha256,
    )


def save_case(case: LoadCase, fatigue: FatigueSet) -> str:
    """Run one case and write its reduction beside its log (a worker's task): the case's name.

    The worker writes the ``.npz`` itself, as it writes the log, so that only the name travels
    back and the command, which shares the cores with the workers, does not compress cycles.
    """
    run_case(case, fatigue).save(fatigue.cycles_path(case))
    return case.name


def file_sha256(path: Path) -> str:
    """SHA-256 of a file's bytes, as hex."""
    with path.open("rb") as f:
        return hashlib.file_digest(f, "sha256").hexdigest()


def case_done(fatigue: FatigueSet, case: LoadCase) -> bool:
    """Whether a case's log is complete and its reduction was made from the same inputs.

    A reduction that fails its CRC check or cannot be read, or a log whose SHA-256 differs from
    the one the reduction recorded (a flipped byte), is damaged: a `CaseFileDamaged` warning
    names the file, and the case is not done (it is computed again).
    """
    from pinwind.io.log_reader import LogReader

    log, cycles = fatigue.log_path(case), fatigue.cycles_path(case)
    if not (log.is_file() and cycles.is_file()):
        return False
    try:
        with zipfile.ZipFile(cycles) as archive:
            bad = archive.testzip()  # every member read and checked against its CRC-32
        if bad is not None:
            raise zipfile.BadZipFile(f"its member {bad} fails its CRC-32 check")
        with np.load(cycles) as data:
            meta = json.loads(str(data["meta"]))
        key, recorded = meta["key"], meta.get("log_sha256", "")
    except (OSError, ValueError, KeyError, zipfile.BadZipFile, zlib.error) as err:
        _damaged(f"{cycles}: the kept reduction of case {case.name} is damaged ({err})")
        return False
    if recorded and file_sha256(log) != recorded:
        _damaged(
            f"{log}: the kept log of case {case.name} is not the one its reduction was made "
            f"from (sha256 {recorded[:12]}… recorded, {file_sha256(log)[:12]}… now): it was "
            "damaged or changed"
        )
        return False
    try:
        with LogReader(log) as reader:
            complete = reader.complete
    except PinwindError:
        return False
    return complete and key == fatigue.case_key(case)


def _damaged(what: str) -> None:
    """Warn, at the caller of `run_cases`, that a kept case file is damaged and redone."""
    import warnings

    from pinwind.errors import CaseFileDamaged

    warnings.warn(CaseFileDamaged(f"{what}; the case is computed again"), stacklevel=4)


@dataclass
class FatigueRun:
    """How the cases of a fatigue set were obtained.

    Attributes:
        computed: names of the cases run in this call (the others were reused).
        total: distinct cases in the set (`LoadCase.name`).
        backend: ``"serial"``, ``"processes (N)"`` or ``"dask (ADDRESS)"`` (`run_tasks`).
        wall_time: seconds for this call.
    """

    computed: list[str]
    total: int
    backend: str
    wall_time: float


def run_cases(
    fatigue: FatigueSet,
    *,
    workers: int | None = None,
    scheduler: str | object | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> FatigueRun:
    """Run the cases not done yet (`case_done`) on local processes or Dask, saving each.

    Each worker writes its case's log and reduction (`save_case`) as soon as the case is done,
    so an interrupted set keeps its finished cases; only the case names come back here.

    Args:
        workers: local worker processes (default: all cores, 1 for a single case).
        scheduler: a Dask scheduler address or ``distributed.Client``; overrides ``workers``.
        progress: called as progress(finished, total) after each case.
    """
    import os

    from pinwind.analysis.sweep import check_workers, run_tasks

    check_workers(workers)
    start = time.perf_counter()
    cases = fatigue.cases()
    unique = {c.name: c for c in cases}
    todo = []
    for case in unique.values():  # a loop, not a comprehension: warnings point at the caller
        if not case_done(fatigue, case):
            todo.append(case)
    finished, computed = len(unique) - len(todo), []
    if progress:
        progress(finished, len(unique))

    def accept(name: str) -> None:
        nonlocal finished
        computed.append(name)
        finished += 1
        if progress:
            progress(finished, len(unique))

    backend = run_tasks(
        save_case,
        todo,
        accept=accept,
        workers=workers or os.cpu_count() or 1,
        scheduler=scheduler,
        fatigue=fatigue,
    )
    return FatigueRun(computed, len(unique), backend, time.perf_counter() - start)
