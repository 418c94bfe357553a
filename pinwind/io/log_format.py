"""The pinwind log format (docs/log_format.md): its identity, topics and columns layout.

What the writer (``io/log_writer.py``) and the readers (``io/log_reader.py``, ``io/log_legacy.py``,
``io/log_columns.py``) all follow; nothing here reads or writes a file.
"""

from __future__ import annotations

from dataclasses import dataclass

from pinwind.dynamics import series

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
ENERGY_TOPIC = "/run/energy"


def array_topics() -> tuple[ArrayTopic, ...]:
    """The viewer topics of the Result's arrays, in the log's topic order.

    A topic per logged series of the schema (``dynamics/series.py``; angle, speed and torque
    are on ``/joints``, the poses on ``/tf``), family after family (``series.TOPIC_ORDER``), and
    the energy ledger after the run's own series. Read when called: a series declared at run
    time has its topic.
    """
    out = []
    for family in series.TOPIC_ORDER:
        for s in series.of_family(family):
            if s.logged:
                element = "" if s.family == "run" else s.family
                out.append(ArrayTopic(s.topic, s.name, s.unit, s.meaning, element, s.frame))
        if family == "run":
            meaning = "energy ledger (docs/log_format.md)"
            out.append(ArrayTopic(ENERGY_TOPIC, "energy", "J", meaning, "term"))
    return tuple(out)


#: Element kind of a topic → its names in the ``model`` metadata record.
NAMES_OF = {**series.NAMES_OF, "term": "energy_terms"}


def mask_bytes(width: int) -> int:
    """Bytes of the constant-series bits of ``width`` series in a columns payload.

    Whole 8-byte words, so that the values after them stay aligned.
    """
    return 8 * ((width + 63) // 64)
