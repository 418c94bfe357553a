"""The shapes of a model's visuals, as the model reader gives them (the replay draws them)."""

from __future__ import annotations

import math

import numpy as np

from pinwind.model.urdf import read_model_file

#: One link with a cylinder and a box whose size is missing (urdfdom skips such a visual with a
#: message and the model loads, so a logged model can hold one).
BOX_WITHOUT_SIZE = """<robot name="r">
  <link name="shaft">
    <visual><geometry><box /></geometry></visual>
    <visual><geometry><cylinder radius="0.25" length="0.5" /></geometry></visual>
  </link>
  <gearbox />
</robot>"""

#: A box turned a quarter turn about z (yaw), then a quarter turn about the new y (pitch).
TURNED_BOX = """<robot name="r">
  <link name="shaft">
    <visual>
      <origin xyz="0.1 0.2 0.3" rpy="0 1.5707963267948966 1.5707963267948966" />
      <geometry><box size="0.1 0.2 0.3" /></geometry>
    </visual>
  </link>
  <gearbox />
</robot>"""


def test_visual_box_without_size_is_left_out_and_the_other_shapes_kept():
    visuals = read_model_file("r.urdf", BOX_WITHOUT_SIZE).visuals
    assert [(v.link, v.kind, v.size) for v in visuals] == [("shaft", "cylinder", (0.25, 0.5))]


def test_visual_origin_is_the_urdf_fixed_axis_roll_pitch_yaw():
    # URDF: R = Rz(yaw) Ry(pitch) Rx(roll). Ry(π/2) takes x to −z, then Rz(π/2) keeps −z; y goes
    # to y under Ry, then to −x under Rz; z goes to x under Ry, then to y under Rz.
    (visual,) = read_model_file("r.urdf", TURNED_BOX).visuals
    assert (visual.kind, visual.size) == ("box", (0.1, 0.2, 0.3))
    np.testing.assert_allclose(visual.xyz, [0.1, 0.2, 0.3], rtol=0, atol=0)
    expected = np.array([[0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0]])
    np.testing.assert_allclose(visual.rotation, expected, atol=1e-15)
    assert math.isclose(np.linalg.det(visual.rotation), 1.0)
