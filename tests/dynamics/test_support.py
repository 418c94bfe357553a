"""The support structure: the housing on compliant mounts, the bedplate on tower modes."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

import pinwind
from pinwind.errors import InvalidSupport, PinwindWarning, UnknownName
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from pinwind.modes.linearisation import linearise
from tests.conftest import two_gear_urdf

G = 9.81
HOUSING_MASS = 20.0
#: The masses of the two-gear model: the housing and shafts a (1 kg) and b (2 kg), at rest on
#: shaft a's axis (a) and 60 mm along x (b).
GEARBOX_MASS = HOUSING_MASS + 1.0 + 2.0
CENTRE_DISTANCE = 0.060
HOUSING = (
    f'<link name="housing"><inertial><mass value="{HOUSING_MASS!r}"/>'
    '<inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>'
)


def supported_pair(support: str, *, gravity: str = f"0 {-G!r} 0") -> str:
    """The conftest two-gear model with a 20 kg housing on the given ``<support>`` body."""
    text = two_gear_urdf().replace('<link name="housing"/>', HOUSING)
    return text.replace("<gearbox>", f'<gearbox gravity="{gravity}">{support}')


def tower(direction: str, frequency: float, mass: float, ratio: float = 0.0) -> str:
    return (
        f'<tower_mode direction="{direction}" frequency_hz="{frequency!r}" mass="{mass!r}" '
        f'damping_ratio="{ratio!r}"/>'
    )


def _load(text: str):
    return loads(text)


def _displacement(res, gearbox, prefix: str) -> np.ndarray:
    """Σ q a over the support's prismatic slides named ``prefix``… [m], world (their axes)."""
    out = np.zeros((len(res.time), 3))
    for name, slide in gearbox.support_slides.items():
        if name.startswith(prefix) and slide.kind == "prismatic":
            axis = gearbox.world_from_housing @ slide.axis
            out += np.outer(res.joint(name).angle, axis)
    return out


def _run(gb, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        return pinwind.simulate(gb, **kwargs)


def test_a_rigid_gearbox_on_a_tower_mode_has_the_frequency_of_the_combined_mass(tmp_path):
    m, f = 40.0, 3.0
    k = m * (2 * math.pi * f) ** 2
    path = tmp_path / "pair.urdf"
    path.write_text(
        supported_pair(f'<support housing="housing">{tower("vertical", f, m)}</support>')
    )
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", "modes", str(path), "--mesh", "all=rigid", "--json"],
        capture_output=True,
        text=True,
        env=env,
        check=True,
    )
    modes = [x for x in json.loads(out.stdout) if x["frequency_hz"] > 0.0]
    expected = math.sqrt(k / (m + GEARBOX_MASS)) / (2 * math.pi)
    np.testing.assert_allclose([x["frequency_hz"] for x in modes], [expected], rtol=1e-10)


def test_the_bedplate_sags_by_the_weight_of_the_gearbox_and_modal_mass_over_k():
    m, f = 40.0, 3.0
    k = m * (2 * math.pi * f) ** 2
    gb = _load(
        supported_pair(f'<support housing="housing">{tower("vertical", f, m, 0.02)}</support>')
    )
    res = _run(gb, duration=0.01, dt=1e-4, meshes={"all": "rigid"})
    sag = (m + GEARBOX_MASS) * G / k
    np.testing.assert_allclose(
        _displacement(res, gb, "support_tower_"), np.tile([0.0, -sag, 0.0], (len(res.time), 1)),
        atol=1e-9 * sag,
    )  # fmt: skip
    np.testing.assert_allclose(_displacement(res, gb, "support_mount_"), 0.0, atol=0.0)


@pytest.mark.parametrize("bearing_stiffness", [1e8, 1e11, 1e13])
def test_a_tower_under_a_stiff_bearing_starts_sagged_whatever_the_stiffness_ratio(
    bearing_stiffness,
):
    # The tower (k ≈ 1.4e4 N/m) under shaft a's bearing of 1e8 to 1e13 N/m: a ratio of up to
    # 7e8, which the static start used to settle by leaving the tower out (issue 36). Each
    # spring carries its own load: the tower the whole weight, (m + M) g / k; the bearing
    # shaft a's, m_a g / k_b (the teeth of an unloaded rigid pair carry no weight across).
    m, f = 40.0, 3.0
    k = m * (2 * math.pi * f) ** 2
    text = supported_pair(f'<support housing="housing">{tower("vertical", f, m, 0.02)}</support>')
    text = text.replace(
        "</gearbox>", f'<bearing joint="a" radial_stiffness="{bearing_stiffness!r}"/></gearbox>'
    )
    gb = _load(text)
    res = _run(gb, duration=0.01, dt=1e-4, meshes={"all": "rigid"})
    sag = (m + GEARBOX_MASS) * G / k
    np.testing.assert_allclose(res.joint("support_tower_vertical").angle, -sag, rtol=1e-9)
    bearing = 1.0 * G / bearing_stiffness
    np.testing.assert_allclose(res.joint("a_radial_y").angle, -bearing, rtol=1e-9)
    np.testing.assert_allclose(res.joint("a_radial_x").angle, 0.0, atol=1e-9 * bearing)
    assert res.metadata["initial_deflection"]["converged"]


