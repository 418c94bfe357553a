"""Tooth-flank friction of a compliant mesh (issue 41 item 1): each pair in contact takes μ F_j
along the common tangent against its sliding (``cpp/flank_friction.hpp``).

The pair is ``tests/conftest.two_gear_urdf``: 20/40 teeth, module 2 mm, 20°, no profile shift, at
the reference centre distance 60 mm; gear A (joint ``a``) at the origin, B at x = 60 mm, both
about +z. A is driven at a constant speed ω_A > 0 (counter-clockwise), B carries a constant load
torque T_L (counter-clockwise, resisting), so A drives B on the front flank.

Hand geometry in the transverse plane (world axes): the pitch point P = (r_w,A, 0); the line of
action n = (sin α, cos α) (the force on B, F n, pushes B away from A and clockwise); the
contact X = P + d n, d < 0 before the pitch point (approach), d > 0 after (recess); its
distances from the tangency points T_A, T_B are ρ_A = r_b,A tan α + d and ρ_B = r_b,B tan α − d.
B's flank slides on A's at v_B(X) − v_A(X) = (ω_B − ω_A) d (k × n) (P is the instantaneous centre
of the relative motion), so friction on B is +μ F sgn(d) e, e = k × n = (−cos α, sin α), and
on A the opposite. Moments about the axes (z):

    on B:  −F r_b,B − μ F sgn(d) ρ_B          on A:  −F r_b,A − μ F sgn(d) ρ_A,

hence in steady running (B's moment balance, A's driver torque)

    F = T_L / (r_b,B + μ Σ_j s_j sgn(d_j) ρ_B,j),    T_A = F (r_b,A + μ Σ_j s_j sgn(d_j) ρ_A,j),

with s_j the pair's share (1/2 in double contact at constant stiffness), and the loss
μ F (|ω_A| + |ω_B|) Σ_j s_j |d_j| (Ohlendorf's picture, ISO/TR 14179-2 §5).
"""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest

import pinwind
from pinwind.cli import main
from pinwind.errors import InputError, MalformedModel
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads
from pinwind.testing.ledger import ledger_residual
from tests.conftest import two_gear_urdf

MODULE, ALPHA = 0.002, math.radians(20.0)
Z_A, Z_B = 20, 40
U = Z_B / Z_A
R_WA, R_WB = Z_A * MODULE / 2, Z_B * MODULE / 2
R_BA, R_BB = R_WA * math.cos(ALPHA), R_WB * math.cos(ALPHA)
BASE_PITCH = math.pi * MODULE * math.cos(ALPHA)
OMEGA_A = 10.0  # [rad/s]
LOAD = 5.0  # T_L on B [N·m]
MESH_PERIOD = 2 * math.pi / (Z_A * OMEGA_A)  # [s]


def _recess_and_approach() -> tuple[float, float]:
    """ε_2 (on A's addendum, recess) and ε_1 (on B's, approach), each over the base pitch."""
    r_a1, r_a2 = R_WA + MODULE, R_WB + MODULE
    recess = math.sqrt(r_a1**2 - R_BA**2) - R_BA * math.tan(ALPHA)
    approach = math.sqrt(r_a2**2 - R_BB**2) - R_BB * math.tan(ALPHA)
    return recess / BASE_PITCH, approach / BASE_PITCH


EPS_2, EPS_1 = _recess_and_approach()
EPS = EPS_1 + EPS_2


def ohlendorf_h_v() -> float:
    """Ohlendorf's H_V = π(u + 1)/(z₁ u) (1 − ε_α + ε₁² + ε₂²), as ISO/TR 14179-2 gives it."""
    return math.pi * (U + 1) / (Z_A * U) * (1 - EPS + EPS_1**2 + EPS_2**2)


def _pairs_at(x: np.ndarray) -> list[np.ndarray]:
    """d_j of the pairs in contact with the entering one at x ∈ [0, p_b) from the path start [m]."""
    length = EPS * BASE_PITCH
    pitch = EPS_1 * BASE_PITCH
    return [
        np.where(x + j * BASE_PITCH <= length, x + j * BASE_PITCH - pitch, np.nan) for j in (0, 1)
    ]


