"""The NREL 5 MW rotor's thrust, weight and wind-shear moment, and the main shaft's rows that carry
them, against the independent recoding of ``benchmarks/independent_hub_loads.py``
(docs/validation.md, "Independent recoding of the main shaft's loads"): short runs of its cases.

The recoding takes only the model file, ROSCO's C_t table and the docs' formulas: T = ½ρπR²v²C_t
(Burton et al. 2011), the hub's F_x = T + m g sin τ, F_z = −m g cos τ, M_y = ℓ T with ℓ by
quadrature over the disc, and the main shaft as a rigid body on its four rows' linear springs,
solved by hand with the stage-1 planets' bearing reactions as the gearbox side's input.
"""

from __future__ import annotations

import numpy as np

from tests.benchmarks import benchmark_module

recoding = benchmark_module("independent_hub_loads.py", "independent_hub_loads")
DURATION = 0.003  # s: 30 steps of 1e-4 s


def test_the_rotor_thrust_is_half_rho_pi_r_squared_v_squared_ct_of_rosco_s_table():
    r = recoding
    res = r.run_case("A", DURATION)
    lam, ct, thrust = r.thrust_of(res.joint("rotor").speed, res.rotor("rotor").wind_speed)
    rotor = res.rotor("rotor")
    np.testing.assert_allclose(rotor.tip_speed_ratio, lam, rtol=1e-13)
    np.testing.assert_allclose(rotor.thrust_coefficient, ct, rtol=1e-13)
    np.testing.assert_allclose(rotor.thrust, thrust, rtol=1e-13)
    # 10 m/s at 12.1 rpm: λ = 7.98 between the table's rows 7.5 and 8.0, β = 1.3° between its
    # columns 1.0° and 1.5° (both interpolations at work)
    assert 7.5 < lam[0] < 8.0 and r.PITCH_DEG == 1.3 and 5.4e5 < thrust[0] < 5.7e5


def test_the_rotor_loads_its_hub_with_thrust_plus_tilted_weight_and_the_shear_moment():
    """A run with the rotor's hub on the main shaft and one with the recoded F_x, F_z, M_y as a
    plain hub load in its place go through the same states: their rows' loads agree."""
    r = recoding
    shaft = r.read_shaft(r.MODEL, "lss")
    g = float(np.linalg.norm(shaft.gravity))
    with_rotor = r.run_case("A", DURATION)
    _, _, thrust = r.thrust_of(
        with_rotor.joint("rotor").speed, with_rotor.rotor("rotor").wind_speed
    )
    arm = r.shear_arm(r.RADIUS, r.HUB_HEIGHT, r.SHEAR_EXPONENT)
    fx, fz, my = r.rotor_hub_load(thrust, arm, g)
    recoded = r.run_case(
        "A'",
        DURATION,
        hub=("fixed", ("csv:1", 0.0, "csv:2", 0.0, "csv:3", 0.0)),
        table=np.column_stack([with_rotor.time, fx, fz, my]),
    )
    assert r.twin_check(with_rotor, recoded, shaft) < 1e-9
    # ℓ by quadrature lies 4.6 % above its small-shear limit α R²/(2H) = 4.41 m
    np.testing.assert_allclose(arm, 4.614764949, rtol=1e-9)


def test_the_main_shaft_s_rows_carry_a_hub_load_as_a_rigid_shaft_on_linear_springs():
    r = recoding
    shaft = r.read_shaft(r.MODEL, "lss")
    up = -shaft.gravity / np.linalg.norm(shaft.gravity)
    res = r.run_case("B", DURATION, hub=("fixed", r.HUB_LOAD))
    table = r.statics_table(res, shaft, r.hub_wrench(r.HUB_LOAD, up), "B")
    assert len(table) == 13  # 4 rows' forces, 3 rows' moments (INP-B has no tilt springs), 6 more
    for name, _, _, difference in table:
        assert difference < 1e-9, name


def test_a_rotating_hub_load_turns_with_the_shaft_angle_and_tilts_with_the_shaft():
    r = recoding
    shaft = r.read_shaft(r.MODEL, "lss")
    up = -shaft.gravity / np.linalg.norm(shaft.gravity)
    res = r.run_case("B", DURATION, hub=("rotating", r.HUB_LOAD))
    psi = float(res.joint("lss").angle[-1])
    assert abs(psi) > 1e-4  # the coupling's wind-up under the rated torque
    assert r.statics_summary(res, shaft, r.hub_wrench(r.HUB_LOAD, up, psi), "B")[3] < 1e-9


def test_each_main_shaft_row_carries_its_springs_and_dampers_at_the_step_s_mean_state():
    """Turning, the rows' loads are −K δ − C δ̇ of docs/model_format.md's δ = (z, x + a θ_w,
    y − a θ_u, θ_u, θ_w), at the mean of the slides' states at the step's two ends (ρ∞ = 1)."""
    r = recoding
    shaft = r.read_shaft(r.MODEL, "lss")
    res = r.run_case("A", DURATION)
    assert np.max(np.abs(r.slides_of(res, "lss", "speed"))) > 0  # the dampers are at work
    assert r.law_check(res, shaft) < 1e-12


def test_a_rotor_known_by_its_power_coefficient_alone_thrusts_by_momentum_theory():
    r = recoding
    rotor = r.momentum_run().rotor("carrier")
    ct = np.array([r.momentum_ct(x) for x in rotor.power_coefficient])
    np.testing.assert_allclose(rotor.thrust_coefficient, ct, rtol=1e-12)
    thrust = 0.5 * r.AIR_DENSITY * np.pi * r.SALEH_RADIUS**2 * rotor.wind_speed**2 * ct
    np.testing.assert_allclose(rotor.thrust, thrust, rtol=1e-12)
    assert 0.4 < rotor.power_coefficient[0] < 16 / 27  # a below 1/3


def test_beyond_rosco_s_table_the_thrust_coefficient_is_held_at_its_edge():
    r = recoding
    res = r.run_case("E", DURATION)
    lam, ct, thrust = r.thrust_of(res.joint("rotor").speed, res.rotor("rotor").wind_speed)
    assert lam[0] > 20.0  # beyond the table's last λ, 14.5
    table = r.read_performance(r.TABLE)
    edge = r.bilinear(table["tsr"], table["pitch_deg"], table["ct"], 14.5, r.PITCH_DEG)
    np.testing.assert_allclose(ct, edge, rtol=1e-15)
    np.testing.assert_allclose(res.rotor("rotor").thrust, thrust, rtol=1e-13)
