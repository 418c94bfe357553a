"""Cai's spur pair under quasi-steady input (Kelso 2011 Table 3-3).

A speed driver turns the input shaft at Ω = A sin(2π f t) + 200 rpm (eq. 2-1) against the 49 N·m
brake; the shafts are split in two halves joined by torsional springs (442.3 N·m/rad). Prints the
min / max / RMS of gear contact force and shaft torques per run, in the shape of Table 4-2.

With rigid teeth and no backlash the contact force oscillates about the static value
49 N·m / (r_2 cos α) = 434.5 N; the thesis' compliant contact with backlash (force dropping to 0)
is not what this model computes, so its Table 4-2 values are not expected to match.

    python examples/cai_quasi_steady.py --duration 20
"""

from __future__ import annotations

import argparse
import itertools
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.markup import escape
from rich.table import Table

import pinwind
from pinwind.analysis.summary import statistics
from pinwind.loads.signals import Scaled, Sine
from pinwind.units import RAD_S_PER_RPM

MODELS = Path(__file__).resolve().parent.parent / "models"
AMPLITUDES_RPM = (7.6, 9.2, 11.0)  # Table 3-3
FREQUENCIES_HZ = (0.05, 0.1, 1.0)
# The output shaft turns backwards (external pair), so a brake that resists it pushes forwards.
BRAKE = 49.0  # N·m


def main(argv: list[str] | None = None) -> list[dict]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=20.0, help="simulated time per run [s]")
    parser.add_argument("--dt", type=float, default=1e-4, help="time step [s]")
    parser.add_argument("--runs", type=int, default=9, help="how many of the nine runs")
    parser.add_argument(
        "--damping",
        type=float,
        default=0.05,
        help="spring damping [N·m·s/rad] so the start-up transient dies out",
    )
    parser.add_argument(
        "--figures", type=Path, help="write the run's figures (pinwind plot) into this folder"
    )
    args = parser.parse_args(argv)

    text = (MODELS / "cai_spur_pair.urdf").read_text()
    text = text.replace('damping="0"', f'damping="{args.damping!r}"')
    gb = pinwind.model.gearbox.loads(text, path="cai_spur_pair.urdf (damped)")
    table = Table(title="Quasi-steady loading (rigid mesh), second half of each run")
    for col in (
        "run",
        "A [rpm]",
        "f [Hz]",
        "F min [N]",
        "F max [N]",
        "F RMS [N]",
        "T_in RMS [N·m]",
        "T_out RMS [N·m]",
    ):
        table.add_column(escape(col), justify="right")  # "[rpm]" is a unit, not markup
    rows = []
    cases = list(itertools.product(AMPLITUDES_RPM, FREQUENCIES_HZ))[: args.runs]
    for run, (amp, freq) in enumerate(cases, start=1):
        driver = Scaled(Sine(200.0, amp, freq), RAD_S_PER_RPM)
        res = pinwind.simulate(
            gb,
            duration=args.duration,
            dt=args.dt,
            speeds={"input_shaft": driver},
            torques={"output_shaft": BRAKE},
            **({"log": log, "overwrite": True} if (log := _log(args, run)) else {}),
        )
        late = res.time >= 0.5 * args.duration
        force = statistics(res.mesh("gear_pair").normal[late])
        # Shaft torques: the driver's torque at the input, the spring's twist at the output.
        t_in = statistics(res.joint("input_shaft").torque[late])
        spring = next(s for s in gb.springs if s.name == "output_spring")
        twist = res.joint("gear2").angle[late] - res.joint("output_shaft").angle[late]
        t_out = statistics(spring.stiffness * twist)
        rows.append({"run": run, "force": force, "t_in": t_in, "t_out": t_out})
        table.add_row(
            str(run),
            f"{amp:g}",
            f"{freq:g}",
            f"{force['min']:.1f}",
            f"{force['max']:.1f}",
            f"{force['rms']:.1f}",
            f"{t_in['rms']:.2f}",
            f"{t_out['rms']:.2f}",
        )
    Console().print(table)
    static = BRAKE / (0.120 * np.cos(np.radians(20.0)))
    Console().print(f"static contact force 49 N·m / (r₂ cos α) = {static:.1f} N")
    if args.figures:
        from pinwind.io.figures import plot_log

        for path in plot_log(_log(args, 1), args.figures):
            Console().print(f"wrote {path}")
    return rows


def _log(args, run: int) -> Path | None:
    """The log of the first run, written when figures are asked for."""
    return args.figures / "cai_quasi_steady_run1.mcap" if args.figures and run == 1 else None


if __name__ == "__main__":
    main()
