"""Kinematic ratios from the teeth: every joint turns at the speed the gear train gives it.

For a train driven at ω_in on its input joint, the meshes (and the torsional springs, as the mean
running speeds of spring-coupled shafts) fix every other joint's speed: ω_j = i_j ω_in, i_j the
ratio of the tooth counts through the meshes between them (signed; for a planetary stage with a
fixed ring, sun over carrier 1 + z_ring/z_sun). ``dynamics/ratios.train_speeds`` gives i_j from the
null space of the mesh rows at the reference pose; this check compares a run's speeds with it at
every sample. A rigid train keeps it to rounding; compliant meshes, springs and bearings vibrate
about it (give the tolerance their vibration takes).
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from pinwind.dynamics.ratios import train_speeds
from pinwind.dynamics.result import Result
from pinwind.errors import InputError, UnknownJoint
from pinwind.model.gearbox import Gearbox
from pinwind.testing.figure import CheckFigure


def tooth_ratios(gearbox: Gearbox, input_joint: str) -> dict[str, float]:
    """Joint name → i_j = ω_j / ω_in from the meshes and springs (``train_speeds``), signed.

    The joints the input drives: those whose ratio is not zero (no slide, no locked bearing, no
    joint of another train).
    """
    speeds = train_speeds(gearbox, {input_joint: 1.0}, through_springs=True)
    still = {*gearbox.locked_joints, *gearbox.slide_joints}
    return {
        name: float(speeds[gearbox.v_index(name)])
        for name in gearbox.joint_names
        if name not in still and abs(speeds[gearbox.v_index(name)]) > 1e-12
    }


def speed_ratios(
    result: Result,
    gearbox: Gearbox,
    *,
    input_joint: str,
    joints: Iterable[str] | None = None,
    rtol: float = 1e-9,
) -> CheckFigure:
    """Each joint's speed is i_j times the input's at every sample (module docstring).

    The error of joint j at sample k is |ω_j,k − i_j ω_in,k| / (|i_j| max_k |ω_in,k|): relative
    to the joint's own speed scale over the run.

    Args:
        result: a run of ``gearbox``.
        gearbox: its model.
        input_joint: the joint the ratios are taken from (the rotor's shaft, the carrier).
        joints: the joints to check; default every joint the input drives (``tooth_ratios``).
        rtol: the largest error accepted [-].

    Returns:
        The figure: the largest error over the joints and samples.

    Raises:
        CheckFailed: beyond ``rtol``, naming the joint, its ratio and the sample.
        UnknownJoint: a joint the gearbox does not have; InputError: the input does not turn.
    """
    if input_joint not in gearbox.joint_names:
        raise UnknownJoint(input_joint, "speed_ratios input_joint", gearbox.joint_names)
    ratios = tooth_ratios(gearbox, input_joint)
    names = list(ratios) if joints is None else list(joints)
    for name in names:
        if name not in gearbox.joint_names:
            raise UnknownJoint(name, "speed_ratios joints", gearbox.joint_names)
        if name not in ratios:
            raise InputError(
                f'joint "{name}" does not turn with "{input_joint}" through the meshes and '
                f"springs; joints that do: {', '.join(ratios)}"
            )
    w_in = result.joint(input_joint).speed
    scale = float(np.abs(w_in).max()) if len(w_in) else 0.0
    if not scale > 0.0:
        raise InputError(
            f'the input joint "{input_joint}" does not turn in this run: no ratio to compare'
        )
    worst, where = 0.0, "no joint"
    for name in names:
        i = ratios[name]
        error = np.abs(result.joint(name).speed - i * w_in) / (abs(i) * scale)
        k = int(np.argmax(error))
        if not error[k] <= worst:  # NaN counts as the worst
            worst = float(error[k])
            where = (
                f'joint "{name}" at sample {k} (t = {result.time[k]:.6g} s): '
                f"{result.joint(name).speed[k]:.9g} rad/s against i = {i:.9g} × "
                f"{w_in[k]:.9g} rad/s"
            )
    return CheckFigure(
        "speed_ratios",
        f"each joint's speed against its tooth ratio times \"{input_joint}\"'s, relative to "
        "its speed scale",
        worst,
        rtol,
        where,
    ).enforced()
