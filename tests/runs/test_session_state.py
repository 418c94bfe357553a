"""A session's saved state: the compiled run's own, taken back without stepping again.

``Session.state()`` copies the compiled stepper's state (``cpp/stepper.hpp`` StepperState) and
``restore`` sets it back. The facts checked, for a model of each element kind and one with them
all: the steps after a restore repeat the first ones bit for bit (every output the model has,
and every series of every sample the steps recorded, the energy ledger's terms with them,
compared exactly: the same compiled code on the same numbers, so any state the copy missed shows
as a difference), while a step with other inputs differs (so that the comparison can fail); a
restore steps no sample again (``samples_stepped``), after 1000 steps as after 10; a state from
another session is refused, naming both models.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pytest

import pinwind
from pinwind.errors import ForeignState, InputError, PinwindWarning, RestoreBeyondLog
from pinwind.loads.generator import InductionMachine, LinearSlip
from pinwind.loads.hub_loads import HubLoad
from pinwind.loads.pitch_control import PitchControl
from pinwind.loads.rotor import Rotor, RotorHub
from pinwind.model.gearbox import loads
from pinwind.runs.scenario import Scenario
from pinwind.runs.session import Session
from tests.conftest import MODELS, two_gear_urdf
from tests.dynamics.test_compliant_bearing import disc_urdf
from tests.dynamics.test_flank_contact import pair_urdf
from tests.dynamics.test_row_springs import _row, shaft_on_rows
from tests.dynamics.test_torsional_spring import _shafts_urdf

RPM = 2.0 * math.pi / 60.0


@dataclass
class Case:
    """A model, its scenario, and the session's open inputs with the range of their values."""

    gearbox: pinwind.Gearbox
    scenario: Scenario
    inputs: dict[str, tuple[float, float]]
    steps: int = 10  # internal steps per communication step


def _quiet(text: str) -> pinwind.Gearbox:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        return loads(text)


def _rigid_pair() -> Case:
    """Rigid mesh rows (RigidMeshes)."""
    return Case(
        _quiet(two_gear_urdf()),
        Scenario(duration=1.0, dt=1e-3),
        {"torque.a": (-2.0, 2.0), "torque.b": (-4.0, 4.0)},
    )


def _driven_pair() -> Case:
    """A speed driver's row (SpeedDrivers) beside the rigid mesh."""
    return Case(
        _quiet(two_gear_urdf()),
        Scenario(duration=1.0, dt=1e-3),
        {"speed.a": (0.0, 10.0), "torque.b": (-4.0, 4.0)},
    )


def _mesh_with_backlash() -> Case:
    """A compliant mesh with backlash, its stiffness changing with the pairs in contact, on a
    pinion in a compliant bearing (CompliantMeshes, BearingSprings): torques of either sign
    move the teeth from flank to flank, and at 100 rad/s a tooth pair enters or leaves every
    1.6 ms."""
    gb = _quiet(pair_urdf(mesh='backlash_mm="0.02" damping="5"'))
    scenario = Scenario(duration=0.5, dt=1e-4, initial_speeds={"a": 100.0})
    return Case(gb, scenario, {"torque.a": (-20.0, 20.0)})


def _sliced_mesh() -> Case:
    """A compliant mesh in four slices across the face (SlicedMeshes)."""
    gb = _quiet(pair_urdf(bearing="", mesh='slices="4" damping="5"'))
    scenario = Scenario(duration=0.5, dt=1e-4, initial_speeds={"a": 100.0})
    return Case(gb, scenario, {"torque.a": (-20.0, 20.0)})


def _spring_and_damper() -> Case:
    """A preloaded torsional spring-damper (TorsionalSprings) and a bearing's viscous damping
    (BearingDamping)."""
    gb = _quiet(_shafts_urdf(stiffness=5e4, spring_damping=30.0, preload=0.01, bearing_damping=0.5))
    return Case(gb, Scenario(duration=1.0, dt=1e-3), {"torque.a": (-50.0, 50.0)})


def _bearing_with_clearance() -> Case:
    """A damped radial bearing with a clearance (BearingSprings: its contact side)."""
    gb = _quiet(disc_urdf('radial_stiffness="1e6" radial_damping="50" radial_clearance_mm="0.01"'))
    return Case(gb, Scenario(duration=1.0, dt=1e-4), {"torque.disc": (-5.0, 5.0)})


def _rows_under_a_hub_load() -> Case:
    """A shaft on two bearing rows (BearingRows) under a hub load that turns in time (HubLoads:
    a signal of time, stepped through ``PreparedRun.step_block``)."""
    rows = [_row("A", -0.3, (1e8, 2e8, 1e8, 1e5, 1e5), (10.0,) * 5),
            _row("B", 0.1, (1e8, 1e8, 2e8, 1e5, 1e5), (10.0,) * 5)]  # fmt: skip
    turning = (0.0, lambda t: 1e4 * math.sin(40.0 * t), 5e3, 0.0, 0.0, 0.0)
    load = HubLoad("shaft", turning, up=(0.0, 1.0, 0.0))
    return Case(
        _quiet(shaft_on_rows(rows)),
        Scenario(duration=1.0, dt=1e-3, hub_loads=(load,)),
        {"torque.shaft": (-100.0, 100.0)},
    )


