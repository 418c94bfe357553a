"""A decompressed columns chunk placed in one compiled call (``ColumnSink.place_chunk``).

A chunk is built here by hand from the format's definition (docs/log_format.md, "Columns",
layout 3: message records of a layout byte, m, p, the constant-series bits, the varying
series' byte planes, the constants, the poses), so every expected value is the one put in;
the damage messages are those ``decode_chunk`` gives for the same bytes; and a real log's
chunks placed in one call equal the same chunks decoded and placed block by block.
"""

import struct

import numpy as np
import pytest
from numpy.testing import assert_array_equal

from pinwind.dynamics._native import place_columns_chunk
from pinwind.io.log_channels import CHANNELS
from pinwind.io.log_columns import ColumnLayout, ColumnSink, decode_chunk
from pinwind.io.log_reader import LogReader
from pinwind.io.mcap_file import DamagedChunk, read_chunk

CHANNEL = 3
#: Series per sample (the time, then four), and per posed sample (the time, then two).
WIDTH, POSE_WIDTH = 5, 3


def _record(payload: bytes, channel: int = CHANNEL, opcode: int = 0x05) -> bytes:
    """An MCAP message record: opcode, length, channel, sequence, log and publish time."""
    body = struct.pack("<HIQQ", channel, 0, 0, 0) + payload
    return struct.pack("<BQ", opcode, len(body)) + body


def _payload(values: np.ndarray, poses: np.ndarray) -> bytes:
    """A columns payload of (WIDTH, m) ``values`` and (POSE_WIDTH, p) ``poses``: a series whose
    m values are all the same bits is stored once, the others as byte planes."""
    m = values.shape[1]
    bits = values.view(np.uint64)
    same = (bits == bits[:, :1]).all(axis=1) if m else np.ones(WIDTH, bool)
    mask = np.zeros(8, np.uint8)  # one 8-byte word holds the bits of 5 series
    mask[0] = sum(1 << j for j in range(WIDTH) if same[j])
    varying = np.ascontiguousarray(values[~same], "<f8").reshape(-1)
    planes = varying.view(np.uint8).reshape(-1, 8).T.reshape(-1)  # byte b of every value
    constants = np.ascontiguousarray(values[same, 0] if m else np.zeros(0), "<f8")
    head = struct.pack("<BII", 3, m, poses.shape[1])
    return head + mask.tobytes() + planes.tobytes() + constants.tobytes() + poses.tobytes()


def _place(
    chunk: bytes, rows, out, at=0, room=None, start=None, stop=None, posed=True, zeroed_from=0
):
    return place_columns_chunk(
        np.frombuffer(chunk, np.uint8),
        CHANNEL,
        WIDTH,
        POSE_WIDTH,
        np.asarray(rows, np.int64),
        out,
        at,
        out.shape[1] - at if room is None else room,
        start,
        stop,
        np.array([1, 2], np.int64),
        posed,
        zeroed_from,
    )


def _blocks():
    """Two blocks of 6 and 4 samples, 0.01 s apart: series 1 varies, 2 is -0.0 throughout,
    3 is +0.0, 4 is a NaN with a payload in the first block and changes at the last sample of
    the second; poses at samples 0, 3 of the first block and 2 of the second, and one pose at
    a time that is no sample's."""
    nan = np.array([0x7FF8_0000_DEAD_BEEF], np.uint64).view(np.float64)[0]
    t1, t2 = np.arange(6) * 0.01, 0.06 + np.arange(4) * 0.01
    first = np.array([t1, np.sin(t1 + 1.0), np.full(6, -0.0), np.zeros(6), np.full(6, nan)])
    second = np.array([t2, np.sin(t2 + 1.0), np.full(4, -0.0), np.zeros(4), [2.5, 2.5, 2.5, 7.0]])
    poses1 = np.array([[t1[0], t1[3], 0.035], [10.0, 13.0, 99.0], [20.0, 23.0, 99.0]])
    poses2 = np.array([[t2[2]], [32.0], [42.0]])
    return first, second, poses1, poses2


