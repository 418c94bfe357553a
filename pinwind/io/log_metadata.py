"""The metadata records of a log: values as JSON in MCAP's string maps, the versions recorded.

MCAP metadata records map strings to strings; pinwind stores every value as JSON
(docs/log_format.md, "Metadata records") and decodes it back when it reads a log.
"""

from __future__ import annotations

import functools
import json
import platform
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
