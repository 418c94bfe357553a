"""The efficiency map's steady speed ratio, across the model's torsional springs."""

from __future__ import annotations

import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.errors import UnknownJoint
from pinwind.runs.efficiency_map import steady_ratio
from tests.conftest import MODELS


def test_nrel_5mw_generator_turns_at_the_ratio_of_the_teeth_across_its_shaft_springs():
    # Nejad et al. 2016 Table V: (1 + 56/19)(1 + 93/18)(95/24) = 96.354, the parallel stage
    # reversing; the main shaft and the generator coupling are torsional springs, so the mesh
    # kinematics alone leave three degrees of freedom
    gb = pinwind.load(MODELS / "nrel5mw_gearbox.urdf")
    ratio = (1 + 56 / 19) * (1 + 93 / 18) * (95 / 24)
    assert_allclose(steady_ratio(gb, "generator", "rotor"), -ratio, rtol=1e-12)
    with pytest.raises(UnknownJoint, match="generatr"):
        steady_ratio(gb, "generatr", "rotor")
