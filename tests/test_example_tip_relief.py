"""examples/dtu500_tip_relief.py: its relief sizing by hand, and a short run of both variants.

The sun–planet mesh of the DTU 500 kW stage (module 10 mm, 20°, sun 20 teeth x = 0.582, planet
35 teeth x = 0.419; ISO 21771): working pressure angle from inv α_w = inv α + 2 tan α
(x1 + x2)/(z1 + z2), centre distance a_w = m (z1 + z2)/2 · cos α / cos α_w, tip radii
r_a = m (z/2 + 1 + x) (the model gives no tip alteration), base radii r_b = m z/2 cos α; the path
g_α = √(r_a1² − r_b1²) + √(r_a2² − r_b2²) − a_w sin α_w and the base pitch p_bt = π m cos α.
"""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

from numpy.testing import assert_allclose
from scipy.optimize import brentq

from pinwind.gears.flank_modification import FlankModification
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.transmission_error import static_transmission_error
from pinwind.model.gearbox import loads

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "dtu500_tip_relief.py"
M, ALPHA = 0.010, math.radians(20.0)
Z1, Z2, X1, X2 = 20, 35, 0.582, 0.419


def _example():
    spec = importlib.util.spec_from_file_location("dtu500_tip_relief", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _inv(a: float) -> float:
    return math.tan(a) - a


def _hand_path() -> tuple[float, float]:
    """(g_α, p_bt) of the sun–planet mesh by ISO 21771 (module docstring) [m]."""
    target = _inv(ALPHA) + 2 * math.tan(ALPHA) * (X1 + X2) / (Z1 + Z2)
    alpha_w = brentq(lambda a: _inv(a) - target, 0.1, 0.8)
    a_w = M * (Z1 + Z2) / 2 * math.cos(ALPHA) / math.cos(alpha_w)
    ra1, ra2 = M * (Z1 / 2 + 1 + X1), M * (Z2 / 2 + 1 + X2)
    rb1, rb2 = M * Z1 / 2 * math.cos(ALPHA), M * Z2 / 2 * math.cos(ALPHA)
    g = math.sqrt(ra1**2 - rb1**2) + math.sqrt(ra2**2 - rb2**2) - a_w * math.sin(alpha_w)
    return g, math.pi * M * math.cos(ALPHA)


def test_the_relief_is_sized_by_hand_from_the_design_load_and_the_double_contact_zone():
    ex = _example()
    model = loads(ex.MODEL.read_text(), str(ex.MODEL))
    mesh = next(m for m in model.meshes if m.name == "sun_planet1")
    g, p = _hand_path()
    assert_allclose(ex.long_relief_length(mesh.path), g - p, rtol=1e-9)
    # Rated 500 kW at 27.1 rpm on the carrier; the sun carries 1/(1 + 91/20) of it, shared by 3.
    carrier = 500e3 / (27.1 * 2 * math.pi / 60)
    r_b1 = M * Z1 / 2 * math.cos(ALPHA)
    force = carrier / (1 + 91 / 20) / (3 * r_b1)
    assert_allclose(ex.design_force(ex.RATED_TORQUE, r_b1), force, rtol=1e-12)
    assert_allclose(ex.flat_te_relief(force, 3.5e9), 6 * force / (7 * 3.5e9), rtol=1e-12)


def test_the_sized_relief_flattens_the_static_transmission_error_at_the_design_load():
    """Unrelieved, the static TE steps between F/(c′b) in single and F/(1.75 c′b) in double
    contact; with the relief of 6F/(7 c′b) on both gears over g_α − p_bt it is flat."""
    ex = _example()
    model = loads(ex.MODEL.read_text(), str(ex.MODEL))
    mesh = next(m for m in model.meshes if m.name == "sun_planet1")
    pair = GearPair.from_mesh(mesh)
    k = 3.5e9
    force = ex.design_force(ex.RATED_TORQUE, pair.geometry.base_radius_1)
    bare = static_transmission_error(pair, force, single_pair=k)
    assert_allclose(bare.peak_to_peak, force / k - force / (1.75 * k), rtol=1e-9)
    relief = FlankModification(
        tip_relief=ex.flat_te_relief(force, k), tip_relief_length=ex.long_relief_length(mesh.path)
    )
    flat = static_transmission_error(pair, force, gear_1=relief, gear_2=relief, single_pair=k)
    assert flat.peak_to_peak < 1e-9 * bare.peak_to_peak


def test_the_relieved_model_carries_the_relief_on_the_sun_and_planets_only():
    ex = _example()
    text = ex.relieved_model(ex.MODEL.read_text(), ex.RELIEVED, 27.5e-6, 13.9e-3)
    model = loads(text, "relieved.urdf")
    for name, gear in model.gears.items():
        mod = gear.spec.modification
        expected = (27.5e-6, 13.9e-3) if name in ex.RELIEVED else (0.0, 0.0)
        assert_allclose((mod.tip_relief, mod.tip_relief_length), expected, rtol=1e-12, atol=0)


def test_the_example_runs_both_variants_and_reports_the_transition_peak():
    found = _example().main(["--duration", "0.3"])
    for name in ("involute", "tip relief"):
        assert found[name]["sun"] > 0 and found[name]["planet1"] > 0
        stress, where = found[name]["transition"]
        assert 0.0 <= where <= 3e-3 and stress > 0
