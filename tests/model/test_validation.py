"""Each check of the model loader (docs/model_format.md "Checks when loading") on a tiny file.

Every error must name the file, the element at fault and the offending numbers.
"""

from __future__ import annotations

import pytest

from pinwind.errors import (
    InconsistentCentreDistance,
    InvalidGearGeometry,
    InvalidInertia,
    MalformedModel,
    ModelError,
    NonParallelAxes,
    UnknownAttribute,
    UnknownName,
)
from pinwind.model.gearbox import load, loads
from tests.conftest import MODELS

PATH = "bad.urdf"


def load_error(text: str, error: type[ModelError]) -> str:
    with pytest.raises(error) as info:
        loads(text, path=PATH)
    message = str(info.value)
    assert info.value.path == PATH
    assert message.startswith(f"{PATH}: ")
    return message


def test_reference_pair_loads(pair_urdf):
    gearbox = loads(pair_urdf(), path=PATH)
    assert [m.name for m in gearbox.meshes] == ["m"]


def test_truncated_file_is_not_well_formed_xml(pair_urdf):
    text = pair_urdf()
    cut = text.index("<joint")
    message = load_error(text[:cut], MalformedModel)
    assert "<file>" in message
    assert "not well-formed XML at line" in message


@pytest.mark.parametrize(
    "head, said",
    [
        (b"\x89MCAP0\r\n", "this is an MCAP log, not a model"),
        (b"<robot>\xff\xfe</robot>", "byte 0xff at position 7 is not UTF-8"),
    ],
)
def test_a_file_that_is_not_text_is_named_with_what_it_is(tmp_path, head, said):
    path = tmp_path / "model.urdf"
    path.write_bytes(head)
    with pytest.raises(MalformedModel) as info:
        load(path)
    assert str(info.value).startswith(f"{path}: <file>: ") and said in str(info.value)


def test_gear_on_unknown_link_is_named(pair_urdf):
    message = load_error(pair_urdf(gear_link_a="shaft_x"), UnknownName)
    assert '<gear name="g1">' in message
    assert 'unknown link "shaft_x"' in message
    assert "a, b, housing" in message


def test_mesh_with_unknown_gear_is_named(pair_urdf):
    message = load_error(pair_urdf(mesh=("g1", "g3")), UnknownName)
    assert '<mesh name="m">' in message
    assert 'unknown gear "g3"' in message
    assert "g1, g2" in message


def test_gear_cannot_mesh_with_itself(pair_urdf):
    message = load_error(pair_urdf(mesh=("g1", "g1")), InvalidGearGeometry)
    assert '<mesh name="m">' in message
    assert 'gear "g1" cannot mesh with itself' in message


def test_gears_on_perpendicular_shafts_cannot_mesh(pair_urdf):
    message = load_error(pair_urdf(axis_b="1 0 0"), NonParallelAxes)
    assert '<mesh name="m">' in message
    assert "90° apart" in message


def test_centre_distance_off_by_one_millimetre_is_rejected(pair_urdf):
    # 20/40 teeth, module 2 mm: m (z1 + z2)/2 = 60 mm; the shafts are 61 mm apart.
    with pytest.raises(InconsistentCentreDistance) as info:
        loads(pair_urdf(centre_distance=0.061), path=PATH)
    message = str(info.value)
    assert f"{PATH}: " in message
    assert '<mesh name="m">' in message
    assert "61.0000 mm" in message
    assert "60.0000 mm" in message
    assert info.value.actual == pytest.approx(0.061, rel=1e-12)
    assert info.value.expected == pytest.approx(0.060, rel=1e-12)


def test_two_internal_gears_cannot_mesh(pair_urdf):
    message = load_error(pair_urdf(internal=("true", "true")), InvalidGearGeometry)
    assert '<mesh name="m">' in message
    assert "both internal" in message


@pytest.mark.parametrize("teeth", ["0", "-3"])
def test_tooth_count_must_be_positive(pair_urdf, teeth):
    message = load_error(pair_urdf(teeth=(teeth, "40")), InvalidGearGeometry)
    assert '<gear name="g1">' in message
    assert f"teeth = {teeth}" in message


