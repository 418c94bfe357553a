"""``pinwind fatigue``: each bad input is one message and exit 2; ``--quick`` end to end."""

from __future__ import annotations

import csv
import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pytest
from numpy.testing import assert_allclose

from pinwind.cli import main
from tests.conftest import fatigue_toml
from tests.test_cli import run


def fatigue_exit(args: list[str], monkeypatch, capsys) -> tuple[int, str]:
    """Run ``pinwind fatigue ARGS`` in this process: (exit code, stderr)."""
    monkeypatch.setattr(sys, "argv", ["pinwind", "fatigue", *args])
    with pytest.raises(SystemExit) as caught:
        main()
    return caught.value.code, capsys.readouterr().err


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("dtu500_planetary.urdf", "no_such_model.urdf", "model: "),
        ("hours = [1000, 250]", "hours = [1000]", "one value per bin (2 bins)"),
        ("m = 3.0", "m = 0.0", "slope exponent m is 0.0 but must be finite and positive"),
        ("endurance_limit_mpa = 0.0", "endurance_limit_mpa = -5.0", "endurance limit [Pa] is -5"),
        ("turbulence = 0.1", "turbulence = 0.0", "must be finite and positive"),
        ("duration = 0.04\n", "", "fatigue.duration: missing: give the simulated seconds per case"),
        (
            "[fatigue.site]",
            '[fatigue.openfast]\nfiles = "of/v{speed:g}.outb"\njoint = "carrier"\n[fatigue.site]',
            "of/v10.outb (case v10.00_ti0.1000_s3) does not exist",
        ),
        (
            "[fatigue.site]",
            "[fatigue.bearings]\nplanet9 = { lubricant_vg = 220 }\n[fatigue.site]",
            'unknown bearing "planet9"; did you mean "planet3"? bearings are: planet1',
        ),
        (
            "[fatigue.site]",
            "[fatigue.bearings]\nplanet1 = { lubricant_vg = 321 }\n[fatigue.site]",
            'lubricant_vg="321" is not an ISO 3448 viscosity grade',
        ),
        (
            "[fatigue.site]",
            '[fatigue.bearings]\nplanet1 = { size_mm = "300 200 60", lubricant = 220 }\n'
            "[fatigue.site]",
            'unknown attribute "lubricant"; did you mean "lubricant_vg"?',
        ),
    ],
)
def test_bad_fatigue_input_is_one_message_and_exit_2(
    tmp_path, monkeypatch, capsys, old, new, message
):
    path = fatigue_toml(tmp_path)
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new))
    code, err = fatigue_exit([str(path)], monkeypatch, capsys)
    assert code == 2
    assert message in err, err
    assert err.strip().count("\n") == 0, err
    assert str(path) in err


