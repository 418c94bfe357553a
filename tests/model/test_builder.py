"""Model builder and the shipped models: seed data in, a loadable and consistent gearbox out."""

from __future__ import annotations

import importlib.util
import math

import numpy as np
import pinocchio as pin
import pytest

from pinwind.errors import (
    ImplausibleGear,
    InputError,
    InvalidGearTrain,
    PinwindWarning,
    PlanetsCollide,
)
from pinwind.model.builders import (
    compound_planetary_urdf,
    planetary_urdf,
    write_planetary,
)
from pinwind.model.gearbox import Gearbox, load, loads
from tests.conftest import MODELS, load_model  # noqa: E402

SALEH_CENTRE_DISTANCE = 0.540  # Saleh 2017 §4.3: r3 = 540 mm


def small_planetary(**overrides) -> dict:
    args = dict(
        sun=20,
        planet=30,
        ring=80,
        planets=4,
        module=4e-3,
        pressure_angle=math.radians(20.0),
        face_width=0.05,
    )
    args.update(overrides)
    return args


def joint_id(gearbox: Gearbox, name: str) -> int:
    return gearbox.model.getJointId(name)


def speed_ratios(gearbox: Gearbox) -> dict[str, float]:
    """Joint speeds per unit carrier speed from rolling at every pitch point.

    For each mesh the pitch point P divides the centre line in the ratio of the tooth counts
    (external: |AP| = a z_A/(z_A + z_B); B internal: P lies beyond A, |AP| = a z_A/(z_B − z_A)).
    Rolling without sliding: the velocities of A's and B's material points at P agree along the
    tangent. Locked bearings do not turn. The train must keep exactly one degree of freedom.
    """
    model = gearbox.model
    data = model.createData()
    pin.computeJointJacobians(model, data, pin.neutral(model))
    axis = np.array([0.0, 0.0, 1.0])

    def point_jacobian(jid: int, point: np.ndarray) -> np.ndarray:
        jac = pin.getJointJacobian(model, data, jid, pin.LOCAL_WORLD_ALIGNED)
        return jac[:3] - pin.skew(point - data.oMi[jid].translation) @ jac[3:]

    rows = []
    for mesh in gearbox.meshes:
        a, b = mesh.gear_a, mesh.gear_b
        centre_a = data.oMi[a.joint_id].act(a.centre_in_joint)
        centre_b = data.oMi[b.joint_id].act(b.centre_in_joint)
        offset = centre_b - centre_a
        offset -= (offset @ axis) * axis
        za, zb = a.spec.teeth, b.spec.teeth
        if b.spec.internal:
            point = centre_a - offset * za / (zb - za)
        else:
            point = centre_a + offset * za / (za + zb)
        tangent = np.cross(axis, point - centre_a)
        tangent /= np.linalg.norm(tangent)
        rows.append(
            tangent @ (point_jacobian(a.joint_id, point) - point_jacobian(b.joint_id, point))
        )
    for name in gearbox.locked_joints:
        row = np.zeros(model.nv)
        row[gearbox.v_index(name)] = 1.0
        rows.append(row)
    _, singular, vt = np.linalg.svd(np.array(rows))
    rank = int(np.sum(singular > 1e-9 * singular[0]))
    assert model.nv - rank == 1, "the gear train must have one degree of freedom"
    v = vt[-1] / vt[-1][gearbox.v_index("carrier")]
    return {name: float(v[gearbox.v_index(name)]) for name in gearbox.joint_names}


# --- the builder --------------------------------------------------------------------------------


def test_built_planetary_with_pins_and_parallel_stage_loads(tmp_path):
    path = write_planetary(
        tmp_path / "p.urdf",
        **small_planetary(),
        parallel=[(60, 20)],
        inertias={"pin": (2.0, 0.01, 0.002)},
    )
    gearbox = load(path)
    assert sorted(gearbox.joint_names) == sorted(
        ["carrier", "sun", "planet1", "planet2", "planet3", "planet4", "ring", "stage1_pinion"]
    )
    assert gearbox.locked_joints == ["ring"]
    assert gearbox.gears["stage1_wheel"].spec.link == "sun"
    assert [m.name for m in gearbox.meshes][-1] == "stage1"
    # The pins are welded into the carrier: 4 pins of 2 kg on top of the steel cheeks.
    cheeks = 7850 * math.pi * (0.1 + 0.06) ** 2 * 0.025
    np.testing.assert_allclose(
        gearbox.model.inertias[joint_id(gearbox, "carrier")].mass, cheeks + 8.0, rtol=1e-9
    )