def test_module_must_be_positive(pair_urdf):
    message = load_error(pair_urdf(module_mm=("0", "2")), InvalidGearGeometry)
    assert '<gear name="g1">' in message
    assert "module_mm = 0" in message


def test_meshing_gears_need_the_same_module(pair_urdf):
    message = load_error(pair_urdf(module_mm=("2", "2.5")), InvalidGearGeometry)
    assert '<mesh name="m">' in message
    assert "2 mm" in message and "2.5 mm" in message


def test_mass_must_be_positive(pair_urdf):
    message = load_error(pair_urdf(mass_a="0"), InvalidInertia)
    assert '<link name="a">' in message
    assert "mass is 0.0 kg" in message


def test_inertia_must_satisfy_triangle_inequality(pair_urdf):
    # Izz = 3 > Ixx + Iyy = 2: no body has these principal moments.
    message = load_error(pair_urdf(inertia_a=("1", "1", "3")), InvalidInertia)
    assert '<link name="a">' in message
    assert "triangle inequality" in message
    assert "(3 > 1 + 1)" in message


# --- found by mutating the shipped models one value or element at a time ------------------------


@pytest.mark.parametrize(
    "old, new, element, said",
    [
        # A mass of 1e300 kg stopped the run "diverged at step 0", naming nothing.
        ('<mass value="1.0"/>', '<mass value="1e300"/>', '<link name="a"> <inertial> <mass>',
         'attribute value="1e300": 1e300 is beyond ±1e+20'),
        # An axis of 1e300 overflowed its norm: "axes ... [nan nan nan] are 90° apart".
        ('<axis xyz="0 0 1"/>', '<axis xyz="0 0 1e300"/>', '<joint name="a"> <axis>',
         'attribute xyz="0 0 1e300": 1e300 is beyond'),
        # A joint 1e300 m away gave numpy's "LinAlgError: Eigenvalues did not converge".
        ('<origin xyz="0 0 0"/>', '<origin xyz="0 1e300 0"/>', '<joint name="a"> <origin>',
         'attribute xyz="0 1e300 0": 1e300 is beyond'),
    ],
)  # fmt: skip
def test_a_number_beyond_any_physical_value_is_refused_naming_it(
    pair_urdf, old, new, element, said
):
    text = pair_urdf()
    assert old in text  # the first is joint a's, or link a's
    message = load_error(text.replace(old, new, 1), MalformedModel)
    assert message.startswith(f"{PATH}: {element}: "), message
    assert said in message


def test_a_joint_a_kilometre_away_is_refused_naming_the_distance(pair_urdf):
    # 3-4-5: the origin (0, 3000, 4000) m is 5000 m from the housing's frame.
    text = pair_urdf().replace('<origin xyz="0 0 0"/>', '<origin xyz="0 3000 4000"/>', 1)
    message = load_error(text, MalformedModel)
    assert message.startswith(f'{PATH}: <joint name="a">: <origin> xyz="0 3000 4000" is 5000 m')


def test_a_centre_of_mass_a_kilometre_off_is_refused(pair_urdf):
    text = pair_urdf().replace(
        '<inertial><mass value="2.0"/>', '<inertial><origin xyz="0 0 -1200"/><mass value="2.0"/>'
    )
    message = load_error(text, MalformedModel)
    assert message.startswith(f'{PATH}: <link name="b">: <inertial> <origin> xyz="0 0 -1200" is')
    assert "1200 m from its parent link's frame" in message


@pytest.mark.parametrize(
    "old, element",
    [
        ('<mass value="2.0"/>', '<link name="b"> <inertial>'),
        ('<axis xyz="0 0 1"/>', '<joint name="a">'),
        ('<parent link="housing"/><child link="a"/>', '<joint name="a">'),
    ],
)
def test_a_second_copy_of_a_one_of_a_kind_element_is_refused(pair_urdf, old, element):
    # The copy was read by no one (both readers take the first): a second <mass> was ignored.
    text = pair_urdf()
    tag = old[1 : old.index(" ")]
    message = load_error(text.replace(old, old + old, 1), MalformedModel)
    assert message.startswith(f"{PATH}: {element}: has 2 <{tag}> elements; it takes one")