def _chunk() -> bytes:
    first, second, poses1, poses2 = _blocks()
    return (
        _record(b"other channel's record", channel=CHANNEL + 1)
        + _record(_payload(first, poses1))
        + _record(b"\x00" * 40, opcode=0x06)  # not a message
        + _record(_payload(second, poses2))
        + _record(struct.pack("<BII", 3, 0, 0) + bytes(8))  # a block's closing record
    )


def test_a_chunk_built_by_hand_lands_at_its_place_bit_for_bit():
    first, second, _, _ = _blocks()
    out = np.zeros((5, 14))
    filled, pose_rows, poses, damage, _ = _place(_chunk(), [0, 1, 2, 3, 4], out, at=2, room=12)
    assert (filled, damage) == (10, "")
    expected = np.zeros((5, 14))
    expected[:, 2:12] = np.concatenate([first, second], axis=1)
    assert_array_equal(out.view(np.uint64), expected.view(np.uint64))  # -0.0, NaN payload kept
    # the posed samples at their samples of out (0.035 s is no sample's: left out)
    assert_array_equal(pose_rows, [2, 5, 10])
    assert_array_equal(poses, [[10.0, 13.0, 32.0], [20.0, 23.0, 42.0]])


def test_a_constant_changing_at_the_last_sample_of_a_block_is_not_stored_once():
    """Series 4 of the second block is 2.5 but at its last sample (7.0): byte planes."""
    _, second, _, _ = _blocks()
    payload = _payload(second, np.zeros((POSE_WIDTH, 0)))
    assert payload[9] == 0b01100  # series 2 and 3 stored once, 0, 1 and 4 vary
    out = np.zeros((5, 4))
    assert _place(_record(payload), range(5), out)[0] == 4
    assert_array_equal(out[4], [2.5, 2.5, 2.5, 7.0])


def test_rows_not_read_are_left_alone_and_a_window_keeps_its_samples():
    first, second, _, _ = _blocks()
    out = np.full((2, 10), 9.0)
    # series 1 → row 1, series 4 → row 0, the others not read; samples with 0.02 ≤ t ≤ 0.07
    filled, pose_rows, poses, *_ = _place(_chunk(), [-1, 1, -1, -1, 0], out, start=0.02, stop=0.07)
    assert filled == 6
    both = np.concatenate([first, second], axis=1)[:, 2:8]
    assert_array_equal(out[1, :6], both[1])
    assert_array_equal(out[0, :6].view(np.uint64), both[4].view(np.uint64))
    assert_array_equal(out[:, 6:], 9.0)
    # poses at 0.03 (sample 1 of the window) and 0.08 (outside it)
    assert_array_equal(pose_rows, [1])
    assert_array_equal(poses, [[13.0], [23.0]])


def test_memory_of_an_earlier_read_gets_its_zeros_written_but_in_the_rows_known_zero():
    """Rows before ``zeroed_from`` hold an earlier read's values: a constant +0.0 is written
    there; from it on the memory is +0.0 already and is left alone. The last row given a value
    other than +0.0 comes back."""
    first, second, _, _ = _blocks()
    both = np.concatenate([first, second], axis=1)
    # series 3 (+0.0 throughout) → row 4, series 4 (a NaN, then 2.5 and 7.0) → row 3
    rows = [0, 1, 2, 4, 3]
    out = np.full((5, 10), 9.0)
    filled, *_, last_row = _place(_chunk(), rows, out, zeroed_from=5)
    assert (filled, last_row) == (10, 3)  # row 4 was given +0.0 only
    assert_array_equal(out.view(np.uint64), both[[0, 1, 2, 4, 3]].view(np.uint64))
    out = np.full((5, 10), 9.0)
    assert _place(_chunk(), rows, out, zeroed_from=4)[-1] == 3
    assert_array_equal(out[4], 9.0)  # taken for +0.0: not written
    assert_array_equal(out[:4].view(np.uint64), both[[0, 1, 2, 4]].view(np.uint64))
    assert _place(_chunk(), [-1, -1, -1, 0, -1], np.zeros((2, 10)))[-1] == -1  # +0.0 alone
    assert _place(_chunk(), [-1, -1, 1, 0, -1], np.zeros((2, 10)))[-1] == 1  # -0.0 is not +0.0


