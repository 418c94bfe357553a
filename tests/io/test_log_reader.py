"""Reading logs in part: time windows, channels, blocks; damaged files; running out of memory."""

from __future__ import annotations

import struct

import numpy as np
import pytest
from mcap.reader import make_reader

import pinwind
from pinwind.dynamics.result import concatenate
from pinwind.errors import LogError, LogRecovered
from pinwind.io import log_legacy, log_reader, mcap_file
from pinwind.io.log_channels import CHANNELS, UnknownChannel
from pinwind.io.log_reader import (
    LogDamaged,
    LogReader,
    LogTooLarge,
    iter_log,
    read_log,
)
from tests.io.conftest import CHUNK, column_chunks
from tests.io.test_log_writer import assert_same_arrays


def rows_of(res: pinwind.Result, rows) -> pinwind.Result:
    """The samples ``rows`` of a Result (slice, indices or mask), names and metadata kept."""
    return res.take(rows)


@pytest.fixture(scope="module")
def whole(logged_run) -> pinwind.Result:
    return read_log(logged_run.path)


# --- windows and channels -------------------------------------------------------------------------


@pytest.mark.parametrize(
    "start, stop",
    [
        (None, None),
        (0.05, 0.2),  # across a chunk boundary (chunks of 100 samples)
        (0.1, 0.199),  # exactly one chunk
        (0.1234, 0.1234),  # between two samples: nothing
        (0.123, 0.123),  # one sample
        (None, 0.0),  # the first sample only
        (0.2, None),  # to the end
        (0.25, 9.0),  # the last sample
        (-1.0, 0.03),  # before the start
        (1.0, 2.0),  # after the end: nothing
        (0.2, 0.1),  # reversed: nothing
    ],
)
def test_window_read_equals_the_same_slice_of_a_whole_read(logged_run, whole, start, stop):
    t = whole.time
    keep = np.ones(len(t), dtype=bool)
    if start is not None:
        keep &= t >= start
    if stop is not None:
        keep &= t <= stop
    part = read_log(logged_run.path, start=start, stop=stop)
    assert_same_arrays(part, rows_of(whole, np.flatnonzero(keep)))


def test_whole_read_equals_the_simulated_run_and_names_what_was_read(logged_run, whole):
    assert_same_arrays(whole, logged_run.result)
    assert whole.metadata["log"]["channels"] == list(CHANNELS)
    assert whole.metadata["log"]["window"] == [None, None]


@pytest.mark.parametrize(
    "channels",
    [["/meshes/normal"], ["/joints", "/bearings/force_local"], ["/tf"], ["/run/energy"], []],
)
def test_channel_read_equals_those_arrays_of_a_whole_read_and_leaves_the_rest_empty(
    logged_run, whole, channels
):
    part = read_log(logged_run.path, channels=channels, start=0.05, stop=0.2)
    expected = rows_of(whole, (whole.time >= 0.05) & (whole.time <= 0.2))
    read = {"time", *(f for topic in channels for f in CHANNELS[topic])}
    for name in whole.ARRAYS:
        a, b = getattr(part, name), getattr(expected, name)
        if name in read:
            np.testing.assert_array_equal(a.view(np.uint64), b.view(np.uint64), err_msg=name)
        else:
            assert a.shape == (0, *b.shape[1:]), name
    for term, values in expected.energy.items():
        if "energy" in read:
            np.testing.assert_array_equal(part.energy[term], values)
        else:
            assert part.energy[term].shape == (0,)
    assert set(part.metadata["log"]["channels"]) == {"/run/time", *channels}


@pytest.mark.parametrize("off", [-1, 7])
def test_whole_read_equals_the_run_when_the_samples_per_chunk_are_guessed_wrong(
    logged_run, monkeypatch, off
):
    # Each chunk is copied into the place its index span gives; a guess too high leaves gaps
    # that must be closed, one too low must send the read back to copying in order.
    guess = LogReader._column_counts

    def wrong(self, chunks, lo, hi):
        return [count + off for count in guess(self, chunks, lo, hi)]

    monkeypatch.setattr(LogReader, "_column_counts", wrong)
    assert_same_arrays(read_log(logged_run.path), logged_run.result)
    window = read_log(logged_run.path, start=0.05, stop=0.2)
    keep = (logged_run.result.time >= 0.05) & (logged_run.result.time <= 0.2)
    assert_same_arrays(window, rows_of(logged_run.result, keep))


def test_a_folder_selects_every_channel_under_it(logged_run):
    part = read_log(logged_run.path, channels=["/bearings"])
    assert part.metadata["log"]["channels"] == [
        "/bearings/force",
        "/bearings/moment",
        "/bearings/force_local",
        "/bearings/moment_local",
        "/bearings/friction_moment",
        "/bearings/friction_power",
        "/bearings/displacement",
        "/bearings/elastic_force",
        "/bearings/radial",
        "/bearings/axial",
        "/bearings/tilting",
        "/bearings/torque",
        "/run/time",
    ]