def test_steel_planet_has_the_mass_of_its_pitch_cylinder():
    gearbox = loads(planetary_urdf(**small_planetary()))
    # 30 teeth × 4 mm: pitch diameter 120 mm, face width 50 mm, 7850 kg/m³.
    mass = 7850 * math.pi * 0.06**2 * 0.05
    inertia = gearbox.model.inertias[joint_id(gearbox, "planet1")]
    np.testing.assert_allclose(inertia.mass, mass, rtol=1e-9)
    np.testing.assert_allclose(inertia.inertia[2, 2], mass * 0.06**2 / 2, rtol=1e-9)


def test_ring_that_does_not_fit_sun_and_planets_is_rejected():
    with pytest.raises(InvalidGearTrain) as info:
        planetary_urdf(**small_planetary(ring=81))
    assert isinstance(info.value, InputError)
    message = str(info.value)
    assert "ring has 81 teeth" in message
    assert "20 + 2·30 = 80" in message


def test_non_positive_teeth_are_rejected():
    with pytest.raises(InvalidGearTrain, match=r"sun = 0; a tooth count"):
        planetary_urdf(**small_planetary(sun=0))


def test_pressure_angle_in_degrees_is_rejected():
    with pytest.raises(InvalidGearTrain, match=r"math.radians\(20\)"):
        planetary_urdf(**small_planetary(pressure_angle=20.0))


def test_overlapping_planets_are_rejected():
    # Sun 10, planet 40, ring 90, module 4 mm: a = 100 mm, planet tip diameter 2·(80 + 4) mm =
    # 168 mm > chord 2·100·sin(36°) = 117.6 mm between 5 planets.
    with pytest.raises(PlanetsCollide) as info:
        planetary_urdf(**small_planetary(sun=10, planet=40, ring=90, planets=5))
    assert "168.00 mm" in str(info.value)
    assert "117.56 mm" in str(info.value)


def test_unassemblable_planet_count_warns():
    # (20 + 80)/3 is not a whole number.
    with pytest.warns(PinwindWarning, match=r"\(20 \+ 80\)/3"):
        planetary_urdf(**small_planetary(planets=3))


def test_compound_planets_with_unequal_centre_distances_are_rejected():
    # CART 600 kW without profile shift: ring–A (93 − 22)·10/2 = 355 mm, sun–B
    # (29 + 103)·5.38/2 = 355.08 mm (IFToMM 2018 Table 1).
    with pytest.raises(InvalidGearTrain) as info:
        compound_planetary_urdf(
            sun=29,
            planet_a=22,
            planet_b=103,
            ring=93,
            planets=3,
            ring_module=10e-3,
            sun_module=5.38e-3,
            pressure_angle=math.radians(20.0),
            ring_face_width=0.15,
            sun_face_width=0.15,
        )
    assert "355.0000 mm" in str(info.value)
    assert "355.0800 mm" in str(info.value)


# --- the shipped models -------------------------------------------------------------------------


def test_shipped_models_are_what_the_generator_writes(tmp_path):
    spec = importlib.util.spec_from_file_location("generate", MODELS / "generate.py")
    generate = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(generate)
    with pytest.warns(ImplausibleGear, match='<link name="gear2">'):  # Cai's, models/README.md
        generate.main(["--out", str(tmp_path)])
    for name in generate.MODELS:
        assert (tmp_path / name).read_text() == (MODELS / name).read_text(), name


