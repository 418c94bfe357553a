"""Numbers typed in the README and the docs agree with what they claim to be."""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np
from numpy.testing import assert_allclose

ROOT = Path(__file__).resolve().parent.parent


def test_documented_balanced_drivetrain_output_torque_is_the_rated_torque_over_the_ratio():
    text = (ROOT / "docs" / "log_format.md").read_text()
    (typed,) = set(re.findall(r"stage2_pinion=(-?[0-9.]+)", text))  # the same in every command
    ratio = 6 * 83 / 23 * 103 / 26  # Saleh 2017: 1 + 120/24, then 83/23, 103/26
    assert_allclose(float(typed), -1e6 / ratio, rtol=1e-6)


def test_readme_quick_start_run_shows_rated_speed_and_tooth_force(tmp_path):
    text = (ROOT / "README.md").read_text()
    line = next(x for x in text.splitlines() if "pinwind simulate models/" in x)
    args = shlex.split(line.split(".venv/bin/pinwind ", 1)[1])
    args[1] = str(ROOT / args[1])
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", *args, "--no-log"],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=tmp_path,
    )
    assert out.returncode == 0, out.stderr
    rows: dict[str, list[str]] = {}  # first row of each name: the speeds, then the tooth forces
    for cells in (line.split() for line in out.stdout.splitlines()):
        if cells:
            rows.setdefault(cells[0], cells)
    # 14.2 rpm rotor, sun 6 × 14.2 = 85.2 rpm (Saleh 2017 §4.1), to 4 decimals.
    assert rows["carrier"][1] == "14.2000" and rows["sun"][1] == "85.2000"
    # Tangential force per sun mesh (1e6/6) / (3 × 0.18 m) = 308.6420 kN.
    assert rows["sun_planet1"][2] == f"{1e6 / 6 / (3 * 0.18) / 1e3:.4f}" == "308.6420"
    # Every table row the README shows is the row the command prints (the first of its name).
    block = text.split("```text\n", 1)[1].split("```", 1)[0]
    model = (ROOT / args[1]).read_text()
    names = set(re.findall(r'<(?:joint|mesh) name="(\w+)"', model))
    shown = [
        cells for cells in (x.split() for x in block.splitlines()) if cells and cells[0] in names
    ]
    assert len(shown) == 6 + 4, shown  # six bearings, four meshes (abridged)
    for cells in shown:
        assert cells == rows[cells[0]], cells


def test_the_documented_series_are_the_declared_ones():
    from pinwind.dynamics.series import markdown_table

    assert markdown_table() in (ROOT / "docs" / "series.md").read_text()


def test_docs_site_builds_without_warnings(tmp_path):
    # --strict turns every warning into an error: a broken link, a page left out of the nav, a
    # docstring whose Args name a parameter the function does not have. Building needs no network.
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1"}
    out = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=ROOT,
        env=env,
    )
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "index.html").is_file() and (tmp_path / "api" / "index.html").is_file()


def _verbs(command, prefix: str) -> list[str]:
    """Every command path under a (Typer) group: ``simulate``, ..., ``sweep planetary``, ..."""
    if not hasattr(command, "commands"):  # a verb, not a group
        return [prefix]
    return [
        path
        for name, sub in command.commands.items()
        for path in _verbs(sub, f"{prefix} {name}".strip())
    ]


def test_every_verb_of_the_command_line_is_on_its_page():
    import typer

    from pinwind.cli.verbs import app

    verbs = _verbs(typer.main.get_command(app), "")
    assert {"simulate", "rate", "fatigue", "sweep planetary", "build planetary"} <= set(verbs)
    text = (ROOT / "docs" / "command_line.md").read_text()
    missing = [v for v in verbs if not re.search(rf"^pinwind {re.escape(v)}\b", text, re.M)]
    assert not missing, f"docs/command_line.md lacks: {', '.join(missing)}"


