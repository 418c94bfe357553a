"""One case's step loop, run for a profiler: instructions per step under callgrind (issue 37).

Runs ``pinwind.simulate`` (or MuJoCo's ``mj_step`` loop) on one case for ``--steps`` steps and
nothing else, so that a profiler restricted to the loop counts what a step costs:

- ``rigid``: the closed-form load case of ``step_rate.py`` (every sample kept, no log), dt 1 ms;
- ``mesh`` / ``bearings``: ``compliant_bearing_step.py``'s case, every mesh compliant, with
  ideal or all turning bearings compliant, ``keep="last"``, dt 20 µs;
- ``mujoco``: the rigid case's model built by ``step_rate.mjcf_from_gearbox``, ``qfrc_applied`` +
  ``mj_step``.

    valgrind --tool=callgrind --dump-instr=no --toggle-collect='pinwind::Stepper::run*' \\
        python benchmarks/step_profile.py saleh2017_planetary rigid --steps 5000
    valgrind --tool=callgrind --dump-instr=no --toggle-collect='mj_step' \\
        python benchmarks/step_profile.py saleh2017_planetary mujoco --steps 5000

Instructions per step: the ``I refs`` callgrind prints over ``--steps``.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

import pinwind
from pinwind.errors import PinwindWarning

sys.path.insert(0, str(Path(__file__).resolve().parent))
from compliant_bearing_step import CASES, with_compliant_bearings  # noqa: E402
from step_rate import closed_form, resolve  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("model", help="a name in models/")
    parser.add_argument("case", choices=["rigid", "mesh", "bearings", "mujoco"])
    parser.add_argument("--steps", type=int, default=5000)
    args = parser.parse_args()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        if args.case in ("rigid", "mujoco"):
            path = resolve(args.model)
            gb, cf = pinwind.load(path), closed_form(path)
            if args.case == "mujoco":
                mujoco_loop(gb, cf.torques, args.steps)
                return
            res = pinwind.simulate(
                gb, duration=args.steps * 1e-3, dt=1e-3, torques=cf.torques, progress=False
            )
        else:
            gb = pinwind.load(ROOT / "models" / f"{args.model}.urdf")
            if args.case == "bearings":
                gb = with_compliant_bearings(gb)
            joint_in, torque, joint_out, speed = CASES[args.model]
            res = pinwind.simulate(
                gb,
                duration=args.steps * 2e-5,
                dt=2e-5,
                torques={joint_in: torque},
                speeds={joint_out: speed},
                meshes={"all": "compliant"},
                keep="last",
                progress=False,
            )
    print(f"step loop {res.metadata['wall_time_s'] / args.steps * 1e6:.2f} µs/step")


def mujoco_loop(gb: pinwind.Gearbox, torques: dict[str, float], steps: int) -> None:
    """``steps`` of ``qfrc_applied`` + ``mj_step`` on the gearbox's MuJoCo model, from rest."""
    import mujoco
    from step_rate import mjcf_from_gearbox, mujoco_dof

    mj = mujoco.MjModel.from_xml_string(mjcf_from_gearbox(gb, dt=1e-3))
    tau = np.zeros(mj.nv)
    for joint, value in torques.items():
        tau[mujoco_dof(mj, gb)[joint]] = value
    d = mujoco.MjData(mj)
    for _ in range(steps):
        d.qfrc_applied[:] = tau
        mujoco.mj_step(mj, d)


if __name__ == "__main__":
    main()