def test_quick_run_prints_damage_whose_bins_add_up_to_the_total(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    quick = "[fatigue.quick]\nduration = 0.03\n"
    path = fatigue_toml(tmp_path)
    path.write_text(path.read_text() + quick)
    out = run("fatigue", str(path), "--quick", "--json", "--workers", "1", "--figures", "figs")
    assert out.returncode == 0, out.stderr
    report = json.loads(out.stdout)
    assert report["cases"] == 2
    # The figures, and the shafts' LDD as CSV: each shaft's hours are the site's 1250.
    names = {Path(p).name for p in report["figures"]}
    assert {"damage_vs_turbulence.png", "load_spectra.png", "load_spectra.csv"} <= names
    with (tmp_path / "figs" / "load_spectra.csv").open() as table:
        rows = list(csv.DictReader(table))
    hours = sum(float(r["time_h"]) for r in rows if r["joint"] == "carrier")
    assert_allclose(hours, 1250.0, rtol=1e-12)
    assert len(report["computed"]) == 2
    assert report["hours"] == [1000.0, 250.0]
    for level in report["damage"]["no limit"]:
        for gear in level.values():
            assert_allclose(sum(gear["per_bin"]), gear["total"], rtol=1e-12)
    assert (tmp_path / "cases_quick").is_dir()
    assert len(list((tmp_path / "cases_quick").glob("*.mcap"))) == 2


def test_json_reports_root_damage_and_the_iso_variant_for_every_gear(tmp_path, monkeypatch):
    """Root damage beside the contact's, each in the limit / no limit / iso 6336 variants, its
    bins adding up to the total, and each gear's root-stress model named."""
    monkeypatch.chdir(tmp_path)
    path = fatigue_toml(tmp_path)
    path.write_text(path.read_text() + "[fatigue.quick]\nduration = 0.03\n")
    out = run("fatigue", str(path), "--quick", "--json", "--workers", "1")
    assert out.returncode == 0, out.stderr
    report = json.loads(out.stdout)
    gears = {"sun", "planet1", "planet2", "planet3", "ring"}
    for table in ("damage", "root_damage"):
        assert set(report[table]) == {"limit", "no limit", "iso 6336"}
        for levels in report[table].values():
            assert set(levels[0]) == gears
            for gear in levels[0].values():
                assert_allclose(sum(gear["per_bin"]), gear["total"], rtol=1e-12)
                assert gear["peak_stress_MPa"] > 0.0
    assert set(report["root_stress"]) == gears
    assert "ISO 6336-3" in report["root_stress"]["sun"]
    assert "not_rated" not in report  # contact, root and bearings are all rated


def test_quick_run_gives_each_rated_bearing_its_l10h_and_lists_the_others_as_not_rated(
    tmp_path, monkeypatch
):
    from pinwind.model.gearbox import load
    from tests.conftest import FATIGUE_MODEL

    monkeypatch.chdir(tmp_path)
    path = fatigue_toml(tmp_path)
    path.write_text(path.read_text() + "[fatigue.quick]\nduration = 0.03\n")
    out = run("fatigue", str(path), "--quick", "--json", "--workers", "1")
    assert out.returncode == 0, out.stderr
    (lives,) = json.loads(out.stdout)["bearings"]
    ratings = load(FATIGUE_MODEL).source.bearings
    assert {b["bearing"] for b in lives if b["rated"]} == set(ratings)
    for life in lives:
        if not life["rated"]:
            assert life["l10_h"] is None
            continue
        # L10h is L10 at the mean speed over the site's hours (1250 h)
        per_hour = life["revolutions"] / 1250.0
        assert_allclose(life["l10_h"], life["l10_million_rev"] * 1e6 / per_hour, rtol=1e-9)
        c = ratings[life["bearing"]].dynamic_load_rating
        assert_allclose(life["l10_million_rev"], (c / life["equivalent_load_N"]) ** (10 / 3),
                        rtol=1e-9)  # fmt: skip


def _relative_change(before: float, after: float) -> float:
    """(after − before) / |after|, 0 when equal: the change dt → dt/2 by its definition."""
    return 0.0 if after == before else (after - before) / abs(after)


def test_check_dt_reruns_the_set_at_half_dt_and_reports_each_figures_change(tmp_path, monkeypatch):
    """The dt/2 logs have half the dt and the same sample times; each row's change is the one
    of the two sets' figures in the JSON; the text prints that change and the same verdict."""
    import re

    from pinwind import read_log
    from pinwind.io.log_reader import LogReader

    monkeypatch.chdir(tmp_path)
    path = fatigue_toml(tmp_path)
    path.write_text(path.read_text() + "[fatigue.quick]\nduration = 0.02\n")
    out = run("fatigue", str(path), "--quick", "--json", "--check-dt", "--workers", "1")
    assert out.returncode == 0, out.stderr
    report = json.loads(out.stdout)
    check = report["check_dt"]
    assert len(check["computed"]) == 2
    logs = sorted((tmp_path / "cases_quick").glob("*.mcap"))
    half_logs = sorted((tmp_path / "cases_quick_half_dt").glob("*.mcap"))
    assert [p.name for p in half_logs] == [p.name for p in logs] and len(logs) == 2
    for log, half_log in zip(logs, half_logs, strict=True):
        with LogReader(log) as reader, LogReader(half_log) as half_reader:
            dt = reader.metadata["pinwind.run"]["dt"]
            half_dt = half_reader.metadata["pinwind.run"]["dt"]
        assert_allclose(half_dt, dt / 2, rtol=1e-15)
        assert_allclose(read_log(half_log).time, read_log(log).time, rtol=0, atol=1e-12)

    sun_stress_change = None
    for k, level in enumerate(check["levels"]):
        assert len(level["rows"]) == 5 * 2 * 4  # gears x (contact, root) x (3 variants, stress)
        for row in level["rows"]:
            table = "damage" if row["group"] == "contact" else "root_damage"
            if row["quantity"] == "max stress":
                variant, key = "limit", "peak_stress_MPa"
            else:
                variant, key = row["quantity"].removeprefix("damage (")[:-1], "total"
            before = report[table][variant][k][row["element"]][key]
            after = check[table][variant][k][row["element"]][key]
            assert_allclose(row["change_half"], _relative_change(before, after), rtol=1e-9)
            if (row["group"], row["element"], row["quantity"]) == ("contact", "sun", "max stress"):
                sun_stress_change = _relative_change(before, after)

    text = run("fatigue", str(path), "--quick", "--check-dt", "--workers", "1")
    assert text.returncode == 0, text.stderr
    assert "cases at dt/2: 0 computed" in text.stdout
    assert f"dt check: {check['verdict']}" in text.stdout
    # The first "max stress" row is the sun's contact stress: "│ sun │ max stress │ 574 (+0.01 %) │"
    line = next(x for x in text.stdout.splitlines() if "sun" in x and "max stress" in x)
    printed = float(re.search(r"\(([-+][0-9.e+-]+) %\)", line).group(1))
    assert_allclose(printed, 100 * sun_stress_change, rtol=0.05, atol=5e-4)


def test_check_dt_with_a_sample_rate_off_the_steps_is_one_message_and_exit_2(
    tmp_path, monkeypatch, capsys
):
    # 1 / (20 kHz · 20 µs) = 2.5 steps: the dt/2 histories could not be read at the same times.
    path = fatigue_toml(tmp_path)
    path.write_text(path.read_text().replace("sample_rate = 50000.0", "sample_rate = 20000.0"))
    code, err = fatigue_exit([str(path), "--check-dt"], monkeypatch, capsys)
    assert code == 2
    assert "sample_rate = 20000 Hz is not a whole number of steps" in err, err
    assert err.strip().count("\n") == 0, err
    assert not (tmp_path / "cases").exists()  # refused before any case ran


@pytest.mark.parametrize(
    "value",
    [0.0, 641.4762694726479, 0.004253438997615594, 2.6e-8, 5.4e-44, 7645.159, 4734560.95, 1e-300],
)
def test_a_table_cell_holds_the_value_to_its_printed_digits_in_six_characters(value):
    from pinwind.cli.fatigue import cell

    text = cell(value)
    digits = len(text.split("e")[0].replace(".", "").lstrip("0")) or 1
    assert len(text) <= 6
    # Rounded to `digits` significant digits: within half a unit of the last one.
    assert_allclose(float(text), value, rtol=0.5 * 10.0 ** (1 - digits), atol=0)


def test_ten_columns_of_iso_damages_fit_80_columns_with_no_cell_cut():
    import io

    from rich.console import Console

    from pinwind.cli.fatigue import cell, table

    speeds = [6, 8, 10, 12, 14, 16, 18, 20]
    grid = table("per bin", "gear", *(str(s) for s in speeds), "Σ")
    damages = [3.78e-9, 6.88e-9, 3.01e-8, 2.28e-8, 9.55e-9, 5.94e-10, 1.05e-10, 8.1e-12]
    grid.add_row("planet", *(cell(d) for d in damages), cell(sum(damages)))
    out = io.StringIO()
    Console(file=out, width=80).print(grid)
    lines = out.getvalue().splitlines()
    assert max(len(line) for line in lines) <= 80
    assert "…" not in out.getvalue()
    row = next(line for line in lines if line.startswith("planet")).split()
    assert_allclose([float(x) for x in row[1:]], [*damages, sum(damages)], rtol=0.05)


# --- errors in workers, signals, files (issue 43) ------------------------------------------------


def _openfast_set(tmp_path: Path, second: str) -> Path:
    """The set on OpenFAST torques: the 10 m/s bin's file whole, the 16 m/s bin's ``second``."""
    header = ["", "Predictions were generated by OpenFAST", "", "", "test run", "",
              "Time\tRotTorq", "(s)\t(kN-m)"]  # fmt: skip
    rows = [f"{0.01 * i:.2f}\t{100.0 + i}" for i in range(11)]
    (tmp_path / "of").mkdir()
    (tmp_path / "of" / "v10.out").write_text("\n".join(header + rows) + "\n")
    (tmp_path / "of" / "v16.out").write_text(second)
    path = fatigue_toml(tmp_path)
    openfast = '[fatigue.openfast]\nfiles = "of/v{speed:g}.out"\njoint = "carrier"\n'
    path.write_text(
        path.read_text().replace("[fatigue.site]", openfast + "[fatigue.site]")
        + "[fatigue.quick]\nduration = 0.01\n"
    )
    return path


def test_a_workers_error_is_the_same_one_line_with_two_workers_as_with_one(tmp_path):
    """The 16 m/s case's file is cut inside its header: its worker's ScenarioError used to
    reach the command as BrokenProcessPool (it could not be unpickled) with two workers."""
    path = _openfast_set(tmp_path, "\nPredictions were generated by OpenFAST\n")
    # Two workers first: the case that works is kept, so that a rerun runs only the other.
    two = run("fatigue", str(path), "--quick", "--workers", "2", cwd=tmp_path)
    assert len(list((tmp_path / "cases_quick").glob("*.npz"))) == 1
    one = run("fatigue", str(path), "--quick", "--workers", "1", cwd=tmp_path)
    assert one.returncode == two.returncode == 2
    assert one.stderr.count("\n") == 1 and "v16.out: the file ends inside its" in one.stderr
    assert two.stderr == one.stderr


def _group_alive(group: int) -> list[str]:
    import psutil

    alive = []
    for process in psutil.process_iter(["pid", "name", "status"]):
        try:
            if os.getpgid(process.pid) == group and process.status() != psutil.STATUS_ZOMBIE:
                alive.append(f"{process.pid} {process.name()}")
        except (ProcessLookupError, psutil.Error):
            continue
    return alive


def _started_set(tmp_path: Path, **popen: Any) -> subprocess.Popen:
    """``pinwind fatigue`` of a 10 s set on two workers, in its own process group, once both
    workers run (a case takes a minute or more: the signal comes mid-case)."""
    import psutil

    path = fatigue_toml(tmp_path)
    path.write_text(path.read_text().replace("duration = 0.04", "duration = 10.0"))
    proc = subprocess.Popen(
        [sys.executable, "-m", "pinwind", "fatigue", str(path), "--workers", "2"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True,
        cwd=tmp_path, **popen,
    )  # fmt: skip
    parent = psutil.Process(proc.pid)
    deadline = time.monotonic() + 60.0
    while time.monotonic() < deadline:
        workers = [p for p in parent.children() if "spawn_main" in " ".join(p.cmdline())]
        if len(workers) == 2 and (tmp_path / "cases").is_dir():
            return proc
        time.sleep(0.1)
    os.killpg(proc.pid, signal.SIGKILL)
    pytest.fail("the workers did not start within 60 s")


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGKILL], ids=["SIGTERM", "SIGKILL"])
def test_a_killed_fatigue_set_leaves_no_process_of_its_group_alive(tmp_path, signum):
    """The workers (~160 MB each) and the resource tracker used to stay alive for good,
    holding the command's output open."""
    proc = _started_set(tmp_path)
    os.kill(proc.pid, signum)
    try:
        # Returns once nothing holds the output open: at once, not when the cases are done.
        _, err = proc.communicate(timeout=15)
        time.sleep(1.0)
        assert _group_alive(proc.pid) == []
    finally:
        for pid in (int(p.split()[0]) for p in _group_alive(proc.pid)):
            os.kill(pid, signal.SIGKILL)
    if signum == signal.SIGTERM:
        assert proc.returncode == 143
        assert err.startswith("terminated (received SIGTERM): 0 of 2 cases"), err
        assert err.count("\n") == 1, err


