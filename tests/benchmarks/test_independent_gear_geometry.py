"""The gear geometry of every shipped model's meshes is that of the closed forms, recoded.

``benchmarks/independent_gear_geometry.py`` recodes each mesh of every ``models/*.urdf`` from the
file alone (docs/validation.md, "Independent recoding of the gear geometry"): ISO 21771's
working pressure angle and centre distance with signed tooth numbers, base and tip radii (tip
alteration included), the path of contact, ε_α, ε_β, β_b, the bearings' centre distance a′ and
pressure angle α′, the planets' places on their carriers, and the tooth phases (docs/
model_format.md, "Tooth phases") with Parker & Lin's (2004) mesh phases. Here every number is
held against what pinwind reports (its meshes, paths, ``tooth_phases``, ``pinwind info``).
"""

from __future__ import annotations

import math

import pytest

from tests.benchmarks import benchmark_module

recoding = benchmark_module("independent_gear_geometry.py", "independent_gear_geometry")

PHASES = ("tooth phase", "interlock residual", "mesh phase")


@pytest.fixture(scope="module")
def rows():
    return recoding.compare(cli=False)


def test_every_shipped_model_and_mesh_is_recoded(rows):
    models = {r.model for r in rows}
    assert models == {p.stem for p in recoding.MODELS}
    assert len(models) == 6
    meshes = {(r.model, r.item) for r in rows if r.quantity == "eps_alpha"}
    # 1 (Cai) + 7 (CART) + 6 (DTU) + 13 (NREL) + 8 (Saleh drivetrain) + 6 (Saleh planetary)
    assert len(meshes) == 41


def test_the_closed_forms_agree_to_rounding(rows):
    closed = [r for r in rows if r.item != "layout" and not any(k in r.quantity for k in PHASES)]
    assert len(closed) > 41 * 20
    worst = max(closed, key=lambda r: r.diff)
    assert worst.diff < 1e-12, worst


def test_the_planets_and_pinions_sit_where_the_sources_put_them(rows):
    layout = [r for r in rows if r.item == "layout"]
    # 3 planets × 2 coordinates in each of 6 planetary stages, plus the parallel pinions
    assert len(layout) >= 36
    for r in layout:  # the file writes 12 significant digits
        assert abs(r.pinwind - r.recoded) < 1e-12, r


def test_tooth_phases_interlock_on_the_working_pitch_circles_at_the_bearings(rows):
    phases = [r for r in rows if r.quantity.startswith("|tooth phase diff| at bearings")]
    assert len(phases) == sum(1 for r in rows if r.quantity == "|tooth phase diff| at iso [rad]")
    for r in phases:
        assert r.pinwind < 1e-12, r
    # At ISO 21771's a_w instead, the first gear of each NREL train differs by its half tooth
    # angle's change tan² α_w Δα_w, Δα_w = (a′ − a_w)/(a_w tan α_w): a few µrad.
    iso = max(
        (r for r in rows if r.quantity == "|tooth phase diff| at iso [rad]"),
        key=lambda r: r.pinwind,
    )
    assert iso.model == "nrel5mw_gearbox" and 1e-7 < iso.pinwind < 1e-5


def test_planet_meshes_are_phased_as_parker_and_lin_give(rows):
    lead = [r for r in rows if "mesh phase vs planet 1" in r.quantity]
    # two planets after the first, sun and ring mesh, in 5 planetary stages (NREL has two)
    assert len(lead) == 2 * 2 * 6
    for r in lead:
        assert r.diff < 1e-10, r
    loops = [r for r in rows if "interlock residual" in r.quantity]
    assert loops and all(r.pinwind < 1e-10 for r in loops)


def test_the_dtu_sun_s_first_tooth_by_hand():
    # Jørgensen 2014's DTU sun, z 20, x 0.582, m 10 mm, α 20°: its tooth 0's leading flank on
    # the x axis at the working pitch circle, so its centre line at −ψ(r_w) with
    # ψ = (π/2 + 2 x tan α)/z + inv α − inv α_w (ISO 21771), α_w from inv α_w = inv α +
    # 2 tan α (x_s + x_p)/(z_s + z_p), x_p 0.419, z_p 35.
    inv = lambda a: math.tan(a) - a  # noqa: E731
    alpha = math.radians(20)
    target = inv(alpha) + 2 * math.tan(alpha) * (0.582 + 0.419) / 55
    lo, hi = alpha, math.radians(40)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if inv(mid) < target else (lo, mid)
    psi = (math.pi / 2 + 2 * 0.582 * math.tan(alpha)) / 20 + inv(alpha) - inv(lo)
    import pinwind

    gb = pinwind.load(str(recoding.ROOT / "models" / "dtu500_planetary.urdf"))
    assert gb.tooth_phases["sun"] == pytest.approx(-psi, abs=1e-11)


def test_pinwind_info_prints_the_bearings_centre_distance_and_pressure_angle():
    path = recoding.ROOT / "models" / "dtu500_planetary.urdf"
    printed = recoding.info_alpha_w(path)
    model = recoding.read_model(path)
    assert set(printed) == {m[0] for m in model.meshes}
    for name, n1, n2 in model.meshes:
        rec = recoding.recode_mesh(model, model.gears[n1], model.gears[n2])
        mm, deg = printed[name]
        assert mm == pytest.approx(rec["a' bearings [m]"] * 1e3, abs=0.6e-4)
        assert deg == pytest.approx(math.degrees(rec["alpha' at a' [rad]"]), abs=0.6e-4)