def test_saleh_planetary_has_table3_mass_properties():
    # Saleh 2017 Table 3: (mass kg, Ixx = Iyy, Izz kg·m²).
    gearbox = load(MODELS / "saleh2017_planetary.urdf")
    table = {
        "ring": (1238.0, 556.639, 1083.485),
        "sun": (263.5, 5.5885, 4.8370),
        "planet1": (1113.1, 52.284, 77.78),
        "planet2": (1113.1, 52.284, 77.78),
        "planet3": (1113.1, 52.284, 77.78),
    }
    for body, (mass, ixx, izz) in table.items():
        inertia = gearbox.model.inertias[joint_id(gearbox, body)]
        np.testing.assert_allclose(inertia.mass, mass, rtol=1e-12, err_msg=body)
        np.testing.assert_allclose(inertia.lever, np.zeros(3), atol=1e-12, err_msg=body)
        np.testing.assert_allclose(
            inertia.inertia, np.diag([ixx, ixx, izz]), rtol=1e-12, atol=1e-12, err_msg=body
        )


def test_saleh_pins_merge_into_the_carrier_by_the_parallel_axis_theorem():
    # Carrier (405.091 kg; 44.2734, 88.264 kg·m²) plus three pins (254.3 kg; 46.14, 1.87 kg·m²)
    # at r = 0.54 m, angles 0°, 120°, 240°: Σ x² = Σ y² = 1.5 r², Σ xy = 0, so the centre of mass
    # stays on the axis, Ixx = Iyy = 44.2734 + 3·46.14 + 254.3·1.5 r² and
    # Izz = 88.264 + 3·1.87 + 3·254.3 r².
    gearbox = load(MODELS / "saleh2017_planetary.urdf")
    inertia = gearbox.model.inertias[joint_id(gearbox, "carrier")]
    r2 = SALEH_CENTRE_DISTANCE**2
    ixx = 44.2734 + 3 * 46.14 + 254.3 * 1.5 * r2
    izz = 88.264 + 3 * 1.87 + 3 * 254.3 * r2
    np.testing.assert_allclose(inertia.mass, 405.091 + 3 * 254.3, rtol=1e-12)
    np.testing.assert_allclose(inertia.lever, np.zeros(3), atol=1e-12)
    np.testing.assert_allclose(inertia.inertia, np.diag([ixx, ixx, izz]), rtol=1e-9, atol=1e-9)


def test_saleh_planets_sit_at_540_mm_equally_spaced():
    gearbox = load(MODELS / "saleh2017_planetary.urdf")
    data = gearbox.model.createData()
    pin.forwardKinematics(gearbox.model, data, gearbox.neutral())
    for i, angle in enumerate((0.0, 120.0, 240.0), start=1):
        centre = data.oMi[joint_id(gearbox, f"planet{i}")].translation
        expected = SALEH_CENTRE_DISTANCE * np.array(
            [math.cos(math.radians(angle)), math.sin(math.radians(angle)), 0.0]
        )
        np.testing.assert_allclose(centre, expected, atol=1e-12)
    for mesh in gearbox.meshes:
        np.testing.assert_allclose(mesh.centre_distance, SALEH_CENTRE_DISTANCE, rtol=1e-12)


def test_saleh_planetary_stage_ratio_is_six():
    # Ring fixed: ω_sun/ω_carrier = 1 + z_ring/z_sun = 1 + 120/24 (Saleh 2017).
    ratios = speed_ratios(load(MODELS / "saleh2017_planetary.urdf"))
    np.testing.assert_allclose(ratios["sun"], 6.0, rtol=1e-9)
    np.testing.assert_allclose(ratios["ring"], 0.0, atol=1e-12)


def test_saleh_drivetrain_overall_ratio_from_tooth_counts():
    # Table 2: planetary 6, then 83/23 and 103/26; two external stages keep the direction.
    ratios = speed_ratios(load(MODELS / "saleh2017_drivetrain.urdf"))
    np.testing.assert_allclose(ratios["stage1_pinion"], -6.0 * 83 / 23, rtol=1e-9)
    np.testing.assert_allclose(ratios["stage2_pinion"], 6.0 * 83 / 23 * 103 / 26, rtol=1e-9)
    assert 85.0 <= ratios["stage2_pinion"] <= 100.0  # §4.1: overall ratio 85 to 100


def test_cart_compound_planets_sit_at_355_mm():
    # IFToMM 2018 Table 1: ring–A (93 − 22)·10 mm/2 = 355 mm.
    gearbox = load(MODELS / "cart600_gearbox.urdf")
    data = gearbox.model.createData()
    pin.forwardKinematics(gearbox.model, data, gearbox.neutral())
    for i in (1, 2, 3):
        centre = data.oMi[joint_id(gearbox, f"planet{i}")].translation
        np.testing.assert_allclose(np.hypot(centre[0], centre[1]), 0.355, rtol=1e-10)
    for mesh in gearbox.meshes[:6]:
        np.testing.assert_allclose(mesh.centre_distance, 0.355, rtol=1e-9, err_msg=mesh.name)


