"""The MCAP container: write records (messages a chunk at a time) and find them again.

``McapWriter`` writes a chunked, indexed file (https://mcap.dev/spec) whose message records come
prebuilt, a block of samples at a time (``message_records`` or a caller's own numpy layout), and
whose other records are written with the ``mcap`` package's record classes. ``read_contents``
finds a file's channels, metadata, attachments and chunks from the summary section (or, when that
is missing or damaged, by walking the data section up to a cut), without reading any message
(the summary's records are decoded here, only those a read needs);
``read_chunk`` then reads, decompresses and CRC-checks one chunk. That is what lets ``read_log``
read only the chunks it needs and recover the intact chunks of a killed run or damaged file.
"""

from __future__ import annotations

import os
import struct
import threading
import zlib
from collections import defaultdict
from collections.abc import Callable, Sequence
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
    ChunkIndex,
    DataEnd,
    Footer,
    Header,
    McapRecord,
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


def _buffer(data: bytes | bytearray | memoryview | np.ndarray) -> bytes | bytearray | memoryview:
    """``data`` as a buffer the type checker knows (an array as the memoryview of its bytes).

    numpy's stubs give ``ndarray`` the buffer protocol (``__buffer__``) only from Python 3.12.
    """
    return data.data if isinstance(data, np.ndarray) else data


def _byte_view(data: bytes | bytearray | memoryview | np.ndarray) -> memoryview:
    """The bytes of ``data`` as a flat memoryview of unsigned bytes."""
    return memoryview(_buffer(data)).cast("B")


