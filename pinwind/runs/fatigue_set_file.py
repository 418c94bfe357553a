"""A fatigue set's file: a scenario file (TOML) with a ``[fatigue]`` table, read and checked.

The run keys of any scenario (``pinwind.runs.scenario``: model, dt, rotor, generator, ...) plus a
``[fatigue]`` table (`load_fatigue_set`, which gives a `pinwind.life.fatigue_set.FatigueSet`)::

    [fatigue]
    out = "dtu500_fatigue"              # folder of the case logs (relative to the file)
    duration = 30.0                     # simulated seconds per case [s] (required)
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

    [fatigue.bearings]                  # bearing and row data of L_nm and L10r over the model's
    planet1 = { size_mm = "300 200 60", fatigue_limit_kN = 50, lubricant_vg = 320 }
    "lss.INP-A" = { temperature_C = 65, contamination = "high_cleanliness" }

    gears = ["sun", "planet1"]          # the gears whose teeth are rated (default: all
                                        # meshed gears; helical ones need ε_β ≥ 1)
    face_load = "run"                   # the tooth stresses at the run's peak line load across
                                        # the face (meshes cut into slices), or "uniform"
                                        # (default: the force spread evenly)

    [fatigue.quick]                     # what --quick changes (any [fatigue] key, and dt)
    duration = 1.5

Per-gear tables take a gear's name or its role in its planetary stage (sun, planet, ring), found
from the model's topology (`pinwind.model.gear_roles`), never from its name; a gear's own name
comes first. Each error names the file, the key at fault and its line; an unknown key is refused
naming the nearest known one (`pinwind.known_names`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pinwind.errors import InputError, PinwindError
from pinwind.gears.hertz import VON_MISES_RATIO
from pinwind.gears.materials import DEFAULT_MATERIAL, MATERIALS
from pinwind.io.folders import folder_problem
from pinwind.known_names import check_keys, toml_keys
from pinwind.life.bearing_life import row_ratings
from pinwind.life.fatigue_set import (
    FatigueSet,
    OpenFastInput,
    TurbulenceLevel,
)
from pinwind.life.life_sums import bearing_life_data
from pinwind.life.peak_line_load import FACE_LOADS
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
from pinwind.model.bearing_life_data import LIFE_ATTRIBUTES, BearingLifeData, life_data
from pinwind.model.gear_roles import ROLES, gear_roles, gearbox_planetary_gears
from pinwind.runs.scenario import ScenarioError, build, key_error, read_toml

if TYPE_CHECKING:
    from pinwind.model.gearbox import Gearbox

#: The keys of the ``[fatigue]`` table, with what they are.
FATIGUE_KEYS: dict[str, str] = {
    "out": "folder of the case logs",
    "duration": "simulated seconds per case [s], required",
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
    "gears": "the gears whose teeth are rated (default: every meshed gear)",
    "bearings": "bearing and row data of the modified and reference lives, over the model's",
    "face_load": '"uniform" (force spread evenly across the face) or "run" (peak line load)',
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
#: Jørgensen 2014 applies it), or ISO 6336-2 and -3's life-factor curves of each gear's material.
SN_PRESETS = ("jorgensen2014", "iso6336", "iso6336_pitting_permitted")


def load_fatigue_set(
    path: str | Path, *, quick: bool = False, fatigue: Mapping[str, Any] | None = None
) -> FatigueSet:
    """Read and check a fatigue set from a scenario file (module docstring).

    Args:
        path: the TOML file.
        quick: apply its ``[fatigue.quick]`` table (a short version), and write the cases into
            the output folder with ``_quick`` appended.
        fatigue: a ``[fatigue]`` table to use instead of the file's, as read from TOML (a plain
            scenario file, which ``pinwind run`` runs, then makes a set: the run keys stay in
            one file). Its keys' messages name the file, without a line.

    Raises:
        ScenarioError: anything wrong, naming the file, the key and its line: a missing model
            or OpenFAST file, a bin without hours, an S-N curve with m ≤ 0 or a negative
            endurance limit, a turbulence intensity ≤ 0, an unknown key, a [fatigue] table
            without duration, ...
    """
    path = Path(path)
    text, values = read_toml(path)
    if fatigue is not None:
        values = {**values, "fatigue": dict(fatigue)}
    return _SetReader(path, text, values, quick).fatigue_set()


class _SetReader:
    """Reads a fatigue set; each error names the key at fault and its line."""

    def __init__(self, path: Path, text: str, values: dict[str, Any], quick: bool):
        self.path, self.text, self.quick = path, text, quick
        self.values = toml_keys(values)
        #: The meshed gears, once the model is read: the names of per-gear tables.
        self.gear_names: tuple[str, ...] = ()
        #: Gear → its role in its planetary stage, from the model's topology.
        self.roles: dict[str, str] = {}

    def fail(self, key: tuple[str, ...], message: str) -> ScenarioError:
        return key_error(str(self.path), self.text, key, message)

    def fatigue_set(self) -> FatigueSet:
        table = self.values.pop("fatigue", None)
        if not isinstance(table, Mapping):
            raise self.fail(
                ("fatigue",),
                "a fatigue set needs a [fatigue] table (module "
                "pinwind.runs.fatigue_set_file says its keys)",
            )
        settings = toml_keys(table)
        check_keys(("fatigue",), settings, FATIGUE_KEYS, self.fail)
        self.require_duration(settings)  # in [fatigue] itself, also when --quick changes it
        quick = settings.pop("quick", None)
        if quick is not None and not isinstance(quick, Mapping):
            raise self.fail(("fatigue", "quick"), "must be a table of [fatigue] keys")
        quick = toml_keys(quick or {})
        check_keys(("fatigue", "quick"), quick, QUICK_KEYS, self.fail)
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
        if "gears" in settings:
            gears = self.rated_gears(settings["gears"], gears)
        self.gear_names = gears
        self.roles = gear_roles(gearbox_planetary_gears(gearbox))
        site = self.site(settings.get("site"))
        levels = self.levels(settings.get("turbulence", 0.1), site)
        seeds = self.seeds(settings.get("seeds", [1]))
        duration = self.number(("fatigue", "duration"), settings["duration"], 0.0)
        skip = self.number(("fatigue", "skip_start"), settings.get("skip_start", 0.0), None)
        if not 0.0 <= skip < duration:
            raise self.fail(
                ("fatigue", "skip_start"),
                f"is {skip:g} s; give 0 ≤ skip_start < duration ({duration:g} s)",
            )
        rate = self.number(("fatigue", "sample_rate"), settings.get("sample_rate", 1e4), 0.0)
        dt = self.number(("dt",), self.values.get("dt", 1e-3), 0.0)
        self.check_sample_rate(rate, dt)
        self.check_steps(duration, dt)
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
        face_load = settings.get("face_load", "uniform")
        if face_load not in FACE_LOADS:
            raise self.fail(
                ("fatigue", "face_load"),
                f'is {face_load!r}; give "uniform" (each pair\'s force spread evenly across the '
                'face) or "run" (at the run\'s peak line load, meshes cut into slices)',
            )
        if face_load == "run" and (stiffness is not None or damping is not None):
            raise self.fail(
                ("fatigue", "face_load"),
                'is "run", which reads the peak line load of meshes cut into slices, but '
                "mesh_stiffness or mesh_damping of [fatigue] replace every mesh's compliance by "
                "one with one contact line; give the stiffness, damping and slices on each "
                '<mesh> of the model instead, or face_load = "uniform"',
            )
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
            bearings={**gearbox.source.bearings, **row_ratings(gearbox)},
            roles=self.roles,
            bearing_life=self.bearing_life(settings.get("bearings", {}), gearbox),
            face_load=face_load,
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

    def check_steps(self, duration: float, dt: float) -> None:
        """Refuse a case of more steps than a run takes (``simulate.MAX_STEPS``).

        Refused here, before the set's first case: a duration of 1e30 s failed inside the
        turbulent wind's synthesis with numpy's "Maximum allowed size exceeded".
        """
        from pinwind.dynamics.simulate import MAX_STEPS

        if duration / dt > MAX_STEPS:
            raise self.fail(
                ("fatigue", "duration"),
                f"is {duration:g} s: {duration / dt:.3g} steps of dt = {dt:g} s per case, more "
                f"than the {MAX_STEPS:.0e} a run can take; give the simulated seconds per case "
                "(Jørgensen 2014: 30 s)",
            )

    def require_duration(self, settings: Mapping[str, Any]) -> None:
        """Refuse a ``[fatigue]`` table without ``duration`` [s]: there is no default.

        A set without it used to run 30 s per case without a word: a length the user never
        chose, which sets both the run time and how well a case samples its bin's wind.
        """
        if "duration" not in settings:
            raise self.fail(
                ("fatigue", "duration"),
                "missing: give the simulated seconds per case in the [fatigue] table, e.g. "
                "duration = 30.0 (Jørgensen 2014's length; each case stands for its wind bin's "
                "hours, so a longer case samples the bin's wind better and takes longer)",
            )

    def rated_gears(self, given: Any, meshed: tuple[str, ...]) -> tuple[str, ...]:
        """The gears named in ``gears``, in the model's order: meshed gears, at least one."""
        key = ("fatigue", "gears")
        if not isinstance(given, list) or not given or not all(isinstance(g, str) for g in given):
            raise self.fail(key, f"is {given!r}; give a list of gear names: {', '.join(meshed)}")
        unknown = [g for g in given if g not in meshed]
        if unknown:
            raise self.fail(
                key, f"{', '.join(unknown)}: no meshed gear of that name; gears are: "
                + ", ".join(meshed),
            )  # fmt: skip
        return tuple(g for g in meshed if g in given)

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
        table = toml_keys(table)
        check_keys(key, table, SITE_HOURS_KEYS + SITE_WEIBULL_KEYS, self.fail)
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
        check_keys(key, table, OPENFAST_KEYS, self.fail)
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
        check_keys(key, value, self.gear_names + ROLES, self.fail)
        kind = self.roles.get(gear)
        chosen = value.get(gear, value.get(kind, None) if kind else None)
        if chosen is None:
            raise self.fail(
                key, f'no value for "{gear}"; give one per gear (or per kind: sun, planet, ring)'
            )
        return chosen

    def bearing_life(self, table: Any, gearbox: Gearbox) -> dict[str, BearingLifeData]:
        """Each bearing's and row's life data: the model's, with ``[fatigue.bearings]`` over it.

        The table's keys are bearings or rows (``"lss.INP-A"``), each a table of the model's
        life attributes (``lubricant_vg``, ``temperature_C``, ``contamination``,
        ``fatigue_limit_kN``, ``size_mm``, ...; docs/bearing_life.md "Model file"), checked as
        the model's are.
        """
        key = ("fatigue", "bearings")
        if not isinstance(table, Mapping):
            raise self.fail(key, "must be a table of bearings or rows → tables of life attributes")
        out = bearing_life_data(gearbox)
        ratings = {**gearbox.source.bearings, **row_ratings(gearbox)}
        check_keys(key, table, tuple(ratings), self.fail, kind="bearing")
        for name, attrs in table.items():
            if not isinstance(attrs, Mapping):
                raise self.fail(
                    key + (name,), "must be a table of life attributes, e.g. { lubricant_vg = 220 }"
                )
            check_keys(key + (name,), attrs, LIFE_ATTRIBUTES, self.fail, kind="attribute")
            given = {k: str(v).lower() if isinstance(v, bool) else str(v) for k, v in attrs.items()}
            try:
                out[name] = life_data(
                    given, where=f"[fatigue.bearings] {name}", path=str(self.path),
                    inherited=out.get(name), rating=ratings[name].dynamic_load_rating,
                )  # fmt: skip
            except PinwindError as err:
                raise self.fail(key + (name,), str(err)) from err
        return out

    def materials(self, given: Any, gears: tuple[str, ...]) -> dict[str, str]:
        """Each gear's material key: one for all, or per gear or kind (default for the rest)."""
        key = ("fatigue", "materials")
        if isinstance(given, Mapping):
            check_keys(key, given, gears + ROLES, self.fail)
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
        check_keys(key, table, gears + ROLES, self.fail)
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
            check_keys(key + (name,), spec, ROOT_STRESS_KEYS, self.fail)
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
        table = toml_keys(table)
        check_keys(key, table, SN_CURVE_KEYS + SN_PRESET_KEYS, self.fail)
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
                        f'the preset rates sun, planet and ring gears; "{gear}" is none of '
                        "them (no planetary stage's ring, planet or sun by the meshes): give "
                        "s0_mpa, m and endurance_limit_mpa",
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
