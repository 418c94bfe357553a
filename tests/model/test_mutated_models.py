"""A model file with one number changed to an absurd value: an error naming it, or a finite run.

Hypothesis (seeded: ``derandomize``, no example database) picks one number of one attribute of the
two-gear model (``tests/conftest.two_gear_urdf``) and writes NaN, ±inf, −1, 0, 1e30, 1e300,
1e-30, a word or nothing in its place. The property, the rule of docs/bad_input.md: loading and a
ten-step run either raise a ``PinwindError`` whose message starts with the file and an element,
or names the attribute or the value, or run with every output series finite. A traceback of
another type, a message that names nothing, or NaN or inf in the Result fails it (main before
the reader's ±1e20 bound: a mass of 1e300 kg ran to an infinite bearing_radial, no error).
"""

from __future__ import annotations

import re
import warnings
import xml.etree.ElementTree as ET

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import pinwind
from pinwind.errors import PinwindError
from pinwind.model.gearbox import loads
from tests.conftest import two_gear_urdf

PATH = "mutated.urdf"
BAD = ("nan", "inf", "-inf", "-1", "0", "1e30", "1e300", "1e-30", "-1e30", "abc", "")
TEXT = two_gear_urdf()


def _numbers(text: str) -> list[tuple[int, str, int]]:
    """(element index, attribute, token index) of every number in the file's attributes."""
    out = []
    for i, el in enumerate(ET.fromstring(text).iter()):
        for attr, raw in el.attrib.items():
            for k, token in enumerate(raw.split()):
                if re.fullmatch(r"-?[\d.]+(e-?\d+)?", token):
                    out.append((i, attr, k))
    return out


NUMBERS = _numbers(TEXT)


def _mutated(place: tuple[int, str, int], value: str) -> tuple[str, list[str]]:
    """The file with the number at ``place`` replaced, and what an error may name it by.

    The element's tag, the attribute, the value, and the element or the link, joint or mesh
    holding it (``name="a"``).
    """
    root = ET.fromstring(TEXT)
    parents = {child: parent for parent in root.iter() for child in parent}
    i, attr, k = place
    el = list(root.iter())[i]
    tokens = el.attrib[attr].split()
    tokens[k] = value
    el.set(attr, " ".join(tokens))
    names = [f"<{el.tag}", attr, value or '""']
    holder: ET.Element | None = el
    while holder is not None:
        if "name" in holder.attrib and holder.tag != "robot":
            names.append(f'<{holder.tag} name="{holder.attrib["name"]}">')
        holder = parents.get(holder)
    return ET.tostring(root, encoding="unicode"), names


@settings(max_examples=50, derandomize=True, database=None, deadline=None,
          suppress_health_check=[HealthCheck.too_slow])  # fmt: skip
@given(place=st.sampled_from(NUMBERS), value=st.sampled_from(BAD))
def test_one_absurd_number_gives_an_error_naming_it_or_a_finite_run(place, value):
    text, names = _mutated(place, value)
    attr = place[1]
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # an implausible gear or a coarse dt only warns
            gearbox = loads(text, path=PATH)
            result = pinwind.simulate(gearbox, duration=0.01, dt=1e-3, torques={"a": 1.0})
    except PinwindError as err:
        # The file and an element (the one changed, its holder, or one it misplaces: a joint
        # moved names the mesh whose centre distance it breaks), or the changed value itself.
        message = str(err)
        element = re.match(rf'{re.escape(PATH)}: <\w+( \w+="[^"]*")?>', message)
        assert element or any(name in message for name in names), message
        return
    for name, array in result.arrays().items():
        values = np.asarray(array)
        if values.dtype.kind == "f":
            assert np.all(np.isfinite(values)), f"{name} is not finite after {attr}={value!r}"
