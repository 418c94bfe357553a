"""element_tangents and conservative_forces see a tangent or a force that is off, and say where."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from pinwind.errors import CheckFailed
from pinwind.model.gearbox import loads
from pinwind.testing import conservative_forces, element_tangents
from pinwind.testing import tangents as module
from tests.dynamics.test_compliant_bearing import disc_urdf

LINEAR = 'radial_stiffness="1e8" radial_damping="300"'


class _Off:
    """A stepper whose element forces are the real ones but one value, changed."""

    def __init__(self, stepper, *, stiffness=1.0, damping=1.0, force=0.0):
        self.stepper, self.k, self.c, self.f = stepper, stiffness, damping, force

    def element_forces(self, q, v):
        at = self.stepper.element_forces(q, v)
        k, c = np.array(at.stiffness), np.array(at.damping)
        k[0, 0] *= self.k  # disc_radial_x along itself
        c[1, 1] *= self.c
        f = np.array(at.force)
        f[0] += self.f * np.asarray(q)[0]  # a spring no potential holds
        return SimpleNamespace(force=f, stiffness=k, damping=c, potential=at.potential)


def _with(monkeypatch, **off):
    real = module.element_stepper
    monkeypatch.setattr(module, "element_stepper", lambda m, **kw: _Off(real(m, **kw), **off))


def test_a_radial_stiffness_off_by_one_part_in_1e4_is_caught_on_its_joint(monkeypatch):
    gb = loads(disc_urdf(LINEAR))
    _with(monkeypatch, stiffness=1.0 + 1e-4)
    with pytest.raises(CheckFailed) as caught:
        element_tangents(gb, states=2, rtol=1e-6)
    np.testing.assert_allclose(caught.value.measured, 1e-4, rtol=1e-3)
    assert "stiffness −∂f/∂q of disc_radial_x along disc_radial_x" in caught.value.detail


def test_a_damping_tangent_off_is_caught_as_damping(monkeypatch):
    gb = loads(disc_urdf(LINEAR))
    _with(monkeypatch, damping=0.5)
    with pytest.raises(CheckFailed, match="damping −∂f/∂v of disc_radial_y"):
        element_tangents(gb, states=2, rtol=1e-6)


def test_a_force_that_no_potential_holds_is_caught(monkeypatch):
    gb = loads(disc_urdf(LINEAR))
    _with(monkeypatch, force=1e3)  # 1e-5 of the bearing's 1e8 N/m
    with pytest.raises(CheckFailed, match="the force on disc_radial_x"):
        conservative_forces(gb, states=2, rtol=1e-6)


def test_states_on_a_contact_change_are_left_out_and_counted():
    """A roller sum's roller 0 touches at x = c = 2 µm; a state a quarter step beyond it has
    differences that straddle the touch (the slope K_n n δ^(1/9) starts there): left out and
    counted, and a check that compared nothing fails rather than passing on nothing."""
    gb = loads(disc_urdf('law="roller_sum" rollers="4" contact_stiffness="1e9" '
                         'radial_clearance_mm="0.002" radial_damping="100"'))  # fmt: skip
    q = gb.neutral()
    q[gb.v_index("disc_radial_x")] = 2e-6 + 0.25 * module.STEP * module.SPREAD_M
    state = [(q, np.zeros(gb.model.nv))]
    figure = element_tangents(gb, states=state, rtol=1e-6)
    assert "1 states, 1 of 2 comparisons left out" in figure.detail  # the damping is compared
    with pytest.raises(CheckFailed) as caught:
        conservative_forces(gb, states=state, rtol=1e-6)
    assert np.isnan(caught.value.measured)
    assert "1 states, 1 left out" in caught.value.detail
