"""Input files of a run: the fingerprint (SHA-256 and size) of every file its loads read.

A log records the fingerprint of each file a run read (CSV and OpenFAST tables, the scenario
file) in its metadata (``input_files``); ``pinwind run --from-log`` compares the files with them
before it repeats the run, so that a table edited since is refused rather than silently used.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pinwind.errors import InputFileChanged


@dataclass(frozen=True)
class InputFile:
    """The fingerprint of one file a run read.

    Attributes:
        where: the input that read it (``torque.carrier``, ``wind``, ``scenario``).
        path: the file as the run was given it (relative to the scenario's folder or the
            working folder).
        resolved: the file's absolute path when it was read.
        sha256: SHA-256 of its bytes, as hex.
        size: its size [bytes].
    """

    where: str
    path: str
    resolved: str
    sha256: str
    size: int

    @classmethod
    def of(cls, path: str | Path, *, given: str | None = None, where: str) -> InputFile:
        """Fingerprint the file at ``path`` (``given``: how the run named it, default path)."""
        data = Path(path).read_bytes()
        return cls(
            where=where,
            path=str(path) if given is None else given,
            resolved=str(Path(path).resolve()),
            sha256=hashlib.sha256(data).hexdigest(),
            size=len(data),
        )

    def record(self) -> dict[str, Any]:
        """What the log stores (``input_files`` of the ``pinwind.run`` record)."""
        return {"where": self.where, "path": self.path, "resolved": self.resolved,
                "sha256": self.sha256, "bytes": self.size}  # fmt: skip


def check_unchanged(records: list[dict[str, Any]], *, skip: tuple[str, ...] = ()) -> None:
    """Refuse when a recorded file differs from its fingerprint (or is gone).

    Args:
        records: the ``input_files`` a log recorded (``InputFile.record``).
        skip: inputs (``where``) not compared, e.g. ``"scenario"``: a repeat of a logged run
            takes the scenario's values from the log, not from its file.

    Raises:
        InputFileChanged: the first file whose SHA-256 or size differs, or that is missing,
            naming it, the input that read it, and both fingerprints.
    """
    for item in records:
        if item.get("where") in skip:
            continue
        path = Path(item["resolved"])
        recorded = (str(item["sha256"]), int(item["bytes"]))
        try:
            now = InputFile.of(path, where=item["where"])
        except OSError:
            raise InputFileChanged(item["where"], item["path"], recorded, None) from None
        if (now.sha256, now.size) != recorded:
            raise InputFileChanged(item["where"], item["path"], recorded, (now.sha256, now.size))
