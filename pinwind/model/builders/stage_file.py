"""A stage file: the TOML description of a multi-stage gearbox that ``stages_urdf`` builds.

``pinwind build stages FILE -o model.urdf`` reads it (``read_stage_file``). Units in the key
names (mm, deg, kN, kg), SI inside. Top level: ``name``, ``pressure_angle_deg`` (every stage's
default, 20), then ``[[stage]]`` tables input side first, each with its ``[[stage.bearing]]``
rolling bearings, and ``[[end_body]]`` tables (rotor, generator):

    [[stage]]
    name = "stage1"
    kind = "planetary"            # or "parallel"
    carrier = "lss"               # member = shaft name, or "fixed" (one member of a planetary)
    sun = "iss"
    ring = "fixed"
    planets = 3
    module_mm = 45                # normal module
    helix_deg = 0                 # the sun's (wheel's) hand; planets (pinion) the opposite
    face_width_mm = 491
    centre_distance_mm = 863      # working centre distance a_w
    teeth = { sun = 19, planet = 17, ring = 56 }          # or { wheel = 95, pinion = 24 }
    profile_shift = { sun = 0.617, planet = 0.802, ring = -0.501 }   # ISO 21771 sign
    tip_alteration_mm = { sun = -10.861, planet = -10.861 }          # k·m_n, < 0 shortens

    [[stage.bearing]]
    name = "PL-A"
    on = "planet"                 # the member it holds
    type = "cylindrical_roller"   # model.bearing.BEARING_TYPES
    position_mm = -68             # from the member's gear plane, along the shaft (+z downwind)
    rating_c_kN = 5500
    load_factors = [0.15, 0, 0.92, 0.4]        # ISO 281 e, Y1, X2, Y2 (optional)
    stiffness = [9.1e4, 9.4e9, 3.2e9, 1.4e6, 4.5e6]   # K_x (axial), K_y, K_z [N/m], K_β, K_γ
    damping = [453, 42000, 30600, 34.3, 47.8]         # c_x, c_y, c_z [N·s/m], c_β, c_γ
    size_mm = [600, 400, 272]                 # D, d, B (optional)

    [[end_body]]
    name = "rotor"
    shaft = "lss"                 # coupled to it by a torsional spring
    mass_kg = 110000
    ixx_kgm2 = 28615767.5         # about a diameter (optional: Izz/2, a planar body)
    izz_kgm2 = 57231535           # about the shaft
    position_mm = -2368           # its joint on the shaft's axis (stage 1's plane z = 0)
    shaft_diameter_mm = 700       # a solid steel shaft: k = G π d⁴/(32 L) ...
    shaft_length_mm = 2000
    # torsional_stiffness = 9.3e8 # ... or k [N·m/rad]
    # torsional_damping = 0       # [N·m·s/rad]

Errors name the file and the key (``stage[1].teeth.ring``) and say what is expected.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from pinwind.errors import InputError, InvalidGearTrain
from pinwind.gears.materials import DEFAULT_MATERIAL, material
from pinwind.known_names import unknown_message, unknown_name
from pinwind.model.bearing_rows import BearingRow
from pinwind.model.builders.stages import (
    EndBody,
    ParallelStage,
    PlanetaryStage,
    Stage,
    StageBearing,
    StageGear,
)

_TOP_KEYS = ("name", "pressure_angle_deg", "stage", "end_body")
_STAGE_KEYS = (
    "name", "kind", "planets", "module_mm", "helix_deg", "face_width_mm", "centre_distance_mm",
    "pressure_angle_deg", "teeth", "profile_shift", "tip_alteration_mm", "inertias", "bearing",
    "sun", "carrier", "ring", "wheel", "pinion",
)  # fmt: skip
_BEARING_KEYS = (
    "name", "on", "type", "position_mm", "rating_c_kN", "load_factors", "stiffness", "damping",
    "size_mm",
)  # fmt: skip
_END_BODY_KEYS = (
    "name", "shaft", "mass_kg", "ixx_kgm2", "izz_kgm2", "position_mm", "shaft_diameter_mm",
    "shaft_length_mm", "torsional_stiffness", "torsional_damping",
)  # fmt: skip


def solid_shaft_stiffness(diameter: float, length: float, shear_modulus: float) -> float:
    """Torsional stiffness of a solid round shaft, k = G π d⁴/(32 L) [N·m/rad].

    Args:
        diameter: d [m].
        length: L [m].
        shear_modulus: G [Pa].
    """
    return shear_modulus * math.pi * diameter**4 / (32.0 * length)


def steel_shear_modulus() -> float:
    """G = E/(2 (1 + ν)) of the default gear steel (``gears.materials``) [Pa]."""
    steel = material(DEFAULT_MATERIAL)
    return steel.youngs_modulus / (2.0 * (1.0 + steel.poisson_ratio))


class _Reader:
    """Values of one stage file, each refused with the file and its key when wrong."""

    def __init__(self, path: str) -> None:
        self.path = path

    def fail(self, key: str, message: str) -> InvalidGearTrain:
        return InvalidGearTrain(f"{self.path}: {key}: {message}")

    def keys(self, where: str, table: Mapping[str, Any], known: tuple[str, ...]) -> None:
        name = unknown_name(table, known)
        if name is not None:
            raise self.fail(f"{where}.{name}" if where else name, unknown_message(name, known))

    def table(self, where: str, value: Any) -> Mapping[str, Any]:
        if not isinstance(value, Mapping):
            raise self.fail(where, f"must be a table, got {value!r}")
        return value

    def number(self, where: str, table: Mapping[str, Any], key: str, default=None) -> float:
        value = table.get(key, default)
        if value is None:
            raise self.fail(f"{where}.{key}", "missing; give a number")
        if (
            isinstance(value, bool)
            or not isinstance(value, (int, float))
            or not math.isfinite(value)
        ):
            raise self.fail(f"{where}.{key}", f"= {value!r}; give a finite number")
        return float(value)

    def text(self, where: str, table: Mapping[str, Any], key: str) -> str:
        value = table.get(key)
        if not isinstance(value, str) or not value:
            raise self.fail(f"{where}.{key}", f"= {value!r}; give a name (a string)")
        return value

    def numbers(self, where: str, table: Mapping[str, Any], key: str, count: int) -> list[float]:
        value = table.get(key)
        if not (isinstance(value, list) and len(value) == count):
            raise self.fail(f"{where}.{key}", f"= {value!r}; give a list of {count} numbers")
        return [self.number(f"{where}.{key}", {str(i): v for i, v in enumerate(value)}, str(i))
                for i in range(count)]  # fmt: skip


def read_stage_file(path: str | Path) -> tuple[str, list[Stage], list[EndBody]]:
    """The gearbox name, stages and end bodies of a stage file (module docstring), SI.

    Raises:
        InputError: the file cannot be read.
        InvalidGearTrain: not TOML, an unknown or missing key, a value of the wrong kind; the
            message names the file and the key.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as err:
        raise InputError(f"cannot read the stage file {path}: {err.strerror or err}") from err
    reader = _Reader(str(path))
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise InvalidGearTrain(f"{path}: not a TOML file: {err}") from err
    reader.keys("", data, _TOP_KEYS)
    alpha_deg = reader.number("", data, "pressure_angle_deg", 20.0)
    stages = [
        _stage(reader, f"stage[{k}]", reader.table(f"stage[{k}]", table), alpha_deg)
        for k, table in enumerate(data.get("stage", []), start=1)
    ]
    bodies = [
        _end_body(reader, f"end_body[{k}]", reader.table(f"end_body[{k}]", table))
        for k, table in enumerate(data.get("end_body", []), start=1)
    ]
    name = data.get("name", path.stem)
    if not isinstance(name, str):
        raise reader.fail("name", f"= {name!r}; give the model's name")
    return name, stages, bodies


