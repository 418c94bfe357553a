"""Write the shipped model files of models/ with pinwind.model.builders.

Every value and its source (seed table or documented assumption) is listed in models/README.md.
Run ``python models/generate.py`` after changing the builder; the outputs are checked in.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable
from pathlib import Path

from pinwind.model.builders import (
    compound_planetary_urdf,
    cylinder_inertia,
    planetary_urdf,
    read_stage_file,
    shift_sum_for_centre_distance,
    split_shaft_pair_urdf,
    stages_urdf,
)
from pinwind.model.gearbox import load

HERE = Path(__file__).resolve().parent

# --- Saleh et al. 2017, 1.4 MW -----------------------------------------

#: Table 3 (kg, kg·m²): body → (mass, Ixx = Iyy, Izz).
SALEH_TABLE_3 = {
    "ring": (1238.0, 556.639, 1083.485),
    "sun": (263.5, 5.5885, 4.8370),
    "carrier": (405.091, 44.2734, 88.264),
    "pin": (254.3, 46.14, 1.87),
    "planet": (1113.1, 52.284, 77.78),
}
#: Table 2 and §4.3: 24/48/120 teeth, 3 planets, m = 15 mm, α = 24.5°, F = 380 mm.
SALEH_PLANETARY = dict(
    sun=24,
    planet=48,
    ring=120,
    planets=3,
    module=15e-3,
    pressure_angle=math.radians(24.5),
    face_width=0.380,
    inertias=SALEH_TABLE_3,
)
#: Table 2 parallel stages (wheel, pinion); module and width assumed (models/README.md).
SALEH_PARALLEL = dict(
    parallel=[(83, 23), (103, 26)],
    parallel_module=[15e-3, 10e-3],
    parallel_face_width=[0.330, 0.170],
)


def saleh2017_planetary() -> str:
    """Planetary stage of the 1.4 MW gearbox with Table 3 mass properties."""
    return planetary_urdf(name="saleh2017_planetary", **SALEH_PLANETARY)


def saleh2017_drivetrain() -> str:
    """Planetary stage plus the two parallel stages 83/23 and 103/26."""
    return planetary_urdf(name="saleh2017_drivetrain", **SALEH_PLANETARY, **SALEH_PARALLEL)


# --- CART 600 kW (IFToMM 2018 Table 1) -------------------------------------------

CART_CENTRE_DISTANCE = 0.355
CART_SUN_MODULE = 5.38e-3
CART_PRESSURE_ANGLE = math.radians(20.0)


def cart600_shift_sum() -> float:
    """x_sun + x_planet_b that puts the 29/103 pair of module 5.38 mm at exactly 355 mm."""
    return shift_sum_for_centre_distance(
        29,
        103,
        module=CART_SUN_MODULE,
        pressure_angle=CART_PRESSURE_ANGLE,
        centre_distance=CART_CENTRE_DISTANCE,
    )


def cart600_gearbox() -> str:
    """Compound-planet stage and output pair of the CART 600 kW gearbox."""
    x_sum = cart600_shift_sum()
    return compound_planetary_urdf(
        name="cart600_gearbox",
        sun=29,
        planet_a=22,
        planet_b=103,
        ring=93,
        planets=3,
        ring_module=10e-3,
        sun_module=CART_SUN_MODULE,
        pressure_angle=CART_PRESSURE_ANGLE,
        ring_face_width=0.150,
        sun_face_width=0.150,
        profile_shift={"sun": x_sum / 2.0, "planet_b": x_sum / 2.0},
        parallel=[(57, 23)],
        parallel_module=5.5e-3,
        parallel_face_width=0.056,
        # Table 1 gives Ixx = 188 about the rotation axis (x in the seed) and Iyy = Izz = 128;
        # in our shaft-along-z convention that is Izz = 188, Ixx = Iyy = 128.
        inertias={"carrier": (1300.0, 128.0, 188.0)},
        bores={
            "sun": 0.125,
            "planet_a": 0.175,
            "planet_b": 0.175,
            "stage1_wheel": 0.080,
            "stage1_pinion": 0.080,
        },
        shafts={
            "planet": (0.100, 0.175, 0.450),
            "sun": (0.075, 0.125, 0.470),
            "stage1_pinion": (0.0, 0.080, 0.300),
        },
    )


# --- Cai's spur pair (Kelso 2011 Tables 3-1, 3-2) ---------------------------------

STEEL_DENSITY = 7850.0
CAI_HALF_SHAFT_MASS = 3.858
CAI_HALF_SHAFT_IZZ = 0.001
CAI_GEARS = ((1.333, 0.002, 0.015), (10.667, 0.002, 0.030))  # mass, Izz, face width


def cai_half_shaft() -> tuple[float, float, float]:
    """Half-shaft (mass, Ixx, Izz): Ixx of the steel cylinder with Table 3-1's mass and Izz."""
    m, izz = CAI_HALF_SHAFT_MASS, CAI_HALF_SHAFT_IZZ
    radius = math.sqrt(2.0 * izz / m)
    length = m / (STEEL_DENSITY * math.pi * radius**2)
    ixx, _ = cylinder_inertia(m, outer_radius=radius, length=length)
    return m, ixx, izz


