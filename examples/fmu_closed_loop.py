"""A closed loop through the gearbox FMU, FMPy as the master, at a 10 ms communication step.

Saleh 2017's planetary stage (ratio 6, rated 1 MN·m at 14.2 rpm on the carrier) exported with
``pinwind fmu``: the master holds a rotor of inertia J_rot whose aerodynamic torque is a table
linear through the rated point, T_aero(ω) = T_r (2 − ω/ω_r), and a generator controller
T_gen = k ω_sun² (region 2) with k = T_r / (6 (6 ω_r)²). Each step the master sends the rotor
speed (``speed.carrier``) and the generator torque (``torque.sun``, braking) and reads the shaft
torque the gearbox needs (``torque.carrier``) and the sun speed; it integrates
J_rot dω/dt = T_aero − T_shaft explicitly. The steady state is the torque balance in closed form:
T_aero(ω) = 6 T_gen(6 ω), so ω = ω_r, the shaft torque T_r and the sun at 6 ω_r.

Run: ``python examples/fmu_closed_loop.py [--duration 4] [--out gearbox.fmu]``.
"""

from __future__ import annotations

import argparse
import math
import tempfile
from pathlib import Path

MODEL = Path(__file__).resolve().parent.parent / "models" / "saleh2017_planetary.urdf"
RATED_TORQUE = 1e6  # T_r [N·m], Saleh 2017
RATED_SPEED = 14.2 * 2 * math.pi / 60  # ω_r [rad/s], 14.2 rpm on the carrier
RATIO = 6.0  # ω_sun / ω_carrier, Saleh 2017 (ring 120 / sun 24 + 1)
ROTOR_INERTIA = 5e5  # J_rot [kg·m²], on the master's side
STEP = 0.01  # communication step [s]: 10 internal steps of 1 ms


def aerodynamic_torque(speed: float) -> float:
    """The rotor's torque [N·m]: a table linear through the rated point (0 at 2 ω_r)."""
    return RATED_TORQUE * (2.0 - speed / RATED_SPEED)


def generator_torque(sun_speed: float) -> float:
    """Region-2 generator torque k ω² [N·m], k putting the balance at the rated point."""
    k = RATED_TORQUE / (RATIO * (RATIO * RATED_SPEED) ** 2)
    return k * sun_speed**2


def main(argv: list[str] | None = None) -> dict[str, float]:
    """Exports the FMU, runs the loop, prints and returns the final values (SI)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=4.0, help="simulated time [s]")
    parser.add_argument("--out", type=Path, default=None, help="the FMU (default: a temp file)")
    args = parser.parse_args(argv)

    import fmpy
    from fmpy.fmi2 import FMU2Slave

    from pinwind.runs.fmu_export import export_fmu

    folder = Path(tempfile.mkdtemp(prefix="pinwind_fmu_"))
    fmu = export_fmu(
        MODEL,
        args.out or folder / "saleh2017_planetary.fmu",
        inputs=["speed.carrier", "torque.sun"],
        outputs=["torque.carrier", "speed.sun", "mesh_normal.sun_planet1"],
        dt=STEP / 10,
        duration=args.duration,
    )
    description = fmpy.read_model_description(str(fmu))
    refs = {v.name: v.valueReference for v in description.modelVariables}
    slave = FMU2Slave(
        guid=description.guid,
        unzipDirectory=fmpy.extract(str(fmu)),
        modelIdentifier=description.coSimulation.modelIdentifier,
        instanceName="gearbox",
    )
    slave.instantiate()
    speed = 0.8 * RATED_SPEED  # the rotor starts below rated
    slave.setupExperiment(startTime=0.0, stopTime=args.duration)
    slave.enterInitializationMode()
    slave.setReal([refs["speed.carrier"], refs["torque.sun"]],
                  [speed, -generator_torque(RATIO * speed)])  # fmt: skip
    slave.exitInitializationMode()
    shaft, sun_speed, mesh = slave.getReal(
        [refs["torque.carrier"], refs["speed.sun"], refs["mesh_normal.sun_planet1"]]
    )
    points = round(args.duration / STEP)
    for i in range(points):
        slave.setReal([refs["speed.carrier"], refs["torque.sun"]],
                      [speed, -generator_torque(sun_speed)])  # fmt: skip
        slave.doStep(currentCommunicationPoint=i * STEP, communicationStepSize=STEP)
        # the rotor, on the master's side: explicit Euler over the communication step
        speed += (aerodynamic_torque(speed) - shaft) * STEP / ROTOR_INERTIA
        shaft, sun_speed, mesh = slave.getReal(
            [refs["torque.carrier"], refs["speed.sun"], refs["mesh_normal.sun_planet1"]]
        )
    slave.terminate()
    slave.freeInstance()
    final = {
        "rotor_speed": speed,
        "sun_speed": sun_speed,
        "shaft_torque": shaft,
        "generator_torque": generator_torque(sun_speed),
        "sun_planet1_normal_force": mesh,
    }
    print(f"rotor {speed * 60 / (2 * math.pi):.4f} rpm (rated 14.2), sun "
          f"{sun_speed * 60 / (2 * math.pi):.4f} rpm, shaft {shaft / 1e3:.2f} kN·m = "
          f"{shaft / final['generator_torque']:.6f} × generator torque")  # fmt: skip
    return final


if __name__ == "__main__":
    main()
