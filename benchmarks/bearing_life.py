"""Bearing lives of a logged 5 MW run against the run's own wall time, in one run (issue 39).

The NREL 5 MW gearbox at rated (scenarios/nrel5mw_rated.toml: rotor 3 945 990 N·m at 12.1 rpm,
generator held at 12.1 · 96.354 rpm, dt = 1e-4 s) with the rotor's steady hub loads on the
main shaft at the rotor centre (1.9 m ahead of the shaft's bearing centre): thrust 700 kN,
weight 1.1 MN and the 5.34 MN·m bending moment. The run is logged at 1 kHz; then the lives of
every bearing are computed from the log as ``pinwind life LOG`` does (read the log, rebuild the
model it holds, every row's ISO 281 basic and modified and ISO/TS 16281 reference life, every
whole rated bearing's life or refusal). Printed: both wall times and their ratio (target
≤ 0.1), and the main shaft's rows.

Run:  python benchmarks/bearing_life.py [--duration S] [--out FILE]
"""

from __future__ import annotations

import argparse
import tempfile
import time
import warnings
from pathlib import Path

import pinwind
from pinwind.errors import PinwindWarning
from pinwind.loads.hub_loads import constant_hub_load
from pinwind.units import rpm_to_rad_s

ROOT = Path(__file__).resolve().parents[1]
RATED_TORQUE, ROTOR_RPM = 3945990.3245924464, 12.1
GENERATOR_RPM = -ROTOR_RPM * (1 + 56 / 19) * (1 + 93 / 18) * (95 / 24)
#: Hub loads on the main shaft, fixed frame (hub x along the shaft): thrust, shear, weight,
#: torque (the rotor's torque is applied on its own joint), bending about y and z [N, N·m].
HUB = [7.0e5, 0.0, -1.1e6, 0.0, 5.34e6, 0.0]


def lives_of(log: Path) -> tuple[list, list]:
    """What ``pinwind life LOG`` computes, without printing."""
    from pinwind.io.log_reader import LogReader
    from pinwind.life.bearing_life import bearing_lives
    from pinwind.life.row_life import LIFE_CHANNELS, row_lives
    from pinwind.model.gearbox import loads

    with LogReader(log) as reader:
        res = reader.read(channels=LIFE_CHANNELS)
        text = reader.model_text
    gearbox = loads(text, path=str(log))
    return row_lives(res, gearbox), bearing_lives(res, gearbox)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=2.0, help="simulated time [s]")
    parser.add_argument("--out", type=Path, default=None, help="log file (default: temporary)")
    args = parser.parse_args()
    gb = pinwind.load(ROOT / "models" / "nrel5mw_gearbox.urdf")
    with tempfile.TemporaryDirectory() as tmp:
        log = args.out or Path(tmp) / "nrel5mw_life.mcap"
        started = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PinwindWarning)
            pinwind.simulate(
                gb, duration=args.duration, dt=1e-4, torques={"rotor": RATED_TORQUE},
                speeds={"generator": rpm_to_rad_s(GENERATOR_RPM)},
                initial_speeds={"rotor": rpm_to_rad_s(ROTOR_RPM)},
                hub_loads=[constant_hub_load("lss", HUB, point=(0.0, 0.0, -1.9))],
                log=log, log_rate=1000.0, progress=False, keep="last",
            )  # fmt: skip
        run_s = time.perf_counter() - started
        started = time.perf_counter()
        rows, whole = lives_of(log)
        life_s = time.perf_counter() - started
    print(
        f"5 MW rated with hub loads, {args.duration:g} s at dt = 1e-4 s: run {run_s:.2f} s, "
        f"lives of {len(rows)} rows and {len(whole)} whole bearings {life_s:.2f} s, "
        f"ratio {life_s / run_s:.3f} (target ≤ 0.1)"
    )
    for r in rows:
        if r.bearing == "lss":
            print(
                f"  lss/{r.name:6} {r.kind:18} P {r.equivalent_load / 1e3:8.1f} kN  "
                f"L10h {r.l10h:10.4g}  L10rh {r.l10rh:10.4g}  "
                f"Q_max {r.max_element_load / 1e3:7.1f} kN"
            )


if __name__ == "__main__":
    main()
