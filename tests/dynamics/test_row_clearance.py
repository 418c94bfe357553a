"""Bearing rows with a radial clearance or a preload in the step (cpp/bearing_rows.hpp).

A row with ``radial_clearance_mm`` c holds each radial direction between two sides, each a
one-sided linear contact of the row's K: L = −K [max(δ − c, 0) − max(−δ − c, 0)]. The
expectations are hand statics of a rigid shaft (axis z, u = world x) on two rows at a_A, a_B with
tilt springs K_γ, loaded by F along u at p on the axis, in the u plane (x, θ_w):

    F + L_A + L_B = 0,     p F + a_A L_A + a_B L_B − Σ K_γ θ_w = 0,     δ_i = x + a_i θ_w

solved here piece by piece (which sides touch) with numpy and ``scipy.optimize.brentq``, never
from the code's output.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.optimize import brentq

import pinwind
from pinwind.errors import InvalidBearingLifeData, PinwindWarning
from pinwind.loads.hub_loads import HubLoad, constant_hub_load
from pinwind.loads.signals import Constant, Sine
from pinwind.model.gearbox import loads

#: Rows A and B [m along the axis], their radial stiffness K [N/m] and tilt stiffness [N·m/rad].
A, B = -0.3, 0.1
K_A, K_B = 1.0e9, 2.0e9
TILT = 1.0e7
#: Where the force acts on the axis [m].
P = 0.3
RPM = 2 * math.pi / 60


def shaft(
    clearance_a_mm: float | None,
    clearance_b_mm: float | None,
    tilt: float = TILT,
    damping: float = 0.0,
) -> str:
    """A shaft on rows A and B (u = world x), each with its clearance (None: none given).

    ``damping``: each row's radial dampers c_u = c_w [N·s/m].
    """

    def row(name: str, at: float, k: float, c_mm: float | None) -> str:
        extra = ""
        if c_mm is not None:
            extra = f' radial_clearance_mm="{c_mm!r}"' + (' preload="true"' if c_mm < 0 else "")
        return (
            f'      <row name="{name}" type="cylindrical_roller" position_mm="{at * 1e3!r}" '
            f'stiffness="0 {k!r} {k!r} {tilt!r} {tilt!r}" damping="0 {damping!r} {damping!r} 0 0" '
            f'rating_c_kN="500"{extra}/>\n'
        )

    return f"""<robot name="shaft">
  <link name="ground"/>
  <link name="shaft"><inertial><mass value="100"/>
    <inertia ixx="10" iyy="10" izz="5" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="shaft" type="continuous"><parent link="ground"/><child link="shaft"/>
    <axis xyz="0 0 1"/></joint>
  <gearbox gravity="0 0 0">
    <bearing joint="shaft" radial_stiffness="1" tilt_stiffness="1">
{row("A", A, K_A, clearance_a_mm)}{row("B", B, K_B, clearance_b_mm)}    </bearing>
  </gearbox>
</robot>"""


def _load(force: float, p: float = P) -> HubLoad:
    """F along u at p on the axis (hub frame: x the axis, y = world x)."""
    return constant_hub_load("shaft", [0.0, force, 0.0, 0, 0, 0], point=(0, 0, p), up=(0, 1, 0))


def _run(text: str, load: HubLoad, **kw):
    gb = loads(text)
    kw.setdefault("duration", 0.01)
    kw.setdefault("dt", 1e-3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        return pinwind.simulate(gb, hub_loads=[load], **kw), gb


def sided(delta: float, k: float, c: float) -> float:
    """The rows' law by hand: −k [max(δ − c, 0) − max(−δ − c, 0)] [N]."""
    return -k * (max(delta - c, 0.0) - max(-delta - c, 0.0))


