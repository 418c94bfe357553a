"""The channels of a pinwind log: which Result arrays each fills, and choosing channels to read.

A read takes channels (MCAP topics: ``/joints``, ``/meshes/normal``, ``/tf``, ...) or folders of
them (``/meshes``); each fills Result arrays, its destinations (the energy ledger one per term,
``energy/<term>``). ``ArrayLayout`` gives the shape of one sample of each destination for the
element names of one log, whatever its format.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping

from pinwind.dynamics import series
from pinwind.dynamics.series import Schema
from pinwind.errors import InputError
from pinwind.io.log_format import ENERGY_TOPIC, JOINTS_TOPIC, NAMES_OF, TF_TOPIC, array_topics

TIME_TOPIC = "/run/time"


class _Channels(Mapping[str, tuple[str, ...]]):
    """Every channel (MCAP topic) that holds samples, and the Result arrays it fills.

    ``/run/time`` is always read. ``channels=`` takes these names, or a folder of them
    (``/meshes``, ``/bearings``, ``/run``). Read from the schema of series
    (``dynamics/series.py``) when used, so a series declared at run time has its channel.
    """

    def __init__(self) -> None:
        self._built: tuple[Schema, dict[str, tuple[str, ...]]] | None = None

    def _table(self) -> dict[str, tuple[str, ...]]:
        # Built once per schema (series.current() is rebound, never changed, by declare and
        # withdraw): a read looks a channel up once per topic, and each build walks the schema.
        schema = series.current()
        if self._built is None or self._built[0] is not schema:
            table = {
                JOINTS_TOPIC: ("angle", "speed", "torque"),
                **{t.topic: (t.field,) for t in array_topics()},
                TF_TOPIC: ("body_position", "body_quaternion"),
            }
            self._built = (schema, table)
        return self._built[1]

    def __getitem__(self, topic: str) -> tuple[str, ...]:
        return self._table()[topic]

    def __iter__(self) -> Iterator[str]:
        return iter(self._table())

    def __len__(self) -> int:
        return len(self._table())


CHANNELS = _Channels()


class UnknownChannel(InputError):
    """``channels=`` (``--channels``) names a channel that pinwind logs do not have."""

    def __init__(self, name: str):
        self.name = name
        super().__init__(
            f'unknown channel "{name}"; channels are: {", ".join(CHANNELS)} (or a folder of '
            "them: /meshes, /bearings, /run)"
        )


def select_channels(channels: Iterable[str] | str | None) -> tuple[str, ...]:
    """The topics asked for: names of ``CHANNELS``, or folders of them; None for every one.

    ``/run/time`` is always included.

    Raises:
        UnknownChannel: a name that is neither a channel nor a folder of channels.
    """
    if channels is None:
        return tuple(CHANNELS)
    if isinstance(channels, str):
        channels = [c for c in channels.split(",") if c.strip()]
    picked = {TIME_TOPIC}
    for name in channels:
        name = name.strip().rstrip("/")
        if name in CHANNELS:
            picked.add(name)
            continue
        under = [t for t in CHANNELS if t.startswith(name + "/")] if name.startswith("/") else []
        if not under:
            raise UnknownChannel(name)
        picked.update(under)
    return tuple(t for t in CHANNELS if t in picked)


class ArrayLayout:
    """The arrays a read of one log fills: destination → shape of one sample.

    Args:
        names: the log's element names (``pinwind.model`` record: ``joint_names``, ...).
        pose_stride: samples k with k mod pose_stride = 0 have link poses.

    Attributes:
        names: as given.
        terms: the energy ledger's terms.
        pose_stride: as given, at least 1.
        count: element kind (``joint``, ``mesh``, ``term``, ...) → how many the log has.
        shapes: destination → shape of one sample.
    """

    def __init__(self, names: dict[str, list[str]], pose_stride: int = 1):
        self.names = names
        self.pose_stride = max(1, int(pose_stride))
        self.terms = names["energy_terms"]
        nj, nm, nb, nl = (
            len(names[k]) for k in ("joint_names", "mesh_names", "bearing_names", "body_names")
        )
        self.count = {"joint": nj, "mesh": nm, "bearing": nb, "term": len(self.terms)}
        self.count.update({kind: len(names.get(key, [])) for kind, key in NAMES_OF.items()})
        self.shapes: dict[str, tuple[int, ...]] = {
            "time": (),
            "angle": (nj,),
            "speed": (nj,),
            "torque": (nj,),
            "body_position": (nl, 3),
            "body_quaternion": (nl, 4),
        }
        for topic in array_topics():
            if topic.field == "energy":
                self.shapes.update({f"energy/{term}": () for term in self.terms})
            elif not topic.element:
                self.shapes[topic.field] = ()
            else:
                count = self.count[topic.element]
                self.shapes[topic.field] = (count, 3) if topic.frame else (count,)

    def keys(self, topics: Iterable[str]) -> list[str]:
        """Destinations filled by the topics (energy split into its terms)."""
        out = []
        for topic in topics:
            if topic == ENERGY_TOPIC:
                out += [f"energy/{term}" for term in self.terms]
            elif topic == TIME_TOPIC:
                out.append("time")
            else:
                out += list(CHANNELS[topic])
        return out
