"""The MCAP container: write records (messages a chunk at a time) and scan them back.

``McapWriter`` writes a chunked, indexed file (https://mcap.dev/spec) whose message records come
prebuilt, a block of samples at a time (``message_records`` or a caller's own numpy layout), and
whose other records are written with the ``mcap`` package's record classes. ``scan`` reads a
file's data section record by record into a ``Scan``, stopping where a file that was cut short
ends; it is what lets ``read_log`` recover the complete chunks of a killed run.
"""

from __future__ import annotations

import struct
import zlib
from collections import defaultdict
from dataclasses import dataclass, field
from io import BytesIO
from typing import Any, BinaryIO

import numpy as np
from mcap.data_stream import ReadDataStream, RecordBuilder
from mcap.opcode import Opcode
from mcap.records import (
    Attachment,
    AttachmentIndex,
    Channel,
    Chunk,
    ChunkIndex,
    DataEnd,
    Footer,
    Header,
    Metadata,
    MetadataIndex,
    Schema,
    Statistics,
    SummaryOffset,
)

from pinwind.io import messages

MAGIC = b"\x89MCAP0\r\n"


class DamagedFile(ValueError):
    """A record of an MCAP file is present but unreadable (the message says which and where)."""


RECORD_HEADER = np.dtype(
    [
        ("op", "u1"),
        ("length", "<u8"),
        ("channel", "<u2"),
        ("sequence", "<u4"),
        ("log_time", "<u8"),
        ("publish_time", "<u8"),
    ]
)


def message_records(
    channel: int, sequence: np.ndarray, log_time: np.ndarray, payloads: np.ndarray
) -> np.ndarray:
    """MCAP Message records (opcode, length, channel, sequence, times, data) as (n, L) bytes."""
    n, size = payloads.shape
    head = np.empty(n, dtype=RECORD_HEADER)
    head["op"] = Opcode.MESSAGE
    head["length"] = 22 + size
    head["channel"] = channel
    head["sequence"] = sequence
    head["log_time"] = log_time
    head["publish_time"] = log_time
    return np.concatenate([head.view(np.uint8).reshape(n, RECORD_HEADER.itemsize), payloads], 1)


