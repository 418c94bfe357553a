"""The multi-stage builder (``builders/stages.py``), its stage file and ``pinwind build stages``.

Checked on the NREL 5 MW gearbox's stage file (Nejad et al. 2016 Table V): stages mesh at their
working centre distance by the involute function, not by z_ring = z_sun + 2 z_planet; the tip
alteration gives the paper's tip diameters; every rolling bearing keeps its own data beside the
shaft's equivalent; a stage that cannot mesh is refused with one message naming it.
"""

from __future__ import annotations

import math
import os
import re
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest

import pinwind
from pinwind.errors import InvalidGearTrain, UnknownAttribute
from pinwind.gears.gear_pair import GearPair
from pinwind.model.bearing_rows import BearingRow, equivalent_bearing
from pinwind.model.builders import (
    PlanetaryStage,
    StageGear,
    check_stage_meshes,
    read_stage_file,
    stages_urdf,
)
from pinwind.model.gearbox import loads
from tests.conftest import MODELS

STAGE_FILE = MODELS / "nrel5mw_gearbox.toml"
ALPHA = math.radians(20.0)


def involute(angle: float) -> float:
    return math.tan(angle) - angle


def working_centre_distance(z1: int, z2: int, x_sum: float, module: float) -> float:
    """a_w of a spur pair from inv α_w = inv α + 2 tan α (x1 + x2)/(z1 + z2) (ISO 21771).

    Signed tooth numbers (an internal gear's negative); bisection on α_w in (0, 60°).
    """
    target = involute(ALPHA) + 2.0 * math.tan(ALPHA) * x_sum / (z1 + z2)
    low, high = 1e-6, math.radians(60.0)
    for _ in range(200):
        mid = 0.5 * (low + high)
        low, high = (mid, high) if involute(mid) < target else (low, mid)
    return abs(module * (z1 + z2) / 2.0 * math.cos(ALPHA) / math.cos(low))


@pytest.fixture(scope="module")
def stage_file():
    return read_stage_file(STAGE_FILE)


def test_profile_shifted_planetary_stages_mesh_at_their_centre_distance_by_the_involute_function(
    stage_file,
):
    """Nejad's stage 1 has 56 ≠ 19 + 2·17 = 53 ring teeth; its shifts put both pairs at 863 mm."""
    _, stages, _ = stage_file
    one, two = stages[0], stages[1]
    assert one.ring.teeth != one.sun.teeth + 2 * one.planet.teeth
    for stage, (zs, zp, zr), (xs, xp, xr), m in (
        (one, (19, 17, 56), (0.617, 0.802, -0.501), 45e-3),
        (two, (18, 36, 93), (0.389, 0.504, 0.117), 21e-3),
    ):
        sun_planet = working_centre_distance(zs, zp, xs + xp, m)
        planet_ring = working_centre_distance(zp, -zr, xp + xr, m)
        # Table V's a_w, rounded to the millimetre: both pairs within 10 µm of it
        np.testing.assert_allclose([sun_planet, planet_ring], stage.centre_distance, atol=10e-6)
        check_stage_meshes(stage)
    gb = pinwind.load(MODELS / "nrel5mw_gearbox.urdf")
    a_w = {m.name: m.centre_distance for m in gb.meshes}
    np.testing.assert_allclose(a_w["stage1_sun_planet1"], 0.863, rtol=1e-12)
    np.testing.assert_allclose(a_w["stage2_planet3_ring"], 0.584, rtol=1e-12)
    np.testing.assert_allclose(a_w["stage3"], 0.861, rtol=1e-12)


def test_a_stage_whose_gears_cannot_mesh_at_its_centre_distance_is_refused_naming_it(stage_file):
    """580 mm for stage 2 (its shifts give 584.002 and 584.000 mm): one message with the
    stage, the numbers and the fix, a total shift that the involute function confirms."""
    _, stages, _ = stage_file
    bad = replace(stages[1], centre_distance=0.580)
    with pytest.raises(InvalidGearTrain) as err:
        check_stage_meshes(bad)
    text = str(err.value)
    assert 'stage "stage2" cannot mesh at its centre distance 580 mm' in text
    assert "584.002 mm" in text and "584.000 mm" in text
    fixes = [float(x) for x in re.findall(r"x1 \+ x2 = (-?[\d.]+)", text)]
    assert len(fixes) == 2
    np.testing.assert_allclose(working_centre_distance(18, 36, fixes[0], 21e-3), 0.580, rtol=1e-4)
    np.testing.assert_allclose(working_centre_distance(36, -93, fixes[1], 21e-3), 0.580, rtol=1e-4)
    with pytest.raises(InvalidGearTrain, match='stage "stage2" cannot mesh'):
        stages_urdf([stages[0], bad, stages[2]])


