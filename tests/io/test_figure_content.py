"""What ``pinwind plot`` draws: the loads in the caption, rounded; rigid meshes without TE;
identical planets told apart; slow and fast shafts on subplots of their own."""

from __future__ import annotations

import re

import numpy as np
import pytest

import pinwind
import pinwind.io.figures as figures
from pinwind.io.figures import SPEED_BAND, caption, plot_log


@pytest.fixture
def drawn(monkeypatch):
    """Every (axes, panel) ``plot_log`` draws, after drawing it."""
    seen: list[tuple[object, figures.DecimatedPanel]] = []
    real = figures._draw

    def record(ax, kept):
        real(ax, kept)
        seen.append((ax, kept))

    monkeypatch.setattr(figures, "_draw", record)
    return seen


def test_caption_lists_the_rotor_generator_and_wind(rotor_run):
    meta = pinwind.read_log(rotor_run.path).metadata
    text = " ".join(caption(meta, "completed", rotor_run.path, (0.0, 0.2), None, None).split())
    assert "loads: none" not in text
    # in the units of the axes: the generator's sync speed −1 rad/s is −60/2π = −9.549 rpm
    assert "a: rotor (radius 40 m," in text
    assert "b: generator (law linear-slip, slope 50 N·m·s/rad, sync speed -9.549 rpm)" in text
    assert "wind: type sine, mean 10 m/s, amplitude 2 m/s, frequency 10 Hz" in text


def test_caption_rounds_numbers_to_four_significant_digits():
    meta = {
        "model_name": "m",
        "dt": 1e-3,
        "torques": {"sun": "-166666.66666666666"},
        "speeds": {"carrier": "15.750374768772428"},
        "pinwind_version": "0.1.0",
    }
    text = " ".join(caption(meta, "completed", "run.mcap", (0.0, 1.0), None, None).split())
    # in the units of the axes: 15.750374768772428 rad/s · 60/2π = 150.4 rpm, −166666.67 N·m
    # = −166.7 kN·m, each to 4 significant digits
    assert "carrier: speed 150.4 rpm" in text and "sun: torque -166.7 kN·m" in text
    assert not re.search(r"\d\.\d{5,}", text)
    assert "pinwind 0.1.0" in text  # a version is not a number to round


def test_rigid_meshes_draw_no_transmission_error_but_say_so(logged_run, tmp_path, drawn):
    plot_log(logged_run.path, tmp_path, groups=["mesh deflection"])
    (_, kept), *_ = [(ax, k) for ax, k in drawn if k.panel.key == "transmission_error"]
    # Every mesh of the shared run is rigid: its teeth stay in contact by construction.
    assert {s.name for s in kept.panel.series} == set(logged_run.result.mesh_names)
    for s in kept.panel.series:
        np.testing.assert_array_equal(s.values, 0.0)
    assert any("rigid meshes: no transmission error" in note for note in kept.panel.notes)


def test_identical_planets_are_drawn_apart_and_named_as_coinciding(logged_run, tmp_path, drawn):
    plot_log(logged_run.path, tmp_path, groups=["mesh forces"])
    ax, kept = next((ax, k) for ax, k in drawn if k.panel.key == "mesh_force")
    labels = [text.get_text() for text in ax.get_legend().get_texts()]
    # Equal planets share the load exactly: the three sun meshes carry one force, as do the
    # three ring meshes.
    assert "sun_planet1–3 coincide" in labels and "planet1–3_ring coincide" in labels
    lines = {line.get_label(): line for line in ax.get_lines()}
    for trio in (["sun_planet1", "sun_planet2", "sun_planet3"], ["planet1_ring", "planet2_ring",
                                                                  "planet3_ring"]):  # fmt: skip
        styles = {(str(lines[n].get_linestyle()), lines[n].get_linewidth()) for n in trio}
        assert len(styles) == 3, trio
        # Drawn widest first, so that each later (narrower) line leaves the earlier one showing.
        widths = [lines[n].get_linewidth() for n in trio]
        assert widths == sorted(widths, reverse=True)


def test_speed_subplots_span_at_most_a_factor_of_ten(drivetrain_run, tmp_path, drawn):
    plot_log(drivetrain_run.path, tmp_path, groups=["speeds"])
    speeds = [k for _, k in drawn if k.panel.key == "speed"]
    assert len(speeds) > 1  # the drivetrain's 819 rpm pinion has its own subplot
    shown = [s.name for k in speeds for s in k.panel.series]
    assert sorted(shown) == sorted(drivetrain_run.result.joint_names)
    fastest = max(float(np.max(np.abs(s.values))) for k in speeds for s in k.panel.series)
    for k in speeds:
        peaks = [float(np.max(np.abs(s.values))) for s in k.panel.series]
        moving = [p for p in peaks if p > 1e-9 * fastest]  # the locked ring's rounding aside
        assert max(moving) <= SPEED_BAND * min(moving) * (1 + 1e-12), k.panel.title