def test_unknown_channel_is_refused_naming_the_known_ones(logged_run):
    with pytest.raises(UnknownChannel, match=r'unknown channel "/meshes/norml"; .*/meshes/normal'):
        read_log(logged_run.path, channels=["/meshes/norml"])


def test_window_read_decompresses_only_the_chunks_it_needs(logged_run, monkeypatch):
    read = []
    original = mcap_file.read_chunk

    def spy(fd, chunk, into=None):
        read.append(chunk.offset)
        return original(fd, chunk, into)

    monkeypatch.setattr(mcap_file, "read_chunk", spy)
    spans = column_chunks(logged_run.path)  # samples 0-99, 100-199, 200-250
    read_log(logged_run.path, start=0.12, stop=0.15)
    assert read == [spans[1][0]]
    read.clear()
    read_log(logged_run.path)
    assert read == [offset for offset, _, _ in spans]  # never the model's or the viewers' chunks


def test_a_log_without_bearing_rows_reads_without_loading_its_model(logged_run, monkeypatch):
    """The derived row series of a model without compliant-bearing rows have no columns: a read
    fills nothing for them and never rebuilds the model from the log (38 ms, twice the read of
    a 20 000-sample log, issue 37)."""
    from pinwind.model import gearbox

    def refuse(*args, **kwargs):
        raise AssertionError("the model was loaded")

    monkeypatch.setattr(gearbox, "loads", refuse)
    res = read_log(logged_run.path)
    assert res.row_names == []
    assert res.row_radial.shape == (len(res), 0) and res.row_axial.shape == (len(res), 0)


# --- blocks -------------------------------------------------------------------------------------


@pytest.mark.parametrize("block", [1, 37, CHUNK, 1000])
def test_blocks_concatenate_to_the_whole_read(logged_run, whole, block):
    blocks = list(iter_log(logged_run.path, block=block))
    assert all(len(b) == block for b in blocks[:-1]) and 1 <= len(blocks[-1]) <= block
    assert_same_arrays(concatenate(blocks), whole)


def test_blocks_of_a_window_and_channels_equal_that_read(logged_run):
    part = read_log(logged_run.path, start=0.033, stop=0.21, channels=["/meshes"])
    blocks = list(iter_log(logged_run.path, block=64, start=0.033, stop=0.21, channels="/meshes"))
    np.testing.assert_array_equal(np.concatenate([b.time for b in blocks]), part.time)
    np.testing.assert_array_equal(
        np.concatenate([b.mesh_force_on_b for b in blocks]), part.mesh_force_on_b
    )
    assert all(b.bearing_force.shape[0] == 0 for b in blocks)


@pytest.mark.parametrize(
    "start, stop, block, expected",
    [
        # samples every DT = 1 ms from 0 to 0.25 s: blocks end at 0.099, 0.199, 0.25 s
        (None, None, 100, [(0.099, 0.25), (0.199, 0.25), (0.25, 0.25)]),
        # from 0.05 s: blocks of 0.050-0.099 and 0.100-0.149 s, then 0.150-0.170 s
        (0.05, 0.17, 50, [(0.049, 0.12), (0.099, 0.12), (0.12, 0.12)]),
    ],
)
def test_blocks_report_the_simulated_time_read_of_the_window(
    logged_run, start, stop, block, expected
):
    calls = []
    with LogReader(logged_run.path) as log:
        blocks = log.blocks(block, start=start, stop=stop, progress=lambda *a: calls.append(a))
        for res in blocks:
            assert calls[-1][0] == pytest.approx(res.time[-1] - (start or 0.0), abs=1e-9)
    np.testing.assert_allclose(calls, expected, rtol=0, atol=1e-9)


def test_report_and_export_pass_the_progress_on(logged_run, tmp_path):
    from pinwind.io.export import export_log
    from pinwind.io.report import report_log

    for run in (
        lambda p: report_log(logged_run.path, block=100, progress=p),
        lambda p: export_log(logged_run.path, tmp_path / "t.csv", block=100, progress=p),
    ):
        calls: list = []
        run(lambda *a, calls=calls: calls.append(a))
        np.testing.assert_allclose(calls[-1], (0.25, 0.25), rtol=0, atol=1e-9)
        assert len(calls) == 3  # 251 samples in blocks of 100


# --- files laid out by other writers -------------------------------------------------------------


