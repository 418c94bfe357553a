"""A log's summary section read by pinwind's own record parser, against the ``mcap`` package's.

The reference is the ``mcap`` package's reader (``make_reader(...).get_summary()``), an
independent implementation of the MCAP specification: every channel, chunk index, metadata
index and attachment index must come out the same, and a read through the package's parse of
the summary must give every series bit for bit.
"""

from __future__ import annotations

import os
import struct

import numpy as np
import pytest
from mcap.opcode import Opcode
from mcap.reader import make_reader

from pinwind.dynamics.result import Result
from pinwind.io import mcap_file
from pinwind.io.log_reader import LogDamaged, read_log

FOOTER = struct.Struct("<BQQQI")  # opcode, length, summary start, summary offsets, CRC


def _contents(path) -> mcap_file.Contents:
    fd = os.open(path, os.O_RDONLY)
    try:
        return mcap_file.read_contents(fd, os.fstat(fd).st_size)
    finally:
        os.close(fd)


def _reference_summary(summary: bytes, at: int, contents: mcap_file.Contents) -> None:
    """The summary's records as the ``mcap`` package parses them (the reader before)."""
    pos = 0
    while pos < len(summary):
        opcode, length = struct.unpack_from("<BQ", summary, pos)
        body = memoryview(summary)[pos + 9 : pos + 9 + length]
        if opcode == Opcode.CHANNEL:
            channel = mcap_file._parse(mcap_file.Channel, body)
            contents.channels[channel.id] = channel
        elif opcode == Opcode.CHUNK_INDEX:
            ix = mcap_file._parse(mcap_file.ChunkIndex, body)
            contents.chunks.append(
                mcap_file.ChunkRef(
                    ix.chunk_start_offset,
                    ix.chunk_length,
                    ix.message_start_time,
                    ix.message_end_time,
                    dict(ix.message_index_offsets),
                    ix.uncompressed_size,
                )
            )
        elif opcode == Opcode.METADATA_INDEX:
            ix = mcap_file._parse(mcap_file.MetadataIndex, body)
            contents.metadata[ix.name] = (ix.offset, ix.length)
        elif opcode == Opcode.ATTACHMENT_INDEX:
            ix = mcap_file._parse(mcap_file.AttachmentIndex, body)
            contents.attachments[ix.name] = (ix.offset, ix.length)
        pos += 9 + length


def _assert_same_arrays(a: Result, b: Result) -> None:
    assert len(a) == len(b) > 0
    for name in Result.ARRAYS:
        assert np.array_equal(getattr(a, name), getattr(b, name), equal_nan=True), name
    assert a.energy.keys() == b.energy.keys()
    for term in a.energy:
        assert np.array_equal(a.energy[term], b.energy[term], equal_nan=True), term
    assert np.array_equal(a.pose_rows, b.pose_rows)


def test_the_summary_is_read_as_the_mcap_package_reads_it(logged_run):
    contents = _contents(logged_run.path)
    assert contents.indexed and not contents.damage
    with open(logged_run.path, "rb") as f:
        summary = make_reader(f).get_summary()
    assert summary is not None
    assert contents.channels == summary.channels
    chunks = sorted(summary.chunk_indexes, key=lambda c: c.chunk_start_offset)
    # the shared run: 251 samples in chunks of 100 (conftest.CHUNK)
    assert len(contents.chunks) == len(chunks) >= 3
    for ref, ix in zip(contents.chunks, chunks, strict=True):
        assert (ref.offset, ref.length) == (ix.chunk_start_offset, ix.chunk_length)
        assert (ref.start_ns, ref.end_ns) == (ix.message_start_time, ix.message_end_time)
        assert ref.index == ix.message_index_offsets
        assert ref.size == ix.uncompressed_size
    assert contents.metadata == {m.name: (m.offset, m.length) for m in summary.metadata_indexes}
    assert contents.attachments == {
        a.name: (a.offset, a.length) for a in summary.attachment_indexes
    }
    assert contents.attachments  # the model file is attached


def test_a_read_gives_every_series_as_through_the_mcap_package(logged_run, monkeypatch):
    new = read_log(logged_run.path)
    monkeypatch.setattr(mcap_file, "_summary_records", _reference_summary)
    old = read_log(logged_run.path)
    _assert_same_arrays(new, old)


def test_a_string_past_its_record_is_damage_and_the_data_section_is_walked(logged_run, tmp_path):
    """A summary without a CRC (0: not set) whose first channel's topic length runs past it."""
    data = bytearray(logged_run.path.read_bytes())
    footer_at = len(data) - 8 - FOOTER.size
    opcode, length, start, offsets, _ = FOOTER.unpack_from(data, footer_at)
    FOOTER.pack_into(data, footer_at, opcode, length, start, offsets, 0)
    pos = start
    while data[pos] != Opcode.CHANNEL:
        pos += 9 + struct.unpack_from("<Q", data, pos + 1)[0]
    struct.pack_into("<I", data, pos + 9 + 4, 0xFFFF_FFF0)  # after channel id and schema id
    path = tmp_path / "bad_summary.mcap"
    path.write_bytes(bytes(data))
    with pytest.warns(LogDamaged, match=rf"summary section at byte {start} is damaged"):
        back = read_log(path)
    _assert_same_arrays(back, read_log(logged_run.path))
