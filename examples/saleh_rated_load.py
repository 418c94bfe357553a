"""Saleh 2017 drivetrain: the rotor torque ramps to its rated 1 MN·m.

The generator holds the high-speed shaft at the speed that gives 14.2 rpm at the rotor (a speed
driver; its torque is the driver's multiplier); the rotor torque ramps from 0 to 1e6 N·m over the
first half of the run.
Prints the summary table and the closed-form check of the sun mesh at the end of the run.

    python examples/saleh_rated_load.py --duration 2 [--figures figures/saleh]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from rich.console import Console

import pinwind
from pinwind.analysis.summary import summary_tables
from pinwind.dynamics.ratios import speed_ratio
from pinwind.io.figures import plot_log
from pinwind.units import rpm_to_rad_s

MODELS = Path(__file__).resolve().parent.parent / "models"
RATED_TORQUE = 1e6  # N·m, Saleh 2017 §4.1
ROTOR_RPM = 14.2


def main(argv: list[str] | None = None) -> pinwind.Result:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=2.0, help="simulated time [s]")
    parser.add_argument("--dt", type=float, default=1e-3, help="time step [s]")
    parser.add_argument("--out", type=Path, help="MCAP log to write (default: none)")
    parser.add_argument(
        "--figures", type=Path, help="write the run's figures (pinwind plot) into this folder"
    )
    args = parser.parse_args(argv)
    log = args.out or (args.figures / "saleh_rated_load.mcap" if args.figures else None)

    gb = pinwind.load(MODELS / "saleh2017_drivetrain.urdf")
    ratio = speed_ratio(gb, "stage2_pinion", "carrier")  # 6 × 83/23 × 103/26
    ramp = 0.5 * args.duration

    def rotor_torque(t: float) -> float:
        return RATED_TORQUE * min(1.0, t / ramp)

    res = pinwind.simulate(
        gb,
        duration=args.duration,
        dt=args.dt,
        torques={"carrier": rotor_torque},
        speeds={"stage2_pinion": rpm_to_rad_s(ROTOR_RPM) * ratio},
        **({"log": log, "overwrite": True} if log else {}),
    )
    console = Console()
    for table in summary_tables(res):
        console.print(table)
    sun_mesh = gb.mesh("sun_planet1")
    # At constant speed the sun mesh carries the rotor torque's share: T/(ratio·N·r_b,sun).
    expected = RATED_TORQUE / 6 / (3 * sun_mesh.base_radius_a)
    console.print(
        f"sun–planet F_n at the end: {res.mesh('sun_planet1').normal[-1]:.6g} N; "
        f"closed form {expected:.6g} N"
    )
    if args.figures:
        for path in plot_log(log, args.figures):
            console.print(f"wrote {path}")
    return res


if __name__ == "__main__":
    main()
