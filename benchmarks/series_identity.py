"""Every series of a run, saved by one build of the step loop and compared with another's.

A change meant to make the step faster must not change what it computes: this runs the cases
the speed work targets (issue 37), the rigid step of ``saleh2017_planetary`` and
``saleh2017_drivetrain`` under the closed-form torques of ``step_rate.py`` and the
all-bearings-compliant compliant-mesh case of ``compliant_bearing_step.py``, keeping every
sample, and either saves every array of each Result (``Result.arrays()`` and ``energy``) to an
``.npz`` file or compares them with a saved file: per array, the largest difference relative
to the array's largest magnitude, ``max|new − old| / max|old|`` (0 when bit-identical).

    python benchmarks/series_identity.py save before.npz     # with the old module
    python benchmarks/series_identity.py compare before.npz  # with the new one
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


def runs(steps: int) -> dict[str, np.ndarray]:
    """Every array of every case, keyed ``case/series``."""
    out: dict[str, np.ndarray] = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PinwindWarning)
        for name in ("saleh2017_planetary", "saleh2017_drivetrain"):
            path = resolve(name)
            res = pinwind.simulate(
                pinwind.load(path),
                duration=steps * 1e-3,
                dt=1e-3,
                torques=closed_form(path).torques,
                progress=False,
            )
            out.update(arrays(f"{name}/rigid", res))
        name = "saleh2017_planetary"
        joint_in, torque, joint_out, speed = CASES[name]
        res = pinwind.simulate(
            with_compliant_bearings(pinwind.load(ROOT / "models" / f"{name}.urdf")),
            duration=steps * 2e-5,
            dt=2e-5,
            torques={joint_in: torque},
            speeds={joint_out: speed},
            meshes={"all": "compliant"},
            progress=False,
        )
        out.update(arrays(f"{name}/compliant_bearings", res))
    return out


def arrays(case: str, res: pinwind.Result) -> dict[str, np.ndarray]:
    """The Result's arrays and energy terms, keyed ``case/name``."""
    out = {f"{case}/{k}": np.asarray(v) for k, v in res.arrays().items()}
    out.update({f"{case}/energy.{k}": np.asarray(v) for k, v in res.energy.items()})
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("action", choices=["save", "compare"])
    parser.add_argument("file", type=Path)
    parser.add_argument("--steps", type=int, default=3000)
    args = parser.parse_args()
    new = runs(args.steps)
    if args.action == "save":
        np.savez(args.file, **new)
        print(f"saved {len(new)} arrays to {args.file}")
        return
    old = dict(np.load(args.file))
    worst = 0.0
    for key in sorted(set(old) | set(new)):
        if key not in old or key not in new or old[key].shape != new[key].shape:
            print(f"{key}: missing or reshaped")
            worst = np.inf
            continue
        a, b = new[key], old[key]
        same = np.array_equal(a, b, equal_nan=True)
        scale = np.nanmax(np.abs(b)) if b.size and not np.all(np.isnan(b)) else 0.0
        diff = np.nanmax(np.abs(a - b)) if b.size and not same else 0.0
        rel = diff / scale if scale > 0 else diff
        worst = max(worst, rel)
        if not same:
            print(f"{key:60} max|Δ|/max|old| {rel:.2e}")
    print(f"{len(new)} arrays, worst max|Δ|/max|old| {worst:.2e}")


if __name__ == "__main__":
    main()
