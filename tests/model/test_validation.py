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
    UnknownName,
)
from pinwind.model.gearbox import load, loads

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
