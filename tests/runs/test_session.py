"""The session: held inputs stepped from outside equal one ``simulate`` with the same inputs."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pinwind
from pinwind.dynamics.simulate import simulate
from pinwind.errors import NonFiniteInput, RestoreBeyondLog, StepNotOnGrid, UnknownSessionName
from pinwind.runs.scenario import Scenario
from pinwind.runs.session import Session
from tests.conftest import two_gear_urdf

DT = 1e-3
#: Communication step: 10 internal steps.
H = 10 * DT
#: Start torques [N·m], balanced through the 20/40 pair: T_a ω_a + T_b ω_b = 0.
START = {"torque.a": 1.0, "torque.b": 2.0}


@pytest.fixture
def pair(tmp_path):
    """The 20/40 pair of ``two_gear_urdf``: joints a and b, mesh m."""
    path = tmp_path / "pair.urdf"
    path.write_text(two_gear_urdf())
    return pinwind.load(path)


def _inputs(seed: int, points: int) -> np.ndarray:
    """Seeded torques on a and b [N·m] for each communication step."""
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.uniform(0.5, 2.0, points), rng.uniform(1.0, 4.0, points)])


def _held(start: float, values: np.ndarray, steps_per_point: int):
    """u(t_k): the start value at k = 0, values[i] on samples (i·n, (i + 1)·n]."""

    def signal(t: float) -> float:
        k = round(t / DT)
        return start if k == 0 else float(values[(k - 1) // steps_per_point])

    return signal


def test_session_with_held_torques_equals_simulate_with_piecewise_constant_torques(pair):
    points = 12
    u = _inputs(1, points)
    scenario = Scenario(duration=points * H, dt=DT)
    session = Session(pair, scenario, inputs=["torque.a", "torque.b"], start=START)
    seen = [session.advance((i + 1) * H, {"torque.a": u[i, 0], "torque.b": u[i, 1]})
            for i in range(points)]  # fmt: skip
    n = round(H / DT)
    res = simulate(
        pair,
        duration=points * H,
        dt=DT,
        torques={"a": _held(1.0, u[:, 0], n), "b": _held(2.0, u[:, 1], n)},
        keep="all",
    )
    for i, out in enumerate(seen):
        k = (i + 1) * n
        for name, array in (("speed.a", res.joint("a").speed), ("angle.b", res.joint("b").angle),
                            ("mesh_normal.m", res.mesh("m").normal)):  # fmt: skip
            np.testing.assert_allclose(out[name], array[k], rtol=1e-9, atol=1e-12)
        assert "torque.a" not in out  # an input is not also an output


@pytest.mark.parametrize("ramp_on_b", [True, False])
def test_a_held_speed_equals_simulate_with_the_speed_one_sample_later(pair, ramp_on_b):
    """A speed input u_i holds from sample k_prev + 2 (its first step ramps to it).

    Speed driver on a; on b a ramp torque from the scenario (a signal of time: the session
    evaluates the signals) or a constant one (the held values handed to the step as they are):
    equal to ``simulate`` with the speed u_i on samples i n + 2 … (i + 1) n + 1 at every
    point, the driver's torque included.
    """
    from pinwind.loads.signals import Ramp

    points, n = 10, 10
    rng = np.random.default_rng(5)
    u = rng.uniform(5.0, 15.0, points)
    ramp = Ramp(start_value=0.5, end_value=2.0, start_time=0.0, end_time=points * H)
    ramp = ramp if ramp_on_b else 0.8
    scenario = Scenario(duration=points * H, dt=DT, torques={"b": ramp})
    session = Session(pair, scenario, inputs=["speed.a"], start={"speed.a": 10.0})
    seen = [session.advance((i + 1) * H, {"speed.a": u[i]}) for i in range(points)]

    def speed(t: float) -> float:
        k = round(t / DT)
        return 10.0 if k <= 1 else float(u[(k - 2) // n])

    res = simulate(pair, duration=points * H, dt=DT, speeds={"a": speed}, torques={"b": ramp},
                   initial_speeds={"a": 10.0}, keep="all")  # fmt: skip
    for i, out in enumerate(seen):
        k = (i + 1) * n
        np.testing.assert_allclose(out["torque.a"], res.joint("a").torque[k], rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(out["speed.b"], res.joint("b").speed[k], rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(out["speed.b"], -0.5 * u[i], rtol=1e-12)  # held, by the ratio


def test_held_torques_accelerate_the_pair_as_the_hand_calculation_says(pair):
    """ω_a(t_k) = Σ_j (T_a + T_b ω_b/ω_a)(t_j) dt / J_eq over steps j < k (rigid 20/40 pair).

    J_eq = J_a + J_b (ω_b/ω_a)², ω_b/ω_a = −20/40; step j takes the torques of t_j: the start
    values for step 0, the values given to the i-th ``advance`` for steps 10 i + 1 … 10 i + 10.
    """
    scenario = Scenario(duration=0.1, dt=DT)
    session = Session(pair, scenario, inputs=["torque.a", "torque.b"], start=START)
    ratio = -20 / 40
    j_eq = 0.0015 + 0.006 * ratio**2  # Izz of the links a and b [kg·m²]
    u = _inputs(2, 5)
    out = {}
    for i in range(5):
        out = session.advance((i + 1) * H, {"torque.a": u[i, 0], "torque.b": u[i, 1]})
    net = [START["torque.a"] + START["torque.b"] * ratio]
    net += [u[(j - 1) // 10, 0] + u[(j - 1) // 10, 1] * ratio for j in range(1, 50)]
    np.testing.assert_allclose(out["speed.a"], sum(net) * DT / j_eq, rtol=1e-9)
    np.testing.assert_allclose(out["speed.b"], ratio * out["speed.a"], rtol=1e-12)


def test_restore_then_advance_repeats_the_step_bit_for_bit(pair):
    scenario = Scenario(duration=0.1, dt=DT)
    session = Session(pair, scenario, inputs=["torque.a", "torque.b"],
                      start=START)  # fmt: skip
    session.advance(H, {"torque.a": 1.5})
    saved = session.state()
    first = session.advance(2 * H, {"torque.a": 0.7, "torque.b": 3.0})
    session.advance(3 * H, {"torque.a": 9.0})  # a step the master then discards
    session.restore(saved)
    again = session.advance(2 * H, {"torque.a": 0.7, "torque.b": 3.0})
    assert again == first  # bit for bit: every output equal as floats
    assert session.time == pytest.approx(2 * H, abs=1e-15)


def test_bad_inputs_raise_one_error_naming_the_value(pair):
    scenario = Scenario(duration=0.1, dt=DT)
    with pytest.raises(UnknownSessionName, match=r'unknown input "torque\.c".*torque\.a'):
        Session(pair, scenario, inputs=["torque.c"])
    session = Session(pair, scenario, inputs=["torque.a", "torque.b"],
                      start=START)  # fmt: skip
    with pytest.raises(UnknownSessionName, match='"torque.z"'):
        session.advance(H, {"torque.z": 1.0})
    with pytest.raises(NonFiniteInput, match='"torque.a" is nan'):
        session.advance(H, {"torque.a": math.nan})
    with pytest.raises(StepNotOnGrid, match=r"4\.5 steps.*0\.004 s and 0\.005 s"):
        session.advance(4.5 * DT)
    with pytest.raises(StepNotOnGrid, match="duration 0.1 s"):
        session.advance(0.2)
    with pytest.raises(UnknownSessionName, match='output "speed.q"'):
        Session(pair, scenario, inputs=["torque.a"], outputs=["speed.q"])
    # the session goes on after a refused step: the pair balanced at rest stays at rest
    assert session.advance(H)["speed.a"] == 0.0


def test_a_session_log_reads_back_as_the_run(pair, tmp_path):
    """40 points of 30 steps: 1201 samples, the log's 1000-sample chunk split inside a point."""
    points, h = 40, 30 * DT
    scenario = Scenario(duration=points * h, dt=DT)
    path = tmp_path / "session.mcap"
    u = _inputs(3, points)
    with Session(pair, scenario, inputs=["torque.a", "torque.b"], log=path,
                 start=START) as session:  # fmt: skip
        outs = []
        for i in range(points):
            outs.append(session.advance((i + 1) * h, {"torque.a": u[i, 0], "torque.b": u[i, 1]}))
            if i == 2:
                saved = session.state()
            if i == 10:  # the state before the last step: its samples are not logged yet
                before = session.state()
                repeat = session.advance((i + 2) * h, {"torque.a": 5.0})
                session.restore(before)
                assert repeat != session.outputs()
        with pytest.raises(RestoreBeyondLog, match="already holds"):
            session.restore(saved)
    res = pinwind.read_log(path)
    assert len(res) == points * 30 + 1
    np.testing.assert_allclose(res.time, np.arange(len(res)) * DT, rtol=0, atol=1e-12)
    np.testing.assert_allclose(res.joint("a").speed[30::30], [o["speed.a"] for o in outs],
                               rtol=0, atol=0)  # fmt: skip
    np.testing.assert_allclose(res.mesh("m").normal[30::30], [o["mesh_normal.m"] for o in outs],
                               rtol=0, atol=0)  # fmt: skip
    assert res.metadata["status"] == "completed"


