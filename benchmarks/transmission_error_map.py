"""Cost of the loaded static transmission error over 20 torque levels (the Harris map), one mesh.

`pinwind.gears.transmission_error.transmission_error_map` of the DTU stage's sun–planet mesh
(``models/dtu500_planetary.urdf``) at 20 torques from 5·10⁴ to 4·10⁵ N·m on the sun, 128 roll
positions per mesh cycle: what ``pinwind te MODEL --mesh sun_planet1 --torque 5e4:4e5`` computes,
once with one contact line (an aligned spur pair) and once cut into 40 slices under a 10 µm
misalignment (the command's default for a modified lead). Beside them, the cost of one step of
the same mesh in a compliant run (``sliced_mesh_step.py``'s case), so the map's cost reads as a
number of steps (the whole ``simulate`` call of 20 000 steps over their count, set-up included).
Issue 40's budget: the 20 levels "in a few seconds".

Measured 2026-12-07 17:10 UTC on the shared 2-core machine (``--repeats 3``): one contact line
0.126 s best, 0.166 s median; 40 slices under 10 µm 0.135 s best, 0.197 s median (about 9 000
steps of the compliant DTU stage at 14.6 µs per step). The command itself (``pinwind te
models/dtu500_planetary.urdf --mesh sun_planet1 --torque 5e4:4e5``) took 0.87 s wall with Python's
start-up and the model's load.

Run:  python benchmarks/transmission_error_map.py [--repeats R] [--levels N]
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np
from step_timing import seconds_per_step

import pinwind
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.transmission_error import transmission_error_map
from pinwind.model.compliance import MeshCompliance

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "models" / "dtu500_planetary.urdf"
MESH = "sun_planet1"
CASE = ("carrier", 1.76e5, "sun", 15.75)  # input joint, torque [N·m], output joint, speed [rad/s]


def map_seconds(pair: GearPair, forces: np.ndarray, *, slices: int, misalignment: float) -> float:
    """Wall seconds of one `transmission_error_map` call over ``forces`` [N]."""
    start = time.perf_counter()
    transmission_error_map(pair, forces, misalignment=misalignment, slices=slices)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--levels", type=int, default=20)
    args = parser.parse_args()

    gearbox = pinwind.load(MODEL)
    mesh = next(m for m in gearbox.meshes if m.name == MESH)
    pair = GearPair.from_mesh(mesh)
    forces = np.linspace(5e4, 4e5, args.levels) / pair.geometry.base_radius_1
    one_line, sliced = [], []
    for _ in range(args.repeats):  # interleaved, so a load change on the machine hits both
        one_line.append(map_seconds(pair, forces, slices=1, misalignment=0.0))
        sliced.append(map_seconds(pair, forces, slices=40, misalignment=10e-6))
    step = seconds_per_step(gearbox, CASE, steps=20_000, dt=2e-5, meshes={"all": MeshCompliance()})
    for name, times in (("1 contact line", one_line), ("40 slices, F_β 10 µm", sliced)):
        best = min(times)
        print(
            f"{args.levels} torque levels, {name}: best {best:.3f} s, median "
            f"{statistics.median(times):.3f} s of {args.repeats} (= {best / step:,.0f} steps of "
            f"the compliant DTU stage at {step * 1e6:.2f} µs/step)"
        )


if __name__ == "__main__":
    main()
