"""The metadata records of a log: values as JSON in MCAP's string maps, the versions recorded.

MCAP metadata records map strings to strings; pinwind stores every value as JSON
(docs/log_format.md, "Metadata records") and decodes it back when it reads a log. MCAP gives
metadata records no CRC, so pinwind adds one to each (``crc32``): a one-byte edit of ``dt`` or
a joint name would otherwise be read as if the run had said it.
"""

from __future__ import annotations

import functools
import json
import platform
import struct
import zlib
from datetime import UTC, datetime
from typing import Any

import numpy as np


def utc_now() -> str:
    """The current UTC time, ISO 8601 to the second."""
    return datetime.now(UTC).isoformat(timespec="seconds")


def _plain(value: Any) -> Any:
    """JSON fallback: numpy scalars and arrays as numbers and lists, anything else as text."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    return str(value)


def json_record(values: dict[str, Any]) -> dict[str, str]:
    """MCAP metadata holds strings: every value is stored as JSON."""
    return {
        key: json.dumps(value, ensure_ascii=False, default=_plain) for key, value in values.items()
    }


@functools.cache
def versions() -> dict[str, str]:
    """Versions of Python and the packages a log records (looked up once per process)."""
    from importlib.metadata import PackageNotFoundError, version

    out = {"python": platform.python_version()}
    for dist in ("pinwind", "pin", "proxsuite", "numpy", "mcap", "protobuf", "rerun-sdk"):
        try:
            out[dist] = version(dist)
        except PackageNotFoundError:
            out[dist] = "not installed"
    return out


def json_values(record: dict[str, str]) -> dict[str, Any]:
    """A metadata record's values decoded from JSON (a value that is not JSON stays text)."""
    out = {}
    for key, text in record.items():
        try:
            out[key] = json.loads(text)
        except json.JSONDecodeError:
            out[key] = text
    return out


#: The key of a metadata record's checksum (absent from the logs of earlier pinwind versions).
CHECKSUM_KEY = "crc32"


def record_crc32(record: dict[str, str]) -> str:
    """CRC-32 of a record's entries, as 8 hex digits; its own ``crc32`` entry left out.

    The bytes are those MCAP stores for each entry (key length uint32 little-endian, key in
    UTF-8, value length, value), entries in key order, so that a tool that rewrites the record
    in another order keeps it valid.
    """
    body = bytearray()
    for key in sorted(record):
        if key == CHECKSUM_KEY:
            continue
        for text in (key, record[key]):
            data = text.encode("utf-8")
            body += struct.pack("<I", len(data)) + data
    return f"{zlib.crc32(body):08x}"


def with_checksum(record: dict[str, str]) -> dict[str, str]:
    """The record with its ``crc32`` entry (what the log writer writes)."""
    return {**record, CHECKSUM_KEY: record_crc32(record)}


def checksum_problem(record: dict[str, str]) -> str | None:
    """Why a record fails its checksum, ``""`` when it passes, None when it has none (old log).

    The checksum entry is removed from ``record``.
    """
    recorded = record.pop(CHECKSUM_KEY, None)
    if recorded is None:
        return None
    computed = record_crc32(record)
    if recorded == computed:
        return ""
    return f"fails its CRC-32 check (recorded {recorded}, computed {computed})"
