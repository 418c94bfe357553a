"""Tip relief in the run's compliant mesh: the deflection of a slowly turning pair is the static
transmission error, the energy ledger closes, and unmodified meshes are untouched.

The pair is ``tests/conftest.two_gear_urdf`` (20/40 teeth, module 2 mm) with ISO's pair stiffness
along the path (c′ b in the single-pair zone, 0.875 c′ b per pair in the double-pair zones), both
gears with linear "long" tip relief. Turned at a crawl and braked, the pair is quasi-static: at
each sample its overlap δ is the approach at which the pairs in contact, each behind its relief's
gap, carry the brake's force (`pinwind.gears.transmission_error`, computed here at the run's own
contact positions, independently of the compiled step).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

import pinwind
from pinwind.dynamics.integrator import Integrator
from pinwind.errors import InputError
from pinwind.gears.flank_modification import FlankModification
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.transmission_error import static_transmission_error
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from tests.conftest import two_gear_urdf

K_SINGLE = 1e8  # c′ b [N/m]
TORQUE_B = 8.0  # brake on gear B [N·m]
ALPHA = math.radians(20.0)
R_BA = 20 * 0.002 * math.cos(ALPHA) / 2
R_BB = 40 * 0.002 * math.cos(ALPHA) / 2


def relieved_pair(relief_um: float, *, on: tuple[str, ...] = ("g1", "g2")) -> pinwind.Gearbox:
    text = two_gear_urdf()
    pair = GearPair(20, 40, module=0.002, pressure_angle=ALPHA, face_width=0.02)
    length_mm = (pair.path.length - pair.path.base_pitch) * 1e3
    for gear in on:
        text = text.replace(
            f'<gear name="{gear}" ',
            f'<gear name="{gear}" tip_relief_um="{relief_um}" '
            f'tip_relief_length_mm="{length_mm!r}" ',
        )
    return loads(text, "relieved_pair.urdf")


def crawl(gearbox, *, damping_ratio=0.6, duration=1.2, dt=2e-5, speed=0.3):
    """Gear A driven at ``speed`` [rad/s], B braked: 0.3 rad/s rolls a base pitch in 1.05 s."""
    return pinwind.simulate(
        gearbox,
        duration=duration,
        dt=dt,
        speeds={"a": speed},
        torques={"b": TORQUE_B},
        gravity=np.zeros(3),
        meshes={"m": MeshCompliance(stiffness=K_SINGLE, damping_ratio=damping_ratio)},
        initial_deflection="static",
    )


@pytest.mark.parametrize("relief_um", [0.0, 0.5])
def test_a_crawling_pair_deflects_by_the_static_transmission_error(relief_um):
    gb = relieved_pair(relief_um)
    res = crawl(gb)
    mesh = res.mesh("m")
    pair = GearPair(20, 40, module=0.002, pressure_angle=ALPHA, face_width=0.02)
    path = pair.path
    relief = FlankModification(
        tip_relief=relief_um * 1e-6, tip_relief_length=path.length - path.base_pitch
    )
    x = mesh.contact_position - path.start_roll_1  # the entering pair, from A
    force = TORQUE_B / R_BB
    te = static_transmission_error(
        pair, force, gear_1=relief, gear_2=relief, single_pair=K_SINGLE, roll=x % path.base_pitch
    )
    # Away from the ISO curve's stiffness steps (a few ms of ringing each): where the leading
    # pair leaves at E (entering pair at B) and where a new pair enters at A (x wraps to 0).
    steps = np.array([0.0, path.single_start, path.base_pitch])
    ringing = 0.01 * 0.3 * R_BA  # 10 ms of roll at 0.3 rad/s
    away = np.min(np.abs(x[:, None] - steps[None, :]), axis=1) > ringing
    assert away.sum() > 0.5 * away.size
    assert_allclose(mesh.deflection[away], te.approach[away], rtol=5e-4)


def test_relief_reshapes_the_deflection_as_the_hand_solution_of_two_pairs():
    # In a double-pair zone both pairs touch (δ above both gaps): 1.75 k δ = F + 0.875 k C_a.
    relief = 0.3e-6
    res = crawl(relieved_pair(relief * 1e6))
    mesh = res.mesh("m")
    pair = GearPair(20, 40, module=0.002, pressure_angle=ALPHA, face_width=0.02)
    path = pair.path
    x = mesh.contact_position - path.start_roll_1
    force = TORQUE_B / R_BB
    delta = (force + 0.875 * K_SINGLE * relief) / (1.75 * K_SINGLE)
    assert delta > relief
    inside = (x > 0.2 * path.single_start) & (x < 0.8 * path.single_start)
    assert inside.sum() > 100
    assert_allclose(mesh.deflection[inside], delta, rtol=5e-4)


def test_the_energy_ledger_closes_through_the_reliefs_undamped():
    gb = relieved_pair(0.4)
    res = pinwind.simulate(
        gb,
        duration=0.05,
        dt=1e-5,
        integrator=Integrator(rho_infinity=1.0),
        initial_speeds={"a": 20.0},
        torques={"b": TORQUE_B, "a": TORQUE_B / 2},  # balanced: ω_b / ω_a = −1/2
        gravity=np.zeros(3),
        meshes={"m": MeshCompliance(stiffness=K_SINGLE, damping=0.0)},
    )
    energy = res.energy
    # The integrator's own loss, against the energy the springs hold and the work the moving
    # stiffness and gaps put in.
    scale = np.max(energy["potential_spring"])
    assert np.max(np.abs(energy["work_parametric"])) > 0.05 * scale
    # Measured: 2.5e-6 of it (the pairs engaged are held over a step, as their stiffness).
    assert np.max(np.abs(energy["numerical"])) < 1e-5 * scale


def test_profile_relief_on_a_helical_compliant_mesh_is_refused_with_the_reason():
    beta = math.radians(10.0)
    centre = 0.002 / math.cos(beta) * 30  # m_t (z1 + z2) / 2
    text = (
        two_gear_urdf(centre_distance=centre)
        .replace('<gear name="g1" ', '<gear name="g1" helix_angle_deg="10" ')
        .replace('<gear name="g2" ', '<gear name="g2" helix_angle_deg="-10" ')
    )
    text = text.replace(
        '<gear name="g1" ', '<gear name="g1" tip_relief_um="5" tip_relief_length_mm="1" '
    )
    with pytest.raises(InputError, match="helical"):
        pinwind.simulate(
            loads(text, "helical.urdf"),
            duration=0.001,
            dt=1e-4,
            torques={"a": 1.0},
            speeds={"b": 0.0},
            meshes={"m": "compliant"},
        )
