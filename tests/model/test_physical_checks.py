"""Models that are physically wrong are refused (or warned about), naming the element at fault.

One test per check of docs/model_format.md "Checks when loading" added for physically wrong
models; each breaks one thing in a small model that otherwise loads.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.errors import (
    ImplausibleGear,
    InvalidGearGeometry,
    InvalidInertia,
    InvalidMount,
    MalformedModel,
    ModelError,
    TorquesUnbalanced,
    UnknownElement,
)
from pinwind.model.gearbox import loads
from tests.conftest import MODELS

PATH = "bad.urdf"

HUB = """<link name="hub"><inertial><mass value="0.2"/>
      <inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="hub" type="fixed"><parent link="{parent}"/><child link="hub"/>
    <origin xyz="{xyz}"/></joint>
  <link name="b">"""


def with_hub(text: str, parent: str = "a", xyz: str = "0 0 0.01") -> str:
    """Add a link "hub" welded to ``parent`` at ``xyz`` (before link b)."""
    return text.replace('<link name="b">', HUB.format(parent=parent, xyz=xyz), 1)


def load_error(text: str, error: type[ModelError], element: str) -> str:
    with pytest.raises(error) as info:
        loads(text, path=PATH)
    message = str(info.value)
    assert message.startswith(f"{PATH}: {element}: "), message
    return message


def test_model_without_gearbox_element_is_refused(pair_urdf):
    text = pair_urdf()
    start, end = text.index("<gearbox>"), text.index("</gearbox>") + len("</gearbox>")
    message = load_error(text[:start] + text[end:], MalformedModel, "<robot>")
    assert "no <gearbox> element" in message and "<gearbox/>" in message


def test_link_without_inertial_is_refused(pair_urdf):
    text = pair_urdf()
    start = text.index('<link name="b">')
    end = text.index("</link>", start) + len("</link>")
    message = load_error(
        text[:start] + '<link name="b"/>' + text[end:], InvalidInertia, '<link name="b">'
    )
    assert "has no <inertial>" in message
    assert 'the root link, "housing"' in message


def test_all_zero_inertia_tensor_is_refused(pair_urdf):
    message = load_error(pair_urdf(inertia_a=("0", "0", "0")), InvalidInertia, '<link name="a">')
    assert "all zero" in message


def test_zero_inertia_about_the_bearing_axis_is_refused(pair_urdf):
    # Ixx = Iyy = 1e-3, Izz = 0 passes the triangle inequality but the shaft turns about z.
    message = load_error(
        pair_urdf(inertia_a=("0.001", "0.001", "0")), InvalidInertia, '<link name="a">'
    )
    assert 'bearing "a"' in message and "no inertia about the bearing axis [0. 0. 1.]" in message


@pytest.mark.parametrize("value", ["nan", "inf"])
def test_non_finite_mass_names_the_link(pair_urdf, value):
    message = load_error(pair_urdf(mass_a=value), MalformedModel, '<link name="a">')
    assert f'<mass> attribute value="{value}" is not finite' in message


def test_non_finite_inertia_names_the_link(pair_urdf):
    message = load_error(
        pair_urdf(inertia_a=("0.001", "nan", "0.0015")), MalformedModel, '<link name="a">'
    )
    assert '<inertia> attribute iyy="nan" is not finite' in message


def test_duplicate_link_name_is_refused(pair_urdf):
    text = pair_urdf().replace('<link name="b">', '<link name="a">', 1)
    message = load_error(text, MalformedModel, '<link name="a">')
    assert 'a link named "a" is defined twice' in message


def test_duplicate_joint_name_is_refused(pair_urdf):
    text = pair_urdf().replace('<joint name="b"', '<joint name="a"', 1)
    message = load_error(text, MalformedModel, '<joint name="a">')
    assert 'a joint named "a" is defined twice' in message


def test_nan_joint_origin_names_the_joint(pair_urdf):
    message = load_error(pair_urdf(centre_distance=math.nan), MalformedModel, '<joint name="b">')
    assert '<origin> attribute xyz="nan 0 0" is not three finite numbers' in message


def test_zero_joint_axis_names_the_joint(pair_urdf):
    message = load_error(pair_urdf(axis_b="0 0 0"), MalformedModel, '<joint name="b">')
    assert "has no direction" in message


def test_negative_bearing_damping_is_refused(pair_urdf):
    text = pair_urdf().replace(
        '<axis xyz="0 0 1"/>\n  </joint>',
        '<axis xyz="0 0 1"/><dynamics damping="-0.5"/>\n  </joint>',
        1,
    )
    message = load_error(text, InvalidMount, '<joint name="a">')
    assert "damping -0.5 N·m·s/rad" in message and "must be ≥ 0" in message


def test_nan_bearing_damping_names_the_joint(pair_urdf):
    text = pair_urdf().replace(
        '<axis xyz="0 0 1"/>\n  </joint>',
        '<axis xyz="0 0 1"/><dynamics damping="nan"/>\n  </joint>',
        1,
    )
    message = load_error(text, MalformedModel, '<joint name="a">')
    assert '<dynamics> attribute damping="nan" is not finite' in message


def test_gear_welded_off_its_centre_onto_a_turning_body_is_explained(pair_urdf):
    # g2's link welded to shaft a, 60 mm off a's axis: it would orbit, not turn.
    text = with_hub(pair_urdf(mesh=("g1", "g2")), parent="a", xyz="0.06 0 0")
    text = text.replace('<gear name="g2" link="b"', '<gear name="g2" link="hub"')
    message = load_error(text, InvalidMount, '<gear name="g2">')
    assert 'welded (fixed joints) to link "a", which turns on bearing "a"' in message
    assert "60.0000 mm off" in message


def test_mesh_between_two_gears_welded_to_the_ground_is_refused(pair_urdf):
    # Both shafts welded to the housing: the tooth force would be indeterminate.
    text = pair_urdf().replace('type="continuous"', 'type="fixed"')
    message = load_error(text, InvalidMount, '<mesh name="m">')
    assert "both on fixed mounts" in message


def test_gear_on_a_hub_welded_to_its_shaft_turns_with_the_shaft(pair_urdf):
    # A gear on a hub link welded coaxially onto shaft a is part of shaft a's body: the weld is
    # kept (not turned into a locked bearing), and the pair behaves as with the gear on the
    # shaft, with the hub's inertia added. By hand, torque T on a, b free, ratio 20/40:
    # J_eq = I_a + I_hub + I_b (20/40)², α_a = T / J_eq; b's spin: I_b α_b = r_b F_t.
    text = with_hub(pair_urdf(gear_link_a="hub"), parent="a", xyz="0 0 0.01")
    gb = loads(text, path="hub.urdf")
    assert gb.joint_names == ["a", "b"] and gb.locked_joints == []
    torque, i_a, i_hub, i_b, r_b = 0.1, 0.0015, 1e-4, 0.006, 0.040
    with pytest.warns(TorquesUnbalanced):
        res = pinwind.simulate(gb, duration=0.05, dt=1e-3, torques={"a": torque})
    alpha_a = torque / (i_a + i_hub + i_b / 4)
    assert_allclose(res.joint("a").acceleration, alpha_a, rtol=1e-9)
    assert_allclose(res.joint("b").acceleration, -alpha_a / 2, rtol=1e-9)
    f_t = i_b * alpha_a / 2 / r_b
    assert_allclose(res.mesh("m").normal, f_t / math.cos(math.radians(20)), rtol=1e-9)


def test_gears_that_cannot_mesh_give_a_model_error_not_a_value_error(pair_urdf):
    # An internal gear of as many teeth as its pinion: pair_geometry raises ValueError.
    text = pair_urdf(teeth=("40", "40"), internal=("false", "true"), centre_distance=0.0)
    message = load_error(text, InvalidGearGeometry, '<mesh name="m">')
    assert '"g1" (40 teeth' in message and "cannot mesh" in message


def test_unknown_mesh_name_lists_the_meshes():
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    with pytest.raises(UnknownElement, match='no mesh named "sun_planet4"; meshes are: sun_pl'):
        gb.mesh("sun_planet4")


def test_gear_far_heavier_than_its_steel_disc_warns_with_both_numbers(pair_urdf):
    # g1: 20 teeth × 2 mm = 40 mm pitch diameter, 20 mm wide; steel disc by hand:
    disc = 7850 * math.pi * 0.020**2 * 0.020  # 0.1973 kg
    with pytest.warns(ImplausibleGear) as caught:
        loads(pair_urdf(mass_a="1000"), path=PATH)
    messages = [str(w.message) for w in caught if "mass" in str(w.message)]
    assert len(messages) == 1
    assert messages[0].startswith(f'{PATH}: <link name="a">: mass 1000 kg is ')
    assert f"{disc:.4g} kg" in messages[0] and '"g1" 40 mm × 20 mm' in messages[0]


def test_shipped_cai_gear_2_inertia_is_flagged_as_the_models_readme_says():
    # models/README.md: Table 3-1's 0.002 kg·m² (+ half-shaft, 0.003) for a 240 mm × 30 mm
    # steel gear whose disc has m r²/2 = 0.077 kg·m².
    disc = 0.5 * (7850 * math.pi * 0.12**2 * 0.03) * 0.12**2
    with pytest.warns(ImplausibleGear, match=r'<link name="gear2">: axial inertia 0\.003') as w:
        pinwind.load(MODELS / "cai_spur_pair.urdf")
    assert f"{disc:.4g} kg·m²" in str(w[0].message)


def test_shipped_models_other_than_cai_load_without_warnings():
    import warnings

    for path in sorted(MODELS.glob("*.urdf")):
        if path.name == "cai_spur_pair.urdf":
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            gb = pinwind.load(path)
        assert np.isfinite(gb.gravity).all()


def test_a_generator_rotor_lumped_on_a_pinion_link_is_no_implausible_gear(pair_urdf):
    import warnings

    # g1: 40 mm × 20 mm steel disc, m r²/2 by hand; a rotor lumped on its shaft gives the link
    # 300 times that inertia (and 5 times its mass): heavy, but no unit slip (below 1000 times).
    disc_mass = 7850 * math.pi * 0.020**2 * 0.020
    disc = 0.5 * disc_mass * 0.020**2
    text = pair_urdf(mass_a=f"{5 * disc_mass!r}", inertia_a=("0.1", "0.1", f"{300 * disc!r}"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        loads(text, path=PATH)


def test_a_gear_lighter_than_its_teeth_alone_warns_with_the_teeth_mass(pair_urdf):
    # g1: z = 20, m = 2 mm, b = 20 mm: r = 20 mm, root circle 20 − 1.25·2 = 17.5 mm, tip circle
    # 20 + 2 = 22 mm (ISO 53 basic rack); the teeth fill half that ring.
    teeth = 0.5 * 7850 * math.pi * (0.022**2 - 0.0175**2) * 0.020
    with pytest.warns(ImplausibleGear) as caught:
        loads(pair_urdf(mass_a=f"{0.5 * teeth!r}"), path=PATH)
    (message,) = [str(w.message) for w in caught]
    assert message.startswith(f'{PATH}: <link name="a">: mass {0.5 * teeth:.4g} kg is less ')
    assert f"teeth alone give, {teeth:.4g} kg" in message


def test_a_model_loaded_twice_warns_once_at_its_link_s_line():
    import warnings

    path = MODELS / "cai_spur_pair.urdf"
    lines = path.read_text(encoding="utf-8").splitlines()
    line = next(i for i, text in enumerate(lines, start=1) if '<link name="gear2"' in text)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")  # Python's own: once per place and message
        pinwind.load(path)
        pinwind.load(path)  # a command's second load (its run, its log) of the same file
    (shown,) = [w for w in caught if w.category is ImplausibleGear]
    assert (shown.filename, shown.lineno) == (str(path), line)