def test_log_rewritten_by_the_mcap_writer_reads_back_the_same_arrays(logged_run, whole, tmp_path):
    """Another tool's chunks (schemas and channels inside, 64 kB each) decode record by record."""
    from mcap.writer import Writer

    path = tmp_path / "rewritten.mcap"
    with open(logged_run.path, "rb") as f, open(path, "wb") as out:
        reader = make_reader(f)
        writer = Writer(out, chunk_size=64 * 1024)
        writer.start(profile="", library=reader.get_header().library)
        schemas, channels = {}, {}
        for schema, channel, message in reader.iter_messages(log_time_order=False):
            if channel.id not in channels:
                if schema is not None:  # /pinwind/columns has none
                    schemas.setdefault(
                        schema.id, writer.register_schema(schema.name, schema.encoding, schema.data)
                    )
                channels[channel.id] = writer.register_channel(
                    channel.topic,
                    channel.message_encoding,
                    schemas[schema.id] if schema is not None else 0,
                    channel.metadata,
                )
            writer.add_message(
                channels[channel.id],
                log_time=message.log_time,
                data=message.data,
                publish_time=message.publish_time,
                sequence=message.sequence,
            )
        for record in reader.iter_metadata():
            writer.add_metadata(record.name, record.metadata)
        writer.finish()
    assert_same_arrays(read_log(path), whole)
    assert_same_arrays(read_log(path, start=0.1, stop=0.15), rows_of(whole, slice(100, 151)))


# --- damaged files ------------------------------------------------------------------------------


def _damaged(logged_run, tmp_path, at: int, bit: int = 0x10, name: str = "bad.mcap"):
    data = bytearray(logged_run.path.read_bytes())
    data[at] ^= bit
    path = tmp_path / name
    path.write_bytes(bytes(data))
    return path


def test_a_flipped_bit_in_a_chunk_loses_that_chunk_only_with_a_warning(logged_run, whole, tmp_path):
    offset, length, _ = column_chunks(logged_run.path)[1]  # samples 100-199
    path = _damaged(logged_run, tmp_path, offset + length - 1000)
    with pytest.warns(LogDamaged, match=rf"chunk at byte {offset} .*t = 0\.1 to 0\.199 s lost"):
        back = read_log(path)
    assert_same_arrays(back, rows_of(whole, np.r_[0:100, 200:251]))
    assert back.status == "completed"


@pytest.mark.parametrize("start, stop", [(0.05, 0.22), (0.15, None), (None, 0.12), (0.1, 0.2)])
def test_a_window_across_a_damaged_chunk_is_the_window_of_the_intact_samples(
    logged_run, whole, tmp_path, start, stop
):
    # The reading threads copy each chunk into its place; the lost chunk's place is closed up.
    offset, length, _ = column_chunks(logged_run.path)[1]  # samples 100-199
    path = _damaged(logged_run, tmp_path, offset + length - 1000)
    t = whole.time
    keep = ((t < 0.1) | (t > 0.199)) & (t >= (start if start is not None else -1.0))
    keep &= t <= (stop if stop is not None else 1.0)
    with pytest.warns(LogDamaged):
        back = read_log(path, start=start, stop=stop)
    assert_same_arrays(back, rows_of(whole, np.flatnonzero(keep)))


def test_first_chunk_whose_records_do_not_decode_is_lost_with_a_warning_not_read_as_empty(
    logged_run, whole, monkeypatch
):
    # Records that decompress and pass their checksum but do not decode (a writer's bug): the
    # first chunk, which the reader decodes in Python to lay out the arrays, is reported lost.
    def undecodable(data, layout):
        raise mcap_file.DamagedChunk("a columns record is cut short")

    monkeypatch.setattr(log_reader, "decode_chunk", undecodable)
    with pytest.warns(LogDamaged, match=r"a columns record is cut short: t = 0 to 0\.099 s lost"):
        back = read_log(logged_run.path)
    assert_same_arrays(back, rows_of(whole, np.r_[100:251]))


def test_a_damaged_chunk_header_loses_that_chunk_only_with_a_warning(logged_run, whole, tmp_path):
    offset, _, _ = column_chunks(logged_run.path)[0]  # samples 0-99
    path = _damaged(logged_run, tmp_path, offset, bit=0x78)  # opcode 0x06 → 0x7e
    with pytest.warns(LogDamaged, match=rf"chunk at byte {offset} is an unknown MCAP record"):
        back = read_log(path)
    assert_same_arrays(back, rows_of(whole, slice(100, None)))


def test_damaged_summary_is_replaced_by_the_data_section_without_losing_samples(
    logged_run, whole, tmp_path
):
    with open(logged_run.path, "rb") as f:
        f.seek(-8 - 29, 2)
        _, _, summary_start, _, _ = struct.unpack("<BQQQI", f.read(29))
    path = _damaged(logged_run, tmp_path, summary_start + 40)
    with pytest.warns(LogDamaged, match=rf"summary section at byte {summary_start} fails its CRC"):
        back = read_log(path)
    assert_same_arrays(back, whole)
    assert back.status == "completed"


