"""Parallel-axis stages: a wheel on the driving shaft, a pinion on its own shaft above it.

Stage k is given as (wheel teeth, pinion teeth), e.g. 83/23. A wheel turns with the shaft that
drives it, so it is not a joint of its own: gear ``stage{k}_wheel`` sits on the driving link —
``sun`` after a planetary stage, ``input`` for a parallel train alone, ``stage{k-1}_pinion`` for
k > 1 — at an axial offset (``xyz`` of the gear element), and its mass is added to that link. The
pinion is a continuous joint and link ``stage{k}_pinion`` on the housing, parallel to the wheel
at the exact centre distance m (z_wheel + z_pinion)/2, offset along +y from the wheel (the
high-speed shaft above the low-speed one, as in wind-turbine gearboxes). Mesh ``stage{k}``: gear1
the wheel, gear2 the pinion. (A wheel on its own link welded to the shaft by a fixed joint would
not work: the loader keeps a fixed joint that carries a gear as a locked bearing.)

Default mass properties: steel cylinders of pitch diameter × face width
(``gear_bodies.steel_gear``). Default modules after a planetary stage: those whose teeth carry the
planetary's load per face width and module (``load_matched_modules``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from pinwind.errors import InvalidGearTrain
from pinwind.gears.involute import pitch_radius
from pinwind.model.builders.arguments import (
    helix_angles,
    inertia_table,
    per_stage,
    pressure_angle_rad,
    teeth_count,
)
from pinwind.model.builders.gear_bodies import MassProperties, steel_gear
from pinwind.model.builders.urdf_writer import Train, TrainGear, TrainJoint

#: Default modules of parallel stages are rounded up to a multiple of this [m].
MODULE_STEP = 0.5e-3


def load_matched_modules(
    stages: Sequence[tuple[int, int]], *, module: float, sun_teeth: int, planets: int
) -> list[float]:
    """Modules [m] of parallel stages after a planetary stage, sized from each stage's torque.

    Each stage's teeth get the tooth load intensity F_t/(b m) of the sun–planet meshes (the
    root bending stress is about Y F_t/(b m)), with faces as wide in modules as the planetary's
    (b_k/m_k = b/m, so F_t/(b m) ∝ F_t/m²). The sun passes its torque T_s through ``planets``
    meshes on its pitch diameter m z_sun: F_t = 2 T_s/(planets m z_sun). Stage k's wheel carries
    T_k = T_s Π_{j<k} z_pinion,j/z_wheel,j in one mesh on m_k z_wheel,k. Equal F_t/m² gives

        m_k = m (planets z_sun T_k / (T_s z_wheel,k))^(1/3),

    rounded up to ``MODULE_STEP`` (never a higher load than the planetary's).

    Args:
        stages: (wheel teeth, pinion teeth) per stage, input side first.
        module: module of the planetary stage [m].
        sun_teeth: sun tooth count.
        planets: number of planets.
    """
    out = []
    torque = 1.0  # T_k / T_s
    for wheel, pinion in stages:
        exact = module * (planets * sun_teeth * torque / wheel) ** (1.0 / 3.0)
        out.append(math.ceil(exact / MODULE_STEP - 1e-9) * MODULE_STEP)
        torque *= pinion / wheel
    return out


def add_parallel_stages(
    train: Train,
    *,
    stages: Sequence[tuple[int, int]],
    first_link: str,
    first_link_z: float,
    previous_face_end: float,
    pressure_angle: float,
    modules: Sequence[float],
    face_widths: Sequence[float],
    inertias: Mapping[str, MassProperties],
    bores: Mapping[str, float] | None = None,
    helix_angles: Sequence[float] | None = None,
) -> None:
    """Stage k: wheel gear on the driving link, pinion joint ``stage{k}_pinion`` on the housing.

    Axial layout: the face of each stage's gears starts one half face width after the previous
    gear's face ends (``previous_face_end`` [m], world z of the last face before stage 1).
    Helical stages (``helix_angles`` [rad], default spur): the wheel has +β, the pinion −β (an
    external pair needs opposite hands, docs/model_format.md); the centre distance is then
    m_n (z_wheel + z_pinion)/(2 cos β). ``bores``: gear name → bore diameter [m].
    """
    bores = bores or {}
    helix_angles = list(helix_angles) if helix_angles is not None else [0.0] * len(stages)
    link, link_xyz = first_link, np.array([0.0, 0.0, first_link_z])
    face_end = previous_face_end

    def props(gear: str, teeth: int, m: float, b: float, beta: float) -> MassProperties:
        return inertias.get(gear) or steel_gear(
            teeth, module=m, face_width=b, bore=bores.get(gear, 0.0), helix_angle=beta
        )

    for k, (wheel, pinion) in enumerate(stages, start=1):
        wheel = teeth_count(f"parallel stage {k} wheel teeth", wheel)
        pinion = teeth_count(f"parallel stage {k} pinion teeth", pinion)
        m, b, beta = modules[k - 1], face_widths[k - 1], helix_angles[k - 1]
        z = face_end + b  # the face starts b/2 after the previous one ends
        face_end = z + 0.5 * b
        wheel_name, pinion_name = f"stage{k}_wheel", f"stage{k}_pinion"
        centre_distance = pitch_radius(wheel, m, beta) + pitch_radius(pinion, m, beta)
        pinion_xyz = link_xyz + np.array([0.0, centre_distance, 0.0])
        pinion_xyz[2] = z
        train.joints.append(
            TrainJoint(pinion_name, "continuous", "housing", pinion_name, tuple(pinion_xyz))
        )
        train.gear(
            TrainGear(wheel_name, link, wheel, m, pressure_angle, b, z=z - link_xyz[2],
                      helix_angle=beta),
            props(wheel_name, wheel, m, b, beta),
        )  # fmt: skip
        train.gear(
            TrainGear(pinion_name, pinion_name, pinion, m, pressure_angle, b, helix_angle=-beta),
            props(pinion_name, pinion, m, b, beta),
        )
        train.meshes.append((f"stage{k}", wheel_name, pinion_name))
        link, link_xyz = pinion_name, pinion_xyz


def parallel_urdf(
    *,
    stages: Sequence[tuple[int, int]],
    module: float | Sequence[float],
    pressure_angle: float,
    face_width: float | Sequence[float],
    helix_angle: float | Sequence[float] = 0.0,
    name: str = "parallel",
    inertias: Mapping[str, MassProperties] | None = None,
) -> str:
    """URDF text of a parallel-axis gear train alone (no planetary stage before it).

    Joint ``input`` (continuous, on the housing at the origin) is the low-speed input shaft and
    carries ``stage1_wheel``; stage k's pinion ``stage{k}_pinion`` drives stage k + 1's wheel
    (module docstring), the first wheel's face centred on z = 0. Default mass properties: steel
    cylinders of pitch diameter × face width.

    Args:
        stages: (wheel teeth, pinion teeth) per stage, input side first (Saleh 2017's 83/23,
            103/26).
        module: normal module m_n [m], one value or one per stage.
        pressure_angle: normal pressure angle [rad].
        face_width: face width [m], one value or one per stage.
        helix_angle: helix angle β [rad] of each stage's wheel (its pinion gets −β), one value or
            one per stage; 0 for spur gears.
        name: robot name.
        inertias: ``stage{k}_wheel`` / ``stage{k}_pinion`` → (mass [kg], Ixx = Iyy, Izz [kg·m²]).

    Raises:
        InvalidGearTrain: no stage, non-positive teeth, module or width, or |β| ≥ 45°.
    """
    stages = list(stages)
    if not stages:
        raise InvalidGearTrain("parallel_urdf needs at least one stage (wheel teeth, pinion teeth)")
    allowed = [f"stage{k}_{g}" for k in range(1, len(stages) + 1) for g in ("wheel", "pinion")]
    table = inertia_table(inertias, allowed)
    modules = per_stage("module", module, math.nan, len(stages))
    widths = per_stage("face_width", face_width, math.nan, len(stages))
    betas = helix_angles("helix_angle", helix_angle, len(stages))
    train = Train(name, "pinwind.model.builders.parallel_urdf")
    train.link("housing")
    train.joints.append(TrainJoint("input", "continuous", "housing", "input", (0.0, 0.0, 0.0)))
    train.link("input")
    add_parallel_stages(
        train,
        stages=stages,
        first_link="input",
        first_link_z=0.0,
        previous_face_end=-widths[0],
        pressure_angle=pressure_angle_rad(pressure_angle),
        modules=modules,
        face_widths=widths,
        inertias=table,
        helix_angles=betas,
    )
    return train.render()