def test_nothing_is_placed_past_the_room_or_for_samples_not_consecutive():
    out = np.zeros((5, 12))
    assert _place(_chunk(), range(5), out, room=9)[0] == 10
    assert not out.any()
    # times out of order: a window of samples 0, 2 is not consecutive
    values = np.array([[0.0, 0.5, 0.1], [1.0, 2.0, 3.0], *np.zeros((3, 3))])
    chunk = _record(_payload(values, np.zeros((POSE_WIDTH, 0))))
    assert _place(chunk, range(5), out, stop=0.2)[0] == -1
    assert not out.any()
    # without a window they are placed as they come
    assert _place(chunk, range(5), out)[0] == 3
    assert_array_equal(out[1, :3], [1.0, 2.0, 3.0])


def _damaged_chunks() -> dict[str, bytes]:
    first, _, poses1, _ = _blocks()
    good = _record(_payload(first, poses1))
    wrong_layout = bytearray(good)
    wrong_layout[31] = 2
    return {
        "cut": good + b"\x05\x01",
        "past its end": good[:-1],
        "layout": bytes(wrong_layout),
        "holds": _record(_payload(first, poses1) + bytes(8)),
    }


@pytest.mark.parametrize("kind", ["cut", "past its end", "layout", "holds"])
def test_a_damaged_chunk_is_reported_in_decode_chunks_words_and_nothing_placed(kind):
    chunk = _damaged_chunks()[kind]
    layout = ColumnLayout(CHANNEL, WIDTH, POSE_WIDTH, {})
    with pytest.raises(DamagedChunk) as raised:
        decode_chunk(chunk, layout)
    out = np.zeros((5, 6))
    filled, rows, poses, damage, _ = _place(chunk, range(5), out)
    assert (filled, damage) == (0, str(raised.value))
    assert not out.any() and len(rows) == 0 and poses.shape == (2, 0)


def test_a_logs_chunks_placed_in_one_call_equal_them_decoded_block_by_block(logged_run):
    """Every chunk of the shared run, whole and in a window that cuts the second chunk."""
    with LogReader(logged_run.path) as log:
        keys = log._layout.keys(tuple(CHANNELS))
        chunks = [read_chunk(log._fd, c) for c in log._sample_chunks(None)]
        for start, stop in [(None, None), (0.1305, 0.2)]:
            sinks = [ColumnSink(log._columns, log._layout.shapes, keys, 251) for _ in range(2)]
            at = [0, 0]
            for data in chunks:
                filled, damage = sinks[0].place_chunk(data, at[0], 251 - at[0], start, stop)
                assert damage == ""
                at[0] += filled
                for block in decode_chunk(data, log._columns):
                    time = block.time
                    inside = np.flatnonzero(
                        (time >= (start or -np.inf)) & (time <= (stop or np.inf))
                    )
                    if len(inside):
                        rows = slice(int(inside[0]), int(inside[-1]) + 1)
                        sinks[1].place(block, rows, len(inside), at[1])
                        at[1] += len(inside)
            assert at[0] == at[1] == (251 if start is None else 70)
            for sink in sinks:
                sink.n = at[0]
            one, by_block = (s.arrays() for s in sinks)
            assert one.keys() == by_block.keys()
            for key in one:
                assert_array_equal(one[key], by_block[key], err_msg=key, strict=True)
            assert len(one["pose_rows"]) == (26 if start is None else 7)
