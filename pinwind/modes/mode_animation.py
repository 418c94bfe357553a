"""A natural mode animated in Rerun: the bodies at q₀ + A Re(φ e^{iωt}), drawn by the replay scene.

The mode's shape φ (``dynamics/normal_modes.py``; real, or complex for a mode at speed,
``modes/gyroscopic_modes.py``) is scaled so that its largest motion is visible
and small: a rotation turns the largest pitch circle by ``AMPLITUDE`` of its radius along the
circle, a translation moves its body by ``AMPLITUDE`` of that radius. The bodies' poses follow
from the joint coordinates by Pinocchio's forward kinematics, as a run's do, and go to Rerun as
a run's frames would (``io/replay.send_frames``: gears with their teeth, the model's shapes,
bearings, labels; no force arrows, the mode has no load). The ``time`` timeline is slowed to one
period per second so the viewer plays the motion at a pace the eye can follow; a rigid mode
(0 Hz) is drawn as one slow swing, one period per second too.
"""

from __future__ import annotations

import math
import os
import uuid
from pathlib import Path

import numpy as np
import pinocchio as pin

from pinwind.dynamics.coordinates import coordinates
from pinwind.dynamics.normal_modes import Mode
from pinwind.dynamics.result import Result
from pinwind.io.log_model import model_geometry
from pinwind.io.log_reader import LogFile
from pinwind.io.replay import blueprint, send_frames
from pinwind.model.gearbox import Gearbox

#: Largest motion of the animated shape, as a fraction of the largest pitch radius [-].
AMPLITUDE = 0.05
#: Frames per period of the mode.
FRAMES_PER_PERIOD = 48


def mode_motion(gearbox: Gearbox, mode: Mode, *, periods: int = 3) -> Result:
    """The bodies' poses over ``periods`` periods of ``mode``, one period per second.

    Joint coordinates ``angle`` (n, joints) [rad or m] and the link poses ``body_position``,
    ``body_quaternion``; the other series of the Result are not filled (NaN).
    """
    model, data = gearbox.model, gearbox.model.createData()
    largest = max((g.spec.module * g.spec.teeth / 2 for g in gearbox.gears.values()), default=0.1)
    reach = [largest if c.kind == "rotation" else 1.0 for c in coordinates(gearbox)]
    # A mode at speed moves as Re(φ e^{iωt}) (a whirl's orbit is an ellipse); a real φ as
    # Re(−i φ e^{iωt}) = sin(ωt) φ.
    shape = -1j * mode.shape if mode.complex_shape is None else mode.complex_shape
    scale = float(np.max(np.abs(shape) * reach))
    amplitude = AMPLITUDE * largest / scale if scale > 0.0 else 0.0
    n = periods * FRAMES_PER_PERIOD + 1
    time = np.linspace(0.0, float(periods), n)  # one period per second
    q0 = gearbox.neutral()
    q = q0[None, :] + amplitude * np.real(np.exp(2j * math.pi * time)[:, None] * shape[None, :])
    frames = gearbox.body_frames()
    position = np.zeros((n, len(frames), 3))
    quaternion = np.zeros((n, len(frames), 4))
    for k in range(n):
        pin.framesForwardKinematics(model, data, q[k])
        for i, f in enumerate(frames):
            pose = data.oMf[f]
            position[k, i] = pose.translation
            quaternion[k, i] = pin.Quaternion(pose.rotation).coeffs()
    order = sorted(gearbox.joint_names, key=gearbox.v_index)
    angle = np.stack([q[:, model.joints[model.getJointId(j)].idx_q] for j in order], axis=1)
    return Result(
        joint_names=order,
        mesh_names=[],
        bearing_names=[],
        body_names=[model.frames[f].name for f in frames],
        time=time,
        angle=angle,
        body_position=position,
        body_quaternion=quaternion,
        metadata={"model": gearbox.name, "mode_frequency_hz": mode.frequency},
    )


def save_mode_animation(
    gearbox: Gearbox,
    mode: Mode,
    out: str | os.PathLike,
    *,
    number: int,
    periods: int = 3,
) -> Path:
    """Write a Rerun recording (.rrd) of ``mode`` animated (module docstring).

    Args:
        number: the mode's number in ``pinwind modes``'s list (names the recording).
        periods: periods of the mode drawn.

    Returns:
        The .rrd path.
    """
    import rerun as rr

    result = mode_motion(gearbox, mode, periods=periods)
    view = LogFile(
        path=Path(str(gearbox.path)),
        result=result,
        metadata={"pinwind.model": model_geometry(gearbox)},
        attachments={"model.urdf": gearbox.source_text.encode("utf-8")},
        channels={},
        complete=True,
    )
    path = Path(out)
    path.parent.mkdir(parents=True, exist_ok=True)
    recording = rr.RecordingStream(application_id="pinwind_modes", recording_id=uuid.uuid4())
    recording.save(path)
    recording.send_recording_name(
        f"{gearbox.name} mode {number}: {mode.frequency:.5g} Hz {mode.kind}".strip()
    )
    scene = send_frames(view, recording)
    rr.send_blueprint(blueprint([], scene), recording=recording)
    recording.flush()
    recording.disconnect()
    return path
