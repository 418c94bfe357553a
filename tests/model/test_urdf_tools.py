"""The shipped models are real URDF: rerun's URDF loader reads them, gears and all."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import pytest
import rerun as rr
from rerun.chunk import RrdReader

from tests.conftest import MODELS

SHIPPED = sorted(p.name for p in MODELS.glob("*.urdf"))


@pytest.mark.parametrize("name", SHIPPED)
def test_rerun_urdf_loader_shows_the_visual_of_every_link(name, tmp_path):
    rrd = tmp_path / "model.rrd"
    rec = rr.RecordingStream("pinwind-urdf-check")
    rec.save(rrd)
    rec.log_file_from_path(MODELS / name)
    rec.flush()
    rec.disconnect()
    paths = {str(chunk.entity_path) for chunk in RrdReader(rrd).stream().to_chunks()}
    root = ET.parse(MODELS / name).getroot()
    visual_links = [el.get("name") for el in root.findall("link") if el.find("visual") is not None]
    assert visual_links
    for link in visual_links:
        assert any(f"/visual_geometries/{link}/" in path for path in paths), (link, sorted(paths))
