"""The flanks a linearisation takes are the machine's, not the model file's (``loaded_flanks.py``).

Lin & Parker's (1999) planar model: a four-planet stage with every member in a compliant radial
bearing (two translations and a rotation each), the ring held in torsion. With translations the
two flanks of a mesh have different rows (the radial part of the line of action), so the modes
depend on which flank is in contact; the contact is set by the load. Writing a mesh A–B as B–A
exchanges the names of its flanks, not the contact, and the order of the meshes in the file is
no property of the machine: the modes must be the same, to rounding, however the file is written.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from pinwind.dynamics.drivetrain import drivetrain
from pinwind.dynamics.simulate import simulate
from pinwind.errors import StepTooCoarse
from pinwind.model.builders import planetary_urdf
from pinwind.model.gearbox import loads
from pinwind.modes.linearisation import linearise

MEMBERS = ["sun", "carrier", "ring", *(f"planet{i}" for i in range(1, 5))]


def lin_parker_text() -> str:
    """The four-planet stage (24/24/72, module 10 mm, 20°) in compliant bearings of 1e9 N/m.

    Its planet → ring meshes are written as the builder writes them.
    """
    text = planetary_urdf(
        sun=24, planet=24, ring=72, planets=4, module=0.01, pressure_angle=math.radians(20.0),
        face_width=0.1, name="lin_parker",
    )  # fmt: skip
    text = text.replace(
        '<joint name="ring" type="fixed">',
        '<joint name="ring" type="continuous"><axis xyz="0 0 1"/>',
    )
    bearings = "".join(f'<bearing joint="{m}" radial_stiffness="1e9"/>' for m in MEMBERS)
    return text.replace("</gearbox>", bearings + "</gearbox>")


def swapped(text: str, which: str) -> str:
    """The file with gear1 and gear2 exchanged on the meshes whose name matches ``which``."""
    return re.sub(
        rf'<mesh name="({which})" gear1="(\w+)" gear2="(\w+)"',
        lambda m: f'<mesh name="{m.group(1)}" gear1="{m.group(3)}" gear2="{m.group(2)}"',
        text,
    )


def reordered(text: str) -> str:
    """The file with its mesh lines in the opposite order."""
    lines = re.findall(r"<mesh [^>]*/>", text)
    body = re.sub(r"<mesh [^>]*/>", "@MESH@", text)
    for line in reversed(lines):
        body = body.replace("@MESH@", line, 1)
    return body


#: Ways of writing the same stage: as built, ring meshes ring → planet, sun meshes planet → sun,
#: both, and every mesh line in the opposite order.
WRITINGS = {
    "ring meshes swapped": lambda t: swapped(t, r"planet\d_ring"),
    "sun meshes swapped": lambda t: swapped(t, r"sun_planet\d"),
    "all swapped": lambda t: swapped(swapped(t, r"planet\d_ring"), r"sun_planet\d"),
    "mesh lines reversed": reordered,
}

#: Static loads of the checks: sun torque against a held carrier (a speed driver at rest), each
#: direction, and a carrier torque against the sun.
LOADS = {
    "sun drives": ({"sun": 2000.0}, {"carrier": 0.0}),
    "sun brakes": ({"sun": -2000.0}, {"carrier": 0.0}),
    "carrier drives": ({"carrier": 12000.0}, {"sun": 0.0}),
}


def _linearised(text: str, load: str):
    torques, speeds = LOADS[load]
    gb = loads(text, "lin_parker.urdf")
    train = drivetrain(gb, meshes={"all": "compliant"}, torques=torques, speeds=speeds)
    return gb, linearise(train, held=["ring"])


@pytest.mark.parametrize("load", list(LOADS))
@pytest.mark.parametrize("writing", list(WRITINGS))
def test_lin_and_parker_s_stage_has_the_same_modes_however_its_meshes_are_written(writing, load):
    text = lin_parker_text()
    _, built = _linearised(text, load)
    _, other = _linearised(WRITINGS[writing](text), load)
    f_built = np.array([m.frequency for m in built.modes()])
    f_other = np.array([m.frequency for m in other.modes()])
    np.testing.assert_allclose(f_other, f_built, rtol=1e-9, atol=1e-9 * f_built.max())
    # The same contact: each mesh's row the same, up to its sign (a quadratic spring).
    rows = {e.name: e.row for e in built.elements if e.kind == "mesh"}
    for e in other.elements:
        if e.kind == "mesh":
            sign = np.sign(rows[e.name] @ e.row)
            np.testing.assert_allclose(sign * e.row, rows[e.name], atol=1e-12)
    assert not built.flanks.unloaded and not other.flanks.unloaded


@pytest.mark.parametrize("load", list(LOADS))
def test_the_linearised_flanks_are_those_the_run_s_static_start_loads(load):
    # The compiled static start (cpp/stepper.hpp Stepper::equilibrium) settles the flanks by
    # Newton iterations on the nonlinear contact; its first sample's flank series says which.
    torques, speeds = LOADS[load]
    for text in (lin_parker_text(), WRITINGS["all swapped"](lin_parker_text())):
        gb, lin = _linearised(text, load)
        with pytest.warns(StepTooCoarse, match="leaves 1 step"):  # the first sample is the point
            res = simulate(
                gb, duration=1e-5, dt=1e-5, torques=torques, speeds={**speeds, "ring": 0.0},
                meshes={"all": "compliant"}, gravity=np.zeros(3), keep="all",
            )  # fmt: skip
        np.testing.assert_array_equal(res.mesh_flank[0], lin.flanks.flank)


def test_a_stage_without_load_states_the_flank_it_assumes():
    gb = loads(lin_parker_text(), "lin_parker.urdf")
    lin = linearise(gb, meshes={"all": "compliant"}, held=["ring"])
    assert set(lin.flanks.unloaded) == {m.name for m in gb.meshes}
    (note,) = lin.flanks.notes()
    assert "no static load on mesh sun_planet1" in note
    assert "planet1 turning forward drives sun" in note  # planet1 comes first in the joints


def test_without_load_the_assumed_flanks_do_not_depend_on_how_the_meshes_are_written():
    text = lin_parker_text()
    frequencies = []
    for variant in [text, *(w(text) for w in WRITINGS.values())]:
        gb = loads(variant, "lin_parker.urdf")
        modes = linearise(gb, meshes={"all": "compliant"}, held=["ring"]).modes()
        frequencies.append([m.frequency for m in modes])
    np.testing.assert_allclose(frequencies[1:], [frequencies[0]] * 4, rtol=1e-9)