def _rotor_and_generator() -> Case:
    """Saleh 2017's rotor with a pitch controller on the carrier (RotorAerodynamics: its
    controller's states) and Krause's dq induction machine on the sun (InductionMachineDq: its
    fluxes), the wind an input."""
    gb = pinwind.load(MODELS / "saleh2017_planetary.urdf")
    control = PitchControl.nrel5mw(speed_set=14.0 * RPM)
    scenario = Scenario(
        duration=1.0, dt=1e-3, initial_speeds={"carrier": 14.2 * RPM},
        rotors={"carrier": Rotor.saleh2017(pitch_control=control)},
        generators={"sun": InductionMachine.cart600(poles=84, dynamic=True)},
    )  # fmt: skip
    return Case(gb, scenario, {"wind": (8.0, 16.0)})


def _nrel5mw_with_every_kind() -> Case:
    """The NREL 5 MW gearbox with compliant meshes (every mesh), torsional couplings, bearing
    rows and compliant bearings, the NREL 5 MW rotor with its pitch controller and its hub's
    loads, a slip-law generator, a hub load and a speed driver: every kind but sliced meshes and
    the dq machine, with the wind and the driver's speed as inputs."""
    gb = pinwind.load(MODELS / "nrel5mw_gearbox.urdf")
    rotor_end = (0.0, 0.0, -2.36825 + 1.48115361446)  # tests/runs/test_nrel5mw_rotor.py
    generator_speed = -12.1 * RPM * 96.35416666666667
    scenario = Scenario(
        duration=0.1, dt=1e-4, initial_speeds={"rotor": 12.1 * RPM}, meshes={"all": "compliant"},
        rotors={"rotor": Rotor.nrel5mw(hub=RotorHub("lss", rotor_end),
                                       pitch_control=PitchControl.nrel5mw())},
        generators={"hss": LinearSlip(slope=1e3, sync_speed=generator_speed)},
        hub_loads=(HubLoad("lss", (0.0, 2e5, -1e5, 0.0, 3e5, 0.0), point=rotor_end),),
    )  # fmt: skip
    return Case(gb, scenario, {"wind": (8.0, 14.0), "speed.generator": (-130.0, -110.0)}, 5)


CASES: dict[str, Callable[[], Case]] = {
    "rigid meshes": _rigid_pair,
    "speed driver": _driven_pair,
    "compliant mesh with backlash": _mesh_with_backlash,
    "sliced mesh": _sliced_mesh,
    "torsional spring and bearing damping": _spring_and_damper,
    "bearing with clearance": _bearing_with_clearance,
    "bearing rows under a hub load": _rows_under_a_hub_load,
    "rotor with pitch control and dq generator": _rotor_and_generator,
    "NREL 5 MW with every kind": _nrel5mw_with_every_kind,
}


def _open(case: Case, **kwargs) -> Session:
    """A session of the case giving every output its model has."""
    names = list(case.inputs)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        probe = Session(case.gearbox, case.scenario, inputs=names)
        outputs = [n for n in probe.available_outputs if n not in names]
        return Session(case.gearbox, case.scenario, inputs=names, outputs=outputs, **kwargs)


def _values(case: Case, rng: np.random.Generator) -> dict[str, float]:
    return {name: float(rng.uniform(lo, hi)) for name, (lo, hi) in case.inputs.items()}


def _array(outputs: dict[str, float]) -> np.ndarray:
    return np.array(list(outputs.values()))


def _block(session: Session, steps: int) -> dict[str, np.ndarray]:
    """Every series of the last advance's samples, the energy ledger's terms too (the block the
    session steps into, read before the next advance overwrites it)."""
    block = session._buffers[steps]
    arrays = {name: np.array(getattr(block, name)) for name in block.ARRAYS}
    arrays.update({f"energy/{k}": np.array(v) for k, v in block.energy.items()})
    arrays.pop("energy/numerical")  # the log's alone: left unfilled without one
    return arrays