def statics(force: float, c_a: float, c_b: float, *, k_a=K_A, k_b=K_B, p: float = P):
    """(L_A, L_B, x, θ_w) of the module docstring's statics, by trying each set of sides.

    Each row is one of: open (no load), touching the + side, the − side, or both (a preload):
    L = −k_eff δ + f0 with (k_eff, f0) = (0, 0), (k, k c), (k, −k c), (2k, 0). The pieces are
    linear; the one whose solution has the sides it assumed is the answer (the law is the
    gradient of a convex energy, so exactly one fits).
    """
    pieces = {"open": (0.0, 0.0), "+": (1.0, 1.0), "-": (1.0, -1.0), "both": (2.0, 0.0)}
    found = []
    for sa, (ma, sign_a) in pieces.items():
        for sb, (mb, sign_b) in pieces.items():
            ka, fa = ma * k_a, sign_a * k_a * c_a if sa in "+-" else 0.0
            kb, fb = mb * k_b, sign_b * k_b * c_b if sb in "+-" else 0.0
            # F − ka δ_A + fa − kb δ_B + fb = 0; p F + A(−ka δ_A + fa) + B(…) − 2 TILT θ = 0
            m = np.array(
                [[ka + kb, ka * A + kb * B], [ka * A + kb * B, ka * A**2 + kb * B**2 + 2 * TILT]]
            )
            rhs = np.array([force + fa + fb, p * force + A * fa + B * fb])
            if abs(np.linalg.det(m)) < 1e-9 * (k_a + k_b) ** 2 * (A**2 + B**2):
                continue  # nothing holds the shaft in this piece
            x, theta = np.linalg.solve(m, rhs)
            d_a, d_b = x + A * theta, x + B * theta
            if _sides(d_a, c_a) == sa and _sides(d_b, c_b) == sb:
                found.append((sided(d_a, k_a, c_a), sided(d_b, k_b, c_b), x, theta))
    assert len(found) == 1, found
    return found[0]


def _sides(delta: float, c: float) -> str:
    plus, minus = delta - c > 0.0, -delta - c > 0.0
    return {(False, False): "open", (True, False): "+", (False, True): "-", (True, True): "both"}[
        (plus, minus)
    ]


def _row_loads(res) -> tuple[np.ndarray, np.ndarray]:
    return res.row("shaft.A").force[:, 0], res.row("shaft.B").force[:, 0]


def test_rows_with_one_clearance_and_no_tilt_springs_share_by_the_lever_rule():
    # Two rows without tilt springs: statically determinate, so the gap c on both rows moves the
    # shaft by c and leaves the shares at the lever rule (L_B (B − A) + F (p − A) = 0).
    c = 40e-6
    force = 5e3
    res, _ = _run(shaft(c * 1e3, c * 1e3, tilt=0.0), _load(force))
    l_b = -force * (P - A) / (B - A)
    l_a = -force - l_b
    load_a, load_b = _row_loads(res)
    # The shaft tilts by θ ≈ 2e-4 rad across the gaps, which turns the load's arm to p cos θ:
    # the moments agree to θ²/2 ≈ 2e-8 (the rows' δ are first order in the tilts).
    x = res.joint("shaft_radial_x").angle[-1]
    theta = res.joint("shaft_tilt_y").angle[-1]
    assert 1e-4 < abs(theta) < 1e-3
    assert_allclose(load_a + load_b, -force, rtol=1e-12)
    assert_allclose(load_a, l_a, rtol=1e-7)
    assert_allclose(load_b, l_b, rtol=1e-7)
    # Each row is pushed beyond its side by its load: δ_i = ±c − L_i / k_i.
    for at, load, k in ((A, l_a, K_A), (B, l_b, K_B)):
        delta = x + at * theta
        assert_allclose(delta, math.copysign(c, -load) - load / k, rtol=1e-6)


def test_a_load_that_does_not_close_a_row_s_gap_leaves_that_row_without_load():
    # Row A has the clearance, B none: B and the tilt springs carry F alone until A's deflection
    # reaches c. The force that closes A's gap from the statics with A open (brentq), then a
    # load at half of it (A: no load) and at three times it (A: the piecewise statics).
    c = 50e-6

    def deflection_a(force: float) -> float:
        # A open: K_B δ_B = F and B K_B δ_B + 2 TILT θ = p F (moments about the centre)
        theta = (P - B) * force / (2 * TILT)
        x = force / K_B - B * theta
        return abs(x + A * theta) - c

    closing = brentq(deflection_a, 1.0, 1e9, xtol=1e-9, rtol=1e-14)
    assert 1e3 < closing < 1e6  # a plain number of N: the geometry is as meant
    for scale in (0.5, 3.0):
        force = scale * closing
        res, _ = _run(shaft(c * 1e3, None), _load(force))
        l_a, l_b, x, theta = statics(force, c, 0.0)
        load_a, load_b = _row_loads(res)
        # to θ²/2 ~ 1e-8: the tilt turns the load's arm to p cos θ (the lever-rule test)
        assert_allclose(load_a, l_a, rtol=1e-7, atol=1e-9 * force)
        assert_allclose(load_b, l_b, rtol=1e-7)
        assert_allclose(res.joint("shaft_tilt_y").angle[-1], theta, rtol=1e-7)
        if scale < 1.0:
            assert np.all(load_a == 0.0)  # inside the dead band: exactly no load
        else:
            assert abs(l_a) > 0.1 * force  # closed: A takes a real share