def test_build_stages_writes_the_shipped_model_and_exits_2_on_a_stage_that_cannot_mesh(tmp_path):
    def build(source):
        return subprocess.run(
            [sys.executable, "-m", "pinwind", "build", "stages", str(source),
             "-o", str(tmp_path / "built.urdf")],
            capture_output=True, text=True, timeout=120, env=os.environ,
        )  # fmt: skip

    done = build(STAGE_FILE)
    assert done.returncode == 0, done.stderr
    shipped = (MODELS / "nrel5mw_gearbox.urdf").read_text()
    assert (tmp_path / "built.urdf").read_text() == shipped
    bad = tmp_path / "bad.toml"
    bad.write_text(
        STAGE_FILE.read_text().replace("centre_distance_mm = 861", "centre_distance_mm = 870")
    )
    done = build(bad)
    assert done.returncode == 2
    assert done.stderr.count("\n") <= 2  # one message
    assert 'stage "stage3" cannot mesh at its centre distance 870 mm' in done.stderr


def test_tip_alteration_gives_nejads_tip_diameters():
    """d_a = d + 2 m_n (1 + x) + 2 k m_n (internal: d − 2 m_n (1 + x)), Nejad et al. 2016 Table V
    diameters to 0.05 mm (the tip alterations are given to 1 µm of k m_n, the diameters to
    three decimals: 31 µm the largest difference, on the stage-1 sun)."""
    gb = pinwind.load(MODELS / "nrel5mw_gearbox.urdf")
    meshes = {m.name: m for m in gb.meshes}
    reported = {  # mesh: (pinion, wheel) tip diameters [mm], the wheel internal for a ring
        "stage1_sun_planet1": (905.440, 978.839),  # the planet (17) is the pinion
        "stage1_planet1_ring": (905.440, 2475.087),
        "stage2_sun_planet1": (432.845, 815.655),
        "stage2_planet1_ring": (815.655, 1906.074),
        "stage3": (380.751, 1395.372),
    }
    for name, (d1, d2) in reported.items():
        pair = GearPair.from_mesh(meshes[name])
        np.testing.assert_allclose(
            [pair.tip_diameter(1) * 1e3, pair.tip_diameter(2) * 1e3], [d1, d2], atol=0.05,
            err_msg=name,
        )  # fmt: skip
    sun = GearPair.from_mesh(meshes["stage1_sun_planet1"])
    shortened = 855.0 + 2 * 45 * (1 + 0.617) - 2 * 10.861
    np.testing.assert_allclose(sun.tip_diameter(2) * 1e3, shortened, rtol=1e-12)
    unaltered = replace(sun, tip_alteration_1=0.0, tip_alteration_2=0.0)
    assert unaltered.path.contact_ratio > sun.path.contact_ratio  # shorter tips, shorter path


def test_equivalent_bearing_sums_rows_about_their_stiffness_centre():
    """Two rows 1 m apart, 1e9 and 3e9 N/m (mean of K_y, K_z): centre 0.75 m from the first,
    k_t = 1e9·0.75² + 3e9·0.25² + Σ mean(K_β, K_γ)."""
    stiffness_a, damping_a = (1e7, 0.5e9, 1.5e9, 1e5, 3e5), (1.0, 2.0, 4.0, 5.0, 7.0)
    stiffness_b, damping_b = (2e7, 3e9, 3e9, 0.0, 0.0), (1.0, 6.0, 6.0, 0.0, 0.0)
    rows = [
        BearingRow("A", "cylindrical_roller", 0.0, None, stiffness_a, damping_a),
        BearingRow("B", "tapered_roller", 1.0, None, stiffness_b, damping_b),
    ]
    eq = equivalent_bearing(rows)
    np.testing.assert_allclose(eq.centre, 0.75, rtol=1e-12)
    np.testing.assert_allclose(eq.radial_stiffness, 4e9, rtol=1e-12)
    np.testing.assert_allclose(eq.axial_stiffness, 3e7, rtol=1e-12)
    np.testing.assert_allclose(eq.tilt_stiffness, 1e9 * 0.75**2 + 3e9 * 0.25**2 + 2e5, rtol=1e-12)
    np.testing.assert_allclose(eq.radial_damping, 9.0, rtol=1e-12)
    np.testing.assert_allclose(eq.tilt_damping, 3.0 * 0.75**2 + 6.0 * 0.25**2 + 6.0, rtol=1e-12)


