"""A rolling bearing's operation and inside in a model, for its modified and reference lives.

ISO 281:2007 §9 and ISO/TS 16281:2008 need the lubricant, the cleanliness, the fatigue load
limit, the static rating and the internal geometry.

A ``<bearing>`` or one of its ``<row>`` elements may give (docs/model_format.md "Bearing life"):

    lubricant_vg="320"            ISO 3448 viscosity grade (default 320)
    temperature_C="70"            operating temperature (default 70 °C)
    viscosity_100C_cSt="24"       the oil's viscosity at 100 °C (default: Walther slope 3.5)
    viscosity_cSt="60"            the operating viscosity outright (then the three above go)
    contamination="normal_cleanliness"   ISO 281 Table 13 class, or e_C as a number
    fatigue_limit_kN="420"        C_u (else estimated from C₀, else no modified life)
    rating_c0_kN="9000"           basic static load rating C₀
    size_mm="D d B"               outer diameter, bore, width (a ``<row>`` has it already)
    rollers="24" roller_mm="D_we L_we" contact_angle_deg="10"   internal geometry (else estimated)
    radial_clearance_mm="0.05" preload="true"   clearance (negative only with preload="true")
    rotating_ring="inner"         the ring that turns relative to the load (default: outer for
                                  a planet's bearing, inner for the others)

A ``<row>`` takes what its ``<bearing>`` gives and may change any of it. ``life_data`` reads and
checks the attributes; ``life/row_life.py`` uses them.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass

from pinwind.errors import InvalidBearingLifeData
from pinwind.losses.oil import VG_GRADES

#: Default lubrication of a bearing whose model gives none: a wind-turbine gear oil ISO VG 320
#: at 70 °C, normally clean (filtered circulating oil); said wherever it is used.
DEFAULT_VG = 320
DEFAULT_TEMPERATURE = 273.15 + 70.0
DEFAULT_CONTAMINATION = "normal_cleanliness"

#: ISO 281:2007 Table 13: class → (e_C range for d_m < 100 mm, e_C range for d_m ≥ 100 mm).
CONTAMINATION_RANGES: dict[str, tuple[tuple[float, float], tuple[float, float]]] = {
    "extreme_cleanliness": ((1.0, 1.0), (1.0, 1.0)),
    "high_cleanliness": ((0.6, 0.8), (0.8, 0.9)),
    "normal_cleanliness": ((0.5, 0.6), (0.6, 0.8)),
    "slight_contamination": ((0.3, 0.5), (0.4, 0.6)),
    "typical_contamination": ((0.1, 0.3), (0.2, 0.4)),
    "severe_contamination": ((0.0, 0.1), (0.0, 0.1)),
    "very_severe_contamination": ((0.0, 0.0), (0.0, 0.0)),
}
CONTAMINATION_CLASSES = tuple(CONTAMINATION_RANGES)


#: The attributes ``life_data`` reads (on ``<bearing>`` and ``<row>``).
LIFE_ATTRIBUTES = (
    "lubricant_vg", "temperature_C", "viscosity_100C_cSt", "viscosity_cSt", "contamination",
    "fatigue_limit_kN", "rating_c0_kN", "rollers", "roller_mm", "contact_angle_deg",
    "radial_clearance_mm", "preload", "rotating_ring", "size_mm",
)  # fmt: skip


@dataclass(frozen=True)
class BearingLifeData:
    """A bearing's operation and inside for its modified and reference lives (SI units).

    Attributes:
        grade: ISO VG grade of the oil.
        temperature: operating temperature [K].
        viscosity_100: oil's ν at 100 °C [m²/s], or None (Walther slope assumed).
        viscosity: operating viscosity given outright [m²/s], or None (from the grade).
        contamination: e_C given as a number, or None (from ``contamination_class``).
        contamination_class: ISO 281 Table 13 class.
        fatigue_limit: C_u [N], or None.
        static_rating: C₀ [N], or None.
        size: (D, d, B) [m], or None.
        rollers: Z per row, or None (estimated from the size).
        roller: (D_we, L_we) [m], or None.
        contact_angle: α [rad], or None (the type's).
        clearance: radial clearance [m] (negative: a preload).
        rotating: "inner" or "outer" (when not given, ``row_life`` takes "outer" for a planet's
            bearing, whose outer ring turns in the planet's bore, and "inner" for the others).
        defaults: the attributes taken at pinwind's defaults (said in the output).
    """

    grade: int = DEFAULT_VG
    temperature: float = DEFAULT_TEMPERATURE
    viscosity_100: float | None = None
    viscosity: float | None = None
    contamination: float | None = None
    contamination_class: str = DEFAULT_CONTAMINATION
    fatigue_limit: float | None = None
    static_rating: float | None = None
    size: tuple[float, float, float] | None = None
    rollers: int | None = None
    roller: tuple[float, float] | None = None
    contact_angle: float | None = None
    clearance: float = 0.0
    rotating: str = "inner"
    defaults: tuple[str, ...] = ("lubricant_vg", "temperature_C", "contamination", "rotating_ring")


def _numbers(where: str, attr: str, raw: str, count: int, path: str) -> list[float]:
    try:
        values = [float(x) for x in raw.split()]
    except ValueError:
        values = []
    if len(values) != count or not all(math.isfinite(v) for v in values):
        raise InvalidBearingLifeData(
            where, attr, raw, f'{attr}="{raw}" must be {count} number(s)', path=path
        )
    return values


def life_data(
    attrs: Mapping[str, str],
    *,
    where: str,
    path: str,
    inherited: BearingLifeData | None = None,
    rating: float | None = None,
) -> BearingLifeData:
    """The life data an element's attributes give, over those it inherits (module docstring).

    Args:
        attrs: the element's attributes (others are ignored).
        where: the element, for messages (``<bearing joint="lss"> <row name="INP-A">``).
        path: the model file, for messages.
        inherited: its ``<bearing>``'s data (a ``<row>``), or None: the defaults.
        rating: its dynamic load rating C [N], to check C_u < C.

    Raises:
        InvalidBearingLifeData: a grade outside ISO 3448's list, a temperature or viscosity
            that is not a finite positive number, an unknown cleanliness class or e_C outside
            [0, 1], C_u or C₀ not positive or C_u ≥ C, a negative clearance without
            preload="true", a geometry that is not positive.
    """
    base = inherited or BearingLifeData()
    given = {k: v.strip() for k, v in attrs.items() if k in LIFE_ATTRIBUTES}
    out: dict[str, object] = {}
    defaults = [d for d in base.defaults if d not in given]

    def bad(attr: str, message: str) -> InvalidBearingLifeData:
        return InvalidBearingLifeData(where, attr, given[attr], message, path=path)

    if "lubricant_vg" in given:
        raw = given["lubricant_vg"]
        grade = int(float(raw)) if raw.replace(".", "", 1).isdigit() else -1
        if grade not in VG_GRADES or float(raw) != grade:
            raise bad(
                "lubricant_vg",
                f'lubricant_vg="{raw}" is not an ISO 3448 viscosity grade; give one of '
                f"{', '.join(str(g) for g in VG_GRADES)}",
            )
        out["grade"] = grade
    positive = {"viscosity_100C_cSt": "viscosity_100", "viscosity_cSt": "viscosity"}
    for attr, field in positive.items():
        if attr in given:
            (value,) = _numbers(where, attr, given[attr], 1, path)
            if value <= 0.0:
                raise bad(attr, f"{attr} = {value:g} mm²/s; a viscosity is > 0")
            out[field] = value * 1e-6
    if "temperature_C" in given:
        (value,) = _numbers(where, "temperature_C", given["temperature_C"], 1, path)
        if not -50.0 <= value <= 200.0:
            raise bad(
                "temperature_C",
                f"temperature_C = {value:g} °C; give the bearing's operating temperature "
                "(−50 … 200 °C)",
            )
        out["temperature"] = value + 273.15
    if "contamination" in given:
        raw = given["contamination"]
        if raw in CONTAMINATION_CLASSES:
            out["contamination_class"], out["contamination"] = raw, None
        else:
            try:
                value = float(raw)
            except ValueError:
                value = math.nan
            if not 0.0 <= value <= 1.0:
                raise bad(
                    "contamination",
                    f'contamination="{raw}": give e_C from 0 to 1 or an ISO 281 Table 13 '
                    f"class: {', '.join(CONTAMINATION_CLASSES)}",
                )
            out["contamination"] = value
    for attr, field in (("fatigue_limit_kN", "fatigue_limit"), ("rating_c0_kN", "static_rating")):
        if attr in given:
            (value,) = _numbers(where, attr, given[attr], 1, path)
            if value <= 0.0:
                raise bad(attr, f"{attr} = {value:g} kN; give the catalogue's value, > 0")
            out[field] = value * 1e3
    if "size_mm" in given:
        values = _numbers(where, "size_mm", given["size_mm"], 3, path)
        if not (values[0] > values[1] > 0.0 and values[2] > 0.0):
            raise bad("size_mm", f'size_mm="{given["size_mm"]}": give D > d > 0 and B > 0 [mm]')
        out["size"] = (values[0] * 1e-3, values[1] * 1e-3, values[2] * 1e-3)
    if "rollers" in given:
        (value,) = _numbers(where, "rollers", given["rollers"], 1, path)
        if value != int(value) or value < 3:
            raise bad("rollers", f"rollers = {value:g}: a whole number of rolling elements ≥ 3")
        out["rollers"] = int(value)
    if "roller_mm" in given:
        values = _numbers(where, "roller_mm", given["roller_mm"], 2, path)
        if values[0] <= 0.0 or values[1] < 0.0:
            raise bad(
                "roller_mm",
                f'roller_mm="{given["roller_mm"]}": the rolling element\'s diameter D_we > 0 '
                "and length L_we ≥ 0 (0 for a ball) [mm]",
            )
        out["roller"] = (values[0] * 1e-3, values[1] * 1e-3)
    if "contact_angle_deg" in given:
        (value,) = _numbers(where, "contact_angle_deg", given["contact_angle_deg"], 1, path)
        if not 0.0 <= value < 60.0:
            raise bad("contact_angle_deg", f"contact_angle_deg = {value:g}: give 0 … 60°")
        out["contact_angle"] = math.radians(value)
    preload = given.get("preload", "false").lower()
    if preload not in ("true", "false"):
        raise bad("preload", f'preload="{given["preload"]}" must be "true" or "false"')
    if "radial_clearance_mm" in given:
        (value,) = _numbers(where, "radial_clearance_mm", given["radial_clearance_mm"], 1, path)
        if value < 0.0 and preload != "true":
            raise bad(
                "radial_clearance_mm",
                f"radial_clearance_mm = {value:g}: a negative clearance is a preload; add "
                'preload="true" if it is one, or give the clearance (≥ 0)',
            )
        out["clearance"] = value * 1e-3
    if "rotating_ring" in given:
        if given["rotating_ring"] not in ("inner", "outer"):
            raise bad("rotating_ring", 'rotating_ring must be "inner" or "outer"')
        out["rotating"] = given["rotating_ring"]
    data = dataclasses.replace(base, **out, defaults=tuple(defaults))  # type: ignore[arg-type]
    if data.fatigue_limit is not None and rating is not None and data.fatigue_limit >= rating:
        raise InvalidBearingLifeData(
            where,
            "fatigue_limit_kN",
            data.fatigue_limit / 1e3,
            f"fatigue load limit C_u = {data.fatigue_limit / 1e3:g} kN is not below the dynamic "
            f"load rating C = {rating / 1e3:g} kN; C_u is a few % of C (check the units: kN)",
            path=path,
        )
    return data
