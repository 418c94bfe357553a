"""pinwind plot: one figure per panel group, with content, in PNG, SVG or PDF."""

from __future__ import annotations

import numpy as np
import pytest

from pinwind.errors import InputError
from pinwind.io.figures import envelope, plot_log
from tests.io.test_cli_log import run

#: The planetary run has no rotor: no figure 03_rotor.
GROUP_FILES = [
    "01_speeds.png",
    "02_torques_and_power.png",
    "04_mesh_forces.png",
    "05_force_components.png",
    "06_mesh_deflection.png",
    "07_bearings.png",
    "08_load_sharing.png",
    "09_energy.png",
]


@pytest.fixture(scope="module")
def figures(logged_run, tmp_path_factory):
    """``pinwind plot LOG -o DIR``: the files it names, and the folder."""
    out = tmp_path_factory.mktemp("figures")
    done = run("plot", str(logged_run.path), "-o", str(out))
    assert done.returncode == 0, done.stderr
    paths = [out / line.split("/")[-1] for line in done.stdout.split() if line.endswith(".png")]
    return paths, out


def test_plot_writes_one_png_per_group(figures):
    paths, out = figures
    assert [p.name for p in paths] == GROUP_FILES
    assert sorted(p.name for p in out.iterdir()) == GROUP_FILES


def test_every_figure_has_drawn_content(figures):
    import matplotlib.image as mpimg

    paths, _ = figures
    for path in paths:
        pixels = mpimg.imread(path)[..., :3]
        # A blank (one-colour) image has zero variance; lines, text and grids give > 1e-3.
        assert pixels.var() > 1e-3, path.name
        # Coloured series are drawn: some pixels are far from grey.
        saturation = pixels.max(axis=-1) - pixels.min(axis=-1)
        assert (saturation > 0.3).sum() > 500, path.name


def test_svg_and_pdf_by_format_and_window(logged_run, tmp_path):
    svg = plot_log(logged_run.path, tmp_path, format="svg", start=0.1, stop=0.2, groups=["speeds"])
    assert [p.name for p in svg] == ["01_speeds.svg"]
    assert "<svg" in svg[0].read_text()[:2000]
    pdf = plot_log(logged_run.path, tmp_path, format="PDF", groups=["energy"])
    assert pdf[0].name == "09_energy.pdf"
    assert pdf[0].read_bytes()[:5] == b"%PDF-"


def test_unknown_format_is_refused(logged_run, tmp_path):
    with pytest.raises(InputError, match='unknown figure format "jpgg"'):
        plot_log(logged_run.path, tmp_path, format="jpgg")


def test_envelope_keeps_every_peak_of_a_long_series():
    t = np.linspace(0.0, 1.0, 100_001)
    v = np.sin(2 * np.pi * 3 * t)
    v[54_321] = 7.0
    te, ve = envelope(t, v, columns=500)
    assert len(ve) == 1000
    assert ve.max() == 7.0 and ve.min() == pytest.approx(-1.0, abs=1e-6)
    assert np.all(np.diff(te) >= 0)


def test_plot_cli_refuses_an_empty_window_in_one_line(logged_run, tmp_path):
    out = run("plot", str(logged_run.path), "-o", str(tmp_path), "--from", "5")
    assert out.returncode == 2
    assert out.stderr.count("\n") == 1 and "no samples between --from 5" in out.stderr


def test_a_run_with_a_rotor_gets_the_rotor_figure(rotor_run, tmp_path):
    written = plot_log(rotor_run.path, tmp_path, groups=["torques and power", "rotor"])
    assert [p.name for p in written] == ["02_torques_and_power.png", "03_rotor.png"]
    for path in written:
        assert path.stat().st_size > 10_000, path.name