@pytest.mark.parametrize("name", list(CASES))
def test_restore_then_advance_repeats_the_first_advance_bit_for_bit(name):
    case = CASES[name]()
    session = _open(case)
    assert session.saves_state  # every kind copies its state: no replay
    rng = np.random.default_rng(42)
    h = case.steps * case.scenario.dt
    for i in range(3):
        session.advance((i + 1) * h, _values(case, rng))
    saved = session.state()
    at_state = session.outputs()
    inputs = [_values(case, rng) for _ in range(3)]
    first, first_blocks = [], []
    for i, u in enumerate(inputs):
        first.append(session.advance((4 + i) * h, u))
        first_blocks.append(_block(session, case.steps))
    stepped = session.samples_stepped
    other = session.advance(7 * h, _values(case, rng))  # a step the master discards
    session.restore(saved)
    assert session.samples_stepped == stepped + case.steps  # the restore stepped nothing
    assert session.outputs() == at_state
    assert session.time == pytest.approx(3 * h, rel=1e-12)
    for i, u in enumerate(inputs):
        again = session.advance((4 + i) * h, u)
        assert list(again) == list(first[i])
        np.testing.assert_array_equal(_array(again), _array(first[i]))  # bit for bit
        for name, values in _block(session, case.steps).items():  # every sample, every series
            np.testing.assert_array_equal(values, first_blocks[i][name], err_msg=name)
    # the comparison can fail: a step with other inputs gives other outputs
    assert not np.array_equal(_array(other), _array(session.advance(7 * h, inputs[0])))


def test_a_restore_after_1000_steps_steps_no_more_than_after_10():
    """Replayed, a restore stepped every sample to the state again (100 times the cost at 1000
    steps); a compiled state steps none, at 10 steps as at 1000."""
    case = _rigid_pair()
    case.scenario = Scenario(duration=2.0, dt=1e-3)
    session = _open(case)
    rng = np.random.default_rng(7)
    h = 10 * case.scenario.dt
    stepped_by_restore = {}
    for points in (1, 100):
        while session.time < points * h - 1e-12:
            session.advance(session.time + h, _values(case, rng))
        saved = session.state()
        session.advance(session.time + h, _values(case, rng))
        before = session.samples_stepped
        session.restore(saved)
        stepped_by_restore[points * 10] = session.samples_stepped - before
    assert stepped_by_restore == {10: 0, 1000: 0}
    # sample 0, then each advance's samples: to 10, one discarded, to 1000, one discarded
    assert session.samples_stepped == 1 + 10 + 10 + 990 + 10


def test_a_state_from_another_session_is_refused_naming_both_models():
    pair = _open(_rigid_pair())
    shafts = _open(_spring_and_damper())
    pair.advance(0.01, {"torque.a": 1.0})
    shafts.advance(0.01, {"torque.a": 1.0})
    with pytest.raises(ForeignState, match=r'model "pair"; this one steps "shafts"'):
        shafts.restore(pair.state())
    twin = _open(_rigid_pair())  # the same model, another session: refused as well
    with pytest.raises(ForeignState, match="another session"):
        twin.restore(pair.state())
    # the compiled stepper refuses another's state itself
    with pytest.raises(InputError, match="another run"):
        twin._run.stepper.restore(pair.state().compiled)


def test_with_a_log_a_state_ahead_of_the_session_is_refused(tmp_path):
    """The log holds the samples the session stepped: a state of a discarded branch ahead of
    the session's time would leave a gap in it."""
    case = _rigid_pair()
    with _open(case, log=tmp_path / "s.mcap") as session:
        session.advance(0.01, {"torque.a": 1.0})
        back = session.state()
        session.advance(0.02, {"torque.a": 2.0})
        ahead = session.state()
        session.restore(back)
        with pytest.raises(RestoreBeyondLog):
            session.restore(ahead)


def test_a_restore_gives_back_the_outputs_of_the_state_whatever_their_order():
    """Outputs named out of their series' order (the session gathers them by series)."""
    case = _rigid_pair()
    names = ["speed.a", "mesh_normal.m", "speed.b", "bearing_force.a.y", "angle.a"]
    session = Session(case.gearbox, case.scenario, inputs=list(case.inputs), outputs=names)
    session.advance(0.01, {"torque.a": 1.0, "torque.b": -1.0})
    saved, at_state = session.state(), session.outputs()
    assert at_state["speed.a"] > 0.0 > at_state["speed.b"]  # the pair turns: values differ
    session.advance(0.02, {"torque.a": 3.0})
    session.restore(saved)
    assert session.outputs() == at_state


def test_without_compiled_states_a_restore_replays_the_run_to_the_same_bits():
    """The fallback for an element kind that keeps no copy (``Session.saves_state`` False,
    forced here): the run stepped again from t = 0, every sample to the state's once more."""
    case = _rigid_pair()
    session = _open(case)
    session._saves = False  # as for a model with a kind whose Element::copy() is null
    rng = np.random.default_rng(3)
    for i in range(5):
        session.advance((i + 1) * 0.01, _values(case, rng))
    saved = session.state()
    assert saved.compiled is None and len(saved.history) == 5
    u = _values(case, rng)
    first = session.advance(0.06, u)
    stepped = session.samples_stepped
    session.restore(saved)
    assert session.samples_stepped == stepped + 51  # sample 0 and the five points again
    np.testing.assert_array_equal(_array(session.advance(0.06, u)), _array(first))