def test_ctrl_c_on_a_fatigue_set_prints_one_line_and_exits_130(tmp_path):
    """Ctrl-C reaches every process of the terminal's group: the command says what is kept."""
    proc = _started_set(tmp_path, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    os.killpg(proc.pid, signal.SIGINT)
    try:
        _, err = proc.communicate(timeout=15)
    finally:
        for pid in (int(p.split()[0]) for p in _group_alive(proc.pid)):
            os.kill(pid, signal.SIGKILL)
    assert proc.returncode == 130
    assert err == (
        f"interrupted: 0 of 2 cases of the set are finished and kept in {tmp_path / 'cases'}; "
        "the same command computes the rest\n"
    )


@pytest.mark.parametrize("workers", ["0", "-3"])
def test_workers_below_one_are_refused_before_any_case_runs(tmp_path, monkeypatch, capsys, workers):
    """``--workers 0`` ran on all cores, ``--workers -3`` in this process, without a word."""
    path = fatigue_toml(tmp_path)
    code, err = fatigue_exit([str(path), "--workers", workers], monkeypatch, capsys)
    assert code == 2
    assert err.startswith(f"error: --workers {workers}: give 1 or more worker processes")
    assert err.count("\n") == 1
    assert not (tmp_path / "cases").exists()


@pytest.mark.parametrize(
    ("args", "file", "said"),
    [
        ([], "cases", "fatigue.out: {out}: it is a file, not a folder"),
        (
            ["--figures", "afile/figs"],
            "afile",
            "--figures afile/figs: afile is a file, not a folder",
        ),
    ],
    ids=["out", "figures"],
)
def test_a_file_where_a_folder_goes_is_one_line_before_any_case_runs(
    tmp_path, monkeypatch, capsys, args, file, said
):
    """Both used to end in a traceback (FileExistsError, NotADirectoryError), the figures' after
    the whole set had run."""
    monkeypatch.chdir(tmp_path)
    path = fatigue_toml(tmp_path)
    (tmp_path / file).write_text("a file")
    code, err = fatigue_exit([str(path), "--workers", "1", *args], monkeypatch, capsys)
    assert code == 2
    assert said.format(out=tmp_path / "cases") in err
    assert err.count("\n") == 1
    assert list(tmp_path.glob("**/*.mcap")) == []


def test_a_worker_ignores_ctrl_c_and_is_killed_with_its_parent():
    """What `_run_local`'s workers set up first: Ctrl-C is the command's to handle (a worker's
    own KeyboardInterrupt printed a traceback), and Linux kills the worker with its parent."""
    code = (
        "import ctypes, os, signal\n"
        "from pinwind.runs.executor import _worker_started\n"
        "_worker_started(os.getppid())\n"
        "death = ctypes.c_int()\n"
        "ctypes.CDLL(None).prctl(2, ctypes.byref(death), 0, 0, 0)  # PR_GET_PDEATHSIG\n"
        "print(signal.getsignal(signal.SIGINT) is signal.SIG_IGN, death.value)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["True", str(int(signal.SIGKILL))]


# --- what the output says (issue 39 part 7) ------------------------------------------------------

#: "003" as a word: the paper's file number, which users do not know (not "0.003" or "2003").
FILE_NUMBER = re.compile(r"(?<![\w.])003(?![\w])")


def _quick_text_and_json(tmp_path: Path, extra: str = "") -> tuple[str, dict[str, Any]]:
    """The text and the JSON of one 2-case quick set (the JSON's run reuses the text's cases)."""
    path = fatigue_toml(tmp_path, fatigue=extra)
    path.write_text(path.read_text() + "[fatigue.quick]\nduration = 0.03\n")
    text = run("fatigue", str(path), "--quick", "--workers", "1", cwd=tmp_path)
    assert text.returncode == 0, text.stderr
    report = run("fatigue", str(path), "--quick", "--json", "--workers", "1", cwd=tmp_path)
    assert report.returncode == 0, report.stderr
    return text.stdout, json.loads(report.stdout)


def test_the_tables_keep_their_units_name_the_paper_and_say_which_variant_to_believe(tmp_path):
    """The titles kept "[m/s]" from rich's markup; the paper is "Jørgensen 2014", never its file
    number; one line per S-N variant, the no-limit one with its factor over Table 8."""
    out, report = _quick_text_and_json(tmp_path)
    words = " ".join(out.split())  # a title longer than the 80 columns of a pipe wraps
    assert "Contact damage per wind bin [m/s] at turbulence 10%" in words
    assert "Jørgensen 2014 Table 7 shape" in words and "Jørgensen 2014 Table 8 shape" in words
    assert FILE_NUMBER.search(out) is None, FILE_NUMBER.search(out)
    notes = out[out.index("Which S-N variant to believe") :].splitlines()[:4]
    assert 'docs/fatigue.md, "What differs from Jørgensen 2014, and why"' in notes[0]
    assert notes[1].strip().startswith("iso 6336: ") and "design basis" in notes[1]
    # The set's curve has no endurance limit (endurance_limit_mpa = 0): its damage is not 0,
    # so the line must not say it is.
    assert notes[2].strip().startswith("limit: Jørgensen 2014's Table 5 method")
    assert "0 here" not in notes[2]
    # Jørgensen 2014 Table 8 gives the sun 0.69 at 10 % turbulence (the set's one level).
    sun = report["damage"]["no limit"][0]["sun"]["total"]
    assert notes[3].strip().startswith("no limit: the same line without the limit, an upper bound")
    factor = float(re.search(r"is (\d+)x Jørgensen 2014's Table 8 \(0\.69\)", notes[3]).group(1))
    assert factor == round(sun / 0.69)
    assert report["variant_notes"] == [line.strip() for line in notes]


def test_limit_damage_below_every_endurance_limit_is_said_to_be_zero_and_why(tmp_path):
    """An endurance limit of 5000 MPa, above any stress of the stage (its largest contact and
    root stresses are below 1000 MPa, checked here): every cycle is below it, the damage 0."""
    path = fatigue_toml(tmp_path)
    path.write_text(
        path.read_text().replace("endurance_limit_mpa = 0.0", "endurance_limit_mpa = 5000.0")
        + "[fatigue.quick]\nduration = 0.03\n"
    )
    out = run("fatigue", str(path), "--quick", "--json", "--workers", "1", cwd=tmp_path)
    report = json.loads(out.stdout)
    for table in ("damage", "root_damage"):
        for gear in report[table]["limit"][0].values():
            assert gear["peak_stress_MPa"] < 1000.0
            assert gear["total"] == 0.0
    assert report["variant_notes"][2].endswith(
        "; 0 here because every stress range is below its endurance limit"
    )


def test_a_fixed_rings_speed_prints_as_0_rpm_not_its_round_off(tmp_path):
    """The ring's joint is fixed (models/dtu500_planetary.urdf): its mean speed is 0 but came
    out as 1e-13 rpm from the subtraction of the body speeds, and printed "7e-13"."""
    from pinwind.model.gearbox import load
    from tests.conftest import FATIGUE_MODEL

    assert load(FATIGUE_MODEL).source.joints["ring"]["type"] == "fixed"
    out, report = _quick_text_and_json(tmp_path)
    (lives,) = report["bearings"]
    ring = next(life for life in lives if life["bearing"] == "ring")
    assert abs(ring["mean_speed_rpm"]) < 1e-9  # round-off, as the JSON keeps it
    row = next(line for line in out.splitlines() if line.startswith("ring ") and "rated" in line)
    assert row.split()[-1] == "0", row


@pytest.mark.parametrize(
    ("rpm", "printed"),
    [(6.9e-13, "0"), (-3e-13, "0"), (0.0, "0"), (26.9128, "26.9"), (149.4, "149"), (1e-3, "0.001")],
)
def test_a_speed_is_0_only_when_it_is_round_off_beside_the_fastest(rpm, printed):
    from pinwind.cli.fatigue import speed_cell

    # beside a sun at 149.37 rpm, double precision leaves ~1e-14 rpm; 0.001 rpm is a speed
    assert speed_cell(rpm, 149.4) == printed


def test_a_quick_sets_figures_say_so_and_carry_a_caption(tmp_path):
    """Each PNG keeps its caption and title (its Description and Title): the title marks the
    quick set, 2 cases (2 bins x 1 level x 1 seed) of [fatigue.quick]'s 0.03 s."""
    from PIL import Image

    path = fatigue_toml(tmp_path)
    path.write_text(path.read_text() + "[fatigue.quick]\nduration = 0.03\n")
    out = run("fatigue", str(path), "--quick", "--workers", "1", "--figures", "figs", cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    for name in ("damage_vs_turbulence.png", "range_cycles.png", "load_spectra.png"):
        with Image.open(tmp_path / "figs" / name) as image:
            text = dict(image.text)
        assert text["Title"] == "quick set (2 cases x 0.03 s): a first look", name
        caption = text["Description"]
        assert "Set: set.toml, 2 cases x 0.03 s (counted from 0 s)" in caption, name
        assert FILE_NUMBER.search(caption) is None, caption
    with Image.open(tmp_path / "figs" / "damage_vs_turbulence.png") as image:
        caption = image.text["Description"]
    assert "levels 10%" in caption and "Dashed: Jørgensen 2014 Table 8" in caption


def _fake_run(total: int):
    """A ``run_cases`` that runs nothing: every one of ``total`` cases is said to be done."""
    from pinwind.runs.case_runner import FatigueRun

    def run_cases(fatigue, *, workers=None, scheduler=None, progress=None):
        if progress:
            progress(total, total)
        return FatigueRun([], total, "serial", 0.0)

    return run_cases


def _ctrl_c(*args, **kwargs):
    raise KeyboardInterrupt


@pytest.mark.parametrize(
    ("patched", "said"),
    [
        (
            "pinwind.runs.fatigue_set_file.load_fatigue_set",
            "interrupted while reading the set, before any case started: the same command "
            "starts it (cases kept from an earlier run are reused)",
        ),
        (
            "pinwind.runs.case_runner.case_done",
            "interrupted while checking which of the set's 2 cases kept in {out} are finished, "
            "before any case started: the same command checks them again and computes the rest",
        ),
        (
            "pinwind.life.set_damage.set_damage",
            "interrupted after the cases, while rating them: all 2 cases of the set are finished "
            "and kept in {out}; the same command reuses them and prints the results",
        ),
    ],
    ids=["reading", "checking", "rating"],
)
def test_ctrl_c_at_any_step_prints_what_is_kept_and_exits_130(
    tmp_path, monkeypatch, capsys, patched, said
):
    """Typer turned a Ctrl-C outside the cases into exit 130 without a word. The set has 2
    cases (2 bins x 1 level x 1 seed); Ctrl-C is raised where the command reads the set,
    checks the kept cases, or rates the finished ones."""
    module, name = patched.rsplit(".", 1)
    if name == "set_damage":
        monkeypatch.setattr("pinwind.runs.case_runner.run_cases", _fake_run(2))
    monkeypatch.setattr(f"{module}.{name}", _ctrl_c)
    path = fatigue_toml(tmp_path)
    code, err = fatigue_exit([str(path), "--workers", "1"], monkeypatch, capsys)
    assert code == 130
    assert err == said.format(out=tmp_path / "cases") + "\n"


def test_the_bearing_table_gives_each_bearings_modified_and_reference_life(
    tmp_path, monkeypatch, capsys
):
    """planet1 at a constant radial load and speed per bin (tests/life/test_life_sums.py): its
    L10h, L_nmh (ISO 281 by hand over the two bins) and L10rh (= L10h in the calibration case)
    in the text and the JSON."""
    from pinwind.cli.fatigue import cell
    from pinwind.runs.fatigue_set_file import load_fatigue_set
    from tests.life.test_life_sums import hand_lives, write_cases

    monkeypatch.setattr("pinwind.runs.case_runner.run_cases", _fake_run(2))
    path = fatigue_toml(tmp_path)
    fset = load_fatigue_set(path)
    write_cases(fset)
    expected = hand_lives(fset.bearings["planet1"].dynamic_load_rating)
    lines = {}
    for args in ([], ["--json"]):
        monkeypatch.setattr(sys, "argv", ["pinwind", "fatigue", str(path), "--workers", "1", *args])
        with pytest.raises(SystemExit) as caught:
            main()
        assert caught.value.code in (0, None)
        lines[bool(args)] = capsys.readouterr().out
    text = lines[False]
    assert "L10h [h]" in text and "L_nmh [h]" in text and "L10rh [h]" in text
    row = next(line for line in text.splitlines() if line.startswith("planet1 "))
    cells = row.split()
    assert cells[-3:-1] == [cell(expected["l10h"]), cell(expected["lnmh"])]
    assert_allclose(float(cells[-1]), expected["l10h"], rtol=1e-2)  # L10r = L10 (calibration)
    assert "-: not computed" in text
    (lives,) = json.loads(lines[True])["bearings"]
    (planet1,) = [b for b in lives if b["bearing"] == "planet1"]
    assert_allclose(planet1["lnm_h"], expected["lnmh"], rtol=1e-9)
    assert_allclose(planet1["l10r_h"], expected["l10h"], rtol=1e-2)


def test_fatigue_bearings_gives_a_bearing_its_modified_and_reference_lives(tmp_path, monkeypatch):
    """planet1 given a size, C_u and oil in [fatigue.bearings] (the model gives none): a quick
    set gives it L_nm and L10r; under its pure radial load at zero clearance (ISO/TS 16281's
    calibration case) L10r = L10 within 1 %, and a_ISO = L_nm / L10 lies within ISO 281's
    0.1 … 50. The others keep "-" (no size in the model)."""
    monkeypatch.chdir(tmp_path)
    extra = (
        "[fatigue.bearings]\n"
        'planet1 = { size_mm = "300 200 60", fatigue_limit_kN = 50, lubricant_vg = 320, '
        "temperature_C = 60 }\n"
    )
    path = fatigue_toml(tmp_path)
    path.write_text(
        path.read_text().replace("[fatigue.site]", extra + "[fatigue.site]")
        + "[fatigue.quick]\nduration = 0.03\n"
    )
    out = run("fatigue", str(path), "--quick", "--json", "--workers", "1")
    assert out.returncode == 0, out.stderr
    (lives,) = json.loads(out.stdout)["bearings"]
    by_name = {b["bearing"]: b for b in lives}
    planet1 = by_name["planet1"]
    assert_allclose(planet1["l10r_h"], planet1["l10_h"], rtol=1e-2)
    assert 0.1 <= planet1["lnm_h"] / planet1["l10_h"] <= 50.0
    assert by_name["planet2"]["lnm_h"] is None and by_name["planet2"]["l10r_h"] is None


def test_a_narrow_tables_long_title_reads_on_two_lines_not_in_a_column():
    # The largest-stress table of a two-level set is 26 columns wide: its 101-character title
    # came out in five lines of 26. At 80 columns it takes ⌈101 / 80⌉ = 2.
    import io

    from rich.console import Console

    from pinwind.cli.fatigue import table

    title = (
        "Largest stress [MPa]: von Mises contact (Jørgensen 2014: 600-700 at 20 m/s, 10 %) and "
        "root (Jørgensen 2014: about 60)"
    )
    grid = table(title, "gear", "stress", "10%", "20%", left=2)
    grid.add_row("sun", "contact", "583", "582")
    out = io.StringIO()
    Console(width=80, file=out, color_system=None).print(grid)
    lines = out.getvalue().splitlines()
    heading = lines[: next(i for i, line in enumerate(lines) if line.startswith("gear"))]
    assert len(heading) == 2 and "[MPa]" in heading[0], heading
