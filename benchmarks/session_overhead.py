"""Cost of stepping a run from outside: a Session per communication point, and the FMU.

Saleh 2017's planetary stage (rigid meshes, dt = 1 ms), a carrier torque of 1 MN·m and a sun
torque balancing it held: ``--points`` communication points of ``--steps`` internal steps.
Times, best of ``--repeats``:

- ``simulate``: one ``pinwind.dynamics.simulate.simulate`` over all the steps (keep="last", no
  log), end to end, and its step loop alone (``PreparedRun.run``);
- ``session``: the ``advance`` calls of a Session over the same steps (its opening apart);
- ``fmu``: the ``doStep`` calls (with ``setReal``/``getReal``) of the exported FMI 2.0 FMU under
  FMPy, and those (with ``setFloat64``/``getFloat64``) of the FMI 3.0 FMU (``--fmi-version 3``);
- ``state() + restore()``: the pair at the run's end (a copy of the compiled run's state: the
  same at any time).

Prints µs per communication point and the session's overhead beside ``simulate``'s step loop
(issue 42 asks ≤ 20 % at 10 internal steps per point).

    python benchmarks/session_overhead.py [--points 2000] [--steps 10] [--repeats 3]
"""

from __future__ import annotations

import argparse
import math
import tempfile
import time
from pathlib import Path

import pinwind
from pinwind.dynamics.drivetrain import drivetrain
from pinwind.dynamics.run_settings import RunSettings
from pinwind.dynamics.simulate import prepare, simulate
from pinwind.runs.scenario import Scenario
from pinwind.runs.session import Session

MODEL = Path(__file__).resolve().parent.parent / "models" / "saleh2017_planetary.urdf"
SCENARIO = Path(__file__).resolve().parent.parent / "scenarios" / "saleh2017_drivetrain.toml"
DT = 1e-3
TORQUES = {"carrier": 1e6, "sun": -1e6 / 6}


def main(argv: list[str] | None = None) -> None:
    """Measures and prints the three costs."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=2000)
    parser.add_argument("--steps", type=int, default=10)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--no-fmu", action="store_true")
    args = parser.parse_args(argv)
    gearbox = pinwind.load(MODEL)
    h = args.steps * DT
    duration = args.points * h
    whole, loop, session_s, state_s, changing_s = [], [], [], [], []
    fmu_s: dict[int, list[float]] = {2: [], 3: []}
    for _ in range(args.repeats):
        started = time.perf_counter()
        simulate(gearbox, duration=duration, dt=DT, torques=TORQUES, keep="last")
        whole.append(time.perf_counter() - started)
        run = prepare(drivetrain(gearbox, torques=TORQUES), duration=duration, dt=DT,
                      settings=RunSettings(keep="last"))  # fmt: skip
        started = time.perf_counter()
        run.run()
        loop.append(time.perf_counter() - started)
        inputs = {f"torque.{j}": t for j, t in TORQUES.items()}
        session = Session(gearbox, Scenario(dt=DT, duration=duration), inputs=list(inputs),
                          start=inputs)  # fmt: skip
        started = time.perf_counter()
        for i in range(args.points):
            session.advance((i + 1) * h, inputs)
        session_s.append(time.perf_counter() - started)
        state_s.append(_state_time(session))
        # the same with every input changed at every point (the held rows computed again)
        session = Session(gearbox, Scenario(dt=DT, duration=duration), inputs=list(inputs),
                          start=inputs)  # fmt: skip
        changed = [{k: v * (1.0 + 1e-6 * (i % 2)) for k, v in inputs.items()} for i in range(2)]
        started = time.perf_counter()
        for i in range(args.points):
            session.advance((i + 1) * h, changed[i % 2])
        changing_s.append(time.perf_counter() - started)
        if not args.no_fmu:
            for version, times in fmu_s.items():
                times.append(_fmu_time(args.points, h, duration, inputs, version))
    per = 1e6 / args.points
    print(f"planetary stage: {args.points} points of {args.steps} steps (dt = {DT:g} s), "
          f"best of {args.repeats}")  # fmt: skip
    print(f"simulate end to end   {min(whole) * per:9.1f} µs per point")
    print(f"simulate step loop    {min(loop) * per:9.1f} µs per point")
    print(f"session advance       {min(session_s) * per:9.1f} µs per point "
          f"(overhead {min(session_s) / min(loop) - 1:+.1%} beside the step loop, "
          f"{min(session_s) / min(whole) - 1:+.1%} beside simulate end to end)")  # fmt: skip
    print(f"  inputs changed      {min(changing_s) * per:9.1f} µs per point "
          f"(overhead {min(changing_s) / min(loop) - 1:+.1%})")  # fmt: skip
    print(f"state() + restore()   {min(state_s) * 1e6:9.1f} µs at the run's end "
          f"({args.points * args.steps} steps)")  # fmt: skip
    for version, times in fmu_s.items():
        if times:
            print(f"FMU {version} under FMPy      {min(times) * per:9.1f} µs per point")
    _drivetrain(args.points, args.steps, args.repeats)


def _state_time(session: Session, count: int = 20) -> float:
    """Seconds per ``state()`` and ``restore()`` pair at the session's time, best of ``count``."""
    best = math.inf
    for _ in range(count):
        started = time.perf_counter()
        session.restore(session.state())
        best = min(best, time.perf_counter() - started)
    return best