def rigid_statics(mu: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """F [N] and Σ_j s_j |d_j| [m] at entering positions x (module docstring's statics)."""
    d = _pairs_at(x)
    pairs = sum(np.isfinite(dj).astype(float) for dj in d)
    lever_b = np.full_like(x, R_BB)
    slide = np.zeros_like(x)
    for dj in d:
        on = np.isfinite(dj)
        dd = np.where(on, dj, 0.0)
        lever_b += np.where(on, mu * np.sign(dd) * (R_BB * math.tan(ALPHA) - dd) / pairs, 0.0)
        slide += np.where(on, np.abs(dd) / pairs, 0.0)
    return LOAD / lever_b, slide


def _run(
    mu: float, *, per_period: int, periods: float, damping_ratio: float = 0.3, slices: int = 1
):
    """A steady run of ``periods`` mesh periods at ``per_period`` steps a period."""
    gb = loads(two_gear_urdf(), "pair.urdf")
    compliance = MeshCompliance(
        stiffness=1e8,
        variation="constant",
        damping_ratio=damping_ratio,
        friction_coefficient=mu,
        slices=slices,
    )
    return pinwind.simulate(
        gb,
        duration=round(periods * per_period) * (MESH_PERIOD / per_period),
        dt=MESH_PERIOD / per_period,
        speeds={"a": OMEGA_A},
        torques={"b": LOAD},
        gravity=np.zeros(3),
        meshes={"m": compliance},
    )


def _last_periods(res, periods: int) -> slice:
    """The samples of the last whole mesh periods (an integer number of them)."""
    n = round(periods * MESH_PERIOD / (res.time[1] - res.time[0]))
    return slice(len(res.time) - n, len(res.time))


def test_sliding_velocity_is_the_speed_sum_times_the_distance_from_the_pitch_point():
    res = _run(0.05, per_period=16000, periods=1.25)
    mesh = res.mesh("m")
    omega_b = res.joint("b").speed
    np.testing.assert_allclose(res.joint("a").speed, OMEGA_A, rtol=1e-12)
    # d of the entering pair: its roll length from T_A less the pitch point's, r_b,A tan α.
    d = mesh.contact_position - R_BA * math.tan(ALPHA)
    assert d.min() < -1e-4 and d.max() > 1e-4  # the entering pair crosses the pitch point
    # e·(v_B − v_A) at X = P + d n, v = ω k × (X − C), e = (−cos α, sin α): the rolling
    # mismatch at P, −sin α (ω_A r_w,A + ω_B r_w,B) (zero in pure rolling: the mesh's vibration),
    # plus (ω_B − ω_A) d.
    mismatch = -math.sin(ALPHA) * (OMEGA_A * R_WA + omega_b * R_WB)
    expected = mismatch + (omega_b - OMEGA_A) * d
    scale = OMEGA_A * BASE_PITCH
    np.testing.assert_allclose(mesh.sliding_velocity, expected, rtol=0, atol=1e-9 * scale)
    # In rolling (after the start's friction transient has decayed) that is (ω_A + |ω_B|)|d|:
    # zero at the pitch point, its sign that of −d.
    steady = res.time > 0.25 * MESH_PERIOD
    assert np.abs(mismatch[steady]).max() < 1e-3 * scale
    np.testing.assert_allclose(
        np.abs(mesh.sliding_velocity[steady]),
        (OMEGA_A + np.abs(omega_b[steady])) * np.abs(d[steady]),
        rtol=0,
        atol=1e-3 * scale,
    )


def test_an_internal_pair_slides_at_the_speed_difference_times_the_distance():
    # Pinion A (24 teeth) inside ring B (72 teeth), centre distance m (z_B − z_A)/2 = 48 mm: both
    # turn the same way, P stays the relative motion's centre, so |v_s| = |ω_A − ω_B| |d|.
    text = two_gear_urdf(teeth=("24", "72"), internal=("false", "true"), centre_distance=0.048)
    gb = loads(text, "ring.urdf")
    period = 2 * math.pi / (24 * OMEGA_A)
    res = pinwind.simulate(
        gb,
        duration=20000 * (period / 16000),
        dt=period / 16000,
        speeds={"a": OMEGA_A},
        torques={"b": -LOAD},
        gravity=np.zeros(3),
        meshes={
            "m": MeshCompliance(
                stiffness=1e8, variation="constant", damping_ratio=0.3, friction_coefficient=0.05
            )
        },
    )
    mesh = res.mesh("m")
    r_ba = 24 * MODULE / 2 * math.cos(ALPHA)
    d = mesh.contact_position - r_ba * math.tan(ALPHA)  # the entering pair's, from P
    omega_b = res.joint("b").speed
    np.testing.assert_allclose(omega_b, OMEGA_A / 3, rtol=1e-3)  # the same sense as A
    steady = res.time > 0.25 * period
    slip = np.abs(OMEGA_A - omega_b)
    scale = OMEGA_A * BASE_PITCH
    np.testing.assert_allclose(
        np.abs(mesh.sliding_velocity[steady]), (slip * np.abs(d))[steady], rtol=0, atol=1e-3 * scale
    )
    # Every pair: the loss is μ F |ω_A − ω_B| Σ_j |d_j| / pairs, d_j = d + j p_b; the second
    # pair crosses the pitch point here (ε_α = 1.93, the pitch point beyond the entering span).
    second = np.where(mesh.pairs == 2, np.abs(d + BASE_PITCH), 0.0)
    assert (d + BASE_PITCH)[mesh.pairs == 2].min() < 0 < (d + BASE_PITCH)[mesh.pairs == 2].max()
    loss = 0.05 * mesh.normal * slip * (np.abs(d) + second) / mesh.pairs
    np.testing.assert_allclose(
        mesh.friction_power[steady], loss[steady], rtol=0, atol=1e-3 * loss.max()
    )


def test_mean_mesh_loss_at_small_mu_is_ohlendorfs_tooth_loss_factor():
    mu = 1e-4
    res = _run(mu, per_period=20000, periods=2.0)
    window = _last_periods(res, 1)
    loss = res.mesh("m").friction_power[window].mean()
    power = (LOAD * np.abs(res.joint("b").speed[window])).mean()
    # P_loss/(μ P) → H_V as μ → 0: F varies by μ ρ/r_b ~ 4e-5 of itself here.
    np.testing.assert_allclose(loss / (mu * power), ohlendorf_h_v(), rtol=1e-4)


@pytest.mark.parametrize("slices", [1, 4])
def test_mean_mesh_loss_at_mu_005_is_the_quadrature_of_rigid_statics_with_friction(slices):
    # Sliced (4 slices across the face, the gears aligned): each slice carries a quarter, the
    # friction acts at the load centre, the same loss.
    mu = 0.05
    res = _run(mu, per_period=10000, periods=4.0, slices=slices)
    window = _last_periods(res, 2)
    loss = res.mesh("m").friction_power[window].mean()
    power = (LOAD * np.abs(res.joint("b").speed[window])).mean()
    # Midpoint quadrature over one base pitch of the entering pair's position x.
    x = (np.arange(200000) + 0.5) / 200000 * BASE_PITCH
    force, slide = rigid_statics(mu, x)
    speeds = OMEGA_A * (1 + 1 / U)
    expected = np.mean(mu * force * speeds * slide) / (LOAD * OMEGA_A / U)
    np.testing.assert_allclose(loss / power, expected, rtol=1e-4)
    # Friction moves the mean loss off μ H_V by O(μ ρ/r_b): the test can tell the two apart.
    assert abs(expected / (mu * ohlendorf_h_v()) - 1) > 3e-3


def test_friction_changes_the_bearing_force_and_driver_torque_by_hand_statics():
    mu = 0.05
    res = _run(mu, per_period=4000, periods=2.25)
    mesh = res.mesh("m")
    d = mesh.contact_position - R_BA * math.tan(ALPHA)
    single = (mesh.pairs == 1) & (res.time > 0.5 * MESH_PERIOD)
    approach, recess = single & (d < -1e-4), single & (d > 1e-4)
    assert approach.sum() > 50 and recess.sum() > 50
    n = np.array([math.sin(ALPHA), math.cos(ALPHA), 0.0])
    e = np.array([-math.cos(ALPHA), math.sin(ALPHA), 0.0])
    scale = LOAD / R_BB
    # The friction on A along e is −μ F sgn(d) (module docstring; F predicted at the step's
    # start from its deflection and the last step's acceleration: within 1e-3 of the step's F
    # at the step after a pair leaves, where the friction's moment jumps, 1e-5 elsewhere).
    friction = mesh.friction_force
    np.testing.assert_allclose(
        friction[single], -mu * mesh.normal[single] * np.sign(d[single]), rtol=1e-3
    )
    # It flips across the pitch point: B is pulled along +e before it, along −e after.
    assert np.all(friction[approach] > 0.9 * mu * scale)
    assert np.all(friction[recess] < -0.9 * mu * scale)
    # B's centre does not move: its bearing holds the teeth's force, friction included,
    # −(F n − friction e) (gravity off; B's mass centre on its axis).
    on_b = mesh.normal[:, None] * n - friction[:, None] * e
    np.testing.assert_allclose(
        res.bearing("b").force[single], -on_b[single], rtol=0, atol=1e-9 * scale
    )
    # The friction acts at the contact points: about B's axis its moment in the reactions is the
    # one the dynamics felt, so B's bearing passes on exactly the load torque T_L (I ω̇ less the
    # teeth's moment), and A's its driver's torque.
    np.testing.assert_allclose(res.bearing("b").moment[:, 2], LOAD, rtol=1e-9)
    np.testing.assert_allclose(res.bearing("a").moment[:, 2], res.joint("a").torque, rtol=1e-9)
    # A turns at a constant speed: its driver holds the teeth's moment about A's axis,
    # F r_b,A − friction ρ_A (friction e at X: moment (X − C_A)·n = ρ_A = r_b,A tan α + d).
    rho_a = R_BA * math.tan(ALPHA) + d
    np.testing.assert_allclose(
        res.joint("a").torque[single],
        (mesh.normal * R_BA - friction * rho_a)[single],
        rtol=1e-9,
    )
    # And F itself is B's hand statics, T_L / (r_b,B + μ sgn(d) ρ_B), once the mesh mode
    # (1 kHz, ζ = 0.3: 0.5 ms to decay by e) has settled after the friction's last jump (a pair
    # leaving, the pitch point): 0.1 mesh period, 3 ms, later.
    rho_b = R_BB * math.tan(ALPHA) - d
    statics = LOAD / (R_BB + mu * np.sign(d) * rho_b)
    jumps = np.flatnonzero((np.diff(mesh.pairs) != 0) | (np.diff(np.sign(d)) != 0)) + 1
    since = res.time - res.time[jumps[np.searchsorted(jumps, np.arange(len(d)), "right") - 1]]
    settled = single & (since > 0.1 * MESH_PERIOD)
    assert settled.sum() > 0.3 * single.sum()
    np.testing.assert_allclose(mesh.normal[settled], statics[settled], rtol=3e-4)
    jump = statics[recess].mean() / statics[approach].mean() - 1
    assert jump < -0.02  # the friction's moment moves F by 1.8 % each way


@pytest.mark.parametrize("slices", [1, 4])
def test_input_less_output_work_is_the_losses_over_a_steady_run(slices):
    res = _run(0.05, per_period=2000, periods=3.0, slices=slices)
    e = res.energy
    work_in = e["work_drivers"][-1]
    assert e["friction_loss"][-1] > 1e-3 * work_in
    np.testing.assert_allclose(
        e["friction_loss"][-1] / (res.time[-1] - res.time[0]),
        res.mesh("m").friction_power[:-1].mean(),
        rtol=2e-2,
    )
    assert np.abs(ledger_residual(res)).max() <= 1e-9 * work_in


@pytest.mark.parametrize("mu", [-0.1, 1.0, 1.5])
def test_a_friction_coefficient_outside_0_1_is_refused_naming_the_mesh(mu):
    gb = loads(two_gear_urdf(), "pair.urdf")
    with pytest.raises(InputError, match=r'meshes\["m"\]: friction_coefficient is'):
        pinwind.simulate(
            gb,
            duration=0.01,
            dt=1e-3,
            meshes={"m": MeshCompliance(friction_coefficient=mu)},
        )
    text = two_gear_urdf().replace(
        '<mesh name="m" gear1="g1" gear2="g2"/>',
        f'<mesh name="m" gear1="g1" gear2="g2" type="compliant" friction_coefficient="{mu}"/>',
    )
    with pytest.raises(MalformedModel, match=r'<mesh name="m">.*friction_coefficient is'):
        loads(text, "pair.urdf")


def test_a_bad_friction_coefficient_in_the_model_file_is_one_message_and_exit_2(
    tmp_path, monkeypatch, capsys
):
    path = tmp_path / "pair.urdf"
    path.write_text(
        two_gear_urdf().replace(
            '<mesh name="m" gear1="g1" gear2="g2"/>',
            '<mesh name="m" gear1="g1" gear2="g2" type="compliant" friction_coefficient="1.2"/>',
        )
    )
    monkeypatch.setattr(sys, "argv", ["pinwind", "info", str(path)])
    with pytest.raises(SystemExit) as caught:
        main()
    assert caught.value.code == 2
    err = capsys.readouterr().err
    assert "friction_coefficient is 1.2" in err, err
    assert err.strip().count("\n") == 0, err