def test_damaged_summary_and_chunk_still_give_every_intact_chunk(logged_run, whole, tmp_path):
    offset, length, _ = column_chunks(logged_run.path)[2]  # samples 200-250
    with open(logged_run.path, "rb") as f:
        f.seek(-8 - 29, 2)
        _, _, summary_start, _, _ = struct.unpack("<BQQQI", f.read(29))
    data = bytearray(logged_run.path.read_bytes())
    data[summary_start + 40] ^= 1
    data[offset + length // 2] ^= 1  # inside the chunk's compressed records
    path = tmp_path / "both.mcap"
    path.write_bytes(bytes(data))
    with pytest.warns(LogDamaged, match=r"t = 0\.2 to 0\.25 s lost"):
        back = read_log(path)
    assert_same_arrays(back, rows_of(whole, slice(0, 200)))


def test_damaged_end_status_record_is_a_warning_not_an_error(logged_run, whole, tmp_path):
    with LogReader(logged_run.path) as log:
        offset, _ = log._contents.metadata["pinwind.end"]
    path = _damaged(logged_run, tmp_path, offset + 1, bit=0x40)  # its length field
    with pytest.warns(LogDamaged, match="'pinwind.end' metadata record") as caught:
        back = read_log(path)
    assert_same_arrays(back, whole)
    assert back.status == "unknown: the end-status record is damaged"
    assert [w.category for w in caught] == [LogDamaged]


def test_log_without_samples_in_the_window_reads_as_an_empty_result(logged_run):
    back = read_log(logged_run.path, start=5.0)
    assert len(back) == 0 and back.mesh_normal.shape == (0, len(back.mesh_names))


# --- memory -------------------------------------------------------------------------------------


def test_running_out_of_memory_says_so_with_the_log_size_and_the_fix(logged_run, monkeypatch):
    monkeypatch.setattr(log_reader, "_available_memory", lambda: 1000)
    with pytest.raises(LogTooLarge, match="memory ran out") as caught:
        read_log(logged_run.path)
    message = str(caught.value)
    assert isinstance(caught.value, LogError)  # the CLI prints it on one line, exit code 2
    size_mb = f"{logged_run.path.stat().st_size / 1e6:.0f} MB on disk"
    assert size_mb in message and "251 samples" in message
    assert "start=/stop=" in message and "channels=" in message and "iter_log" in message
    assert "corrupt" not in message


def test_memory_error_while_decompressing_is_not_reported_as_damage(logged_run, monkeypatch):
    def no_memory(fd, chunk, into=None):
        raise MemoryError

    monkeypatch.setattr(mcap_file, "read_chunk", no_memory)
    with pytest.raises(LogTooLarge, match="memory ran out"):
        read_log(logged_run.path)
    with pytest.raises(LogTooLarge, match="memory ran out"):
        list(iter_log(logged_run.path, block=50))


def test_reading_a_cut_log_in_a_window_warns_that_it_was_recovered(logged_run, tmp_path):
    offset, length, _ = column_chunks(logged_run.path)[2]  # samples 200-250
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(logged_run.path.read_bytes()[: offset + length // 2])
    with pytest.warns(LogRecovered, match="recovered 51 samples"):
        back = read_log(cut, start=0.149)
    np.testing.assert_array_equal(back.time, np.arange(149, 200) * 1e-3)


def test_streaming_a_damaged_window_names_the_samples_times_it_read(logged_run, tmp_path):
    offset, length, _ = column_chunks(logged_run.path)[1]  # samples 100-199
    path = _damaged(logged_run, tmp_path, offset + length - 1000)
    with pytest.warns(LogDamaged) as caught:
        blocks = list(iter_log(path, block=64, start=0.05))
    read = np.concatenate([b.time for b in blocks])
    assert read[0] == pytest.approx(0.05, abs=1e-12)  # the window's first sample, 50 rows in
    message = str(caught[0].message)
    assert f"t = {read[0]:.6g} to {read[-1]:.6g} s" in message, message


def test_joint_state_fixed_bytes_are_all_but_the_stamp_and_three_value_arrays():
    # One log's codec may be freed and its id() reused by another log's: the positions must
    # follow each codec's own layout.
    from pinwind.io.messages import JointStateCodec

    for names in (["a", "b"], ["a", "b", "c", "d", "e"], ["sun"]):
        codec = JointStateCodec(names, "world")
        fixed = log_legacy._joint_fixed(codec)
        assert fixed.max() < codec.size
        assert len(fixed) == codec.size - 8 - 3 * 8 * len(names)
        del codec