class McapWriter:
    """A chunked, indexed MCAP file written record by record (https://mcap.dev/spec).

    Schemas, channels, attachments and metadata go in the data section as they come; messages
    come as whole chunks (records already assembled, plus each channel's (log time, offset)
    index). ``finish`` writes the summary section and the footer.
    """

    def __init__(self, stream: BinaryIO, *, compression: str = "zstd", compression_level: int = 1):
        self._stream = stream
        self._pos = 0
        #: end of the last complete unit (the start records, a chunk with its message indexes, a
        #: metadata record): what ``rewind`` cuts the file back to after a failed write
        self.complete = 0
        self.compression = compression
        self._compress: Callable[[bytes | bytearray | memoryview], bytes]
        if compression == "zstd":
            import zstandard

            # zstd's own frame checksum (XXH64, ~10× faster than CRC32) guards the chunk, so
            # the chunk's CRC32 field is 0 ("not computed", MCAP spec): a flipped bit still
            # fails the read of that chunk, at a fifth of the cost on each side.
            self._compress = zstandard.ZstdCompressor(
                level=compression_level, write_checksum=True
            ).compress
        elif compression == "lz4":
            import lz4.frame

            def lz4_compress(data, level=compression_level):
                return lz4.frame.compress(data, compression_level=level, store_size=False)

            self._compress = lz4_compress
        elif compression == "":
            self._compress = bytes
        else:
            raise ValueError(f'unknown chunk compression "{compression}" (zstd, lz4 or "")')
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

    @property
    def position(self) -> int:
        """Bytes written so far."""
        return self._pos

    def _write(self, data: bytes | bytearray | memoryview | np.ndarray) -> int:
        """Write all of ``data`` (a raw file may take it in parts); returns where it starts."""
        at = self._pos
        view = _byte_view(data)
        while view:
            written = self._stream.write(view)
            if not written:
                raise OSError(f"the file accepted none of {len(view)} bytes")
            self._pos += written
            view = view[written:]
        return at

    def rewind(self) -> None:
        """Cut the file back to the end of its last complete unit (after a failed write).

        Raises:
            OSError: the file cannot be truncated.
        """
        self._stream.truncate(self.complete)
        self._stream.seek(self.complete)
        self._pos = self.complete

    def _record(self, record) -> tuple[int, int]:
        builder = RecordBuilder()
        record.write(builder)
        data = builder.end()
        return self._write(data), len(data)

    def start(self, library: str) -> None:
        """Magic and header (empty profile: channels may mix encodings)."""
        self._write(MAGIC)
        self._record(Header(profile="", library=library))

    def mark(self) -> None:
        """Everything written so far is complete (``rewind`` comes back here)."""
        self.complete = self._pos

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
        self.complete = self._pos

    def chunk(self, data: bytes | np.ndarray, index: dict[int, np.ndarray]) -> None:
        """One chunk of message records; ``index``: channel → (n, 2) uint64 (log time, offset).

        The chunk counts in the summary only once it and its message indexes are all written.
        """
        start = min(int(rows[0, 0]) for rows in index.values() if len(rows))
        end = max(int(rows[:, 0].max()) for rows in index.values() if len(rows))
        size = len(data)
        records = _buffer(data)
        compressed = self._compress(records)
        compression_checks = self.compression == "zstd"
        # the chunk record: its fixed fields, then the compressed records as they are
        name = self.compression.encode()
        head = struct.pack(
            f"<BQQQQII{len(name)}sQ",
            Opcode.CHUNK,
            8 + 8 + 8 + 4 + 4 + len(name) + 8 + len(compressed),
            start,
            end,
            size,
            0 if compression_checks else zlib.crc32(records),
            len(name),
            name,
            len(compressed),
        )
        chunk_at = self._write(head)
        self._write(compressed)
        chunk_length = self._pos - chunk_at
        # its message indexes, one record per channel, in one write
        offsets = {}
        index_at = self._pos
        parts = []
        at = index_at
        for channel, rows in index.items():
            body = np.ascontiguousarray(rows, dtype="<u8").tobytes()
            parts += [struct.pack("<BQHI", Opcode.MESSAGE_INDEX, 6 + len(body), channel, len(body))]
            parts.append(body)
            offsets[channel] = at
            at += 15 + len(body)
        self._write(b"".join(parts))
        self.complete = self._pos
        self._chunk_indexes.append(
            ChunkIndex(
                message_start_time=start,
                message_end_time=end,
                chunk_start_offset=chunk_at,
                chunk_length=chunk_length,
                message_index_offsets=offsets,
                message_index_length=self._pos - index_at,
                compression=self.compression,
                compressed_size=len(compressed),
                uncompressed_size=size,
            )
        )
        stats = self._stats
        count = 0
        for channel, rows in index.items():
            stats.channel_message_counts[channel] += len(rows)
            count += len(rows)
        stats.message_start_time = (
            start if not stats.message_count else min(start, stats.message_start_time)
        )
        stats.message_end_time = max(end, stats.message_end_time)
        stats.message_count += count
        stats.chunk_count += 1
        self._stream.flush()

    def finish(self) -> None:
        """Data end, summary section (schemas, channels, statistics, indexes), footer, magic."""
        self._record(DataEnd(data_section_crc=0))
        summary_start = self._pos
        builder = RecordBuilder()
        groups: list[tuple[Opcode, Sequence[McapRecord]]] = [
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


# --- reading a file by its indexes ----------------------------------------------------------------


@dataclass(frozen=True)
class ChunkRef:
    """Where a chunk is and what it holds, from the summary's chunk index or the data section.

    Attributes:
        offset: file offset of the chunk record [bytes].
        length: length of the whole chunk record, opcode and length field included [bytes].
        start_ns, end_ns: log times of its first and last message [ns].
        index: channel id → file offset of that channel's message-index record (empty when the
            indexes are missing, e.g. in a file cut just after the chunk).
        size: bytes of its records once decompressed (0: unknown).
    """

    offset: int
    length: int
    start_ns: int
    end_ns: int
    index: dict[int, int]
    size: int = 0


@dataclass
class Contents:
    """An MCAP file's records other than messages, and where its chunks are.

    Attributes:
        library: the header's library string.
        channels: channel id → Channel record.
        metadata: metadata name → (offset, length) of its record.
        attachments: attachment name → (offset, length) of its record.
        chunks: every chunk, in file order.
        indexed: the chunks come from the summary's chunk index (else from the data section).
        data_end: the data section ends with a data-end record (the file was finished).
        problem: where a file that was cut short ends, else ``""``.
        damage: damaged parts that were stepped over (the summary, a metadata record, ...).
    """

    library: str = ""
    channels: dict[int, Channel] = field(default_factory=dict)
    metadata: dict[str, tuple[int, int]] = field(default_factory=dict)
    attachments: dict[str, tuple[int, int]] = field(default_factory=dict)
    chunks: list[ChunkRef] = field(default_factory=list)
    indexed: bool = False
    data_end: bool = False
    problem: str = ""
    damage: list[str] = field(default_factory=list)


_RECORD_HEAD = struct.Struct("<BQ")
_FOOTER = struct.Struct("<BQQQI")  # opcode, length (20), summary start, summary offsets, CRC
_CHUNK_HEAD = struct.Struct("<QQQII")  # start, end, uncompressed size and CRC, compression length
_INDEX_HEAD = struct.Struct("<BQHI")  # opcode, length, channel, byte length of the entries


def read_at(fd: int, offset: int, length: int) -> bytes:
    """``length`` bytes at ``offset`` (fewer at the end of the file); safe from several threads."""
    if hasattr(os, "pread"):
        return os.pread(fd, length, offset)
    with _SEEK_LOCK:  # pragma: no cover (Windows)
        os.lseek(fd, offset, os.SEEK_SET)
        return os.read(fd, length)


_SEEK_LOCK = threading.Lock()


def read_contents(fd: int, size: int) -> Contents:
    """Schemas, channels, metadata, attachments and chunks of an MCAP file, without its messages.

    The summary section (chunk, metadata and attachment indexes) is used when the footer points
    to one and its CRC holds; otherwise the data section is walked record by record, reading only
    record headers and the fixed part of each chunk, up to a cut or an unreadable record.

    Raises:
        DamagedFile: a record before the first chunk cannot be read (nothing can be trusted).
    """
    contents = Contents()
    head = read_at(fd, len(MAGIC), 9)
    if len(head) == 9 and head[0] == Opcode.HEADER:
        (length,) = struct.unpack_from("<Q", head, 1)
        body = read_at(fd, len(MAGIC) + 9, min(length, 1 << 20))
        try:
            contents.library = _parse(Header, memoryview(body)).library
        except Exception:  # a damaged header only loses the writer's name
            contents.library = ""
    if not _read_summary(fd, size, contents):
        _walk_data_section(fd, size, contents)
    return contents


def _read_summary(fd: int, size: int, contents: Contents) -> bool:
    """Fill ``contents`` from the summary section; False when there is none or it is damaged."""
    tail = len(MAGIC) + _FOOTER.size
    if size < len(MAGIC) + tail or read_at(fd, size - len(MAGIC), len(MAGIC)) != MAGIC:
        return False  # no footer: a file cut short (the data section says where)
    footer_at = size - tail
    opcode, length, summary_start, offsets_start, crc = _FOOTER.unpack(
        read_at(fd, footer_at, _FOOTER.size)
    )
    if opcode != Opcode.FOOTER or length != 20:
        contents.damage.append(f"the footer at byte {footer_at} is damaged")
        return False
    if summary_start == 0:
        return False
    if not len(MAGIC) < summary_start <= footer_at or offsets_start > footer_at:
        contents.damage.append(f"the footer at byte {footer_at} points outside the file")
        return False
    summary = read_at(fd, summary_start, footer_at - summary_start)
    footer_head = _FOOTER.pack(opcode, length, summary_start, offsets_start, 0)[:-4]
    if crc and zlib.crc32(footer_head, zlib.crc32(summary)) != crc:
        contents.damage.append(f"the summary section at byte {summary_start} fails its CRC check")
        return False
    try:
        _summary_records(summary, summary_start, contents)
    except Exception as err:  # struct, UTF-8, lengths: damaged although the CRC was not set
        contents.channels.clear()
        contents.metadata.clear()
        contents.attachments.clear()
        contents.chunks.clear()
        contents.damage.append(f"the summary section at byte {summary_start} is damaged ({err})")
        return False
    contents.chunks.sort(key=lambda c: c.offset)
    contents.indexed = True
    contents.data_end = True
    return True


#: Summary records that a read does not need (skipped whole; their opcode is still checked).
_SUMMARY_SKIPPED = {Opcode.SCHEMA, Opcode.STATISTICS, Opcode.SUMMARY_OFFSET}
_U32 = struct.Struct("<I")
_U64_PAIR = struct.Struct("<QQ")
_CHANNEL_IDS = struct.Struct("<HH")  # channel id, schema id
_CHUNK_INDEX = struct.Struct("<QQQQI")  # start, end time, chunk offset, length, map bytes
_INDEX_OFFSET = struct.Struct("<HQ")  # channel id, offset of its message index


def _string(body: memoryview, pos: int) -> tuple[str, int]:
    """The length-prefixed UTF-8 string at ``pos`` of a record's body, and the position after."""
    (length,) = _U32.unpack_from(body, pos)
    pos += 4
    if pos + length > len(body):
        raise ValueError(f"a string of {length} bytes runs past its record")
    return str(body[pos : pos + length], "utf-8"), pos + length


def _channel(body: memoryview) -> Channel:
    """A Channel record's fields (MCAP specification, "Channel")."""
    channel_id, schema_id = _CHANNEL_IDS.unpack_from(body, 0)
    topic, pos = _string(body, 4)
    encoding, pos = _string(body, pos)
    (length,) = _U32.unpack_from(body, pos)
    pos += 4
    end = pos + length
    if end > len(body):
        raise ValueError(f"a channel's metadata of {length} bytes runs past its record")
    metadata: dict[str, str] = {}
    while pos < end:
        key, pos = _string(body, pos)
        metadata[key], pos = _string(body, pos)
    return Channel(
        id=channel_id,
        schema_id=schema_id,
        topic=topic,
        message_encoding=encoding,
        metadata=metadata,
    )


def _chunk_ref(body: memoryview) -> ChunkRef:
    """A Chunk Index record as a ChunkRef (MCAP specification, "Chunk Index")."""
    start_ns, end_ns, offset, length, map_bytes = _CHUNK_INDEX.unpack_from(body, 0)
    pos = _CHUNK_INDEX.size
    if pos + map_bytes > len(body):
        raise ValueError(f"a chunk index's offsets of {map_bytes} bytes run past its record")
    index = dict(_INDEX_OFFSET.iter_unpack(body[pos : pos + map_bytes]))
    _, pos = _string(body, pos + map_bytes + 8)  # after the message index length: compression
    _, size = _U64_PAIR.unpack_from(body, pos)  # compressed and uncompressed size
    return ChunkRef(offset, length, start_ns, end_ns, index, size)


def _summary_records(summary: bytes, at: int, contents: Contents) -> None:
    """Fill ``contents`` with the channels, chunks, metadata and attachments of a summary section.

    Only the records a read needs are decoded, by their layout in the MCAP specification
    (schemas, statistics and summary offsets are skipped); the ``mcap`` package's record
    classes parse every field through a stream, several times slower.

    Raises:
        ValueError, struct.error, UnicodeDecodeError: a record that does not fit its lengths.
    """
    view = memoryview(summary)
    pos = 0
    while pos < len(view):
        opcode, length = _RECORD_HEAD.unpack_from(view, pos)
        end = pos + 9 + length
        if end > len(view):
            raise ValueError(f"a record at byte {at + pos} runs past the footer")
        body = view[pos + 9 : end]
        if opcode == Opcode.CHUNK_INDEX:
            contents.chunks.append(_chunk_ref(body))
        elif opcode == Opcode.CHANNEL:
            channel = _channel(body)
            contents.channels[channel.id] = channel
        elif opcode == Opcode.METADATA_INDEX:
            offset, size = _U64_PAIR.unpack_from(body, 0)
            name, _ = _string(body, 16)
            contents.metadata[name] = (offset, size)
        elif opcode == Opcode.ATTACHMENT_INDEX:
            offset, size = _U64_PAIR.unpack_from(body, 0)
            name, _ = _string(body, 40)  # after log time, create time and data size
            contents.attachments[name] = (offset, size)
        elif opcode not in _SUMMARY_SKIPPED:
            raise ValueError(f"unexpected record type 0x{opcode:02x} at byte {at + pos}")
        pos = end


def _walk_data_section(fd: int, size: int, contents: Contents) -> None:
    """Find channels, metadata, attachments and chunks by walking the data section."""
    pos = len(MAGIC)
    chunk: ChunkRef | None = None
    while pos < size:
        head = read_at(fd, pos, 9)
        if len(head) < 9:
            contents.problem = f"the file ends inside a record header at byte {pos}"
            break
        opcode, length = _RECORD_HEAD.unpack(head)
        name = _OPCODE_NAMES.get(opcode)
        if name is None:
            message = f"unknown MCAP record type 0x{opcode:02x} at byte {pos}"
            if not contents.chunks:
                raise DamagedFile(f"{message}: the file is corrupted")
            contents.problem = f"{message}: the rest of the file cannot be read"
            break
        end = pos + 9 + length
        if end > size:
            contents.problem = (
                f"the file ends inside a {name} record at byte {pos} ({size - pos} of "
                f"{length + 9} bytes present)"
            )
            break
        if opcode == Opcode.CHUNK:
            fixed = read_at(fd, pos + 9, _CHUNK_HEAD.size)
            start, stop, records = (
                struct.unpack_from("<QQQ", fixed) if len(fixed) >= 24 else (0, 0, 0)
            )
            chunk = ChunkRef(pos, 9 + length, start, stop, {}, records)
            contents.chunks.append(chunk)
        elif opcode == Opcode.MESSAGE_INDEX:
            if chunk is not None and length >= 6:
                (channel,) = struct.unpack("<H", read_at(fd, pos + 9, 2))
                chunk.index[channel] = pos
        elif opcode in (Opcode.CHANNEL, Opcode.METADATA, Opcode.ATTACHMENT):
            if opcode == Opcode.ATTACHMENT:
                name_at = read_at(fd, pos + 9 + 16, 4)
                (name_length,) = struct.unpack("<I", name_at) if len(name_at) == 4 else (0,)
                label = read_at(fd, pos + 9 + 20, min(name_length, 4096))
                contents.attachments[label.decode("utf-8", "replace")] = (pos, 9 + length)
            else:
                body = memoryview(read_at(fd, pos + 9, length))
                try:
                    record = _parse(Channel if opcode == Opcode.CHANNEL else Metadata, body)
                except Exception as err:
                    where = f"{name} record at byte {pos} is damaged ({err})"
                    if not contents.chunks:
                        raise DamagedFile(f"{where}: the file is corrupted") from err
                    contents.damage.append(where)
                else:
                    if opcode == Opcode.CHANNEL:
                        contents.channels[record.id] = record
                    else:
                        contents.metadata[record.name] = (pos, 9 + length)
        elif opcode in (Opcode.DATA_END, Opcode.FOOTER):
            contents.data_end = True
            break
        pos = end
    else:
        contents.problem = f"the file ends at byte {size} without a data-end record or footer"


def read_metadata(fd: int, offset: int, length: int) -> dict[str, str]:
    """The key-value map of the metadata record at ``offset``.

    Raises:
        ValueError: the bytes there are not a readable metadata record.
    """
    data = read_at(fd, offset, length)
    if len(data) < 9 or data[0] != Opcode.METADATA:
        raise ValueError(f"no metadata record at byte {offset}")
    if _RECORD_HEAD.unpack_from(data)[1] != length - 9:
        raise ValueError(f"the metadata record at byte {offset} has a damaged length field")
    return dict(_parse(Metadata, memoryview(data)[9:]).metadata)


def read_attachment(fd: int, offset: int, length: int) -> bytes:
    """The data of the attachment record at ``offset``, its CRC checked.

    Raises:
        ValueError: not an attachment record, or its CRC fails.
    """
    data = memoryview(read_at(fd, offset, length))
    if len(data) < 13 or data[0] != Opcode.ATTACHMENT:
        raise ValueError(f"no attachment record at byte {offset}")
    body = data[9:]
    stored = struct.unpack_from("<I", body, len(body) - 4)[0]
    if stored and stored != zlib.crc32(body[:-4]):
        raise ValueError(f"the attachment at byte {offset} fails its CRC check")
    return bytes(_parse(Attachment, body).data)


def index_entries(fd: int, offset: int, channel: int, count_only: bool) -> np.ndarray | int:
    """A message-index record: its (log time, offset) entries as (k, 2) uint64, or just k.

    Raises:
        ValueError: the bytes at ``offset`` are not that channel's message index.
    """
    head = read_at(fd, offset, _INDEX_HEAD.size)
    if len(head) < _INDEX_HEAD.size:
        raise ValueError(f"the message index at byte {offset} is cut")
    opcode, length, found, size = _INDEX_HEAD.unpack(head)
    if opcode != Opcode.MESSAGE_INDEX or found != channel or size % 16 or size + 6 != length:
        raise ValueError(f"no message index of channel {channel} at byte {offset}")
    if count_only:
        return size // 16
    body = read_at(fd, offset + _INDEX_HEAD.size, size)
    if len(body) != size:
        raise ValueError(f"the message index at byte {offset} is cut")
    return np.frombuffer(body, dtype="<u8").reshape(-1, 2)


class DamagedChunk(ValueError):
    """A chunk that cannot be used: not a chunk record, fails its CRC, does not decompress."""


def read_chunk(fd: int, ref: ChunkRef, into: np.ndarray | None = None) -> bytes | np.ndarray:
    """The message records of a chunk, decompressed and CRC-checked.

    ``into``: a uint8 buffer to decompress a zstd chunk into when it is larger than the records
    (then a view of it is returned): fresh memory for every chunk costs more page faults than
    the decompression itself.

    Raises:
        DamagedChunk: the reason, naming the chunk's byte offset.
        MemoryError: no memory for the chunk (never reported as damage).
    """
    data = read_at(fd, ref.offset, ref.length)
    where = f"the chunk at byte {ref.offset}"
    if len(data) < 9 + _CHUNK_HEAD.size:
        raise DamagedChunk(f"{where} is cut")
    opcode, length = _RECORD_HEAD.unpack_from(data)
    if opcode != Opcode.CHUNK:
        name = _OPCODE_NAMES.get(opcode)
        what = f"a {name} record" if name else f"an unknown MCAP record type 0x{opcode:02x}"
        raise DamagedChunk(f"{where} is {what}")
    if 9 + length != ref.length:
        raise DamagedChunk(f"{where} has a damaged length field")
    _, _, size, crc, name_length = _CHUNK_HEAD.unpack_from(data, 9)
    at = 9 + _CHUNK_HEAD.size
    if name_length > 16 or at + name_length + 8 > len(data):
        raise DamagedChunk(f"{where} has a damaged header")
    compression = bytes(data[at : at + name_length]).decode("ascii", "replace")
    at += name_length
    (stored,) = struct.unpack_from("<Q", data, at)
    compressed = memoryview(data)[at + 8 :]
    if stored != len(compressed):
        raise DamagedChunk(f"{where} has a damaged header")
    records: bytes | np.ndarray
    try:
        if compression == "zstd" and into is not None and into.size > size:
            records = _zstd_into(compressed, into)
        else:
            records = _decompress_bytes(compression, compressed, size)
    except MemoryError:
        raise
    except Exception as err:  # zstd and lz4 errors: the compressed bytes are damaged
        if "memory" in str(err).lower():
            raise MemoryError(str(err)) from err
        raise DamagedChunk(f"{where} does not decompress ({err})") from err
    if len(records) != size:
        raise DamagedChunk(f"{where} decompresses to the wrong size")
    if crc and zlib.crc32(_byte_view(records)) != crc:
        raise DamagedChunk(f"{where} fails its CRC check")
    return records


def _zstd_into(data: memoryview, into: np.ndarray) -> np.ndarray:
    """The part of ``into`` that a zstd frame decompresses to.

    ``into`` is larger than the frame's contents, so that the whole frame is read and its
    checksum checked.
    """
    decompressor = getattr(_thread_zstd, "decompressor", None)
    if decompressor is None:  # one per thread: a context is not thread-safe, and costs 3 %
        import zstandard

        decompressor = _thread_zstd.decompressor = zstandard.ZstdDecompressor()
    filled = decompressor.stream_reader(data).readinto(into)
    return into[:filled]


#: Each reading thread's zstd decompressor (``_zstd_into``).
_thread_zstd = threading.local()


def _decompress_bytes(compression: str, data: memoryview, size: int) -> bytes:
    if compression == "":
        return bytes(data)
    if compression == "zstd":
        import zstandard

        return zstandard.ZstdDecompressor().decompress(data, max_output_size=size)
    if compression == "lz4":
        import lz4.frame

        return lz4.frame.decompress(data)
    raise ValueError(f'unknown compression "{compression}"')