def test_a_preload_keeps_both_rows_loaded_where_a_clearance_leaves_one_unloaded():
    # The same load on the same rows: with a 50 µm clearance on A it carries nothing; with a
    # 20 µm preload on both rows both sides press (2 K each), A carries its share of the
    # stiffer statics, and each row's loaded side carries K |c| + |L|/2.
    force = 1.2e4
    open_a, _, _, _ = statics(force, 50e-6, 0.0)
    assert open_a == 0.0
    pre = -20e-6
    res, gb = _run(shaft(pre * 1e3, pre * 1e3), _load(force))
    l_a, l_b, x, theta = statics(force, pre, pre)
    assert _sides(x + A * theta, pre) == "both" and _sides(x + B * theta, pre) == "both"
    load_a, load_b = _row_loads(res)
    assert_allclose(load_a, l_a, rtol=1e-9)
    assert_allclose(load_b, l_b, rtol=1e-9)
    assert abs(l_a) > 0.05 * force


def _turning(text: str, force: float):
    return _run(text, _load(force), duration=0.02, speeds={"shaft": 30.0 * RPM})


def _set_share(res, gb, row: str) -> float:
    """The row's share of the time below its minimum load in a fatigue set's sums."""
    from pinwind.life.life_sums import run_load_sums

    return next(s for s in run_load_sums(res, gb) if s.joint == row).below_minimum_share


def test_a_preload_removes_the_unloaded_row_s_skidding_risk():
    # The check. C = 500 kN: a roller row needs 0.02 C = 10 kN to roll (SKF). Under
    # 12 kN row A, in its 50 µm clearance, turns unloaded the whole run (share 1) while B
    # carries 12 kN (share 0); preloaded by 20 µm, A's loaded side carries at least
    # K_A |c| = 20 kN, so neither row skids.
    from pinwind.life.row_life import row_lives

    force = 1.2e4
    res, gb = _turning(shaft(50e-3, None), force)
    lives = {life.name: life for life in row_lives(res, gb)}
    assert_allclose(lives["A"].below_minimum, 1.0)
    assert_allclose(lives["B"].below_minimum, 0.0)
    assert math.isinf(lives["A"].l10)  # no load, no fatigue
    assert_allclose(lives["B"].l10, (5e5 / force) ** (10 / 3), rtol=1e-6)
    assert _set_share(res, gb, "shaft.A") == 1.0  # a fatigue set's sums alike
    res, gb = _turning(shaft(-20e-3, -20e-3), force)
    lives = {life.name: life for life in row_lives(res, gb)}
    assert lives["A"].below_minimum == 0.0 and lives["B"].below_minimum == 0.0
    assert _set_share(res, gb, "shaft.A") == 0.0
    l_a, l_b, _, _ = statics(force, -20e-6, -20e-6)
    assert_allclose(lives["A"].l10, (5e5 / abs(l_a)) ** (10 / 3), rtol=1e-6)


def test_rows_without_clearance_and_with_a_zero_one_run_bit_for_bit_alike():
    # radial_clearance_mm="0" keeps the linear law (no sides): the same floats, not close ones.
    load = HubLoad(
        "shaft",
        (Constant(0.0), Sine(0.0, 3e3, 9.0), Sine(500.0, 2e3, 13.0, 0.3), Constant(0.0),
         Sine(0.0, 200.0, 11.0), Constant(0.0)),  # fmt: skip
        "fixed", (0.0, 0.0, 0.4), (0.0, 1.0, 0.0),
    )  # fmt: skip
    plain, gb = _run(shaft(None, None), load, duration=0.05, dt=1e-4)
    zero, _ = _run(shaft(0.0, 0.0), load, duration=0.05, dt=1e-4)
    from pinwind.dynamics.bearing_springs import row_specs

    assert not any(s.has_clearance for s in row_specs(gb.compliant_bearings["shaft"]))
    np.testing.assert_array_equal(zero.row_force, plain.row_force)
    np.testing.assert_array_equal(zero.angle, plain.angle)


