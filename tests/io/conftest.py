"""Logged runs shared by the log tests: the Saleh planetary stage under a time-varying torque."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import pytest
from rerun.chunk import RrdReader

import pinwind
from pinwind.dynamics.result import Result
from pinwind.loads.generator import LinearSlip
from pinwind.loads.rotor import Rotor
from pinwind.loads.signals import Ramp, Sine
from pinwind.model.gearbox import loads
from tests.conftest import MODELS, two_gear_urdf

PLANETARY = MODELS / "saleh2017_planetary.urdf"
DT = 1e-3
DURATION = 0.25
#: Samples per observer call (and per MCAP chunk) in the shared run: 251 samples → 100, 100, 51.
CHUNK = 100
#: Link poses go to the log at 100 Hz (pinwind.io.log_writer.POSE_RATE): every 10th sample of 1 ms.
POSE_EVERY = 10
#: The viewers' topics too (pinwind.io.log_writer.VIEW_RATE, 100 Hz); /pinwind/columns has all.
VIEW_EVERY = 10


class RotorTorque:
    """1 MN·m on the carrier with a 20 % ripple at 7 Hz, so that every series moves."""

    description = "1e6 N·m · (1 + 0.2 sin(2π·7 Hz·t))"

    def __call__(self, t: float) -> float:
        return 1.0e6 * (1.0 + 0.2 * math.sin(2.0 * math.pi * 7.0 * t))


TORQUES = {"carrier": RotorTorque(), "sun": -1.0e6 / 6.0}


@dataclass
class LoggedRun:
    result: Result
    path: Path


@pytest.fixture(scope="session")
def planetary() -> pinwind.Gearbox:
    return pinwind.load(PLANETARY)


@pytest.fixture(scope="session")
def logged_run(planetary, tmp_path_factory) -> LoggedRun:
    """The planetary run, in memory and logged at full rate in chunks of 100 samples."""
    path = tmp_path_factory.mktemp("logs") / "planetary.mcap"
    result = pinwind.simulate(
        planetary, duration=DURATION, dt=DT, torques=TORQUES, log=path, chunk=CHUNK
    )
    return LoggedRun(result, path)


#: The rotor run: a 40 m rotor on shaft a, driven from 1.2 to 1.8 rad/s over 0.2 s, in a wind of
#: 10 ± 2 m/s at 10 Hz; a slip-law generator on b (turning at −½ a).
ROTOR_RADIUS = 40.0
ROTOR_SPEED = Ramp(1.2, 1.8, 0.0, 0.2)
WIND = Sine(10.0, 2.0, 10.0)


@pytest.fixture(scope="session")
def rotor_run(tmp_path_factory) -> LoggedRun:
    """A two-gear pair with a rotor on a and a generator on b, logged in chunks of 50 samples."""
    path = tmp_path_factory.mktemp("logs") / "rotor.mcap"
    pair = loads(two_gear_urdf(), path="pair.urdf")
    result = pinwind.simulate(
        pair,
        duration=0.2,
        dt=1e-3,
        speeds={"a": ROTOR_SPEED},
        rotors={"a": Rotor(radius=ROTOR_RADIUS)},
        wind=WIND,
        generators={"b": LinearSlip(slope=50.0, sync_speed=-1.0)},
        log=path,
        chunk=50,
        progress=False,
    )
    return LoggedRun(result, path)


def column_chunks(path: Path) -> list[tuple[int, int, int]]:
    """(offset, length, first log time [ns]) of the chunks that hold /pinwind/columns, in file
    order (one per block of samples), from the official MCAP reader's summary."""
    from mcap.reader import make_reader

    with open(path, "rb") as f:
        summary = make_reader(f).get_summary()
    columns = next(i for i, c in summary.channels.items() if c.topic == "/pinwind/columns")
    return [
        (c.chunk_start_offset, c.chunk_length, c.message_start_time)
        for c in summary.chunk_indexes
        if columns in c.message_index_offsets
    ]


def rrd_columns(rrd: Path) -> dict[str, dict[str, list]]:
    """entity path → component column → its arrow arrays, read back from an .rrd file."""
    columns: dict[str, dict[str, list]] = {}
    for chunk in RrdReader(rrd).stream().to_chunks():
        batch = chunk.to_record_batch()
        for name in batch.schema.names:
            columns.setdefault(chunk.entity_path, {}).setdefault(name, []).append(
                batch.column(name)
            )
    return columns


@pytest.fixture(scope="session")
def drivetrain_run(tmp_path_factory) -> LoggedRun:
    """Saleh's drivetrain (planetary + parallel stages 83/23, 103/26) for 10 ms: carrier at
    1 rad/s, 10 kN·m on the high-speed pinion."""
    path = tmp_path_factory.mktemp("logs") / "drivetrain.mcap"
    gearbox = pinwind.load(MODELS / "saleh2017_drivetrain.urdf")
    result = pinwind.simulate(
        gearbox,
        duration=0.01,
        dt=1e-3,
        speeds={"carrier": 1.0},
        torques={"stage2_pinion": -1.0e4},
        log=path,
        progress=False,
    )
    return LoggedRun(result, path)
