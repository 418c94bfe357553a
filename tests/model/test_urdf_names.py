"""A misspelt element or attribute of a model file is refused, naming the nearest known name.

urdfdom and the ``<gearbox>`` reader look attributes up by name, so one they do not know was
ignored: ``<bearing joint="a" radial_stifness="1e9"/>`` left the bearing rigid and
``<mount stifness_x="5e9"/>`` the housing on the ground, without a word (issue 43).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from pinwind.errors import UnknownAttribute
from pinwind.model.gearbox import loads
from pinwind.model.urdf import GEARBOX_ELEMENTS
from tests.conftest import two_gear_urdf

PATH = "bad.urdf"
DOCS = Path(__file__).resolve().parents[2] / "docs" / "model_format.md"


def with_elements(text: str, extra: str) -> str:
    """The conftest two-gear file with ``extra`` appended inside its ``<gearbox>``."""
    return text.replace("</gearbox>", f"{extra}\n  </gearbox>")


def refused(text: str) -> UnknownAttribute:
    with pytest.raises(UnknownAttribute) as info:
        loads(text, path=PATH)
    return info.value


def test_a_bearing_with_the_radial_stiffness_spelt_right_is_compliant():
    """The control of the next test: the same file, spelt right, makes bearing "a" compliant."""
    gearbox = loads(with_elements(two_gear_urdf(), '<bearing joint="a" radial_stiffness="1e9"/>'))
    assert set(gearbox.source.compliant_bearings) == {"a"}


def test_a_misspelt_bearing_stiffness_is_refused_not_left_rigid():
    bearing = '<bearing joint="a" type="cylindrical_roller" radial_stifness="1e9"/>'
    err = refused(with_elements(two_gear_urdf(), bearing))
    assert (err.name, err.nearest, err.kind) == ("radial_stifness", "radial_stiffness", "attribute")
    message = str(err)
    assert message.startswith(f'{PATH}: <bearing joint="a">: unknown attribute "radial_stifness"')
    assert 'did you mean "radial_stiffness"?' in message
    assert "\n" not in message


def test_a_misspelt_mount_stiffness_is_refused_not_left_on_the_ground():
    support = '<support housing="housing"><mount stifness_x="5e9"/></support>'
    err = refused(with_elements(two_gear_urdf(), support))
    assert (err.name, err.nearest) == ("stifness_x", "stiffness_x")
    assert str(err).startswith(f'{PATH}: <support housing="housing"> <mount>: unknown attribute')


#: One misspelling per element the file can hold: (where it goes, the text, the meant name).
MISSPELT = [
    ("gearbox", '<gearbox gravty="0 -9.81 0">', "gravity"),
    ("gear", '<gear name="g1" modul_mm="2" ', "module_mm"),
    ("mesh", '<mesh name="m" type="compliant" backlash="0.1" ', "backlash_mm"),
    ("torsional_spring", '<torsional_spring name="s" joint1="a" joint2="b" stiffness="1" '
     'dampng="1"/>', "damping"),
    ("bearing", '<bearing joint="b" type="cylindrical_roller" rating_c_kn="30"/>', "rating_c_kN"),
    ("support", '<support housing="housing" shaft_axs="0 0 1"/>', "shaft_axis"),
    ("tower_mode", '<support housing="housing"><tower_mode direction="vertical" '
     'frequency_hz="8" mass="1e4" damping_ration="0.01"/></support>', "damping_ratio"),
    ("dynamics", '<dynamics damping="5" frction="1"/>', "friction"),
    ("origin", '<origin xyz="0 0 0" rp="0 0 0.1"/>', "rpy"),
    ("element", '<torsional_sprng name="s" joint1="a" joint2="b" stiffness="1"/>',
     "torsional_spring"),
]  # fmt: skip


def _misspelt_file(where: str, text: str) -> str:
    base = two_gear_urdf()
    if where == "gearbox":
        return base.replace("<gearbox>", text)
    if where in ("gear", "mesh"):
        start = {"gear": '<gear name="g1" ', "mesh": '<mesh name="m" '}[where]
        return base.replace(start, text)
    if where == "dynamics":
        return base.replace('<axis xyz="0 0 1"/>', f'<axis xyz="0 0 1"/>{text}', 1)
    if where == "origin":
        return base.replace('<origin xyz="0 0 0"/>', text, 1)
    return with_elements(base, text)


@pytest.mark.parametrize(("where", "text", "meant"), MISSPELT, ids=[m[0] for m in MISSPELT])
def test_every_element_refuses_a_misspelt_name_naming_the_one_meant(where, text, meant):
    err = refused(_misspelt_file(where, text))
    assert err.nearest == meant, str(err)
    assert err.path == PATH and f'did you mean "{meant}"?' in str(err)


def test_a_name_like_no_known_one_is_refused_with_the_list_and_no_guess():
    err = refused(with_elements(two_gear_urdf(), '<bearing joint="a" colour="red"/>'))
    assert err.nearest is None
    assert "did you mean" not in str(err)
    assert str(err).endswith("attributes of <bearing> are: " + ", ".join(err.known))


def test_a_rating_without_its_type_on_a_compliant_bearing_is_refused_not_dropped():
    """The rating of a compliant bearing was read only when its type was given: without the
    type, ``rating_c_kN`` was dropped and the bearing listed as not rated."""
    text = with_elements(two_gear_urdf(), '<bearing joint="a" radial_stiffness="1e9" '
                         'rating_c_kN="30"/>')  # fmt: skip
    with pytest.raises(Exception, match='missing attribute "type"'):
        loads(text, path=PATH)


def _documented() -> dict[str, set[str]]:
    """Element → attributes, from the tables of docs/model_format.md (``| gear | teeth | ...``)."""
    out: dict[str, set[str]] = {}
    for element, names in re.findall(r"^\| (\w+) \| ([\w, ]+) \|", DOCS.read_text(), re.M):
        if element in GEARBOX_ELEMENTS:
            out.setdefault(element, set()).update(n.strip() for n in names.split(","))
    return out


def test_the_documented_attributes_are_the_ones_the_reader_takes():
    documented = _documented()
    taken = {tag: set(attributes) for tag, (attributes, _) in GEARBOX_ELEMENTS.items()}
    assert documented == taken