def test_cart_overall_ratio_follows_compound_planet_formula():
    # Ring fixed, compound planets: ω_sun/ω_carrier = 1 + (z_ring z_B)/(z_A z_sun); the output
    # pair 57/23 reverses the direction.
    ratios = speed_ratios(load(MODELS / "cart600_gearbox.urdf"))
    stage = 1 + 93 * 103 / (22 * 29)
    np.testing.assert_allclose(ratios["sun"], stage, rtol=1e-9)
    np.testing.assert_allclose(ratios["stage1_pinion"], -stage * 57 / 23, rtol=1e-9)


def test_cart_carrier_has_188_about_its_rotation_axis():
    # Table 1: 1300 kg, Ixx = 188 about the seed's rotation axis x, Iyy = Izz = 128 kg·m².
    gearbox = load(MODELS / "cart600_gearbox.urdf")
    inertia = gearbox.model.inertias[joint_id(gearbox, "carrier")]
    np.testing.assert_allclose(inertia.mass, 1300.0, rtol=1e-12)
    np.testing.assert_allclose(inertia.inertia, np.diag([128.0, 128.0, 188.0]), rtol=1e-12)


def test_cai_gear_bodies_carry_a_half_shaft_and_springs_join_the_halves():
    # Kelso 2011 Table 3-1: half-shaft 3.858 kg, 0.001 kg·m²; gear 1 1.333 kg,
    # gear 2 10.667 kg, 0.002 kg·m² each; shaft stiffness 442.3 N·m/rad.
    gearbox = load_model(MODELS / "cai_spur_pair.urdf")
    for body, mass, izz in (
        ("input_shaft", 3.858, 0.001),
        ("gear1", 1.333 + 3.858, 0.002 + 0.001),
        ("gear2", 10.667 + 3.858, 0.002 + 0.001),
        ("output_shaft", 3.858, 0.001),
    ):
        inertia = gearbox.model.inertias[joint_id(gearbox, body)]
        np.testing.assert_allclose(inertia.mass, mass, rtol=1e-12, err_msg=body)
        np.testing.assert_allclose(inertia.inertia[2, 2], izz, rtol=1e-12, err_msg=body)
    springs = {s.name: (s.joint_1, s.joint_2, s.stiffness) for s in gearbox.springs}
    assert springs == {
        "input_spring": ("input_shaft", "gear1", 442.3),
        "output_spring": ("gear2", "output_shaft", 442.3),
    }
    # Table 3-2: pitch diameters 120 and 240 mm, so the shafts are 180 mm apart.
    np.testing.assert_allclose(gearbox.mesh("gear_pair").centre_distance, 0.180, rtol=1e-12)


def test_dtu_planets_sit_at_the_sun_planet_working_centre_distance():
    # Jørgensen 2014: 20/35 teeth, x 0.582 + 0.419, module 10 mm, 20°:
    # inv α_w = inv 20° + 2 tan 20° · 1.001/55, a_w = 10 mm · 55/2 · cos 20°/cos α_w.
    alpha = math.radians(20.0)
    target = math.tan(alpha) - alpha + 2 * math.tan(alpha) * 1.001 / 55
    alpha_w = alpha
    for _ in range(50):
        alpha_w -= (math.tan(alpha_w) - alpha_w - target) / math.tan(alpha_w) ** 2
    a_w = 10e-3 * 55 / 2 * math.cos(alpha) / math.cos(alpha_w)
    gearbox = load(MODELS / "dtu500_planetary.urdf")
    data = gearbox.model.createData()
    pin.forwardKinematics(gearbox.model, data, gearbox.neutral())
    centre = data.oMi[joint_id(gearbox, "planet1")].translation
    np.testing.assert_allclose(centre, [a_w, 0.0, 0.0], atol=1e-11)
    np.testing.assert_allclose(a_w / 10e-3, 28.4005, rtol=5e-6)
