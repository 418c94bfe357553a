"""pinwind plot: one figure per panel group, with content, in PNG, SVG or PDF."""

from __future__ import annotations

import numpy as np
import pytest

from pinwind.errors import FigureFailed, InputError
from pinwind.io.figures import plot_log
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


def test_a_full_disk_stops_the_plot_in_one_error_and_leaves_no_partial_figure(
    logged_run, tmp_path, monkeypatch
):
    import errno

    from matplotlib.figure import Figure

    written = []

    def savefig(self, fname, **kwargs):  # the second figure meets a full disk
        if written:
            with open(fname, "wb") as f:
                f.write(b"partial")
            raise OSError(errno.ENOSPC, "No space left on device")
        written.append(fname)
        with open(fname, "wb") as f:
            f.write(b"png")

    monkeypatch.setattr(Figure, "savefig", savefig)
    with pytest.raises(FigureFailed, match="No space left on device") as failed:
        plot_log(logged_run.path, tmp_path)
    assert failed.value.path.endswith("02_torques_and_power.png")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["01_speeds.png"]


def test_unknown_format_is_refused(logged_run, tmp_path):
    with pytest.raises(InputError, match='unknown figure format "jpgg"'):
        plot_log(logged_run.path, tmp_path, format="jpgg")


def test_plot_reads_the_log_a_block_at_a_time_and_draws_every_peak(logged_run, tmp_path):
    # Memory must not grow with the log: the figures come from blocks of `block` samples, never
    # from one array of the whole run; the largest mesh force of the run is still on the plot.
    import matplotlib.pyplot as plt

    from pinwind.io import log_reader

    capacities = []
    sink = log_reader.ColumnSink

    def spy(layout, shapes, keys, capacity):
        capacities.append(capacity)
        return sink(layout, shapes, keys, capacity)

    drawn = []
    savefig = plt.Figure.savefig

    def keep_lines(fig, *args, **kwargs):
        drawn.extend(line.get_ydata() for ax in fig.axes for line in ax.get_lines())
        return savefig(fig, *args, **kwargs)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(log_reader, "ColumnSink", spy)
        mp.setattr(plt.Figure, "savefig", keep_lines)
        plot_log(logged_run.path, tmp_path, block=40, groups=["mesh forces"])
    assert set(capacities) == {40}
    peak_kN = np.abs(logged_run.result.mesh_normal).max() / 1e3  # the panel is in kN
    np.testing.assert_allclose(max(np.abs(y).max() for y in drawn), peak_kN, rtol=1e-12)


def test_plot_cli_refuses_an_empty_window_in_one_line(logged_run, tmp_path):
    out = run("plot", str(logged_run.path), "-o", str(tmp_path), "--from", "5")
    assert out.returncode == 2
    assert out.stderr.count("\n") == 1 and "no samples between --from 5" in out.stderr


def test_a_run_with_a_rotor_gets_the_rotor_figure(rotor_run, tmp_path):
    written = plot_log(rotor_run.path, tmp_path, groups=["torques and power", "rotor"])
    assert [p.name for p in written] == ["02_torques_and_power.png", "03_rotor.png"]
    for path in written:
        assert path.stat().st_size > 10_000, path.name


def test_caption_gives_a_rotors_settings_in_units_and_leaves_unset_ones_out():
    # The caption of `pinwind spectrum`'s PNG read "mass 0, shaft tilt 0, ..., hub height None",
    # and for the NREL 5 MW rotor it printed its whole C_p and C_t tables, number by number.
    from pinwind.io.figures import loads_text
    from pinwind.loads.pitch_control import PitchControl
    from pinwind.loads.rotor import Rotor

    saleh = loads_text({"rotors": {"carrier": Rotor.saleh2017().describe()}})[0]
    assert "None" not in saleh and "hub height" not in saleh and "mass 0 kg" in saleh
    rotor = Rotor.nrel5mw(pitch_control=PitchControl.nrel5mw())
    nrel = loads_text({"rotors": {"rotor": rotor.describe()}})[0]
    # Jonkman et al. 2009 Table 1-1: hub height 90 m, shaft tilt 5° = 0.08727 rad, rotor 110 t;
    # §7.4: pitch rate 8°/s = 0.1396 rad/s; the set point 12.1 rpm.
    assert "hub height 90 m" in nrel and "shaft tilt 0.08727 rad" in nrel
    assert "mass 1.1e+05 kg" in nrel and "cp table, ct table," in nrel
    assert "speed set 12.1 rpm" in nrel and "rate 0.1396 rad/s" in nrel
    assert len(nrel) < 500, nrel
