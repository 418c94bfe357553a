"""The NREL 5 MW rotor in wind on the shipped 5 MW gearbox: its thrust reaches the main bearings.

The rotor preset's tables are ROSCO's (loads/rotor_performance.py); here the thrust the main shaft's
bearing carries is checked against the file's own C_t, interpolated independently, and the rotor's
weight by the shaft tilt of Jonkman et al. 2009 Table 1-1.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from numpy.testing import assert_allclose
from scipy.interpolate import RegularGridInterpolator

import pinwind
from pinwind.errors import PinwindWarning
from pinwind.loads.rotor import Rotor, RotorHub
from pinwind.loads.rotor_performance import NREL5MW_PERFORMANCE, read_performance
from pinwind.model.gearbox import load
from pinwind.runs.scenario import build
from tests.conftest import MODELS

RPM = 2.0 * math.pi / 60.0
#: The main shaft's rotor end in its joint's frame [m] (models/README.md: 333 mm before INP-A).
ROTOR_END = (0.0, 0.0, -2.36825 + 1.48115361446)
#: Rated rotor speed and wind (Jonkman et al. 2009 Table 1-1), the generator's speed at the
#: teeth's ratio 96.354 (tests/model/test_nrel5mw_gearbox.py), negative (the parallel stage).
ROTOR_SPEED, WIND, GENERATOR_SPEED = 12.1 * RPM, 11.4, -12.1 * RPM * 96.35416666666667


def test_the_main_shaft_bearing_carries_the_thrust_and_the_tilted_weight_along_the_shaft():
    # Spur stages 1 and 2 put no axial force on the main shaft (with its stage-1 carrier), so its
    # bearing's axial reaction is the rotor's axial load: −(T + m g sin τ), T = ½ρπR²v²C_t(λ)
    # with C_t from ROSCO's file at λ = ω R / v, β = 0, bilinear (scipy's interpolator here).
    gearbox = load(MODELS / "nrel5mw_gearbox.urdf")
    rotor = Rotor.nrel5mw(hub=RotorHub("lss", ROTOR_END))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        res = pinwind.simulate(
            gearbox, duration=2e-3, dt=1e-4, rotors={"rotor": rotor}, wind=WIND,
            initial_speeds={"rotor": ROTOR_SPEED}, speeds={"generator": GENERATOR_SPEED},
        )  # fmt: skip
    grid = read_performance(NREL5MW_PERFORMANCE)
    ct = RegularGridInterpolator((grid.tsr, grid.pitch), grid.ct)
    omega = res.joint("rotor").speed
    thrust = 0.5 * 1.225 * math.pi * 63.0**2 * WIND**2 * ct(np.column_stack(
        [omega * 63.0 / WIND, np.zeros_like(omega)]))  # fmt: skip
    axial = thrust + 110_000.0 * 9.81 * math.sin(math.radians(5.0))
    assert_allclose(res.rotor("rotor").thrust, thrust, rtol=1e-12)
    # The shaft's axial mode starts in equilibrium: the reaction along the housing's shaft axis
    # (world z) is the load, but for the stage-1 mesh forces, which tilt with the carrier by its
    # bearing's tilt θ: their axial part is at most θ Σ|F_mesh|.
    model = gearbox.model
    slides = gearbox.compliant_bearings["lss"].v_index
    tilts = [model.names[j] for j in range(1, model.njoints)
             if model.joints[j].idx_v in (slides["tilt_x"], slides["tilt_y"])]  # fmt: skip
    theta = np.hypot(*(res.joint(name).angle for name in tilts))
    stage1 = [i for i, name in enumerate(res.mesh_names) if name.startswith("stage1")]
    bound = theta * np.abs(res.mesh_normal[:, stage1]).sum(axis=1)
    assert np.all(np.abs(res.bearing("lss").force[:, 2] + axial) <= bound)
    assert np.max(bound) < 2e-3 * axial[0]  # θ ≈ 1e-4 rad: the check is a tight one
    assert 6e5 < thrust[0] < 9e5  # C_t 0.73 at λ 7.0: 0.73 MN


def test_a_scenario_places_the_nrel5mw_rotor_on_the_main_shaft():
    scenario = build({
        "model": str(MODELS / "nrel5mw_gearbox.urdf"), "wind": 11.4,
        "rotor": {"rotor": {"preset": "nrel5mw", "hub_body": "lss", "hub_point": list(ROTOR_END),
                            "shaft_tilt_deg": 6.0}},
    })  # fmt: skip
    rotor = scenario.rotors["rotor"]
    assert rotor.hub == RotorHub("lss", ROTOR_END)
    assert_allclose(rotor.shaft_tilt, math.radians(6.0), rtol=1e-15)
    assert rotor.radius == 63.0 and rotor.mass == 110_000.0 and rotor.hub_height == 90.0
