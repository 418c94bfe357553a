"""Metadata records carry a CRC-32: a one-byte edit of dt, a name or the status is noticed."""

from __future__ import annotations

import shutil
import struct
import warnings
import zlib
from pathlib import Path

import pytest

import pinwind
from pinwind.errors import LogError, TorquesUnbalanced
from pinwind.io.log_reader import LogDamaged, LogReader, open_log
from pinwind.runs import scenario as sc
from tests.io.conftest import PLANETARY


def _entry(key: str, value: str) -> bytes:
    """A metadata entry as MCAP stores it: length-prefixed key and value."""
    k, v = key.encode(), value.encode()
    return struct.pack("<I", len(k)) + k + struct.pack("<I", len(v)) + v


def _edit(path: Path, where: tuple[int, int], old: bytes, new: bytes) -> None:
    """Replace ``old`` by ``new`` (as long) once within bytes ``where`` (offset, length)."""
    assert len(old) == len(new)
    data = bytearray(path.read_bytes())
    offset, length = where
    at = data.find(old, offset, offset + length)
    assert at >= 0, old
    data[at : at + len(old)] = new
    path.write_bytes(bytes(data))


def _copy(logged_run, tmp_path: Path) -> tuple[Path, dict[str, tuple[int, int]]]:
    path = tmp_path / "edited.mcap"
    shutil.copy(logged_run.path, path)
    with LogReader(path) as reader:
        return path, dict(reader._contents.metadata)


def test_every_metadata_record_of_a_log_passes_its_crc32(logged_run):
    with LogReader(logged_run.path) as reader:
        assert reader.checksums == "verified"
        for name, (offset, length) in reader._contents.metadata.items():
            data = Path(logged_run.path).read_bytes()[offset : offset + length]
            # the record: opcode, length, name, then the map: its byte length and entries
            (name_length,) = struct.unpack_from("<I", data, 9)
            entries = data[9 + 4 + name_length + 4 :]
            pairs, at = {}, 0
            while at < len(entries):
                (n,) = struct.unpack_from("<I", entries, at)
                key = entries[at + 4 : at + 4 + n].decode()
                at += 4 + n
                (n,) = struct.unpack_from("<I", entries, at)
                pairs[key] = entries[at + 4 : at + 4 + n].decode()
                at += 4 + n
            recorded = pairs.pop("crc32")
            body = b"".join(_entry(k, pairs[k]) for k in sorted(pairs))
            assert recorded == f"{zlib.crc32(body):08x}", name


@pytest.mark.parametrize(
    ("record", "old", "new"),
    [
        ("pinwind.run", _entry("dt", "0.001"), _entry("dt", "0.003")),
        ("pinwind.run", _entry("log_stride", "1"), _entry("log_stride", "3")),
        ("pinwind.end", _entry("status", '"completed"'), _entry("status", '"completes"')),
        ("pinwind", _entry("format_version", "3"), _entry("format_version", "2")),
    ],
)
def test_one_byte_edit_of_a_metadata_record_warns_naming_it(logged_run, tmp_path, record, old, new):
    path, records = _copy(logged_run, tmp_path)
    _edit(path, records[record], old, new)
    with pytest.warns(LogDamaged, match=f"the '{record}' metadata record fails its CRC-32 check"):
        back = pinwind.read_log(path)
    assert back.metadata["log"]["metadata_checksums"] == f"failed: {record}"
    assert len(back) == len(logged_run.result)  # the samples themselves are intact


@pytest.mark.parametrize(
    ("old", "new"), [(b'"carrier"', b'"karrier"'), (b'"planet1"', b'"planet2"')]
)
def test_edited_joint_name_is_refused_rather_than_put_under_a_wrong_name(
    logged_run, tmp_path, old, new
):
    path, records = _copy(logged_run, tmp_path)
    _edit(path, records["pinwind.model"], old, new)
    with pytest.raises(LogError, match="'pinwind.model' metadata record fails its CRC-32 check"):
        pinwind.read_log(path)


def test_log_without_checksums_reads_with_a_note():
    old = Path(__file__).parent / "data" / "planetary_format2.mcap"
    with warnings.catch_warnings():
        warnings.simplefilter("error", LogDamaged)
        back = pinwind.read_log(old)
    assert back.metadata["log"]["metadata_checksums"].startswith("none: written by a pinwind")


def test_damaged_model_attachment_is_reported_as_damaged_not_missing(tmp_path):
    scenario = sc.build({"model": str(PLANETARY), "duration": 0.02, "torque": {"carrier": 1e5}})
    with pytest.warns(TorquesUnbalanced):
        sc.run(scenario, out=tmp_path / "run.mcap")
    path = tmp_path / "run.mcap"
    with LogReader(path) as reader:
        ((offset, length),) = reader._contents.attachments.values()
    _edit(path, (offset, length), b"<robot", b"<robut")
    with pytest.warns(LogDamaged, match="attachment 'saleh2017_planetary.urdf' is damaged"):
        log = open_log(path)
    assert "is damaged" in log.model_problem and "CRC" in log.model_problem
    with pytest.raises(LogError, match=r"model file attached to the log .* is damaged") as err:
        sc.from_log(path)
    assert "no model file" not in str(err.value)


def test_from_log_refuses_a_run_record_that_fails_its_crc32(tmp_path):
    scenario = sc.build({"model": str(PLANETARY), "duration": 0.02, "torque": {"carrier": 1e5}})
    with pytest.warns(TorquesUnbalanced):
        sc.run(scenario, out=tmp_path / "run.mcap")
    path = tmp_path / "run.mcap"
    with LogReader(path) as reader:
        where = reader._contents.metadata["pinwind.run"]
    _edit(path, where, _entry("dt", "0.001"), _entry("dt", "0.003"))
    with pytest.raises(LogError, match="'pinwind.run' metadata record fails its CRC-32 check"):
        sc.from_log(path)
