"""A disc on a rolling bearing (law="roller_sum"): its sag, swing, modes and bad input.

The expectations come from Harris's sum written out here (``carried``) and scipy's brentq,
independent of ``model/roller_sum.py`` and ``cpp/bearing_spring.hpp``.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.optimize import brentq

import pinwind
from pinwind.errors import InvalidBearingCompliance, MalformedModel, PinwindWarning
from pinwind.model.gearbox import loads
from pinwind.modes.linearisation import linearise
from tests.dynamics.test_compliant_bearing import MASS, G, disc_urdf
from tests.test_cli import run

ROLLERS, KN, LINE = 8, 1e7, 10.0 / 9.0  # 8 rollers, K_n [N/m^(10/9)], line contact


def roller_bearing(clearance_mm=0.0, extra=""):
    return (
        f'law="roller_sum" rollers="{ROLLERS}" contact_stiffness="{KN!r}" '
        f'radial_clearance_mm="{clearance_mm!r}" {extra}'
    )


def carried(delta, clearance=0.0, rollers=ROLLERS, load=1.5 * math.pi):
    """The load the rollers carry when the disc sits δ [m] off along the load (Harris's sum).

    Rollers at ψ_j = 2πj/Z from the bearing's x axis, the load (the weight) at ``load`` from it
    (270°: straight down); each presses with K_n (δ cos φ − c)ⁿ, φ its angle from the load.
    """
    total = 0.0
    for j in range(rollers):
        phi = 2 * math.pi * j / rollers - load
        compression = delta * math.cos(phi) - clearance
        if compression > 0.0:
            total += KN * compression**LINE * math.cos(phi)
    return total


def sag(mass=MASS, clearance=0.0, **where):
    """δ with m g = F_r(δ) [m]."""
    return brentq(lambda d: carried(d, clearance, **where) - mass * G, clearance, 1.0, xtol=1e-18)


def vertical_stiffness(delta, clearance=0.0, **where):
    """dF_r/dδ at δ [N/m], central difference of the sum."""
    h = 1e-6 * delta
    return (carried(delta + h, clearance, **where) - carried(delta - h, clearance, **where)) / (
        2 * h
    )


def _run(gb, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        return pinwind.simulate(gb, **kwargs)


def test_the_static_start_puts_the_disc_at_the_sag_where_m_g_equals_the_roller_sum():
    res = _run(loads(disc_urdf(roller_bearing())), duration=0.002, dt=1e-4)
    bearing = res.bearing("disc")
    np.testing.assert_allclose(bearing.displacement[0, 1], -sag(), rtol=1e-7)
    np.testing.assert_allclose(bearing.displacement[0, 0], 0.0, atol=1e-12 * sag())
    np.testing.assert_allclose(bearing.elastic_force[0, 1], MASS * G, rtol=1e-7)
    np.testing.assert_allclose(bearing.force_local[0, 1], MASS * G, rtol=1e-7)


def test_doubling_the_weight_lowers_the_disc_by_two_to_the_one_over_n():
    single = _run(loads(disc_urdf(roller_bearing())), duration=0.001, dt=1e-4)
    text = disc_urdf(roller_bearing()).replace(
        f'mass value="{MASS!r}"', f'mass value="{2 * MASS!r}"'
    )
    double = _run(loads(text), duration=0.001, dt=1e-4)
    ratio = double.bearing("disc").displacement[0, 1] / single.bearing("disc").displacement[0, 1]
    np.testing.assert_allclose(ratio, 2 ** (1 / LINE), rtol=1e-7)


def test_a_damped_disc_released_at_the_centre_settles_at_the_same_sag():
    gb = loads(disc_urdf(roller_bearing(extra='radial_damping="3000"')))
    res = _run(gb, duration=0.15, dt=2e-5, initial_deflection="none")
    np.testing.assert_allclose(res.bearing("disc").displacement[-1, 1], -sag(), rtol=1e-6)


def test_inside_its_clearance_the_disc_falls_freely_then_rests_at_the_clearance_sag():
    clearance = 30e-6
    gb = loads(disc_urdf(roller_bearing(clearance * 1e3, 'radial_damping="3000"')))
    res = _run(gb, duration=0.15, dt=1e-5, initial_deflection="none")
    bearing = res.bearing("disc")
    inside = -bearing.displacement[:, 1] < clearance
    assert inside.sum() > 100
    np.testing.assert_allclose(bearing.elastic_force[inside], 0.0, atol=0.0)
    t = res.time[inside]
    np.testing.assert_allclose(bearing.displacement[inside, 1], -0.5 * G * t**2, atol=1e-10)
    np.testing.assert_allclose(bearing.displacement[-1, 1], -sag(clearance=clearance), rtol=1e-6)


def test_the_disc_swings_about_its_sag_at_the_tangent_stiffness_frequency():
    # A small downward force added after the static start: a linear swing about the new sag at
    # √(K/m), K = dF_r/dδ there.
    gb = loads(disc_urdf(roller_bearing()))
    push = 1e-4 * MASS * G  # [N]
    centre = sag(mass=MASS + push / G)
    omega = math.sqrt(vertical_stiffness(centre) / MASS)
    res = _run(
        gb,
        duration=0.1,
        dt=1e-5,
        torques={"disc_radial_y": lambda t: 0.0 if t < 5e-6 else -push},
    )
    y = res.bearing("disc").displacement[:, 1] + centre
    up = np.flatnonzero((y[:-1] < 0.0) & (y[1:] >= 0.0))
    assert len(up) > 10
    times = res.time[up] - y[up] * (res.time[up + 1] - res.time[up]) / (y[up + 1] - y[up])
    np.testing.assert_allclose(np.mean(np.diff(times)), 2 * math.pi / omega, rtol=2e-4)


def test_an_undamped_disc_on_rollers_keeps_its_energy_and_stores_the_rollers_integral():
    res = _run(
        loads(disc_urdf(roller_bearing())), duration=0.05, dt=1e-5, initial_deflection="none"
    )
    energy = {k: np.asarray(v)[-1] for k, v in res.energy.items()}
    # Each roller stores ∫ K_n δⁿ dδ = K_n δⁿ⁺¹/(n + 1) at the last sample's displacement.
    x, y = res.bearing("disc").displacement[-1, :2]
    stored = 0.0
    for j in range(ROLLERS):
        psi = 2 * math.pi * j / ROLLERS
        compression = x * math.cos(psi) + y * math.sin(psi)
        if compression > 0.0:
            stored += KN * compression ** (LINE + 1) / (LINE + 1)
    np.testing.assert_allclose(energy["potential_spring"], stored, rtol=1e-9)
    # Released from the centre, what gravity did is in the motion and the rollers.
    np.testing.assert_allclose(
        energy["kinetic"] + energy["potential_spring"], energy["work_gravity"], rtol=1e-5
    )


def test_the_modes_linearise_the_rollers_about_the_sag():
    # Ten rollers, the weight along −x: no roller at 90° from the load, where one that touches
    # by rounding alone would add stiffness across it (line contact: K ∝ δ^(1/9)).
    rollers = 10
    text = disc_urdf(roller_bearing().replace(f'rollers="{ROLLERS}"', f'rollers="{rollers}"'))
    text = text.replace(f'gravity="0 {-G!r} 0"', f'gravity="{-G!r} 0 0"')
    modes = [m for m in linearise(loads(text)).modes() if not m.rigid]
    where = {"rollers": rollers, "load": math.pi}
    delta = sag(**where)
    # Across the load: the rollers at φ pressed by δ cos φ, each n K_n (δ cos φ)^(n−1) sin² φ.
    across = sum(
        LINE * KN * (delta * math.cos(phi)) ** (LINE - 1) * math.sin(phi) ** 2
        for phi in (2 * math.pi * j / rollers - math.pi for j in range(rollers))
        if math.cos(phi) > 0.0
    )
    expected = sorted(
        math.sqrt(k / MASS) / (2 * math.pi) for k in (vertical_stiffness(delta, **where), across)
    )
    np.testing.assert_allclose(sorted(m.frequency for m in modes), expected, rtol=1e-6)


@pytest.mark.parametrize(
    ("attributes", "attribute"),
    [
        ('law="roller_sum" rollers="0" contact_stiffness="1e9"', "rollers"),
        ('law="roller_sum" rollers="12" contact_stiffness="0"', "contact_stiffness"),
        ('law="roller_sum" rollers="12" contact_stiffness="-1e9"', "contact_stiffness"),
        ('law="roller_sum" rollers="12" contact_stiffness="nan"', "contact_stiffness"),
        ('law="roller_sum" rollers="12"', "contact_stiffness"),
        (
            'law="roller_sum" rollers="12" contact_stiffness="1e9" radial_stiffness="1e8"',
            "radial_stiffness",
        ),
    ],
)
def test_a_roller_sum_without_rollers_or_contact_stiffness_is_refused_with_its_value(
    attributes, attribute
):
    with pytest.raises(InvalidBearingCompliance, match=attribute) as err:
        loads(disc_urdf(attributes))
    assert err.value.attribute == attribute


@pytest.mark.parametrize(
    ("attributes", "message"),
    [
        ('law="gargiulo" rollers="12" contact_stiffness="1e9"', "linear, roller_sum"),
        ('law="roller_sum" rollers="2.5" contact_stiffness="1e9"', "whole number"),
        ('law="roller_sum" rollers="12" contact_stiffness="1e9" contact="flat"', "line, point"),
    ],
)
def test_an_unknown_law_or_contact_or_a_fractional_roller_count_is_malformed(attributes, message):
    with pytest.raises(MalformedModel, match=message):
        loads(disc_urdf(attributes))


@pytest.mark.parametrize(
    ("bearing", "message"),
    [
        ('law="roller_sum" rollers="0" contact_stiffness="1e9"', "rollers is 0"),
        ('law="roller_sum" rollers="12" contact_stiffness="nan"', "contact_stiffness is nan"),
        ('law="harris" rollers="12" contact_stiffness="1e9"', 'law="harris"'),
    ],
)
def test_a_bad_roller_sum_exits_2_in_one_line(tmp_path, bearing, message):
    model = tmp_path / "disc.urdf"
    model.write_text(disc_urdf(bearing))
    out = run("modes", str(model), cwd=tmp_path)
    assert out.returncode == 2, out.stderr
    assert message in out.stderr
    assert out.stderr.count("\n") == 1, out.stderr