def test_each_tower_direction_sees_its_own_modal_mass_plus_the_gearbox():
    modes = {"fore_aft": (2.0, 300.0), "side_side": (3.0, 50.0), "vertical": (5.0, 120.0)}
    body = "".join(tower(d, f, m) for d, (f, m) in modes.items())
    gb = _load(supported_pair(f'<support housing="housing">{body}</support>'))
    found = sorted(x.frequency for x in linearise(gb, meshes={"all": "rigid"}).modes())
    expected = sorted(
        math.sqrt(m * (2 * math.pi * f) ** 2 / (m + GEARBOX_MASS)) / (2 * math.pi)
        for f, m in modes.values()
    )
    np.testing.assert_allclose(found[-3:], expected, rtol=1e-10)


@pytest.mark.parametrize("bearing", ["", '<bearing joint="a" radial_stiffness="1e8"/>'])
def test_the_torque_arms_roll_by_the_housing_torque_over_k_roll(bearing):
    # Shaft a takes 10 N·m and shaft b 20 N·m from the ground (the 20/40 pair balances them:
    # 10 ω − 20 ω/2 = 0): the torque arms carry their sum, less the moment of b's weight at
    # 60 mm from the roll axis, m_b g x_b; shaft a in a rigid or a compliant bearing.
    k_roll = 1e4
    gb = _load(
        supported_pair(
            f'<support housing="housing"><mount stiffness_roll="{k_roll!r}"/></support>{bearing}'
        )
    )
    res = _run(gb, duration=0.01, dt=1e-4, torques={"a": 10.0, "b": 20.0}, meshes={"all": "rigid"})
    torque = 10.0 + 20.0 - 2.0 * G * CENTRE_DISTANCE
    # b's weight turns with the housing: its lever x_b cos θ is short by θ²/2 (the tolerance).
    np.testing.assert_allclose(
        res.joint("support_mount_roll").angle, torque / k_roll, rtol=(torque / k_roll) ** 2
    )


def test_a_speed_driver_reacts_on_the_housing_so_the_arms_carry_the_input_torque_only():
    k_roll = 1e4
    gb = _load(
        supported_pair(f'<support housing="housing"><mount stiffness_roll="{k_roll!r}"/></support>')
    )
    res = _run(
        gb, duration=0.01, dt=1e-4, torques={"a": 10.0}, speeds={"b": 0.0}, meshes={"all": "rigid"}
    )
    torque = 10.0 - 2.0 * G * CENTRE_DISTANCE
    # b's weight turns with the housing: its lever x_b cos θ is short by θ²/2 (the tolerance).
    np.testing.assert_allclose(
        res.joint("support_mount_roll").angle, torque / k_roll, rtol=(torque / k_roll) ** 2
    )


def test_a_very_stiff_support_gives_the_bearing_forces_of_a_rigid_one():
    # In series with a mesh of stiffness k_m, a support of stiffness k_s moves the train's
    # frequencies and forces by the order of k_m / k_s: the tolerance.
    k_mesh, k_support = 1e8, 1e13
    mesh = MeshCompliance(stiffness=k_mesh, variation="constant", damping=1e2)
    f = math.sqrt(k_support / 100.0) / (2 * math.pi)
    support = (
        f'<support housing="housing"><mount stiffness_x="{k_support!r}" '
        f'stiffness_y="{k_support!r}" stiffness_roll="{k_support!r}"/>'
        f"{tower('vertical', f, 100.0)}</support>"
    )
    forces = []
    for text in (supported_pair(""), supported_pair(support)):
        res = _run(
            _load(text),
            duration=0.02,
            dt=1e-5,
            torques={"a": lambda t: 10.0 + 5.0 * math.sin(2 * math.pi * 50.0 * t)},
            speeds={"b": 0.0},
            meshes={"all": mesh},
        )
        forces.append(res.bearing_force[:, [res.bearing_names.index(j) for j in ("a", "b")]])
    scale = float(np.abs(forces[0]).max())
    np.testing.assert_allclose(forces[1], forces[0], atol=k_mesh / k_support * scale)