def test_the_5mw_model_keeps_its_sixteen_bearings_with_their_own_data():
    gb = pinwind.load(MODELS / "nrel5mw_gearbox.urdf")
    rows = gb.source.bearing_rows
    names = {r.name for shaft in rows.values() for r in shaft}
    assert names == {
        "INP-A", "INP-B", "PL-A", "PL-B", "PLC-A", "PLC-B", "IMS-PL-A", "IMS-PL-B",
        "IMS-PLC-A", "IMS-PLC-B", "IMS-A", "IMS-B", "IMS-C", "HS-A", "HS-B", "HS-C",
    }  # fmt: skip
    main = {r.name: r for r in rows["lss"]}
    assert set(main) == {"INP-A", "INP-B", "PLC-A", "PLC-B"}
    assert main["INP-A"].kind == "toroidal_roller"
    assert main["INP-A"].rating == 22000e3  # Nejad et al. 2016 Table VI as transcribed (C assumed)
    np.testing.assert_allclose(main["INP-B"].position - main["INP-A"].position, 1.166 - 0.333)
    assert main["INP-B"].load_factors == (0.28, 2.4, 0.67, 3.6)
    # the main shaft's compliant bearing: Σ mean(K_y, K_z) of its four rows (Tables VI, IX)
    radial = 1.5e10 + 1.54e10 + 0.5 * (1.7e9 + 1.1e9) * 2
    np.testing.assert_allclose(gb.source.compliant_bearings["lss"].radial_stiffness, radial)
    planet = {r.name: r for r in rows["stage1_planet2"]}
    assert planet["PL-A"].stiffness == (9.1e4, 9.4e9, 3.2e9, 1.4e6, 4.5e6)
    np.testing.assert_allclose(planet["PL-B"].position - planet["PL-A"].position, 0.272)


def test_end_bodies_are_coupled_by_the_solid_steel_shafts_torsional_stiffness():
    """k = G π d⁴/(32 L), G = E/(2(1 + ν)) = 206 GPa / 2.6: the main and high-speed shafts."""
    gb = pinwind.load(MODELS / "nrel5mw_gearbox.urdf")
    springs = {s.name: s for s in gb.source.springs}
    g = 206e9 / 2.6
    np.testing.assert_allclose(
        springs["rotor_coupling"].stiffness, g * math.pi * 0.7**4 / (32 * 2.0), rtol=1e-10
    )
    np.testing.assert_allclose(
        springs["generator_coupling"].stiffness, g * math.pi * 0.333**4 / 32, rtol=1e-10
    )


def test_a_misspelt_row_attribute_is_refused_naming_the_nearest():
    text = (MODELS / "nrel5mw_gearbox.urdf").read_text().replace('size_mm="1750', 'siez_mm="1750')
    with pytest.raises(UnknownAttribute, match='"size_mm"'):
        loads(text)


def test_a_stage_with_two_fixed_members_is_refused():
    stage = PlanetaryStage(
        name="s", sun=StageGear(24), planet=StageGear(48), ring=StageGear(120), planets=3,
        module=15e-3, pressure_angle=ALPHA, face_width=0.3, centre_distance=0.54,
        shafts={"sun": "fixed", "carrier": "in", "ring": "fixed"},
    )  # fmt: skip
    with pytest.raises(InvalidGearTrain, match='stage "s": give exactly one of sun, carrier, ring'):
        stages_urdf([stage])


def test_a_star_stage_with_the_carrier_fixed_turns_the_ring_at_minus_z_sun_over_z_ring():
    """Carrier fixed, sun in, ring out (a star stage), then a helical pair on the ring's shaft:
    ω_ring/ω_sun = −z_s/z_r (Willis's formula with the carrier at rest), ω_pinion/ω_ring =
    −z_wheel/z_pinion."""
    from pinwind.dynamics.ratios import speed_ratio
    from pinwind.model.builders import ParallelStage

    star = PlanetaryStage(
        name="star", sun=StageGear(24), planet=StageGear(48), ring=StageGear(120), planets=3,
        module=15e-3, pressure_angle=ALPHA, face_width=0.3, centre_distance=0.54,
        shafts={"sun": "input", "carrier": "fixed", "ring": "ring_shaft"},
    )  # fmt: skip
    pair = ParallelStage(
        name="pair", wheel=StageGear(83), pinion=StageGear(23), module=10e-3,
        pressure_angle=ALPHA, face_width=0.2, centre_distance=0.53 / math.cos(math.radians(8.0)),
        shafts={"wheel": "ring_shaft", "pinion": "output"}, helix_angle=math.radians(8.0),
    )  # fmt: skip
    gb = loads(stages_urdf([star, pair], name="star"))
    np.testing.assert_allclose(speed_ratio(gb, "ring_shaft", "input"), -24 / 120, rtol=1e-12)
    np.testing.assert_allclose(speed_ratio(gb, "output", "ring_shaft"), -83 / 23, rtol=1e-12)
    # the carrier welded to the housing: the planets turn about fixed axes at −z_s/z_p
    np.testing.assert_allclose(speed_ratio(gb, "star_planet1", "input"), -24 / 48, rtol=1e-12)