def test_code_layout_names_every_module_of_the_package_and_no_other():
    # The modules are read from the tree when the test runs: a module added or moved (a new
    # package, a module split in two) fails here until the page says what it holds.
    package = ROOT / "pinwind"
    text = (ROOT / "docs" / "code_layout.md").read_text()
    modules = sorted(
        p.relative_to(package).as_posix()
        for p in package.rglob("*.py")
        if "__pycache__" not in p.parts
    )
    assert "dynamics/simulate.py" in modules and "cli/verbs.py" in modules
    # A module by its path from pinwind/ (`dynamics/mesh.py`), a package by its folder (`model/`).
    missing = [
        m
        for m in modules
        if f"`{m}`" not in text and f"`{m.removesuffix('__init__.py')}`" not in text
    ]
    assert not missing, f"docs/code_layout.md lacks: {', '.join(missing)}"
    named = set(re.findall(r"`([\w/]+\.pyi?)`", text))
    gone = sorted(m for m in named if not (package / m).is_file() and not (ROOT / m).is_file())
    assert not gone, f"docs/code_layout.md names modules that do not exist: {', '.join(gone)}"


def _documented_options() -> dict[str, set[str]]:
    """The flags docs/command_line.md names under each verb (its lines and their comments)."""
    text = (ROOT / "docs" / "command_line.md").read_text()
    block = text.split("```bash\n", 1)[1].split("```", 1)[0]
    found: dict[str, set[str]] = {}
    verb = ""
    for line in block.splitlines():
        start = re.match(r"pinwind (build|sweep) (\w+)|pinwind (\w+)|pinwind --", line)
        if start:  # "pinwind --version": the program's own options, under ""
            verb = " ".join(w for w in start.groups() if w)
            found.setdefault(verb, set())
        if start or verb:
            found[verb] |= set(re.findall(r"(?<![\w-])(--?[a-zA-Z][\w-]*)", line))
    return found


def test_every_flag_on_the_command_line_page_exists_and_every_flag_is_on_it():
    import typer

    from pinwind.cli.verbs import app

    command = typer.main.get_command(app)
    documented = _documented_options()
    assert {"--torque", "--dt", "--out"} <= documented["simulate"]
    unknown, undocumented = [], []
    for verb in ["", *_verbs(command, "")]:
        sub = command
        for word in verb.split():
            sub = sub.commands[word]
        flags = {
            name: set(p.opts + p.secondary_opts)
            for p in sub.params
            if p.param_type_name == "option"
            for name in p.opts[:1]
            if name != "--help"
        }
        named = {f for opts in flags.values() for f in opts}
        unknown += [f"{verb} {f}" for f in sorted(documented[verb] - named)]
        undocumented += [f"{verb} {n}" for n, opts in flags.items() if not opts & documented[verb]]
    assert not unknown, f"docs/command_line.md names flags the parser lacks: {unknown}"
    assert not undocumented, f"docs/command_line.md lacks: {undocumented}"


def test_api_page_lists_the_top_level_exports():
    import pinwind

    text = (ROOT / "docs" / "api.md").read_text()
    sentence = text.split("exports the core:", 1)[1].split(";", 1)[0]
    named = set(re.findall(r"`(\w+)`", sentence))
    assert named == set(pinwind.__all__) - {"__version__"}
    assert all(f"::: pinwind.{name}\n" in text for name in named - {"PinwindError"})


def test_losses_page_prose_quotes_its_own_nrel5mw_efficiency_table():
    # The table "with the friction in the step" (its η to 0.001 %, the after-the-run table's
    # to 0.1 %). The prose after it once kept the figures of an earlier step (96.34 %, 183 kW):
    # its numbers must be the table's, and the table's overall row the stages' sum and product.
    text = (ROOT / "docs" / "losses.md").read_text()
    rows = re.findall(
        r"^\| (?:\d, \w+|overall)[^|]*\| ([\d.]+) \| ([\d.]+) \| ([\d.]+) \| (\d+\.\d{3}) %",
        text,
        re.M,
    )
    stages = [[float(x) for x in row] for row in rows[:3]]
    overall = [float(x) for x in rows[3]]
    assert len(rows) == 4
    for column in range(3):  # meshes, bearings, loss [kW]
        assert_allclose(sum(s[column] for s in stages), overall[column], atol=0.15)
    assert_allclose(np.prod([s[3] / 100 for s in stages]) * 100, overall[3], atol=2e-3)
    (eta, loss, share) = re.search(
        r"pinwind's ([\d.]+) % at rated \(([\d.]+) kW, ([\d.]+) % of 5 MW\)", text
    ).groups()
    assert_allclose([float(eta), float(loss)], [overall[3], overall[2]], atol=0.006)
    assert_allclose(float(share), 100 * overall[2] / 5e3, atol=0.006)
    quoted = re.search(r"pinwind's stages\s+are ([\d.]+), ([\d.]+) and ([\d.]+) %", text).groups()
    assert_allclose([float(q) for q in quoted], [s[3] for s in stages], atol=0.006)
    (meshes, meshes_share) = re.search(r"μ_mz P H_V\s+\(([\d.]+) kW, ([\d.]+) %\)", text).groups()
    assert_allclose(float(meshes), overall[0], atol=0.05)
    assert_allclose(float(meshes_share), 100 * overall[0] / 5e3, atol=0.05)