def _drivetrain(points: int, steps: int, repeats: int) -> None:
    """The same for Saleh 2017's drivetrain scenario (rotor, two stages, generator), wind held."""
    from pinwind.runs.scenario import load_scenario

    h = steps * DT
    scenario = load_scenario(SCENARIO, changes={"duration": points * h, "wind": 10.0})
    gearbox = scenario.load_model()
    loop, session_s = [], []
    for _ in range(repeats):
        run = prepare(scenario.drivetrain(gearbox), duration=scenario.duration, dt=DT,
                      settings=RunSettings(keep="last"))  # fmt: skip
        started = time.perf_counter()
        run.run()
        loop.append(time.perf_counter() - started)
        session = Session(gearbox, scenario, inputs=["wind"], start={"wind": 10.0})
        started = time.perf_counter()
        for i in range(points):
            session.advance((i + 1) * h, {"wind": 10.0})
        session_s.append(time.perf_counter() - started)
    per = 1e6 / points
    print(
        f"drivetrain scenario (wind held): step loop {min(loop) * per:.1f} µs, session "
        f"{min(session_s) * per:.1f} µs per point ({min(session_s) / min(loop) - 1:+.1%})"
    )


def _fmu_time(
    points: int, h: float, duration: float, inputs: dict[str, float], version: int
) -> float:
    """Seconds of ``points`` FMPy set/doStep/get calls on the FMI ``version`` (2 or 3) FMU."""
    import fmpy
    from fmpy.fmi2 import FMU2Slave
    from fmpy.fmi3 import FMU3Slave

    from pinwind.runs.fmu_export import export_fmu

    folder = Path(tempfile.mkdtemp(prefix="pinwind_bench_"))
    fmu = export_fmu(MODEL, folder / "gearbox.fmu", inputs=list(inputs), dt=DT, duration=duration,
                     fmi_version=version)  # fmt: skip
    description = fmpy.read_model_description(str(fmu))
    refs = {v.name: v.valueReference for v in description.modelVariables}
    kind = FMU2Slave if version == 2 else FMU3Slave
    slave = kind(guid=description.guid, unzipDirectory=fmpy.extract(str(fmu)),
                 modelIdentifier=description.coSimulation.modelIdentifier,
                 instanceName="gearbox")  # fmt: skip
    slave.instantiate()
    if version == 2:
        slave.setupExperiment(startTime=0.0, stopTime=duration)
        slave.enterInitializationMode()
        put, get = slave.setReal, slave.getReal
    else:  # the unit's duration is its own (PythonFMU3 passes no stop time on)
        slave.enterInitializationMode(startTime=0.0, stopTime=duration)
        put, get = slave.setFloat64, slave.getFloat64
    names = list(inputs)
    put([refs[n] for n in names], [inputs[n] for n in names])
    slave.exitInitializationMode()
    outputs = [refs["speed.carrier"], refs["mesh_normal.sun_planet1"]]
    started = time.perf_counter()
    for i in range(points):
        put([refs[n] for n in names], [inputs[n] for n in names])
        slave.doStep(currentCommunicationPoint=i * h, communicationStepSize=h)
        get(outputs)
    elapsed = time.perf_counter() - started
    slave.terminate()
    slave.freeInstance()
    return elapsed


if __name__ == "__main__":
    main()