def test_a_rigid_support_has_no_support_slides():
    gb = _load(supported_pair(""))
    assert gb.support_slides == {}
    assert not [n for n in gb.joint_names if n.startswith("support_")]


def test_a_housing_below_the_root_keeps_its_place_and_its_frame():
    # The housing welded to a "nacelle" root, turned 90° about x: the mounts' x, y, z are the
    # housing's axes, so its mount y lies along world z.
    text = supported_pair(
        '<support housing="housing"><mount stiffness_y="1e6"/></support>', gravity="0 0 -9.81"
    )
    text = text.replace(
        HOUSING,
        HOUSING + '<link name="nacelle"/><joint name="weld" type="fixed"><parent link="nacelle"/>'
        '<child link="housing"/><origin xyz="1 2 3" rpy="1.5707963267948966 0 0"/></joint>',
    )
    gb = _load(text)
    res = _run(gb, duration=0.001, dt=1e-4, meshes={"all": "rigid"})
    np.testing.assert_allclose(
        _displacement(res, gb, "support_mount_")[0], [0.0, 0.0, -GEARBOX_MASS * G / 1e6], atol=1e-12
    )
    a = res.body_names.index("a")
    np.testing.assert_allclose(res.body_position[0, a], [1.0, 2.0, 3.0 - GEARBOX_MASS * G / 1e6])


@pytest.mark.parametrize(
    ("support", "attribute", "value"),
    [
        ('<mount stiffness_roll="-1e6"/>', "stiffness_roll", -1e6),
        ('<mount stiffness_x="nan"/>', "stiffness_x", math.nan),
        (tower("vertical", 3.0, -5.0), "vertical mass", -5.0),
        (tower("side_side", float("nan"), 5.0), "side_side frequency_hz", math.nan),
        (tower("fore_aft", 0.0, 5.0), "fore_aft frequency_hz", 0.0),
    ],
)
def test_a_bad_support_value_is_refused_with_its_value(support, attribute, value):
    with pytest.raises(InvalidSupport) as err:
        _load(supported_pair(f'<support housing="housing">{support}</support>'))
    assert err.value.attribute == attribute
    np.testing.assert_equal(err.value.value, value)
    assert attribute.split()[-1] in str(err.value)


def test_a_support_naming_a_missing_housing_link_lists_the_links():
    with pytest.raises(UnknownName) as err:
        _load(supported_pair('<support housing="gearcase"><mount stiffness_x="1e6"/></support>'))
    assert err.value.name == "gearcase"
    assert "housing" in str(err.value)


def test_the_cli_refuses_a_negative_stiffness_with_one_message_and_exit_2(tmp_path):
    path = tmp_path / "bad.urdf"
    path.write_text(
        supported_pair('<support housing="housing"><mount stiffness_z="-3"/></support>')
    )
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", "modes", str(path)],
        capture_output=True,
        text=True,
        env=env,
    )
    assert out.returncode == 2
    assert "stiffness_z is -3 N/m" in out.stderr
    assert "Traceback" not in out.stderr


@pytest.mark.parametrize("direction", ["vertical", "side_side"])
def test_a_tower_mode_across_a_shaft_along_gravity_is_refused_naming_the_cause(direction):
    """shaft_axis="0 1 0" under gravity along −y: the vertical (gravity made normal to the
    shaft) is the zero vector, and urdfdom printed NaN noise and no cause (issue 43)."""
    text = supported_pair(
        f'<support housing="housing" shaft_axis="0 1 0">{tower(direction, 8.0, 1e4)}</support>'
    )
    with pytest.raises(InvalidSupport) as caught:
        _load(text)
    err = caught.value
    assert (err.attribute, err.value) == ("shaft_axis", 0.0)
    assert str(err).startswith('<string>: <support housing="housing">: shaft_axis="0 1 0" is along')
    assert f"the tower modes {direction} act normal to the shaft axis" in str(err)


def test_a_fore_aft_mode_on_a_shaft_along_gravity_needs_no_vertical_and_loads():
    text = supported_pair(
        f'<support housing="housing" shaft_axis="0 1 0">{tower("fore_aft", 0.7, 2e4)}</support>'
    )
    assert "support_tower_fore_aft" in _load(text).support_slides