def _documented_commands() -> list[tuple[str, str]]:
    """(page, command line after ``pinwind``) of every shell block of the user docs.

    The command-line page's block is a synopsis (``[--flag]``, ``A|B``) and is left out.
    """
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    found = []
    for page in pages:
        if page.name in ("command_line.md", "code_layout.md"):
            continue
        text = page.read_text(encoding="utf-8")
        for language, block in re.findall(r"^```(\w*)\n(.*?)^```", text, re.M | re.S):
            if language not in ("", "bash", "console", "sh"):
                continue
            for line in re.sub(r"\\\n\s*", " ", block).splitlines():
                code = re.split(r"\s#", " " + line.strip().removeprefix("$ "), maxsplit=1)[0]
                start = re.search(r"(?:^ |&& |\.venv/bin/)pinwind (.*)", code)
                if start:
                    found.append((page.name, start.group(1)))
    return found


def test_every_pinwind_command_of_the_docs_parses_as_written():
    # A block a user copies must parse: "[--plots plots/]" in a command is two stray arguments.
    # Parsing runs no verb (placeholders such as LOG stand for any path).
    import typer

    from pinwind.cli.verbs import app

    command = typer.main.get_command(app)
    commands = _documented_commands()
    assert len(commands) > 30 and ("sweeps.md", "sweep plot parallel.csv -o plots/") in commands
    failed = []
    for page, line in commands:
        try:
            context = command.make_context("pinwind", shlex.split(line))
            while hasattr(context.command, "commands"):  # a group: its verb parses the rest
                rest = [*context._protected_args, *context.args]
                if not rest:
                    break
                name, verb, rest = context.command.resolve_command(context, rest)
                context = verb.make_context(name, rest, parent=context)
        except Exception as err:  # typer's own click: its UsageError, BadParameter, ...
            if type(err).__name__ != "Exit":
                failed.append(f"{page}: pinwind {line}: {err}")
    assert not failed, "\n".join(failed)


def test_no_shell_block_of_the_docs_has_a_line_of_bracketed_options():
    # fatigue.md's "In short" had lines "[--json] [--workers N]" under a command: pasted, the
    # shell runs each as a command of its own.
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    found = [
        f"{page.name}: {line.strip()}"
        for page in pages
        if page.name != "command_line.md"
        for language, block in re.findall(r"^```(\w*)\n(.*?)^```", page.read_text(), re.M | re.S)
        if language in ("", "bash", "sh", "console")
        for line in block.splitlines()
        if line.strip().startswith("[")
    ]
    assert not found, found


#: Names of the log's MCAP records and encodings, written like modules (docs/log_format.md).
LOG_RECORDS = {"pinwind.run", "pinwind.end", "pinwind.columns"}


def _resolves(name: str) -> bool:
    """``pinwind.a.b.C``: the longest importable module, then attributes."""
    import importlib

    parts = name.split(".")
    for split in range(len(parts), 0, -1):
        try:
            found = importlib.import_module(".".join(parts[:split]))
        except ImportError:
            continue
        for attribute in parts[split:]:
            if not hasattr(found, attribute):
                return False
            found = getattr(found, attribute)
        return True
    return False


