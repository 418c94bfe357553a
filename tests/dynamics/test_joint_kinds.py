"""Joint kinds: a slide (prismatic joint) has its joint series in m, m/s, m/s² and N."""

from __future__ import annotations

import numpy as np

from pinwind.dynamics import series
from pinwind.dynamics.result import Result
from pinwind.model.gearbox import loads
from tests.dynamics.test_compliant_bearing import disc_urdf


def test_a_compliant_bearing_adds_prismatic_radial_and_axial_slides_and_revolute_tilts():
    gb = loads(disc_urdf('radial_stiffness="1e6" axial_stiffness="1e6" tilt_stiffness="1e4"'))
    kinds = dict(zip(gb.joint_names, gb.joint_kinds, strict=True))
    assert kinds == {
        "disc_radial_x": "prismatic",
        "disc_radial_y": "prismatic",
        "disc_axial": "prismatic",
        "disc_tilt_x": "revolute",
        "disc_tilt_y": "revolute",
        "disc": "revolute",
    }


def test_a_joint_series_on_a_slide_has_the_unit_of_a_length_and_of_a_force():
    on_slide = {s.name: s.unit_for("prismatic") for s in series.of_family("joint")}
    assert on_slide == {"angle": "m", "speed": "m/s", "acceleration": "m/s^2", "torque": "N"}
    on_bearing = {s.name: s.unit_for("revolute") for s in series.of_family("joint")}
    assert on_bearing == {
        "angle": "rad",
        "speed": "rad/s",
        "acceleration": "rad/s^2",
        "torque": "N*m",
    }
    assert [series.get(n).column_unit("prismatic") for n in on_slide] == ["m", "m_s", "m_s2", "N"]


def test_a_slide_kind_changes_no_unit_of_another_family():
    for s in series.schema():
        if s.family != "joint":
            assert s.unit_for("prismatic") == s.unit, s.name


def test_a_result_given_no_joint_kinds_has_only_revolute_joints():
    res = Result(
        joint_names=["a", "b"],
        mesh_names=[],
        bearing_names=[],
        body_names=[],
        time=np.zeros(1),
    )
    assert res.joint_kinds == ["revolute", "revolute"]
    assert res.unit(series.get("speed"), 1) == "rad/s"
