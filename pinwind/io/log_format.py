"""The pinwind log format (docs/log_format.md): its identity, topics and columns layout.

What the writer (``io/mcap_log.py``) and the readers (``io/log_reader.py``, ``io/log_columns.py``)
both follow; nothing here reads or writes a file.
"""

from __future__ import annotations

from dataclasses import dataclass

#: Identity of the file format, in the ``pinwind`` metadata record.
FORMAT = "pinwind-log"
#: 3: every array at the log rate as columns (/pinwind/columns), the ROS 2 topics for viewers at
#: the view rate (2: the ROS 2 topics at the log rate and /tf at the pose rate; 1: /tf in every row)
FORMAT_VERSION = 3

MODEL_TOPIC = "/robot_description"
#: Every Result array at the log rate, link poses at the pose rate: one message per block of
#: samples, in a chunk of its own; what ``read_log`` reads.
COLUMNS_TOPIC = "/pinwind/columns"
#: Message encoding of that topic (docs/log_format.md, "Columns"): a layout byte, two counts, a
#: bit per series (constant over the block or not), then float64 little-endian values, series
#: after series (the values of one series, one element of one array, for every sample of the
#: block, are consecutive; a constant series has one value), the varying ones as byte planes.
COLUMNS_ENCODING = "pinwind.columns"
#: The layout byte of a columns payload: 3, the varying series' values as byte planes (2, the
#: values as they are, was never released).
COLUMNS_LAYOUT = 3
JOINTS_TOPIC = "/joints"
TF_TOPIC = "/tf"
#: Parent frame of every link transform on ``/tf``.
WORLD_FRAME = "world"


@dataclass(frozen=True)
class ArrayTopic:
    """A topic of std_msgs/msg/Float64MultiArray messages holding one Result array per sample.

    Attributes:
        topic: MCAP topic (and Rerun entity path).
        field: Result attribute (``energy`` for the energy ledger).
        unit: SI unit of the values.
        description: what the values are.
        element: kind of the first dimension (``joint``, ``mesh``, ``bearing``, ``term``), or
            ``""`` for one value per sample.
        frame: ``world`` or ``joint`` for 3-vectors (second dimension x, y, z), else ``""``.
    """

    topic: str
    field: str
    unit: str
    description: str
    element: str = ""
    frame: str = ""


#: Every Result array except those on ``/joints`` (angle, speed, torque) and ``/tf`` (poses).
ARRAY_TOPICS: tuple[ArrayTopic, ...] = (
    ArrayTopic(
        "/joints/acceleration",
        "acceleration",
        "rad/s^2",
        "joint acceleration over the step that starts at the sample",
        "joint",
    ),
    ArrayTopic("/meshes/normal", "mesh_normal", "N", "tooth normal force F_n >= 0", "mesh"),
    ArrayTopic("/meshes/tangential", "mesh_tangential", "N", "F_t = F_n cos(alpha_w)", "mesh"),
    ArrayTopic("/meshes/radial", "mesh_radial", "N", "F_r = F_n sin(alpha_w)", "mesh"),
    ArrayTopic("/meshes/axial", "mesh_axial", "N", "F_a = F_t tan(beta)", "mesh"),
    ArrayTopic(
        "/meshes/flank",
        "mesh_flank",
        "1",
        "loaded flank s = +1 when A turning positively drives B, else -1",
        "mesh",
    ),
    ArrayTopic(
        "/meshes/transmission_error",
        "transmission_error",
        "m",
        "position mismatch along the line of action",
        "mesh",
    ),
    ArrayTopic(
        "/meshes/force_on_b", "mesh_force_on_b", "N", "tooth force on gear B", "mesh", "world"
    ),
    ArrayTopic("/meshes/pitch_point", "pitch_point", "m", "pitch point", "mesh", "world"),
    ArrayTopic(
        "/meshes/deflection",
        "mesh_deflection",
        "m",
        "compliant mesh: overlap of the loaded flank (negative: gap); rigid: 0",
        "mesh",
    ),
    ArrayTopic(
        "/meshes/contact_position",
        "mesh_contact_position",
        "m",
        "roll position of the entering tooth pair from gear A's base tangency point",
        "mesh",
    ),
    ArrayTopic("/meshes/pairs", "mesh_pairs", "1", "tooth pairs in contact", "mesh"),
    ArrayTopic(
        "/meshes/single_tooth_force",
        "mesh_single_tooth_force",
        "N",
        "normal force on the entering tooth pair, F_n k1/k",
        "mesh",
    ),
    ArrayTopic(
        "/bearings/force",
        "bearing_force",
        "N",
        "force on the child body at the bearing centre",
        "bearing",
        "world",
    ),
    ArrayTopic(
        "/bearings/moment",
        "bearing_moment",
        "N*m",
        "moment on the child body about the bearing centre",
        "bearing",
        "world",
    ),
    ArrayTopic(
        "/bearings/force_local",
        "bearing_force_local",
        "N",
        "force on the child body at the bearing centre",
        "bearing",
        "joint",
    ),
    ArrayTopic(
        "/bearings/moment_local",
        "bearing_moment_local",
        "N*m",
        "moment on the child body about the bearing centre",
        "bearing",
        "joint",
    ),
    ArrayTopic("/run/time", "time", "s", "sample time (exact; log time is rounded to 1 ns)"),
    ArrayTopic(
        "/run/constraint_residual",
        "constraint_residual",
        "m/s or rad/s",
        "max |J v - target| after the step",
    ),
    ArrayTopic("/run/energy", "energy", "J", "energy ledger (docs/log_format.md)", "term"),
    # Generator and rotor elements (Result.generator, Result.rotor); absent without them.
    ArrayTopic(
        "/generators/torque",
        "generator_torque",
        "N*m",
        "generator torque T_gen on the shaft, > 0 generating",
        "generator",
    ),
    ArrayTopic("/rotors/torque", "rotor_torque", "N*m", "aerodynamic torque on the hub", "rotor"),
    ArrayTopic(
        "/rotors/power", "rotor_power", "W", "aerodynamic power 0.5 rho pi R^2 v^3 Cp", "rotor"
    ),
    ArrayTopic(
        "/rotors/tip_speed_ratio", "rotor_tip_speed_ratio", "1", "tip-speed ratio wR/v", "rotor"
    ),
    ArrayTopic(
        "/rotors/power_coefficient", "rotor_power_coefficient", "1", "power coefficient Cp", "rotor"
    ),
    ArrayTopic("/rotors/wind_speed", "rotor_wind_speed", "m/s", "wind speed at the rotor", "rotor"),
)

#: Element kind of a topic → its names in the ``model`` metadata record.
NAMES_OF = {
    "joint": "joint_names",
    "mesh": "mesh_names",
    "bearing": "bearing_names",
    "term": "energy_terms",
    "generator": "generator_names",
    "rotor": "rotor_names",
}


def mask_bytes(width: int) -> int:
    """Bytes of the constant-series bits of ``width`` series in a columns payload.

    Whole 8-byte words, so that the values after them stay aligned.
    """
    return 8 * ((width + 63) // 64)