def test_every_module_or_object_the_user_docs_name_exists():
    # fatigue.md sent users to `analysis.dask_workers.WORKER_CONFIG`, which is in pinwind.runs.
    subpackages = "analysis|runs|life|dynamics|io|model|gears|loads|losses|modes|testing|cli"
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    named = {
        (page.name, name if name.startswith("pinwind.") else f"pinwind.{name}")
        for page in pages
        for name in re.findall(rf"`((?:pinwind|{subpackages})(?:\.\w+)+)", page.read_text())
    }
    assert len(named) > 100 and ("fatigue.md", "pinwind.life.case_cycles.CaseReduction") in named
    missing = sorted(
        f"{page}: {name}" for page, name in named if name not in LOG_RECORDS and not _resolves(name)
    )
    assert not missing, missing


def test_simulation_page_three_step_snippet_runs_and_gives_its_statistics(monkeypatch):
    # The snippet used `run.run()` with keep="last": a Result of one sample and no statistics.
    import pinwind

    text = (ROOT / "docs" / "simulation.md").read_text()
    snippet = next(b.split("```", 1)[0] for b in text.split("```python\n")[1:] if "prepare(" in b)
    monkeypatch.chdir(ROOT)
    scope = {"gb": pinwind.load("models/saleh2017_planetary.urdf")}
    exec(snippet, scope)
    res = scope["res"]
    assert len(res.time) == 1 and res.time[-1] == 2.0
    # Tangential force per sun mesh (1e6/6) / (3 × 0.18 m) (Saleh 2017: three planets, r_sun).
    row = res.statistics.row("mesh", "sun_planet1", "tangential")
    assert_allclose(row.max, 1e6 / 6 / (3 * 0.18), rtol=1e-9)
    assert "308.6 kN" in snippet


def test_loads_page_lists_every_scenario_key_and_no_other():
    # The page listed 15 of the parser's 23 keys (no hub_load, keep, skip_start, rho_inf, ...).
    from pinwind.runs.scenario import KEYS

    text = (ROOT / "docs" / "loads.md").read_text()
    listed = text.split("\nKeys: ", 1)[1].split(". A bad file", 1)[0]
    assert re.findall(r"`(\w+)`", listed) == list(KEYS)


def test_log_format_page_first_run_is_balanced_at_rated_speed(tmp_path):
    # It ran the drivetrain with 1e6 N·m on the carrier and nothing braking it: an
    # unbalanced-torque warning and a carrier at 5775 rpm after its 60 s.
    text = (ROOT / "docs" / "log_format.md").read_text()
    block = text.split("```bash\n", 1)[1].split("```", 1)[0]
    line = re.sub(r"\\\n\s*", " ", block).splitlines()[0].split("#", 1)[0]
    args = shlex.split(line.removeprefix("pinwind "))
    args[1] = str(ROOT / args[1])
    args[args.index("--duration") + 1] = "0.1"  # 100 steps: the start is what is checked
    args[args.index("--out") : args.index("--out") + 2] = ["--no-log"]
    out = subprocess.run(
        [sys.executable, "-m", "pinwind", *args],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=tmp_path,
    )
    assert out.returncode == 0 and out.stderr == "", out.stderr
    rows: dict[str, list[str]] = {}  # first row of each name: the speeds
    for cells in (x.split() for x in out.stdout.splitlines()):
        if cells:
            rows.setdefault(cells[0], cells)
    # Saleh 2017 §4.1: 14.2 rpm rotor; output 14.2 × 6 × 83/23 × 103/26 = 1218.02 rpm.
    assert abs(float(rows["carrier"][1]) - 14.2) < 1e-3
    assert abs(float(rows["stage2_pinion"][1]) - 14.2 * 6 * 83 / 23 * 103 / 26) < 0.05


def test_performance_page_counts_the_compiled_files_of_the_step_loop():
    # It said thirteen files; the module had fourteen.
    text = (ROOT / "docs" / "performance.md").read_text()
    (word,) = re.findall(r"C\+\+17, (\w+) files of `pinwind/dynamics/cpp/`", text)
    cmake = (ROOT / "pinwind" / "dynamics" / "cpp" / "CMakeLists.txt").read_text()
    sources = re.findall(r"\b\w+\.cpp\b", cmake.split("nanobind_add_module(", 1)[1].split(")")[0])
    words = "one two three four five six seven eight nine ten eleven twelve thirteen fourteen"
    words += " fifteen sixteen seventeen eighteen nineteen twenty"
    assert words.split().index(word) + 1 == len(set(sources)), sources


