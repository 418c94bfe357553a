"""The replay's scene: the shapes of a model's visuals."""

from __future__ import annotations

from pinwind.io.replay_scene import model_visuals

#: One link with a cylinder and a box whose size is missing (urdfdom skips such a visual with a
#: message and the model loads, so a logged model can hold one).
BOX_WITHOUT_SIZE = """<robot name="r">
  <link name="shaft">
    <visual><geometry><box /></geometry></visual>
    <visual><geometry><cylinder radius="0.25" length="0.5" /></geometry></visual>
  </link>
</robot>"""


def test_visual_box_without_size_is_left_out_and_the_other_shapes_kept():
    visuals = model_visuals(BOX_WITHOUT_SIZE)
    assert [(v.link, v.kind, v.size) for v in visuals] == [("shaft", "cylinder", (0.25, 0.5))]