@pytest.mark.parametrize(("clearance_mm", "damping"), [(0.01, 0.0), (-0.002, 0.0), (0.01, 2e4)])
def test_the_energy_ledger_closes_through_the_sides_opening_and_closing(clearance_mm, damping):
    # Rows under a load that swings through zero: the shaft crosses the clearance (or lets a
    # preloaded side go) many times. Each step that opens or closes a side leaves an O(h²)
    # error (pinwind/testing/ledger.py); a tenth of the step leaves about a hundredth. The
    # dampers act while a side touches, and what they take is in the ledger.
    from pinwind.testing import ledger_closure

    load = HubLoad(
        "shaft",
        (Constant(0.0), Sine(0.0, 3e4, 9.0), Sine(0.0, 2e4, 13.0, 0.3), Constant(0.0),
         Constant(0.0), Constant(0.0)),  # fmt: skip
        "fixed", (0.0, 0.0, 0.4), (0.0, 1.0, 0.0),
    )  # fmt: skip
    text = shaft(clearance_mm, clearance_mm, damping=damping)
    coarse, _ = _run(text, load, duration=0.2, dt=1e-4)
    assert (coarse.energy["dissipated"][-1] > 0.0) == (damping > 0.0)
    fine, _ = _run(text, load, duration=0.2, dt=1e-5)
    # Row A in and out of its sides' reach: a clearance leaves it without load, a preload
    # lets one side go where |L| > 2 K |c|.
    load_a = np.abs(coarse.row("shaft.A").force[:, 0])
    beyond = load_a > 2 * K_A * abs(clearance_mm) * 1e-3 if clearance_mm < 0 else load_a > 0.0
    assert 0.05 < np.count_nonzero(beyond) / len(coarse) < 0.95
    error_coarse = ledger_closure(coarse, rtol=1e-2).measured
    error_fine = ledger_closure(fine, rtol=1e-2).measured
    assert error_fine < 0.03 * error_coarse


def test_a_row_with_sides_has_the_tangent_of_its_law():
    # Seeded states spread ±10 µm about the centre with a 5 µm clearance (then a 5 µm preload):
    # the rows on either side, in the gap, or both sides pressing; the step's tangent against
    # central differences of its force, and the force against −∇U.
    from pinwind.testing import conservative_forces, element_tangents

    for c_mm in (0.005, -0.005):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PinwindWarning)
            gb = loads(shaft(c_mm, c_mm))
        element_tangents(gb, states=10, seed=21, rtol=1e-6, spread_m=10e-6)
        conservative_forces(gb, states=10, seed=21, rtol=1e-6, spread_m=10e-6)


def test_a_negative_row_clearance_without_preload_is_refused_naming_the_row():
    text = shaft(-0.02, None).replace(' preload="true"', "")
    with pytest.raises(InvalidBearingLifeData, match=r'<row name="A">.*preload="true"'):
        loads(text)


@pytest.mark.parametrize(("clearance_mm", "sides"), [(0.05, 1.0), (-0.02, 2.0)])
def test_the_modes_take_a_row_with_clearance_as_loaded_and_a_preloaded_one_at_its_centre(
    clearance_mm, sides
):
    # The linear model's radial spring of each row: K (one side: loaded) with a clearance, 2K
    # (both sides press) with a preload; and the step's own tangent at the centre of a
    # preloaded shaft is the same, Σ 2K on the radial slide (no tilt: θ = 0 there).
    from pinwind.dynamics.linear_model import bearing_elements
    from pinwind.testing.tangents import element_stepper

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        gb = loads(shaft(clearance_mm, clearance_mm))
    springs = {e.name: e.stiffness for e in bearing_elements(gb)}
    for row, k in (("A", K_A), ("B", K_B)):
        assert springs[f"shaft.{row}_radial_u"] == sides * k
        assert springs[f"shaft.{row}_radial_w"] == sides * k
        assert springs[f"shaft.{row}_tilt_u"] == TILT
    if clearance_mm < 0:
        q = gb.neutral()
        at = element_stepper(gb).element_forces(q, np.zeros(gb.model.nv))
        x = gb.v_index("shaft_radial_x")
        assert_allclose(at.stiffness[x, x], 2 * (K_A + K_B), rtol=1e-12)
        assert_allclose(at.force[x], 0.0, atol=1e-6)  # the sides' preloads cancel


@pytest.mark.parametrize("force", [0.0, 5e3, 3.9e4, 4.1e4, 1e5])
def test_the_loaded_side_of_a_preloaded_row_carries_the_preload_and_half_the_load(force):
    # model/bearing_rows.rolling_load against the sides' law solved for δ by brentq: the net
    # load F = −L(δ), each side's own force k max(s δ − c, 0), the larger of the two.
    from pinwind.model.bearing_rows import rolling_load

    k, c = 1e9, -20e-6  # both sides press while |F| < 2 k |c| = 40 kN
    delta = brentq(lambda d: sided(d, k, c) + force, -1.0, 1.0, xtol=1e-16, rtol=1e-15)
    side = max(k * max(delta - c, 0.0), k * max(-delta - c, 0.0))
    assert_allclose(rolling_load(np.array([force, -force]), k, c), [side, side], rtol=1e-9)
    assert_allclose(rolling_load(np.array([force]), k, 50e-6), [force], rtol=0)  # a clearance