def test_limitations_page_quotes_the_trapezoidal_rules_frequency_error():
    # It gave −0.49 % at 26 steps per period, the small-ωh form (ωh)²/12; the rule's own
    # (2/h) atan(ωh/2) is −0.482 % there (and −0.81 % at 20, −0.20 % at 40, as quoted).
    text = " ".join((ROOT / "docs" / "limitations.md").read_text().split())
    quoted = re.search(
        r"−([0-9.]+) % at 20 steps per period, −([0-9.]+) % at 26, −([0-9.]+) % at 40", text
    )
    assert quoted is not None
    for steps, typed in zip((20, 26, 40), quoted.groups(), strict=True):
        omega_h = 2 * np.pi / steps
        error = 2 * np.arctan(omega_h / 2) / omega_h - 1  # Hairer & Wanner II §V.1, trapezoidal
        assert f"{-100 * error:.2f}" == typed, (steps, typed)


def test_log_format_page_names_every_entry_of_the_metadata_records(tmp_path):
    # pinwind.model's row_names, slice_names and model_name, and seven entries of pinwind.run
    # (initial_speeds, meshes, keep_stride, ...) were in every log and on no page.
    from mcap.reader import make_reader

    import pinwind

    gb = pinwind.load(ROOT / "models" / "saleh2017_planetary.urdf")
    path = tmp_path / "run.mcap"
    pinwind.simulate(gb, duration=0.02, dt=1e-3, torques={"carrier": 1e6, "sun": -1e6 / 6},
                     initial_speeds={"carrier": 1.0}, log=str(path))  # fmt: skip
    with open(path, "rb") as f:
        records = {m.name: set(m.metadata) - {"crc32"} for m in make_reader(f).iter_metadata()}
    text = (ROOT / "docs" / "log_format.md").read_text()
    for name in ("pinwind", "pinwind.run", "pinwind.model", "pinwind.end"):
        bullet = text.split(f"\n- `{name}`", 1)[1].split("\n- `", 1)[0]
        missing = sorted(k for k in records[name] if f"`{k}`" not in bullet)
        assert not missing, f"docs/log_format.md's {name} record lacks {missing}"


def test_log_format_page_names_only_channels_that_read_log_takes():
    from pinwind.io.log_channels import CHANNELS

    text = (ROOT / "docs" / "log_format.md").read_text()
    bullet = text.split("- **Channels** are", 1)[1].split("\n- **", 1)[0]
    named = set(re.findall(r"`(/[a-z_/]+)`", bullet))
    folders = {"/meshes", "/bearings", "/run"}
    assert len(named) > 20 and not named - set(CHANNELS) - folders, named - set(CHANNELS)


def test_simulation_page_names_every_field_of_run_settings():
    # keep_series was left out of the page's list of RunSettings' fields.
    from dataclasses import fields

    from pinwind.dynamics import RunSettings

    text = " ".join((ROOT / "docs" / "simulation.md").read_text().split())
    listed = text.split("`RunSettings` holds how the run is stepped and what it keeps (", 1)[1]
    named = re.findall(r"`(\w+)`", listed.split(")", 1)[0])
    assert named == [f.name for f in fields(RunSettings)]


def test_model_format_page_lists_every_bearing_type_in_both_tables():
    # The attribute table's `type` row left out toroidal_roller, which its life table rates.
    from pinwind.model.bearing import BEARING_TYPES

    text = (ROOT / "docs" / "model_format.md").read_text()
    row = next(x for x in text.splitlines() if x.startswith("| bearing | type |"))
    assert re.findall(r"`(\w+)`", row) == list(BEARING_TYPES)
    life = text.split("| type | p | e |", 1)[1].split("\n\n", 1)[0]
    assert re.findall(r"^\| `(\w+)` \|", life, re.M) == list(BEARING_TYPES)
