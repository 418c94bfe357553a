"""A rolling bearing's catalogue data in a model: its ISO 281 type, load factors and rating C.

A model file may rate a bearing (a revolute or continuous joint) with
``<bearing joint="planet1" type="spherical_roller" rating_c_kN="2400"/>`` in its ``<gearbox>``
(docs/model_format.md); ``model/urdf.py`` reads it into a ``BearingRating`` checked here, and
``life/bearing_life.py`` turns a run's reactions into its ISO 281 life. The type gives the life
exponent p and default load factors of the dynamic equivalent load (ISO 281:2007 §6)

    P = F_r + Y1 F_a            when F_a / F_r ≤ e
    P = X2 F_r + Y2 F_a         when F_a / F_r > e

(X = 1 up to e for every radial type here); a ``<bearing>`` may give its catalogue's own
``e``, ``y1``, ``x2``, ``y2``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pinwind.errors import InvalidBearingRating

#: ISO 281 life exponents p: 3 for point contact (ball), 10/3 for line contact (roller).
BALL_EXPONENT = 3.0
ROLLER_EXPONENT = 10.0 / 3.0


@dataclass(frozen=True)
class BearingType:
    """A rolling-bearing type's ISO 281 life exponent and load factors.

    Attributes:
        name: the type's name in model files (``tapered_roller``).
        exponent: life exponent p.
        e: limit of F_a / F_r below which P = F_r + Y1 F_a (inf: the axial load never counts).
        y1: axial factor Y up to e.
        x2, y2: radial and axial factors X, Y above e.
        source: where the factors come from.
    """

    name: str
    exponent: float
    e: float
    y1: float
    x2: float
    y2: float
    source: str


def _roller(name: str, rows: int, contact_angle_deg: float) -> BearingType:
    """ISO 281 §6.2 Table 7: radial roller bearings with a contact angle α ≠ 0.

    e = 1.5 tan α; one row: X = 0.4, Y = 0.4 cot α above e; two rows: Y = 0.45 cot α up to e,
    X = 0.67, Y = 0.67 cot α above.
    """
    tan = math.tan(math.radians(contact_angle_deg))
    y1, x2, y2 = (0.0, 0.4, 0.4 / tan) if rows == 1 else (0.45 / tan, 0.67, 0.67 / tan)
    return BearingType(
        name, ROLLER_EXPONENT, 1.5 * tan, y1, x2, y2,
        f"ISO 281 Table 7, {'single' if rows == 1 else 'double'} row, α = {contact_angle_deg:g}°",
    )  # fmt: skip


#: The bearing types a model file may name, with their default load factors; a ``<bearing>``
#: may give its own ``e``, ``y1``, ``x2``, ``y2`` (a catalogue's values for that bearing).
BEARING_TYPES: dict[str, BearingType] = {
    t.name: t
    for t in (
        # ISO 281 Table 3, single row, normal clearance, at f0 F_a / C0 = 1.03 (mid-table).
        BearingType("deep_groove_ball", BALL_EXPONENT, 0.28, 0.0, 0.56, 1.55,
                    "ISO 281 Table 3, single row, f0 Fa/C0 = 1.03"),
        BearingType("angular_contact_ball", BALL_EXPONENT, 1.14, 0.0, 0.35, 0.57,
                    "ISO 281 Table 3, single row, α = 40°"),
        # Radial load only: the ribs take small axial loads that ISO 281 does not rate.
        BearingType("cylindrical_roller", ROLLER_EXPONENT, math.inf, 0.0, 1.0, 0.0,
                    "ISO 281 §6.2, α = 0: P = F_r"),
        _roller("tapered_roller", 1, 15.0),
        _roller("spherical_roller", 2, 10.0),
        # A toroidal roller bearing (SKF's CARB) is a non-locating bearing: it takes no axial
        # load (ISO 281 §6.2 with α = 0, as a cylindrical roller bearing: P = F_r).
        BearingType("toroidal_roller", ROLLER_EXPONENT, math.inf, 0.0, 1.0, 0.0,
                    "ISO 281 §6.2, α = 0 (non-locating, CARB): P = F_r"),
    )
}  # fmt: skip


@dataclass(frozen=True)
class BearingRating:
    """One bearing's ISO 281 data: its type, load factors and dynamic load rating.

    Build it with ``bearing_rating`` (which checks the values); ``life/bearing_life.py`` gives
    its equivalent load and life.

    Attributes:
        joint: the bearing (joint) name.
        kind: the type (a key of ``BEARING_TYPES``).
        dynamic_load_rating: basic dynamic load rating C [N], or None when the model gives
            none (not rated).
        exponent: life exponent p.
        e, y1, x2, y2: load factors (``BearingType``).
    """

    joint: str
    kind: str
    dynamic_load_rating: float | None
    exponent: float
    e: float
    y1: float
    x2: float
    y2: float

    @property
    def rated(self) -> bool:
        """The bearing has a dynamic load rating C, so a life."""
        return self.dynamic_load_rating is not None


def bearing_rating(
    joint: str,
    kind: str,
    *,
    dynamic_load_rating: float | None,
    e: float | None = None,
    y1: float | None = None,
    x2: float | None = None,
    y2: float | None = None,
    path: str = "<python>",
) -> BearingRating:
    """The checked rating of bearing ``joint`` of type ``kind``; factors default to the type's.

    Args:
        joint: the bearing (joint) name.
        kind: a key of ``BEARING_TYPES``.
        dynamic_load_rating: C [N], None for a bearing that is not rated.
        e, y1, x2, y2: load factors, default the type's (``BearingType``).
        path: the model file, for messages.

    Raises:
        InvalidBearingRating: an unknown type, C not a positive finite number, a load factor
            negative or not a number (e may be inf: the axial load never counts).
    """
    if kind not in BEARING_TYPES:
        raise InvalidBearingRating(
            joint,
            f'type "{kind}" has no ISO 281 life exponent in pinwind; give one of '
            f"{', '.join(BEARING_TYPES)} (ball: p = 3, roller: p = 10/3)",
            path=path,
        )
    if dynamic_load_rating is not None and not (
        math.isfinite(dynamic_load_rating) and dynamic_load_rating > 0.0
    ):
        raise InvalidBearingRating(
            joint,
            f"dynamic load rating C = {dynamic_load_rating:g} N; give the catalogue's basic "
            "dynamic load rating, a positive number (rating_c_kN in kN)",
            path=path,
        )
    default = BEARING_TYPES[kind]
    factors = {
        "e": default.e if e is None else e,
        "y1": default.y1 if y1 is None else y1,
        "x2": default.x2 if x2 is None else x2,
        "y2": default.y2 if y2 is None else y2,
    }
    for name, value in factors.items():
        if math.isnan(value) or value < 0.0 or (name != "e" and math.isinf(value)):
            raise InvalidBearingRating(
                joint,
                f"load factor {name} = {value:g}; ISO 281 factors are finite and ≥ 0 (e may be "
                "inf: the axial load never counts)",
                path=path,
            )
    return BearingRating(joint, kind, dynamic_load_rating, default.exponent, **factors)