def _stage(reader: _Reader, where: str, table: Mapping[str, Any], alpha_deg: float) -> Stage:
    reader.keys(where, table, _STAGE_KEYS)
    kind = table.get("kind")
    members: tuple[str, ...]
    gear_names: tuple[str, ...]
    if kind == "planetary":
        members, gear_names = ("sun", "carrier", "ring"), ("sun", "planet", "ring")
    elif kind == "parallel":
        members, gear_names = ("wheel", "pinion"), ("wheel", "pinion")
    else:
        raise reader.fail(f"{where}.kind", f'= {kind!r}; give "planetary" or "parallel"')
    own = (*members, "planets") if kind == "planetary" else members
    others = [k for k in ("sun", "carrier", "ring", "wheel", "pinion", "planets") if k in table]
    others = [k for k in others if k not in own]
    if others:
        raise reader.fail(f"{where}.{others[0]}", f"is not a key of a {kind} stage")
    teeth = reader.table(f"{where}.teeth", table.get("teeth"))
    shifts = reader.table(f"{where}.profile_shift", table.get("profile_shift", {}))
    tips = reader.table(f"{where}.tip_alteration_mm", table.get("tip_alteration_mm", {}))
    for sub, given in (("teeth", teeth), ("profile_shift", shifts), ("tip_alteration_mm", tips)):
        reader.keys(f"{where}.{sub}", given, gear_names)
    gears = {}
    for g in gear_names:
        z = teeth.get(g)
        if isinstance(z, bool) or not isinstance(z, int) or z <= 0:
            raise reader.fail(f"{where}.teeth.{g}", f"= {z!r}; give a positive whole number")
        gears[g] = StageGear(
            z,
            reader.number(f"{where}.profile_shift", shifts, g, 0.0),
            reader.number(f"{where}.tip_alteration_mm", tips, g, 0.0) * 1e-3,
        )
    inertias = {}
    raw_inertias = reader.table(f"{where}.inertias", table.get("inertias", {}))
    for key in raw_inertias:
        props = reader.numbers(f"{where}.inertias", raw_inertias, key, 3)
        inertias[key] = (props[0], props[1], props[2])
    common: dict[str, Any] = dict(
        name=reader.text(where, table, "name"),
        module=reader.number(where, table, "module_mm") * 1e-3,
        pressure_angle=math.radians(reader.number(where, table, "pressure_angle_deg", alpha_deg)),
        face_width=reader.number(where, table, "face_width_mm") * 1e-3,
        centre_distance=reader.number(where, table, "centre_distance_mm") * 1e-3,
        helix_angle=math.radians(reader.number(where, table, "helix_deg", 0.0)),
        shafts={m: reader.text(where, table, m) for m in members},
        bearings=tuple(
            _bearing(reader, f"{where}.bearing[{k}]", reader.table(f"{where}.bearing[{k}]", b))
            for k, b in enumerate(table.get("bearing", []), start=1)
        ),
        inertias=inertias,
    )
    if kind == "planetary":
        planets = table.get("planets")
        if isinstance(planets, bool) or not isinstance(planets, int) or planets <= 0:
            raise reader.fail(f"{where}.planets", f"= {planets!r}; give a positive whole number")
        return PlanetaryStage(
            sun=gears["sun"], planet=gears["planet"], ring=gears["ring"], planets=planets,
            **common,
        )  # fmt: skip
    return ParallelStage(wheel=gears["wheel"], pinion=gears["pinion"], **common)


