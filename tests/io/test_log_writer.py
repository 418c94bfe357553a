"""MCAP logs: round trip, contents readable without pinwind, and faults (raise, interrupt, cut)."""

from __future__ import annotations

import hashlib
import json
import struct
import time
import warnings
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap.stream_reader import StreamReader

import pinwind
from pinwind.dynamics.result import POSE_ARRAYS
from pinwind.errors import (
    InputError,
    InvalidLogRate,
    LogError,
    LogExists,
    LogRecovered,
    SamplesNotLogged,
    TorquesUnbalanced,
)
from pinwind.gears.contact import pairs_in_contact
from pinwind.io import log_writer
from pinwind.io.log_reader import LogDamaged, LogReader, open_log
from pinwind.io.log_writer import McapLogger
from pinwind.io.messages import decode_string
from pinwind.runs.run import log_path
from tests.io.conftest import (
    CHUNK,
    DT,
    DURATION,
    PLANETARY,
    POSE_EVERY,
    TORQUES,
    VIEW_EVERY,
    column_chunks,
)


def assert_same_arrays(
    actual: pinwind.Result, expected: pinwind.Result, *, pose_every: int = POSE_EVERY
) -> None:
    """Every array and name of two Results, bit for bit (float64 compared as raw bits).

    Link poses are logged at sample k = 0, pose_every, 2 pose_every, ... only: ``actual`` has
    the poses of those of ``expected``'s posed samples, and no others.
    """
    for name in ("joint_names", "mesh_names", "bearing_names", "body_names"):
        assert getattr(actual, name) == getattr(expected, name), name
    logged = np.rint(expected.pose_time / DT).astype(np.int64) % pose_every == 0
    np.testing.assert_array_equal(actual.pose_rows, expected.pose_rows[logged])
    for name in expected.ARRAYS:
        a, b = getattr(actual, name), getattr(expected, name)
        if name in POSE_ARRAYS:
            b = b[logged]
        assert a.dtype == np.float64 and a.shape == b.shape, name
        np.testing.assert_array_equal(a.view(np.uint64), b.view(np.uint64), err_msg=name)
    assert list(actual.energy) == list(expected.energy)
    for key, values in expected.energy.items():
        np.testing.assert_array_equal(actual.energy[key], values, err_msg=key)


# --- round trip ---------------------------------------------------------------------------------


def test_read_log_returns_the_simulated_arrays_bit_for_bit(logged_run):
    back = pinwind.read_log(logged_run.path)
    assert len(back) == round(DURATION / DT) + 1
    assert_same_arrays(back, logged_run.result)
    assert back.status == "completed"


@pytest.mark.parametrize("compression", ["", "lz4"])
def test_a_log_with_other_chunk_compression_reads_back_bit_for_bit(
    planetary, tmp_path, compression
):
    # Chunks that are not zstd come back as read-only bytes, not in a reading thread's buffer.
    path = tmp_path / "other.mcap"
    res = pinwind.simulate(
        planetary,
        duration=0.3,
        dt=DT,
        torques=TORQUES,
        chunk=CHUNK,
        observer=McapLogger(path, compression=compression),
    )
    assert_same_arrays(pinwind.read_log(path), res)


def test_read_log_metadata_equals_the_run_metadata(logged_run):
    back = pinwind.read_log(logged_run.path)
    for key, value in logged_run.result.metadata.items():
        if key == "log_path":
            continue
        assert back.metadata[key] == value, key


def test_log_records_model_hash_versions_solver_dt_loads_and_call(logged_run):
    log = open_log(logged_run.path)
    run, ident = log.metadata["pinwind.run"], log.metadata["pinwind"]
    text = PLANETARY.read_text(encoding="utf-8")
    assert run["model_sha256"] == hashlib.sha256(text.encode("utf-8")).hexdigest()
    assert run["dt"] == DT and run["duration"] == DURATION
    assert run["solver"] == logged_run.result.metadata["solver"]
    assert run["torques"]["carrier"] == TORQUES["carrier"].description
    assert ident["pinwind_version"] == pinwind.__version__
    assert ident["versions"]["proxsuite"] and ident["versions"]["pin"]
    assert ident["command"].startswith("pinwind.simulate(pinwind.load(")
    assert "1e6 N·m · (1 + 0.2 sin(2π·7 Hz·t))" in ident["command"]


