"""Each kind of element and constraint: one builder here, one kind in the compiled list.

The compiled step lists its kinds (``cpp/element_kinds.hpp``, read as ``_native.kind_fields``);
``dynamics/element_specs.py`` holds one builder per kind. The lists are compared, and each kind's
compiled check is reached through its builder with the message it has always had.
"""

from __future__ import annotations

import numpy as np
import pytest

from pinwind.dynamics import _native, element_specs
from pinwind.dynamics.compliant import mesh_setup
from pinwind.dynamics.element_specs import SPEC_BUILDERS
from pinwind.dynamics.solver import SolverSettings
from pinwind.dynamics.stepper import CompiledStepper
from pinwind.model.gearbox import loads
from tests.dynamics.test_torsional_spring import _shafts_urdf

#: Stiffness of the test's spring [N·m/rad]: any positive value.
STIFFNESS = 50.0


def _shafts():
    """Two coaxial shafts a and b joined by a torsional spring (``test_torsional_spring``)."""
    return loads(_shafts_urdf(stiffness=STIFFNESS), "shafts.urdf")


def _stepper(gb) -> CompiledStepper:
    return CompiledStepper(
        gb,
        2,
        gb.neutral(),
        np.zeros(gb.model.nv),
        dt=1e-3,
        gravity=gb.gravity,
        driver_index=[],
        driver_names=[],
        settings=SolverSettings(),
        meshes=mesh_setup(gb, gb.meshes, driver_index=[], dt=1e-3),
    )


def test_every_compiled_kind_has_one_builder_and_every_builder_a_compiled_kind():
    fields = _native.kind_fields()
    assert len(fields) == len(set(fields))
    assert set(fields) == set(SPEC_BUILDERS)
    spec = _native.StepperSpec()
    for field in fields:  # each kind is a field of the spec the stepper is built from
        assert hasattr(spec, field), field


def test_the_constraints_rows_are_the_rigid_meshes_then_the_drivers_after_every_element():
    # The rows of the step's QP: rigid meshes in file order, then the speed drivers and locks
    # (CompiledStepper.assemble documents it); the elements' kinds come before, in the order
    # their forces are summed.
    assert _native.kind_fields()[-2:] == ["rigid_meshes", "driver_index"]


def test_the_spring_builder_gives_the_springs_stiffness_on_its_two_joints():
    gb = _shafts()
    run = element_specs.RunElements(gb, mesh_setup(gb, gb.meshes, driver_index=[], dt=1e-3),
                                    None, [])  # fmt: skip
    (spring,) = element_specs.torsional_springs(run)
    assert (spring.index_1, spring.index_2) == (gb.v_index("a"), gb.v_index("b"))
    assert spring.stiffness == STIFFNESS


def test_a_kind_whose_spec_names_a_joint_the_model_lacks_is_refused_by_its_check(monkeypatch):
    gb = _shafts()
    nv = gb.model.nv
    _stepper(gb)  # the spring as the model gives it is accepted

    def off_the_model(run):
        (spring,) = element_specs.torsional_springs(run)
        spring.index_2 = nv  # one past the last velocity
        return [spring]

    monkeypatch.setitem(SPEC_BUILDERS, "springs", off_the_model)
    with pytest.raises(ValueError, match="bad spring joint index"):
        _stepper(gb)


def test_a_bearing_damping_of_the_wrong_size_is_refused_naming_its_field(monkeypatch):
    gb = _shafts()
    monkeypatch.setitem(SPEC_BUILDERS, "bearing_damping", lambda run: np.zeros(gb.model.nv + 1))
    with pytest.raises(ValueError, match="bearing_damping has 3 entries, expected 2"):
        _stepper(gb)


def test_the_element_forces_of_a_spring_are_its_hookes_law_whatever_builds_them():
    # θ_a − θ_b = 0.01 rad: τ_a = −k (θ_a − θ_b), τ_b = +k (θ_a − θ_b) (Hooke), K = k [1 −1; −1 1]
    gb = _shafts()
    q = gb.neutral()
    q[gb.v_index("a")] = 0.01
    forces = _stepper(gb).element_forces(q, np.zeros(gb.model.nv))
    expected = np.zeros(gb.model.nv)
    expected[gb.v_index("a")], expected[gb.v_index("b")] = -STIFFNESS * 0.01, STIFFNESS * 0.01
    np.testing.assert_allclose(forces.force, expected, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(forces.potential, 0.5 * STIFFNESS * 0.01**2, rtol=1e-12)
