"""The NREL 5 MW gearbox's efficiency at rated with friction in the step, at dt and dt/2.

The run of docs/losses.md "With the friction in the step": ``models/nrel5mw_gearbox.urdf`` at
5 MW and 12.1 rpm (the generator held at 12.1 × 97.0 rpm), every mesh compliant with μ from
ISO/TR 14179-2 (``--mu constant``: each mesh's mean μ_mz over a rigid run of 0.01 s at rated from
1 ms on, as ``friction_coefficient``; ``--mu iso14179``: μ_mz in the step at every step), every
bearing with Palmgren's friction (VG 320 at 70 °C, Ra 0.5 µm), from the static start. Prints
each stage's mesh and bearing losses and efficiency over the second half of the run, for each
dt, and the after-the-run estimate of the meshes' losses (Ohlendorf's H_V) on the finest run's
loads beside the step's.

Run:  python benchmarks/nrel5mw_efficiency.py [--duration S] [--dt S] [--halvings N] [--mu LAW]
"""

from __future__ import annotations

import argparse
import math
import re
import time
from pathlib import Path

import numpy as np

import pinwind
from pinwind.analysis.efficiency import efficiency, mesh_friction_coefficients
from pinwind.losses.oil import Lubricant
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import loads

ROOT = Path(__file__).resolve().parents[1]
MODEL = ROOT / "models" / "nrel5mw_gearbox.urdf"
RPM = 2.0 * math.pi / 60.0
RATIO = (1 + 56 / 19) * (1 + 93 / 18) * (95 / 24)  # Nejad et al. 2016: 97.0
OIL = Lubricant(320, 343.15)  # VG 320 at 70 °C
ROUGHNESS = 0.5e-6  # Ra [m]


def rated(gb, *, duration: float, dt: float, meshes=None):
    return pinwind.simulate(
        gb,
        duration=duration,
        dt=dt,
        torques={"rotor": 5e6 / (12.1 * RPM)},
        speeds={"generator": -12.1 * RPM * RATIO},
        initial_speeds={"rotor": 12.1 * RPM},
        meshes=meshes,
    )


def with_bearing_friction():
    text = re.sub(
        r"<bearing joint=",
        '<bearing friction_model="iso_tr_14179_2" lubricant_vg="320" temperature_C="70" joint=',
        MODEL.read_text(),
    )
    return loads(text, path=str(MODEL))


def stage_table(res, gb, source: str = "auto") -> list[tuple[str, float, float, float]]:
    """(stage, mesh loss [kW], bearing loss [kW], η) over the second half of the run."""
    e = efficiency(res, gb, oil=OIL, roughness=ROUGHNESS, source=source)
    half = slice(len(e.time) // 2, None)
    rows = []
    for s in e.stages:
        mesh, bearing = np.mean(s.mesh_loss[half]), np.mean(s.bearing_loss[half])
        rows.append(
            (
                s.stage.name,
                mesh / 1e3,
                bearing / 1e3,
                1 - (mesh + bearing) / np.mean(s.input_power[half]),
            )
        )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=0.1)
    parser.add_argument("--dt", type=float, default=5e-5)
    parser.add_argument("--halvings", type=int, default=1)
    parser.add_argument("--mu", choices=("constant", "iso14179"), default="constant")
    args = parser.parse_args()

    gb = with_bearing_friction()
    if args.mu == "constant":
        rigid = pinwind.load(MODEL)
        first = rated(rigid, duration=0.01, dt=1e-4)
        mu = mesh_friction_coefficients(first, rigid, oil=OIL, start=1e-3)
        meshes = {name: MeshCompliance(friction_coefficient=value) for name, value in mu.items()}
    else:
        meshes = {
            m.name: MeshCompliance(friction_coefficient="iso14179", oil=OIL, roughness=ROUGHNESS)
            for m in gb.meshes
        }
    res = None
    for k in range(args.halvings + 1):
        dt = args.dt / 2**k
        start = time.process_time()
        res = rated(gb, duration=args.duration, dt=dt, meshes=meshes)
        took = time.process_time() - start
        print(f"μ {args.mu}, {args.duration:g} s at dt = {dt:g} s ({took:.1f} s CPU), second half:")
        overall = 1.0
        for name, mesh, bearing, eta in stage_table(res, gb):
            overall *= eta
            print(
                f"  {name}: meshes {mesh:7.2f} kW, bearings {bearing:6.2f} kW, η {100 * eta:.3f} %"
            )
        print(f"  overall η {100 * overall:.3f} %")
    if res is not None:
        print("after-the-run estimate (H_V) on the last run's loads:")
        for name, mesh, _, _ in stage_table(res, gb, source="estimate"):
            print(f"  {name}: meshes {mesh:7.2f} kW")


if __name__ == "__main__":
    main()