def test_log_attaches_the_model_file_verbatim_and_publishes_it(logged_run):
    text = PLANETARY.read_text(encoding="utf-8")
    with open(logged_run.path, "rb") as f:
        reader = make_reader(f)
        attachments = list(reader.iter_attachments())
        descriptions = [
            decode_string(m.data) for _, _, m in reader.iter_messages(topics=["/robot_description"])
        ]
    assert [a.name for a in attachments] == ["saleh2017_planetary.urdf"]
    assert attachments[0].data.decode("utf-8") == text
    assert open_log(logged_run.path).model_text == text
    assert descriptions == [text]


def test_official_mcap_reader_sees_every_message_with_valid_crcs(logged_run):
    n = len(logged_run.result)
    with open(logged_run.path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        counts, log_times = {}, []
        for _, channel, message in reader.iter_messages(log_time_order=True):
            counts[channel.topic] = counts.get(channel.topic, 0) + 1
            log_times.append(message.log_time)
    assert summary.statistics.message_count == sum(counts.values())
    assert np.all(np.diff(log_times) >= 0)  # /tf records after each block's rows are sorted in
    assert counts.pop("/robot_description") == 1
    assert counts.pop("/tf") == len(range(0, n, POSE_EVERY))
    # a block's columns and its closing record, for the blocks of 100, 100 and 51 samples
    assert counts.pop("/pinwind/columns") == 2 * -(-n // CHUNK)
    assert set(counts.values()) == {len(range(0, n, VIEW_EVERY))}  # the viewers' topics
    assert "/meshes/normal" in counts and "/joints" in counts
    with open(logged_run.path, "rb") as f:
        records = list(StreamReader(f, validate_crcs=True).records)  # raises on a bad CRC
    assert records


def test_log_time_is_simulation_time_and_sequence_is_sample_index(logged_run):
    time = logged_run.result.time
    with open(logged_run.path, "rb") as f:
        stamps = [
            (m.log_time, m.sequence)
            for _, _, m in make_reader(f).iter_messages(topics=["/meshes/normal"])
        ]
    log_time, sequence = np.array(stamps).T
    viewed = np.arange(0, len(time), VIEW_EVERY)  # the viewers' topics are at the view rate
    np.testing.assert_array_equal(log_time, np.rint(time[viewed] * 1e9).astype(np.int64))
    np.testing.assert_array_equal(sequence, viewed)


def test_channels_name_their_elements_units_and_frames(logged_run):
    channels = open_log(logged_run.path).channels
    res = logged_run.result
    assert json.loads(channels["/meshes/normal"]["names"]) == res.mesh_names
    assert channels["/meshes/normal"]["unit"] == "N"
    assert json.loads(channels["/bearings/force_local"]["names"]) == res.bearing_names
    assert channels["/bearings/force_local"]["frame"] == "joint"
    assert json.loads(channels["/joints"]["names"]) == res.joint_names


def test_log_rate_keeps_every_stride_th_sample(planetary, tmp_path):
    path = tmp_path / "decimated.mcap"
    full = pinwind.simulate(
        planetary,
        duration=DURATION,
        dt=DT,
        torques=TORQUES,
        log=path,
        log_rate=100.0,
        chunk=CHUNK,
    )
    back = pinwind.read_log(path)
    stride = round(1.0 / (DT * 100.0))
    assert back.metadata["log_stride"] == stride == 10
    np.testing.assert_allclose(back.metadata["log_rate_hz"], 100.0, rtol=1e-12)
    assert_same_arrays(back, _every(full, stride))


@pytest.mark.parametrize(
    "pose_rate, view_rate, pose_every",
    [(None, None, 1), (50.0, 100.0, 20), (1e6, None, 1), (None, 100.0, 10), (1e6, 100.0, 10)],
)
def test_pose_rate_logs_the_poses_of_every_nth_sample_only(
    planetary, tmp_path, pose_rate, view_rate, pose_every
):
    """Poses are for display: at the pose rate, at most the view rate (1 ms steps here)."""
    path = tmp_path / "poses.mcap"
    full = pinwind.simulate(
        planetary,
        duration=0.1,
        dt=DT,
        torques=TORQUES,
        log=path,
        pose_rate=pose_rate,
        view_rate=view_rate,
    )
    back = pinwind.read_log(path)
    assert back.metadata["pose_stride"] == pose_every
    assert_same_arrays(back, full, pose_every=pose_every)


def _every(res: pinwind.Result, stride: int) -> pinwind.Result:
    return res.take(slice(0, len(res), stride))


# --- file names and overwriting -----------------------------------------------------------------


def test_existing_log_is_never_overwritten_without_overwrite(planetary, tmp_path):
    path = tmp_path / "keep.mcap"
    path.write_bytes(b"precious")
    with pytest.raises(LogExists, match="keep.mcap: the file already exists"):
        pinwind.simulate(planetary, duration=0.01, dt=DT, torques=TORQUES, log=path)
    assert path.read_bytes() == b"precious"
    pinwind.simulate(planetary, duration=0.01, dt=DT, torques=TORQUES, log=path, overwrite=True)
    assert len(pinwind.read_log(path)) == 11


def test_bare_log_names_go_in_the_logs_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert log_path("run.mcap", "m").as_posix() == "logs/run.mcap"
    assert log_path(tmp_path / "x" / "run.mcap", "m") == tmp_path / "x" / "run.mcap"
    first = log_path(True, "saleh")
    assert first.parent.as_posix() == "logs" and first.name.startswith("saleh_")
    first.parent.mkdir()
    first.touch()
    assert log_path(True, "saleh") != first


def test_bad_log_rate_is_refused_before_the_run(planetary, tmp_path):
    with pytest.raises(InvalidLogRate, match="positive number"):
        pinwind.simulate(planetary, duration=0.01, dt=DT, log=tmp_path / "r.mcap", log_rate=0.0)
    assert not (tmp_path / "r.mcap").exists()


def test_log_rate_above_the_sample_rate_is_refused_before_the_run(planetary, tmp_path):
    # dt = 1 ms computes 1000 samples per second: 1500 Hz cannot be logged.
    with pytest.raises(InvalidLogRate, match="1500 Hz is above the sample rate 1/dt = 1000 Hz"):
        pinwind.simulate(planetary, duration=0.01, dt=DT, log=tmp_path / "r.mcap", log_rate=1500)
    assert not (tmp_path / "r.mcap").exists()


# --- runs that stop early -----------------------------------------------------------------------


class FailsBetween:
    """Carrier torque that raises ``error`` for start ≤ t < start + 0.02 s (not at t = 0)."""

    def __init__(self, error: BaseException, start: float = 0.1):
        self.error = error
        self.start = start

    def __call__(self, t: float) -> float:
        if self.start <= t < self.start + 0.02:
            raise self.error
        return 1.0e6


@pytest.mark.parametrize("fails_at", [100, 137])  # at a block boundary, and inside a block
def test_run_that_raises_leaves_a_readable_log_saying_why(planetary, tmp_path, fails_at):
    path = tmp_path / "failed.mcap"
    t_fail = fails_at * DT
    with pytest.raises(InputError, match="sensor feed lost") as info:
        with pytest.warns(TorquesUnbalanced):
            pinwind.simulate(
                planetary,
                duration=DURATION,
                dt=DT,
                log=path,
                chunk=CHUNK,
                torques={
                    "carrier": FailsBetween(RuntimeError("sensor feed lost"), t_fail - DT / 2)
                },
            )
    assert isinstance(info.value.__cause__, RuntimeError)
    assert f"at t = {t_fail:g} s (step {fails_at})" in str(info.value)
    log = open_log(path)
    assert log.complete
    end = log.metadata["pinwind.end"]
    assert end["status"].startswith(f"failed at step {fails_at} (t = {t_fail:g} s)")
    assert end["cause"].startswith('InputError: torques["carrier"] raised RuntimeError')
    # Every sample before the failing step is in the log, none after it.
    with pytest.warns(TorquesUnbalanced):
        clean = pinwind.simulate(
            planetary, duration=(fails_at - 1) * DT, dt=DT, torques={"carrier": 1.0e6}
        )
    assert len(log.result) == fails_at == len(clean)
    assert_same_arrays(log.result, clean)


def test_interrupted_run_leaves_a_readable_log_saying_why(planetary, tmp_path):
    path = tmp_path / "interrupted.mcap"
    with pytest.raises(KeyboardInterrupt):
        with pytest.warns(TorquesUnbalanced):
            pinwind.simulate(
                planetary,
                duration=DURATION,
                dt=DT,
                log=path,
                chunk=CHUNK,
                torques={"carrier": FailsBetween(KeyboardInterrupt())},
            )
    back = pinwind.read_log(path)
    assert back.status == "interrupted at step 100 (t = 0.1 s)"
    assert len(back) == 100


def test_input_error_before_the_run_leaves_no_log(planetary, tmp_path):
    path = tmp_path / "never.mcap"
    with pytest.raises(pinwind.PinwindError, match='unknown joint "sunn"'):
        pinwind.simulate(planetary, duration=0.01, dt=DT, torques={"sunn": 1.0}, log=path)
    assert not path.exists()


def test_killed_writer_leaves_its_complete_chunks_readable(planetary, logged_run, tmp_path):
    """A process killed mid-run: begin and two chunks reached the file, end never ran."""
    path = tmp_path / "killed.mcap"
    logger = McapLogger(path)
    res = logged_run.result
    logger.begin(planetary, res)
    logger.samples(res.rows(0, CHUNK), 0)
    logger.samples(res.rows(CHUNK, 2 * CHUNK), CHUNK)
    logger.flush()
    logger._stream.close()  # what the OS has when the process dies
    with pytest.warns(LogRecovered, match="recovered 200 samples"):
        back = pinwind.read_log(path)
    assert back.status.startswith("log cut short: no end-status record")
    assert_same_arrays(back, res.truncated(2 * CHUNK))


def test_run_stopped_before_its_first_block_reads_as_no_samples(planetary, logged_run, tmp_path):
    path = tmp_path / "empty.mcap"
    logger = McapLogger(path)
    logger.begin(planetary, logged_run.result)
    logger.end(logged_run.result.truncated(0), "failed at step 0 (t = 0 s): no solution")
    with pytest.warns(SamplesNotLogged):
        back = pinwind.read_log(path)
    assert len(back) == 0 and back.angle.shape == (0, len(back.joint_names))
    assert back.status == "failed at step 0 (t = 0 s): no solution"


# --- damaged and foreign files ------------------------------------------------------------------


def test_truncated_log_recovers_the_samples_of_its_complete_chunks(logged_run, tmp_path):
    chunks = column_chunks(logged_run.path)
    assert len(chunks) == 3  # samples 0-99, 100-199, 200-250
    start, length, _ = chunks[2]
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(logged_run.path.read_bytes()[: start + length // 2])
    with pytest.warns(LogRecovered, match=f"ends inside a chunk record at byte {start}"):
        log = open_log(cut)
    assert not log.complete
    assert_same_arrays(log.result, logged_run.result.truncated(2 * CHUNK))


def test_log_cut_before_its_metadata_gives_one_error(logged_run, tmp_path):
    cut = tmp_path / "stub.mcap"
    cut.write_bytes(logged_run.path.read_bytes()[:300])
    with pytest.raises(LogError, match="stub.mcap: the file ends inside .* nothing to recover"):
        pinwind.read_log(cut)


def test_corrupted_chunk_is_skipped_with_a_warning_naming_file_place_and_time_lost(
    logged_run, tmp_path
):
    start, length, _ = column_chunks(logged_run.path)[1]  # samples 100-199
    data = bytearray(logged_run.path.read_bytes())
    middle = start + length // 2
    data[middle : middle + 16] = bytes(16)
    bad = tmp_path / "bad.mcap"
    bad.write_bytes(bytes(data))
    with pytest.warns(
        LogDamaged, match=rf"bad\.mcap: damaged.*chunk at byte {start} .*t = 0\.1 to 0\.199 s lost"
    ):
        log = open_log(bad)
    kept = np.r_[0:CHUNK, 2 * CHUNK : len(logged_run.result)]
    np.testing.assert_array_equal(log.result.time, logged_run.result.time[kept])


def test_corrupted_record_header_is_skipped_with_a_warning(logged_run, tmp_path):
    start, _, _ = column_chunks(logged_run.path)[0]  # samples 0-99
    data = bytearray(logged_run.path.read_bytes())
    data[start] = 0x7E
    bad = tmp_path / "bad_header.mcap"
    bad.write_bytes(bytes(data))
    with pytest.warns(
        LogDamaged, match=f"chunk at byte {start} is an unknown MCAP record type 0x7e"
    ):
        log = open_log(bad)
    assert len(log.result) == len(logged_run.result) - CHUNK


def test_corrupted_metadata_record_gives_one_error(logged_run, tmp_path):
    with LogReader(logged_run.path) as log:
        offset, _ = log._contents.metadata["pinwind.run"]
    data = bytearray(logged_run.path.read_bytes())
    data[offset + 1] ^= 0x40  # the record's length field
    bad = tmp_path / "bad_run.mcap"
    bad.write_bytes(bytes(data))
    with pytest.raises(LogError, match="'pinwind.run' metadata record at byte .* is damaged"):
        pinwind.read_log(bad)


@pytest.mark.parametrize(
    "content, message",
    [
        (b"", "not an MCAP file (it is empty"),
        (b"<robot name='x'/>", "not an MCAP file (it starts with"),
    ],
)
def test_non_mcap_file_is_refused(tmp_path, content, message):
    path = tmp_path / "x.mcap"
    path.write_bytes(content)
    with pytest.raises(LogError, match=message.replace("(", r"\(")):
        pinwind.read_log(path)


def test_missing_file_and_folder_are_refused(tmp_path):
    with pytest.raises(LogError, match="nope.mcap: no such file"):
        pinwind.read_log(tmp_path / "nope.mcap")
    with pytest.raises(LogError, match="is a folder"):
        pinwind.read_log(tmp_path)


def test_foreign_mcap_is_refused_naming_its_topics(tmp_path):
    from mcap.writer import Writer

    path = tmp_path / "camera.mcap"
    with open(path, "wb") as f:
        writer = Writer(f)
        writer.start(profile="", library="camera-recorder 2.0")
        schema = writer.register_schema("raw", "", b"")
        channel = writer.register_channel("/camera/image", "raw", schema)
        writer.add_message(channel, log_time=1, data=b"\x00" * 8, publish_time=1)
        writer.finish()
    with pytest.raises(LogError, match=r"not a pinwind log .*camera-recorder 2\.0.*/camera/image"):
        pinwind.read_log(path)


def test_log_of_a_newer_format_is_refused(planetary, tmp_path, monkeypatch):
    path = tmp_path / "future.mcap"
    monkeypatch.setattr(log_writer, "FORMAT_VERSION", 99)
    pinwind.simulate(planetary, duration=0.01, dt=DT, torques=TORQUES, log=path)
    monkeypatch.undo()
    with pytest.raises(LogError, match="format version 99 is newer than this pinwind reads"):
        pinwind.read_log(path)


def test_reading_a_complete_log_warns_nothing(logged_run):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        pinwind.read_log(logged_run.path)


def test_log_folder_that_cannot_be_created_is_one_clear_error(planetary, tmp_path):
    blocker = tmp_path / "not_a_folder"
    blocker.write_text("a file where the log folder should be")
    with pytest.raises(LogError, match="cannot create the folder .*not_a_folder for the log"):
        pinwind.simulate(planetary, duration=0.01, dt=DT, log=blocker / "run.mcap")


def test_a_writer_slower_than_the_steps_holds_the_run_back_instead_of_queueing_blocks(
    planetary, tmp_path, monkeypatch
):
    """Memory must not grow with the run when zstd is slower than the step: the queue of blocks
    waiting for the writer thread stays bounded, and every sample still reaches the file."""
    assemble = McapLogger._assemble_columns
    waiting: list[int] = []

    def slow(self, block, rows, samples):
        waiting.append(self._jobs.qsize())
        time.sleep(0.005)  # a chunk takes longer to write than the run takes to step it
        return assemble(self, block, rows, samples)

    monkeypatch.setattr(McapLogger, "_assemble_columns", slow)
    path = tmp_path / "slow.mcap"
    blocks = 60
    res = pinwind.simulate(
        planetary, duration=blocks * 10 * DT, dt=DT, torques=TORQUES, log=path, chunk=10
    )
    assert len(waiting) == blocks + 1  # the last block holds the final sample alone
    assert max(waiting) <= log_writer.MAX_QUEUED_BLOCKS
    assert_same_arrays(pinwind.read_log(path), res)


# --- format 3: columns at the log rate, viewers' topics at the view rate --------------------------


def test_columns_payload_decoded_by_hand_from_the_documented_layout_equals_the_run(logged_run):
    """docs/log_format.md, "Columns": layout byte 3, m and p (uint32), a bit per series that is
    constant over the block (8-byte words), the byte planes of the varying series' m values
    (byte 0 of every value, then byte 1, ...), the constant ones' single values, then the posed
    samples' series."""
    res = logged_run.result
    with open(logged_run.path, "rb") as f:
        reader = make_reader(f)
        channel = next(
            c for c in reader.get_summary().channels.values() if c.topic == "/pinwind/columns"
        )
        columns = json.loads(channel.metadata["columns"])
        pose_columns = json.loads(channel.metadata["pose_columns"])
        payloads = [m.data for _, _, m in reader.iter_messages(topics=["/pinwind/columns"])]
    width = sum(int(np.prod(shape)) for _, shape in columns)
    pose_width = sum(int(np.prod(shape)) for _, shape in pose_columns)
    words = (width + 63) // 64
    got: dict[str, list] = {key: [] for key, _ in columns}
    pose_time = []
    closing = 0
    for data in payloads:
        assert data[0] == 3
        m, p = struct.unpack_from("<II", data, 1)
        flags = int.from_bytes(data[9 : 9 + 8 * words], "little")
        constant = [bool(flags >> i & 1) for i in range(width)]
        values = np.frombuffer(data, "<f8", offset=9 + 8 * words)
        if m == 0:
            closing += 1
            assert not any(constant) and len(values) == 0
            continue
        varying = width - sum(constant)
        assert len(values) == varying * m + sum(constant) + pose_width * p
        series, singles = [], iter(values[varying * m : varying * m + sum(constant)])
        planes = np.frombuffer(data, np.uint8, 8 * varying * m, 9 + 8 * words).reshape(8, -1)
        unshuffled = np.ascontiguousarray(planes.T).view("<f8")  # (V · m, 1): byte b of value i
        rows = iter(unshuffled.reshape(varying, m))
        for i in range(width):
            series.append(np.full(m, next(singles)) if constant[i] else next(rows))
        series = np.array(series)
        at = 0
        for key, shape in columns:
            count = int(np.prod(shape))
            got[key].append(series[at : at + count].T.reshape(m, *shape))
            at += count
        pose_time.append(values[len(values) - pose_width * p :].reshape(pose_width, p)[0])
    assert closing == 3  # a closing record per block
    for key, parts in got.items():
        expected = res.energy[key[7:]] if key.startswith("energy/") else getattr(res, key)
        np.testing.assert_array_equal(np.concatenate(parts), expected, err_msg=key)
    np.testing.assert_array_equal(np.concatenate(pose_time), res.time[::POSE_EVERY])


def test_a_series_constant_over_a_block_is_stored_once(logged_run):
    # The planetary's meshes are rigid spur meshes: no deflection and no axial force at any
    # sample, so the bits of those series are set in every block; the time always varies.
    with open(logged_run.path, "rb") as f:
        reader = make_reader(f)
        channel = next(
            c for c in reader.get_summary().channels.values() if c.topic == "/pinwind/columns"
        )
        columns = json.loads(channel.metadata["columns"])
        payloads = [m.data for _, _, m in reader.iter_messages(topics=["/pinwind/columns"])]
    width = sum(int(np.prod(shape)) for _, shape in columns)
    first = {}
    at = 0
    for key, shape in columns:
        first[key] = (at, int(np.prod(shape)))
        at += first[key][1]
    blocks = [d for d in payloads if struct.unpack_from("<I", d, 1)[0]]
    assert len(blocks) == 3
    for data in blocks:
        flags = int.from_bytes(data[9 : 9 + 8 * ((width + 63) // 64)], "little")
        for key in ("mesh_deflection", "mesh_axial"):
            at, count = first[key]
            assert all(flags >> i & 1 for i in range(at, at + count)), key
        assert not flags & 1  # the time


def test_view_rate_thins_the_viewers_topics_only(planetary, tmp_path):
    path = tmp_path / "view.mcap"
    full = pinwind.simulate(
        planetary, duration=0.1, dt=DT, torques=TORQUES, log=path, view_rate=250.0, pose_rate=None
    )
    with open(path, "rb") as f:
        normal = [
            np.frombuffer(m.data[-8 * len(full.mesh_names) :], "<f8")
            for _, _, m in make_reader(f).iter_messages(topics=["/meshes/normal"])
        ]
    np.testing.assert_array_equal(np.array(normal), full.mesh_normal[::4])  # 1 kHz / 250 Hz
    assert_same_arrays(pinwind.read_log(path), full, pose_every=4)


def _back_flanks_a_tooth_thickness_behind(gearbox: pinwind.Gearbox, result) -> None:
    """Move an old log's back-flank contact positions to where pinwind now puts them.

    The log was written while pinwind put gear A's back flank at the pitch point together with
    its front flank; it now sits a tooth thickness s behind (``dynamics/compliant.py``
    ``_path_spec``), r_b s/r further along the back flank's path, which for the standard
    (unshifted) teeth of this model is s = half the circular pitch p: r_b (p/2)/r = p_b/2. The
    sun meshes run on their back flank here (flank −1), so their contact position moves half a
    base pitch round the path, their pair count follows from it on the path of contact
    (``gears/contact.pairs_in_contact``), and the force on the entering pair is the mesh force
    shared equally by the pairs (ISO shape: 0.875 c' per pair in double contact).
    """
    for i, name in enumerate(result.mesh_names):
        path = gearbox.mesh(name).path
        back = result.mesh_flank[:, i] < 0
        if not back.any():
            continue
        assert gearbox.mesh(name).gear_a.spec.profile_shift == 0.0
        x = result.mesh_contact_position[back, i] - path.start_roll_1
        x = (x + 0.5 * path.base_pitch) % path.base_pitch
        result.mesh_contact_position[back, i] = path.start_roll_1 + x
        result.mesh_pairs[back, i] = pairs_in_contact(path, x)
        result.mesh_single_tooth_force[back, i] = (
            result.mesh_normal[back, i] / result.mesh_pairs[back, i]
        )


#: Series declared after format 2 (sliced meshes' face load, flank and bearing friction): a
#: format-2 log has no values for them.
NOT_IN_FORMAT_2 = {
    "mesh_face_load_factor", "mesh_load_centre", "mesh_peak_line_load", "mesh_mean_line_load",
    "mesh_sliding_velocity", "mesh_friction_force", "mesh_friction_power",
    "bearing_friction_moment", "bearing_friction_power",
}  # fmt: skip


def test_log_of_format_2_is_still_read(planetary):
    """A log written by the format-2 writer (ROS 2 topics at the log rate, no columns): 0.05 s
    of the shared planetary run at 1 ms in chunks of 20, poses at 100 Hz."""
    # The format fixes where each stored value lands, not how the run that wrote it stepped
    # (the log was written by the former first-order step): every array of today's Result comes
    # back with its shape, the values no step changes equal a fresh run's (the sample times,
    # the start state, the applied torques), and the stored metadata names the written run.
    back = pinwind.read_log(Path(__file__).parent / "data" / "planetary_format2.mcap")
    assert back.metadata["log"]["complete"]
    assert back.metadata["dt"] == DT
    full = pinwind.simulate(planetary, duration=0.05, dt=DT, torques=TORQUES)
    assert len(back) == len(full) == 51
    posed = np.arange(0, len(full), POSE_EVERY)
    np.testing.assert_array_equal(back.pose_rows, posed)
    _back_flanks_a_tooth_thickness_behind(planetary, back)
    for name in full.ARRAYS:
        a, b = getattr(back, name), getattr(full, name)
        if name in POSE_ARRAYS:
            b = b[posed]
        assert a.shape == b.shape, name
        if name in NOT_IN_FORMAT_2:  # not stored: NaN, never left-over memory
            assert np.isnan(a).all(), name
        else:
            assert np.isfinite(a).all(), name
    np.testing.assert_allclose(back.time, np.arange(51) * DT, rtol=1e-12, atol=1e-15)
    # Format 2 stores no flank forces: the loaded flank carries the normal force, the other none.
    loaded = np.where(back.mesh_flank > 0, back.mesh_normal_front, back.mesh_normal_back)
    np.testing.assert_array_equal(loaded, back.mesh_normal)
    np.testing.assert_array_equal(back.mesh_normal_front + back.mesh_normal_back, back.mesh_normal)
    for name in ("angle", "speed"):
        np.testing.assert_allclose(
            getattr(back, name)[0], getattr(full, name)[0], rtol=1e-12, atol=1e-9, err_msg=name
        )
    np.testing.assert_allclose(back.torque, full.torque, rtol=1e-12, atol=1e-9)


def _viewed_normal_forces(path, meshes: int) -> tuple[np.ndarray, np.ndarray, int]:
    """(sequence numbers, mesh normal forces) of every /meshes/normal message, in file order,
    and the number of chunks that hold them."""
    sequence, normal = [], []
    with open(path, "rb") as f:
        reader = make_reader(f)
        for _, _, m in reader.iter_messages(topics=["/meshes/normal"]):
            sequence.append(m.sequence)
            normal.append(np.frombuffer(m.data[-8 * meshes :], "<f8"))
        summary = reader.get_summary()
    channel = next(c.id for c in summary.channels.values() if c.topic == "/meshes/normal")
    chunks = sum(channel in c.message_index_offsets for c in summary.chunk_indexes)
    return np.array(sequence), np.array(normal), chunks


def test_viewers_topics_gathered_over_blocks_hold_every_viewed_sample_once(
    planetary, tmp_path, monkeypatch
):
    """The viewed samples of several blocks go out in one chunk once VIEW_BATCH are held, and
    the rest at the run's end: every sample is then on the viewers' topics exactly once, in
    order, with its values."""
    monkeypatch.setattr(log_writer, "VIEW_BATCH", 150)
    path = tmp_path / "views.mcap"
    res = pinwind.simulate(
        planetary, duration=DURATION, dt=DT, torques=TORQUES, log=path, chunk=CHUNK,
        view_rate=None, pose_rate=None,
    )  # fmt: skip
    sequence, normal, chunks = _viewed_normal_forces(path, len(res.mesh_names))
    # 251 samples in blocks of 100, 100, 51: a chunk of views after the second, one at the end
    assert chunks == 2
    np.testing.assert_array_equal(sequence, np.arange(len(res)))
    np.testing.assert_array_equal(normal, res.mesh_normal)


def test_an_interrupted_run_writes_the_views_it_held(planetary, tmp_path):
    """Ctrl-C at step 100: the held viewed samples of the first block reach the file."""
    path = tmp_path / "interrupted_views.mcap"
    with pytest.raises(KeyboardInterrupt):
        with pytest.warns(TorquesUnbalanced):
            pinwind.simulate(
                planetary, duration=DURATION, dt=DT, log=path, chunk=CHUNK,
                torques={"carrier": FailsBetween(KeyboardInterrupt())}, view_rate=None,
            )  # fmt: skip
    back = pinwind.read_log(path)
    sequence, normal, chunks = _viewed_normal_forces(path, len(back.mesh_names))
    assert chunks == 1
    np.testing.assert_array_equal(sequence, np.arange(100))
    np.testing.assert_array_equal(normal, back.mesh_normal)