class McapWriter:
    """A chunked, indexed MCAP file written record by record (https://mcap.dev/spec).

    Schemas, channels, attachments and metadata go in the data section as they come; messages
    come as whole chunks (records already assembled, plus each channel's (log time, offset)
    index). ``finish`` writes the summary section and the footer.
    """

    def __init__(self, stream: BinaryIO, *, compression_level: int):
        import zstandard

        self._stream = stream
        self._pos = 0
        self._compressor = zstandard.ZstdCompressor(level=compression_level)
        self._schemas: list[Schema] = []
        self._channels: list[Channel] = []
        self._chunk_indexes: list[ChunkIndex] = []
        self._attachment_indexes: list[AttachmentIndex] = []
        self._metadata_indexes: list[MetadataIndex] = []
        self._stats = Statistics(
            message_count=0,
            schema_count=0,
            channel_count=0,
            attachment_count=0,
            metadata_count=0,
            chunk_count=0,
            message_start_time=0,
            message_end_time=0,
            channel_message_counts=defaultdict(int),
        )

    def _write(self, data: bytes | bytearray | memoryview) -> int:
        at = self._pos
        self._stream.write(data)
        self._pos += len(data)
        return at

    def _record(self, record) -> tuple[int, int]:
        builder = RecordBuilder()
        record.write(builder)
        data = builder.end()
        return self._write(data), len(data)

    def start(self, library: str) -> None:
        """Magic and header (empty profile: channels may mix encodings)."""
        self._write(MAGIC)
        self._record(Header(profile="", library=library))

    def schema(self, schema: messages.Schema) -> int:
        """A schema record; returns its id."""
        record = Schema(
            id=len(self._schemas) + 1, name=schema.name, encoding=schema.encoding, data=schema.data
        )
        self._schemas.append(record)
        self._stats.schema_count += 1
        self._record(record)
        return record.id

    def channel(self, topic: str, encoding: str, schema_id: int, metadata: dict[str, str]) -> int:
        """A channel record; returns its id."""
        record = Channel(
            id=len(self._channels) + 1,
            topic=topic,
            message_encoding=encoding,
            schema_id=schema_id,
            metadata=metadata,
        )
        self._channels.append(record)
        self._stats.channel_count += 1
        self._record(record)
        return record.id

    def attachment(self, name: str, media_type: str, data: bytes, create_time: int) -> None:
        """An attachment record (with its CRC), indexed in the summary."""
        record = Attachment(
            create_time=create_time, log_time=0, name=name, media_type=media_type, data=data
        )
        offset, length = self._record(record)
        self._attachment_indexes.append(
            AttachmentIndex(offset, length, 0, create_time, len(data), name, media_type)
        )
        self._stats.attachment_count += 1

    def metadata(self, name: str, data: dict[str, str]) -> None:
        """A metadata record, indexed in the summary."""
        offset, length = self._record(Metadata(name=name, metadata=data))
        self._metadata_indexes.append(MetadataIndex(offset, length, name))
        self._stats.metadata_count += 1

    def chunk(self, data: bytes | np.ndarray, index: dict[int, np.ndarray]) -> None:
        """One chunk of message records; ``index``: channel → (n, 2) uint64 (log time, offset)."""
        times = np.concatenate([rows[:, 0] for rows in index.values()])
        start, end = int(times.min()), int(times.max())
        chunk = Chunk(
            compression="zstd",
            data=self._compressor.compress(data),
            message_start_time=start,
            message_end_time=end,
            uncompressed_crc=zlib.crc32(data),
            uncompressed_size=len(data),
        )
        chunk_at, chunk_length = self._record(chunk)
        offsets = {}
        index_at = self._pos
        for channel, rows in index.items():
            body = np.ascontiguousarray(rows, dtype="<u8").tobytes()
            head = struct.pack("<BQHI", Opcode.MESSAGE_INDEX, 6 + len(body), channel, len(body))
            offsets[channel] = self._write(head + body)
            self._stats.channel_message_counts[channel] += len(rows)
        self._chunk_indexes.append(
            ChunkIndex(
                message_start_time=start,
                message_end_time=end,
                chunk_start_offset=chunk_at,
                chunk_length=chunk_length,
                message_index_offsets=offsets,
                message_index_length=self._pos - index_at,
                compression=chunk.compression,
                compressed_size=len(chunk.data),
                uncompressed_size=len(data),
            )
        )
        stats = self._stats
        stats.message_start_time = (
            start if not stats.message_count else min(start, stats.message_start_time)
        )
        stats.message_end_time = max(end, stats.message_end_time)
        stats.message_count += len(times)
        stats.chunk_count += 1
        self._stream.flush()

    def finish(self) -> None:
        """Data end, summary section (schemas, channels, statistics, indexes), footer, magic."""
        self._record(DataEnd(data_section_crc=0))
        summary_start = self._pos
        builder = RecordBuilder()
        groups = [
            (Opcode.SCHEMA, self._schemas),
            (Opcode.CHANNEL, self._channels),
            (Opcode.STATISTICS, [self._stats]),
            (Opcode.CHUNK_INDEX, self._chunk_indexes),
            (Opcode.ATTACHMENT_INDEX, self._attachment_indexes),
            (Opcode.METADATA_INDEX, self._metadata_indexes),
        ]
        offsets = []
        for opcode, records in groups:
            if not records:
                continue
            group_start = builder.count
            for record in records:
                record.write(builder)
            offsets.append(
                SummaryOffset(opcode, summary_start + group_start, builder.count - group_start)
            )
        summary_offset_start = summary_start + builder.count
        for offset in offsets:
            offset.write(builder)
        summary = builder.end()
        crc = zlib.crc32(summary)
        crc = zlib.crc32(
            struct.pack("<BQQQ", Opcode.FOOTER, 20, summary_start, summary_offset_start), crc
        )
        self._write(summary)
        self._record(
            Footer(
                summary_start=summary_start,
                summary_offset_start=summary_offset_start,
                summary_crc=crc,
            )
        )
        self._write(MAGIC)
        self._stream.flush()


# --- reading --------------------------------------------------------------------------------------


@dataclass
class Scan:
    """Raw contents of an MCAP file, gathered record by record."""

    library: str = ""
    schemas: dict[int, Schema] = field(default_factory=dict)
    channels: dict[int, Channel] = field(default_factory=dict)
    metadata: dict[str, dict[str, str]] = field(default_factory=dict)
    attachments: dict[str, bytes] = field(default_factory=dict)
    #: channel → blocks of (sequences, log times, payloads as (m, L) bytes or a list of bytes)
    messages: dict[int, list[tuple[np.ndarray, np.ndarray, Any]]] = field(
        default_factory=lambda: defaultdict(list)
    )
    data_end: bool = False
    problem: str = ""


_MESSAGE_HEAD = struct.Struct("<BQHIQQ")
_OPCODE_NAMES = {int(op): op.name.lower().replace("_", " ") for op in Opcode}


def _register(scan, opcode: int, body) -> None:
    """Add a schema or channel record to the scan's tables (other records are ignored)."""
    if opcode == Opcode.SCHEMA:
        schema = _parse(Schema, body)
        scan.schemas[schema.id] = schema
    elif opcode == Opcode.CHANNEL:
        channel = _parse(Channel, body)
        scan.channels[channel.id] = channel


def _parse(record_type, body: memoryview):
    return record_type.read(ReadDataStream(BytesIO(body)))


def _decompress(chunk: Chunk) -> bytes:
    if chunk.compression == "":
        return bytes(chunk.data)
    if chunk.compression == "zstd":
        import zstandard

        return zstandard.ZstdDecompressor().decompress(
            chunk.data, max_output_size=chunk.uncompressed_size
        )
    if chunk.compression == "lz4":
        import lz4.frame

        return lz4.frame.decompress(chunk.data)
    raise ValueError(f'unknown compression "{chunk.compression}"')