def test_a_held_hub_force_equals_simulate_with_the_piecewise_constant_load():
    """``hub.BODY.COMPONENT`` holds one component of the scenario's hub load on the body (its
    point, frame and axes kept), as a torque is held."""
    from pinwind.loads.hub_loads import HubLoad
    from tests.dynamics.test_row_springs import _row, shaft_on_rows

    rows = [_row("A", -0.3, (1e8, 2e8, 1e8, 1e5, 1e5)), _row("B", 0.1, (1e8, 1e8, 2e8, 1e5, 1e5))]
    gearbox = pinwind.model.gearbox.loads(shaft_on_rows(rows))
    points, n = 8, 10
    forces = np.random.default_rng(5).uniform(-2e4, 2e4, points)
    up = (0.0, 1.0, 0.0)  # the model has no gravity to give the hub's z
    scenario_load = HubLoad("shaft", (0.0, 0.0, 3e3, 0.0, 0.0, 0.0), up=up)
    scenario = Scenario(duration=points * H, dt=DT, hub_loads=(scenario_load,))
    session = Session(gearbox, scenario, inputs=["hub.shaft.force_y"])
    assert session.input_unit("hub.shaft.force_y") == "N"
    seen = [session.advance((i + 1) * H, {"hub.shaft.force_y": forces[i]}) for i in range(points)]
    load = HubLoad("shaft", (0.0, _held(0.0, forces, n), 3e3, 0.0, 0.0, 0.0), up=up)
    res = simulate(gearbox, duration=points * H, dt=DT, hub_loads=[load])
    got = np.array([[o[f"bearing_force.shaft.{c}"] for c in "xyz"] for o in seen])
    np.testing.assert_allclose(got, res.bearing("shaft").force[n::n], rtol=1e-9, atol=1e-9)
    assert np.ptp(got) > 1e4  # the held force does reach the bearing