def test_an_axis_without_xyz_is_refused_not_read_as_x(pair_urdf):
    # urdfdom reads <axis/> as the zero axis; pinwind read it as x, the default of no <axis>.
    text = pair_urdf().replace('<axis xyz="0 0 1"/>', "<axis/>", 1)
    message = load_error(text, MalformedModel)
    assert message.startswith(f'{PATH}: <joint name="a">: <axis> has no xyz')


def test_a_robot_without_name_is_refused_naming_the_attribute(pair_urdf):
    # Pinocchio said "The XML stream does not contain a valid URDF model".
    message = load_error(pair_urdf().replace('<robot name="pair">', "<robot>"), MalformedModel)
    assert message.startswith(f'{PATH}: <robot>: missing attribute "name"')


@pytest.mark.parametrize(
    "axis, angle",
    [
        (None, "90°"),  # no <axis>: URDF's x axis
        ('<axis xyz="1 0 1"/>', "45°"),
    ],
)
def test_a_carrier_turning_about_another_axis_than_its_planets_is_refused(axis, angle):
    # The carrier carries planet1, not the sun: turning about x it would tilt planet1's axis
    # (z) out of parallel with the sun's. Angle between x and z: 90°; (1, 0, 1) and z: 45°.
    text = (MODELS / "saleh2017_planetary.urdf").read_text()
    start = text.index('<joint name="carrier"')
    end = text.index("</joint>", start)
    joint = text[start:end]
    new = joint.replace('<axis xyz="0 0 1" />', axis or "")
    assert new != joint
    message = load_error(text[:start] + new + text[end:], NonParallelAxes)
    assert message.startswith(f'{PATH}: <mesh name="sun_planet1">: bearing "carrier" carries gear')
    assert '"planet1" (not "sun") about the axis' in message
    assert f"{angle} from the gears' axis [0. 0. 1.]" in message


def test_two_rows_of_one_name_in_a_bearing_are_refused():
    # A copied row doubled the bearing's stiffness and gave two series of one name.
    text = (MODELS / "nrel5mw_gearbox.urdf").read_text()
    start = text.index('<row name="HS-A"')
    row = text[start : text.index("/>", start) + 2]
    message = load_error(text.replace(row, row + row), MalformedModel)
    assert message.startswith(f'{PATH}: <bearing joint="hss"> <row name="HS-A">: the bearing')
    assert 'two rows named "HS-A"' in message


def test_a_planet_moved_onto_its_neighbour_is_refused_naming_both():
    # planet2 at (-0.27, -0.4677) m, planet3's place (a sign slip): the two planets, 48 teeth of
    # module 15 mm unshifted, have tip radii 48 · 15 / 2 + 15 = 375 mm each and are 0 mm apart.
    text = (MODELS / "saleh2017_planetary.urdf").read_text()
    start = text.index('<joint name="planet2"')
    end = text.index("</joint>", start)
    joint = text[start:end]
    new = joint.replace('xyz="-0.27 0.467653718044 0"', 'xyz="-0.27 -0.467653718044 0"')
    assert new != joint
    message = load_error(text[:start] + new + text[end:], InvalidGearGeometry)
    assert message.startswith(f'{PATH}: <gear name="planet2">: its tip circle (radius 375.00 mm)')
    assert 'gear "planet3" (375.00 mm) overlap: their centres are 0.00 mm apart' in message
    assert "less than the 750.00 mm of their tip radii" in message


def test_a_misspelt_child_of_a_urdf_joint_is_refused_naming_the_nearest(pair_urdf):
    # <originx> was ignored: joint b sat at the housing's origin, 60 mm from where it was put.
    text = pair_urdf().replace('<origin xyz="0.06 0 0"/>', '<originx xyz="0.06 0 0"/>')
    assert "<originx" in text
    message = load_error(text, UnknownAttribute)
    assert message.startswith(f'{PATH}: <joint name="b">: unknown element "originx"')
    assert 'did you mean "origin"?' in message