def _bearing(reader: _Reader, where: str, table: Mapping[str, Any]) -> StageBearing:
    reader.keys(where, table, _BEARING_KEYS)
    factors = None
    if "load_factors" in table:
        e, y1, x2, y2 = reader.numbers(where, table, "load_factors", 4)
        factors = (e, y1, x2, y2)
    size = None
    if "size_mm" in table:
        d_out, d_in, width = (v * 1e-3 for v in reader.numbers(where, table, "size_mm", 3))
        size = (d_out, d_in, width)
    rating = table.get("rating_c_kN")
    k = reader.numbers(where, table, "stiffness", 5)
    c = reader.numbers(where, table, "damping", 5) if "damping" in table else [0.0] * 5
    row = BearingRow(
        name=reader.text(where, table, "name"),
        kind=reader.text(where, table, "type"),
        position=reader.number(where, table, "position_mm", 0.0) * 1e-3,
        rating=None if rating is None else reader.number(where, table, "rating_c_kN") * 1e3,
        stiffness=(k[0], k[1], k[2], k[3], k[4]),
        damping=(c[0], c[1], c[2], c[3], c[4]),
        load_factors=factors,
        size=size,
    )
    return StageBearing(reader.text(where, table, "on"), row)


def _end_body(reader: _Reader, where: str, table: Mapping[str, Any]) -> EndBody:
    reader.keys(where, table, _END_BODY_KEYS)
    mass = reader.number(where, table, "mass_kg")
    izz = reader.number(where, table, "izz_kgm2")
    ixx = reader.number(where, table, "ixx_kgm2", izz / 2.0)
    if "torsional_stiffness" in table:
        if "shaft_diameter_mm" in table or "shaft_length_mm" in table:
            raise reader.fail(
                f"{where}.torsional_stiffness",
                "give either torsional_stiffness or shaft_diameter_mm and shaft_length_mm",
            )
        stiffness = reader.number(where, table, "torsional_stiffness")
    else:
        stiffness = solid_shaft_stiffness(
            reader.number(where, table, "shaft_diameter_mm") * 1e-3,
            reader.number(where, table, "shaft_length_mm") * 1e-3,
            steel_shear_modulus(),
        )
    return EndBody(
        name=reader.text(where, table, "name"),
        shaft=reader.text(where, table, "shaft"),
        mass_properties=(mass, ixx, izz),
        stiffness=stiffness,
        position=reader.number(where, table, "position_mm", 0.0) * 1e-3,
        damping=reader.number(where, table, "torsional_damping", 0.0),
    )
