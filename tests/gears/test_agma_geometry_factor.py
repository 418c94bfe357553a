"""AGMA 908-B89 bending geometry factor J: the generated fillet, the Lewis section and J itself."""

import math

import numpy as np
import pytest

from pinwind.errors import InputError
from pinwind.gears.agma_geometry_factor import agma_geometry_factors, fillet, lewis_section
from pinwind.gears.gear_pair import GearPair, MeshLoad
from pinwind.gears.rating_agma import AgmaFactors, resolve_factors

ALPHA = math.radians(20.0)
INCH = 0.0254


def _inv(a):
    return math.tan(a) - a


@pytest.mark.parametrize(("teeth", "shift", "tip"), [(40, 0.0, 0.38), (25, 0.3, 0.25)])
def test_generated_fillet_meets_the_involute_and_the_root_circle(teeth, shift, tip):
    roll = np.linspace(-1.5, 1.5, 200_001)
    xi, eta = fillet(teeth, shift, pressure_angle=ALPHA, tool_addendum=1.25,
                     tool_tip_radius=tip, roll=roll)  # fmt: skip
    ok = np.isfinite(xi)
    radius = np.hypot(xi[ok], eta[ok])
    # Root circle: r − (h_a0 − x), module 1.
    assert radius.min() == pytest.approx(teeth / 2 - (1.25 - shift), abs=1e-6)
    # Where the round hands over to the tool's straight flank the generated point lies on the
    # involute: half thickness R sin(s/(2r) + inv α − inv α_R), s = π/2 + 2 x tan α.
    k = int(np.argmax(radius))
    r_j = radius[k]
    alpha_r = math.acos(teeth / 2 * math.cos(ALPHA) / r_j)
    half = r_j * math.sin((math.pi / 2 + 2 * shift * math.tan(ALPHA)) / teeth + _inv(ALPHA)
                          - _inv(alpha_r))  # fmt: skip
    assert xi[ok][k] == pytest.approx(half, abs=1e-6)


def test_fillet_curvature_at_the_root_is_agma_908s_minimum_fillet_radius():
    roll = np.linspace(-1.5, 1.5, 300_001)
    xi, eta = fillet(40, 0.0, pressure_angle=ALPHA, tool_addendum=1.25, tool_tip_radius=0.38,
                     roll=roll)  # fmt: skip
    ok = np.isfinite(xi)
    x, y = xi[ok], eta[ok]
    dx, dy = np.gradient(x), np.gradient(y)
    ddx, ddy = np.gradient(dx), np.gradient(dy)
    radius = (dx * dx + dy * dy) ** 1.5 / np.abs(dx * ddy - dy * ddx)
    b = 1.25 - 0.38  # the round's centre below the rolling line
    assert radius[5:-5].min() == pytest.approx(0.38 + b**2 / (20 + b), rel=1e-5)


def test_lewis_parabola_touches_the_fillet_where_its_slope_is_the_fillets():
    # Tangency: the parabola ξ² = k (r_L − η) through the section point has slope
    # dη/dξ = −2 h/ξ there; the fillet's own slope at that point must be the same.
    r_l = 20.5
    h, s = lewis_section(40, 0.0, pressure_angle=ALPHA, load_radius=r_l, tool_addendum=1.25,
                         tool_tip_radius=0.38)  # fmt: skip
    roll = np.linspace(-1.5, 1.5, 300_001)
    xi, eta = fillet(40, 0.0, pressure_angle=ALPHA, tool_addendum=1.25, tool_tip_radius=0.38,
                     roll=roll)  # fmt: skip
    ok = np.isfinite(xi)
    k = int(np.argmin(np.abs(xi[ok] - s / 2) + np.abs(eta[ok] - (r_l - h))))
    slope = (eta[ok][k + 1] - eta[ok][k - 1]) / (xi[ok][k + 1] - xi[ok][k - 1])
    assert slope == pytest.approx(-2 * h / (s / 2), rel=1e-3)


def test_shigley_example_14_4_geometry_factors_from_fig_14_6():
    # Budynas & Nisbett, Shigley's MED 10th ed., Example 14-4: 17/52 teeth, P = 10 /in, 20°
    # full depth; J_P = 0.30 and J_G = 0.40 read from Fig. 14-6 (AGMA 218.01, "consistent with
    # AGMA 908-B89"), load at the highest point of single tooth contact. Tool: addendum
    # 1.25/P, tip radius 0.25/P (assumed; the chart's rack is not restated in the example).
    pair = GearPair(17, 52, module=INCH / 10, pressure_angle=ALPHA, face_width=1.5 * INCH,
                    root_radius_coefficient=0.25)  # fmt: skip
    j_p, j_g = agma_geometry_factors(pair)
    # The 52-tooth gear to the chart's reading (±0.005 reading error, 2 %).
    assert j_g == pytest.approx(0.40, rel=0.02)
    # The 17-tooth pinion is undercut by this tool (it needs 2 (1.25 − 0.25 (1 − sin 20°)) /
    # sin² 20° = 18.6 teeth); our fillet is the tip round's alone, so the tooth comes out
    # thicker at the root and J_P high: within 10 % of the chart.
    assert 2 * (1.25 - 0.25 * (1 - math.sin(ALPHA))) / math.sin(ALPHA) ** 2 > 17
    assert j_p == pytest.approx(0.30, rel=0.10)
    assert j_p > 0.30


def test_rating_uses_agma_908_for_external_pairs_and_iso_form_factors_for_internal_ones():
    load = MeshLoad(1e5, 1.0)
    external = GearPair(21, 35, module=0.005, pressure_angle=ALPHA, face_width=0.05)
    assert resolve_factors(external, load, AgmaFactors()).J == agma_geometry_factors(external)
    internal = GearPair(21, 63, module=0.005, pressure_angle=ALPHA, face_width=0.05,
                        internal_2=True)  # fmt: skip
    iso = resolve_factors(internal, load, AgmaFactors(geometry_factor="iso")).J
    assert resolve_factors(internal, load, AgmaFactors()).J == iso
    with pytest.raises(InputError, match="internal gear"):
        agma_geometry_factors(internal)
    with pytest.raises(InputError, match='"agma908" or "iso"'):
        resolve_factors(external, load, AgmaFactors(geometry_factor="lewis"))


def test_a_barely_helical_pair_has_the_spur_pairs_geometry_factors():
    spur = GearPair(21, 35, module=0.005, pressure_angle=ALPHA, face_width=0.05)
    helical = GearPair(21, 35, module=0.005, pressure_angle=ALPHA, face_width=0.05,
                       helix_angle=1e-4)  # fmt: skip
    # m_F = b sin β / (π m_n) = 3e-4: C_ψ = √(1 − m_F (1 − …)) differs from 1 by about m_F/2.
    np.testing.assert_allclose(agma_geometry_factors(helical), agma_geometry_factors(spur),
                               rtol=5e-4)  # fmt: skip
    # A conventional helical pair (face contact ratio m_F > 1) takes the tip-load branch.
    wide = GearPair(21, 35, module=0.005, pressure_angle=ALPHA, face_width=0.1,
                    helix_angle=math.radians(15))  # fmt: skip
    assert 0.1 * math.sin(math.radians(15)) / (math.pi * 0.005) > 1
    assert all(0.2 < j < 0.8 for j in agma_geometry_factors(wide))