def cai_gear(mass: float, izz: float, width: float) -> tuple[float, float, float]:
    """Gear (mass, Ixx, Izz) with Table 3-1's Izz and the thin-disc Ixx = Izz/2 + m b²/12."""
    return mass, izz / 2.0 + mass * width**2 / 12.0, izz


def cai_spur_pair() -> str:
    """Cai's 40/80 spur pair on split input and output shafts."""
    return split_shaft_pair_urdf(
        name="cai_spur_pair",
        teeth=(40, 80),
        module=3e-3,
        pressure_angle=math.radians(20.0),
        face_width=(0.015, 0.030),
        shaft_stiffness=442.3,
        half_shaft=cai_half_shaft(),
        gear_inertias=tuple(cai_gear(*g) for g in CAI_GEARS),
    )


# --- DTU 500 kW (Jørgensen 2014 §2.1, Table 6) -----------------------------------------


#: ISO 281 ratings of the DTU stage's bearings, ASSUMED (Jørgensen 2014 gives none;
#: models/README.md): joint → (type, C [kN]). SKF EC-design cylindrical roller bearings of
#: plausible bore: each planet on two NU 2228 EC (140 x 250 x 68 mm, C = 655 kN each) side by
#: side, rated as one unit with ISO 281's C = i^(7/9) C_1 for i = 2; the sun shaft on an NU 226 EC
#: (130 x 230 x 40 mm, 415 kN); the carrier on an NU 1964 EC (320 x 440 x 56 mm, 693 kN).
DTU500_BEARINGS = {
    **{f"planet{i}": ("cylindrical_roller", round(2.0 ** (7.0 / 9.0) * 655.0)) for i in (1, 2, 3)},
    "sun": ("cylindrical_roller", 415),
    "carrier": ("cylindrical_roller", 693),
}


def with_bearings(text: str, bearings: dict[str, tuple[str, float]]) -> str:
    """Model text with a ``<bearing>`` element per joint (type, C [kN]) in its ``<gearbox>``."""
    elements = "".join(
        f'    <bearing joint="{joint}" type="{kind}" rating_c_kN="{c_kn:g}" />\n'
        for joint, (kind, c_kn) in bearings.items()
    )
    return text.replace("  </gearbox>", elements + "  </gearbox>")


def dtu500_planetary() -> str:
    """Profile-shifted 20/35/91 planetary stage; module 10 mm and 20° from Table 6.

    Its bearings are rated with `DTU500_BEARINGS` (assumed).
    """
    text = planetary_urdf(
        name="dtu500_planetary",
        sun=20,
        planet=35,
        ring=91,
        planets=3,
        module=10e-3,
        pressure_angle=math.radians(20.0),
        face_width=0.210,
        profile_shift=(0.582, 0.419, -0.840),
    )
    return with_bearings(text, DTU500_BEARINGS)


# --- NREL 5 MW reference gearbox (Nejad et al. 2016), from its stage file ---------------------


def nrel5mw_gearbox() -> str:
    """Three stages, sixteen bearings, rotor and generator of ``nrel5mw_gearbox.toml``."""
    name, stages, bodies = read_stage_file(HERE / "nrel5mw_gearbox.toml")
    return stages_urdf(
        stages, name=name, end_bodies=bodies, source="pinwind build stages nrel5mw_gearbox.toml"
    )


MODELS: dict[str, Callable[[], str]] = {
    "saleh2017_planetary.urdf": saleh2017_planetary,
    "saleh2017_drivetrain.urdf": saleh2017_drivetrain,
    "cart600_gearbox.urdf": cart600_gearbox,
    "cai_spur_pair.urdf": cai_spur_pair,
    "dtu500_planetary.urdf": dtu500_planetary,
    "nrel5mw_gearbox.urdf": nrel5mw_gearbox,
}


def main(argv: list[str] | None = None) -> None:
    """Write every model to the output folder and check that each one loads."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=HERE, help="output folder (default: models/)")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    for file_name, build in MODELS.items():
        path = args.out / file_name
        path.write_text(build(), encoding="utf-8")
        print(load(path))


if __name__ == "__main__":
    main()