def _chunk_messages(scan: Scan, data: bytes, where: str) -> None:
    """Gather the records of a chunk: messages by channel, as (m, L) byte blocks when they can."""
    size = len(data)
    offsets, lengths = [], []
    unpack = struct.Struct("<Q").unpack_from
    pos = 0
    while pos < size:
        if pos + 9 > size:
            raise ValueError(f"{where}: a record header runs past the end of the chunk")
        (length,) = unpack(data, pos + 1)
        offsets.append(pos)
        lengths.append(length)
        pos += 9 + length
    if pos != size:
        raise ValueError(f"{where}: a record runs past the end of the chunk")
    if not offsets:
        return
    raw = np.frombuffer(data, dtype=np.uint8)
    starts = np.array(offsets, dtype=np.int64)
    sizes = np.array(lengths, dtype=np.int64)
    opcodes = raw[starts]
    for at, length, opcode in zip(
        starts[opcodes != Opcode.MESSAGE],
        sizes[opcodes != Opcode.MESSAGE],
        opcodes[opcodes != Opcode.MESSAGE],
        strict=True,
    ):
        _register(scan, opcode, memoryview(data)[at + 9 : at + 9 + length])
    is_message = opcodes == Opcode.MESSAGE
    starts, sizes = starts[is_message], sizes[is_message]
    if np.any(sizes < 22):
        raise ValueError(f"{where}: a message record is too short")
    width = RECORD_HEADER.itemsize
    heads = raw[starts[:, None] + np.arange(width)].copy().view(RECORD_HEADER).reshape(-1)
    payload_sizes = sizes - 22
    for channel in np.unique(heads["channel"]):
        pick = heads["channel"] == channel
        first, count = starts[pick] + width, payload_sizes[pick]
        if np.all(count == count[0]):
            payloads: Any = raw[first[:, None] + np.arange(count[0])]
        else:
            payloads = [data[a : a + c] for a, c in zip(first, count, strict=True)]
        scan.messages[int(channel)].append(
            (heads["sequence"][pick].astype(np.int64), heads["log_time"][pick], payloads)
        )


def scan(data: bytes | memoryview) -> Scan:
    """Read an MCAP file's data section record by record; stop at a cut and say where.

    Raises:
        DamagedFile: a record that is present but cannot be read (unknown type, bad CRC, ...).
    """
    scan = Scan()
    view = memoryview(data)
    size = len(data)
    pos = len(MAGIC)
    while pos < size:
        if pos + 9 > size:
            scan.problem = f"the file ends inside a record header at byte {pos}"
            break
        opcode, length = struct.unpack_from("<BQ", view, pos)
        name = _OPCODE_NAMES.get(opcode)
        if name is None:
            raise DamagedFile(
                f"unknown MCAP record type 0x{opcode:02x} at byte {pos}: the file is corrupted"
            )
        end = pos + 9 + length
        if end > size:
            scan.problem = (
                f"the file ends inside a {name} record at byte {pos} ({size - pos} of "
                f"{length + 9} bytes present)"
            )
            break
        body = view[pos + 9 : end]
        try:
            if opcode == Opcode.HEADER:
                scan.library = _parse(Header, body).library
            elif opcode in (Opcode.SCHEMA, Opcode.CHANNEL):
                _register(scan, opcode, body)
            elif opcode == Opcode.METADATA:
                record = _parse(Metadata, body)
                scan.metadata[record.name] = dict(record.metadata)
            elif opcode == Opcode.ATTACHMENT:
                stored = struct.unpack_from("<I", body, len(body) - 4)[0]
                if stored and stored != zlib.crc32(body[:-4]):
                    raise ValueError(f"attachment at byte {pos} fails its CRC check")
                attachment = _parse(Attachment, body)
                scan.attachments[attachment.name] = bytes(attachment.data)
            elif opcode == Opcode.CHUNK:
                chunk = _parse(Chunk, body)
                records = _decompress(chunk)
                if len(records) != chunk.uncompressed_size:
                    raise ValueError(f"chunk at byte {pos} decompresses to the wrong size")
                if chunk.uncompressed_crc and zlib.crc32(records) != chunk.uncompressed_crc:
                    raise ValueError(f"chunk at byte {pos} fails its CRC check")
                _chunk_messages(scan, records, f"chunk at byte {pos}")
            elif opcode == Opcode.MESSAGE:
                _, _, channel, sequence, log_time, _ = _MESSAGE_HEAD.unpack_from(view, pos)
                block = (np.array([sequence]), np.array([log_time], np.uint64), [body[22:]])
                scan.messages[channel].append(block)
            elif opcode in (Opcode.DATA_END, Opcode.FOOTER):
                scan.data_end = True
                break
        except MemoryError:
            raise  # not damage: open_log says that memory ran out
        except Exception as err:  # zstd, struct, UTF-8, CRC: the bytes are damaged
            raise DamagedFile(
                f"{name} record at byte {pos} is damaged ({err}): the file is corrupted"
            ) from err
        pos = end
    else:
        if not scan.data_end:
            scan.problem = f"the file ends at byte {size} without a data-end record or footer"
    return scan
