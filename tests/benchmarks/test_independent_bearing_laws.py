"""The compliant bearings' force laws, recoded from a run's slide series and its model alone.

``benchmarks/independent_bearing_laws.py`` recodes them without pinwind's bearing code
(docs/validation.md, "Independent recoding of the bearing force laws"); here a short part of it:
a linear bearing falling through its dead band, a roller sum with clearance, two rows (one with a
clearance, one preloaded) and Stribeck's Q_max = 4.37 F_r/Z of a ball bearing at zero clearance.
Each series at its own state: ``elastic_force`` at the sample, the reaction and the rows' loads
at the step's weighted state (the mean of the sample and the next at ρ∞ = 1), a roller sum
linearised about r + (h/2) ṙ.
"""

from __future__ import annotations

import math

import numpy as np

from tests.benchmarks import benchmark_module

recoding = benchmark_module("independent_bearing_laws.py", "independent_bearing_laws")
DURATION = 0.004  # 200 steps of 20 µs


def test_a_linear_bearing_carries_nothing_in_its_dead_band_and_k_beyond_it():
    r = recoding
    k, c, cr = 1e8, 20e-6, 400.0
    bearing = (
        f'<bearing joint="shaft" radial_stiffness="{k:g}" radial_damping="{cr:g}" '
        f'radial_clearance_mm="{c * 1e3:g}"/>'
    )
    res = r.run(r.shaft_model(bearing, (0.0, -9.81, 0.0)), duration=DURATION, start="none")
    q, _ = r.slides(res, "shaft", ("radial_x", "radial_y"))
    inside = np.linalg.norm(q, axis=1) < c
    assert 10 < inside.sum() < len(q) - 10  # it falls through the band into contact
    ef = res.bearing("shaft").elastic_force[:, :2]
    np.testing.assert_array_equal(ef[inside], 0.0)
    np.testing.assert_allclose(ef, r.linear_radial(q, k, c), rtol=0, atol=1e-12 * np.abs(ef).max())
    qm, vm = r.mid(q), r.weighted_speed(q)
    recoded = r.linear_radial(qm, k, c) + r.linear_damper(qm, vm, cr, c)
    reaction = res.bearing("shaft").force_local[:-1, :2]
    assert r.rel(recoded, reaction) < 1e-12


def test_a_roller_sum_with_clearance_is_harris_sum_linearised_about_the_predicted_state():
    r = recoding
    z, kn, n, c, cr = 16, 2.2e10, 1.5, 5e-6, 2e4
    bearing = (
        f'<bearing joint="shaft" law="roller_sum" rollers="{z}" contact_stiffness="{kn:g}" '
        f'contact="point" radial_clearance_mm="{c * 1e3:g}" radial_damping="{cr:g}"/>'
    )
    res = r.run(r.shaft_model(bearing, (0.0, -9.81, 0.0)), duration=DURATION, start="none")
    q, v = r.slides(res, "shaft", ("radial_x", "radial_y"))
    assert (~r.roller_in_contact(q, z, c)).sum() > 10  # it starts inside the clearance
    law = r.roller_sum(q, z, kn, n, c)
    assert np.abs(law).max() > 500.0  # and presses its elements
    assert r.rel(law, res.bearing("shaft").elastic_force[:, :2]) < 1e-12
    qm, vm = r.mid(q), r.weighted_speed(q)
    r0 = q[:-1] + 0.5 * r.DT * v[:-1]
    tangent = r.roller_sum_jacobian(r0, z, kn, n, c)
    force = r.roller_sum(r0, z, kn, n, c) + np.einsum("iab,ib->ia", tangent, qm - r0)
    force += np.where(r.roller_in_contact(r0, z, c)[:, None], -cr * vm, 0.0)
    assert r.rel(force, res.bearing("shaft").force_local[:-1, :2]) < 1e-12


def test_rows_with_a_clearance_and_a_preload_carry_their_sides_at_the_weighted_state():
    r = recoding
    damping = np.array([3e3, 1e4, 1e4, 60.0, 60.0])
    rows = [
        r.Row(-0.2, np.array([5e7, 4e7, 6e7, 1e5, 2e5]), damping, 5e-6),
        r.Row(0.2, np.array([6e7, 5e7, 3e7, 2e5, 1e5]), damping, -3e-6),
    ]
    body = r.row_xml("A", rows[0], False) + r.row_xml("B", rows[1], True)
    bearing = (
        '<bearing joint="shaft" radial_stiffness="1e8" axial_stiffness="1e8" '
        f'tilt_stiffness="1e6">{body}</bearing>'
    )
    text = r.shaft_model(bearing, (3.0, -9.81, -2.0), com_z=0.1)
    res = r.run(text, duration=DURATION, start="none")
    q, _ = r.slides(res, "shaft", r.ROW_SLIDES)
    qm, vm = r.mid(q), r.weighted_speed(q)
    springs = np.zeros((len(q), 3))
    for name, row in zip(("A", "B"), rows, strict=True):
        force, moment = r.row_loads(qm, vm, row)
        assert r.rel(force, res.row(f"shaft.{name}").force[:-1]) < 1e-12
        assert r.rel(moment, res.row(f"shaft.{name}").moment[:-1]) < 1e-12
        springs += r.row_springs(q, row)
    assert r.rel(springs, res.bearing("shaft").elastic_force) < 1e-12
    assert np.any(r.row_sides(qm, rows[0]) == 0)  # A inside its dead band
    assert np.any(r.row_sides(qm, rows[0]) == 1)  # and against a side
    assert np.any(r.row_sides(qm, rows[1]) == 2)  # B pressed on both sides


def test_a_ball_bearing_at_zero_clearance_takes_stribecks_q_max():
    r = recoding
    z, kn, n = 16, 2.2e10, 1.5
    bearing = (
        f'<bearing joint="shaft" law="roller_sum" rollers="{z}" contact_stiffness="{kn:g}" '
        'contact="point" radial_damping="2e4"/>'
    )
    res = r.run(r.shaft_model(bearing, (0.0, -9.81, 0.0)), duration=20 * r.DT, start="static")
    deflection = -res.bearing("shaft").displacement[-1, 1]  # along −w, onto element 12
    radial = np.linalg.norm(res.bearing("shaft").elastic_force[-1])
    np.testing.assert_allclose(radial, r.MASS * 9.81, rtol=1e-12)
    cosines = np.maximum(np.cos(2 * np.pi * np.arange(z) / z), 0.0)
    ratio = kn * deflection**n * z / radial  # Q_max Z / F_r
    np.testing.assert_allclose(ratio, z / np.sum(cosines ** (n + 1)), rtol=1e-12)
    # Z → ∞: Stribeck's 4.37 (NSK E728g §5 eq. 4), to its three digits
    assert abs(r.stribeck_limit(n) - 4.37) < 0.005
    assert abs(ratio - 4.37) < 0.01 * 4.37 and math.isfinite(ratio)
