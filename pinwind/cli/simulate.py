"""``pinwind simulate`` and ``pinwind run``: a run from flags, a scenario file or a log.

Both build one ``Scenario`` (``pinwind/runs/scenario.py``), run it, log it to MCAP (``logs/`` by
default) and print speeds, mesh forces, bearing reactions and load sharing.
"""

from __future__ import annotations

import math
import shlex
import signal
import sys
from pathlib import Path
from typing import Annotated, Any, cast

import typer
from rich.markup import escape
from rich.table import Table

from pinwind.cli.app import (
    Terminated,
    app,
    console,
    err_console,
    raise_terminated,
    say,
    warnings_as_lines,
)
from pinwind.cli.flags import (
    FLAGS,
    CheckDtOption,
    CheckWindowOption,
    DurationOption,
    InitialSpeedOption,
    JsonOption,
    SpeedOption,
    StepOption,
    TorqueOption,
    generator_values,
    hub_load_values,
    load_values,
    mesh_values,
    number_or_text,
    parse_keep,
    parse_window,
    position_error_values,
    rotor_values,
)
from pinwind.errors import InputError, LogWriteFailed, PinwindError
from pinwind.loads.generator import LAWS


def _stamp(path: Path) -> tuple[int, int] | None:
    """Size and modification time of a file, None if it does not exist."""
    try:
        stat = path.stat()
    except OSError:
        return None
    return stat.st_size, stat.st_mtime_ns


@app.command()
def simulate(
    model: Annotated[Path, typer.Argument(help="Gearbox model file (URDF with <gearbox>).")],
    torque: TorqueOption = None,
    speed: SpeedOption = None,
    speed_sine: Annotated[
        list[str] | None,
        typer.Option(
            "--speed-sine", help="JOINT=MEAN_RPM,AMPLITUDE_RPM,FREQUENCY_HZ sinusoidal driver."
        ),
    ] = None,
    initial_speed: InitialSpeedOption = None,
    duration: DurationOption = 1.0,
    dt: StepOption = 1e-3,
    progress: Annotated[
        bool | None, typer.Option("--progress/--no-progress", help="Progress bar.")
    ] = None,
    out: Annotated[
        Path | None,
        typer.Option(
            "--out",
            "-o",
            help="MCAP log to write (a bare file name goes in logs/). Default: "
            "logs/<model>_<UTC time>.mcap.",
        ),
    ] = None,
    force: Annotated[bool, typer.Option("--force", help="Overwrite an existing log.")] = False,
    log_rate: Annotated[
        float | None,
        typer.Option("--log-rate", help="Logged samples per simulated second [Hz]; default all."),
    ] = None,
    no_log: Annotated[bool, typer.Option("--no-log", help="Do not write a log.")] = False,
    pose_rate: Annotated[
        float,
        typer.Option("--pose-rate", help="Logged link poses (/tf) per simulated second [Hz]."),
    ] = 100.0,
    view_rate: Annotated[
        float,
        typer.Option(
            "--view-rate",
            help="Samples per simulated second on the topics Rerun and Foxglove plot when they "
            "open the log [Hz] (pinwind reads every logged sample).",
        ),
    ] = 100.0,
    allow_large_log: Annotated[
        bool,
        typer.Option(
            "--allow-large-log",
            help="Write the log even if it would exceed 20 GB or the free disk space.",
        ),
    ] = False,
    mesh: Annotated[
        list[str] | None,
        typer.Option(
            "--mesh",
            help="MESH=rigid or MESH=compliant (MESH may be all; repeatable). Default: the model "
            "file's type of each mesh.",
        ),
    ] = None,
    keep: Annotated[
        str,
        typer.Option(
            "--keep",
            help="Samples kept in memory: all, last, auto (every sample while they fit in "
            "512 MB, else every N-th) or a number N (every N-th). The log holds every sample "
            "either way, and the summary's min / max / RMS are over every sample.",
        ),
    ] = "auto",
    skip_start: Annotated[
        float | None,
        typer.Option(
            "--skip-start",
            help="Leave the first S seconds (the start-up) out of the summary's min / max / RMS "
            "and the load sharing [s].",
        ),
    ] = None,
    position_error: Annotated[
        list[str] | None,
        typer.Option(
            "--position-error",
            help="GEAR=TANGENTIAL_UM,RADIAL_UM position error of a planet's centre [µm] "
            "(repeatable); compliant meshes share the load accordingly.",
        ),
    ] = None,
    generator: Annotated[
        list[str] | None,
        typer.Option(
            "--generator",
            help="JOINT=LAW(params): " + ", ".join(kind.usage for kind in LAWS.values()) + ".",
        ),
    ] = None,
    rotor: Annotated[
        list[str] | None,
        typer.Option(
            "--rotor",
            help="JOINT=PRESET (saleh2017, jorgensen2014, nrel5mw) or JOINT=rotor(radius=, "
            "inertia=, air_density=, pitch_deg=, cp_scale=, performance_file=, mass=, "
            "shaft_tilt_deg=, hub_height=, shear_exponent=, hub_body=, hub_point=(x, y, z), "
            "pitch_control=), or a preset with changes, nrel5mw(hub_body='lss', "
            "hub_point=(0, 0, -0.8871), pitch_control='nrel5mw'): rotor aerodynamics driven by "
            "--wind; with hub_body its thrust, weight and wind-shear moment load that body; "
            "with pitch_control='nrel5mw' Jonkman's gain-scheduled PI pitch controller holds "
            "12.1 rpm above rated wind (gains on the rotor speed; scenario files take a table).",
        ),
    ] = None,
    wind: Annotated[
        str | None,
        typer.Option(
            "--wind",
            help="Wind speed at the rotor [m/s]: a number or a signal, e.g. "
            "kaimal(mean=10, turbulence_intensity=0.1, seed=1).",
        ),
    ] = None,
    hub_load: Annotated[
        list[str] | None,
        typer.Option(
            "--hub-load",
            help="BODY=hub_load(force_x=, force_y=, force_z= [N], moment_x=, moment_y=, "
            'moment_z= [N·m], point=(x, y, z) [m], up=(x, y, z), frame="fixed" or "rotating") '
            'or BODY=openfast(file="run.outb", frame=, point=): the rotor\'s six load '
            "components on a body (repeatable); a component is a number or a quoted signal.",
        ),
    ] = None,
    rho_inf: Annotated[
        float | None,
        typer.Option(
            "--rho-inf",
            help="Spectral radius ρ∞ of the time step, 0 to 1: 1 keeps energy (trapezoidal "
            "rule, the default), smaller damps the modes dt does not resolve.",
        ),
    ] = None,
    initial_deflection: Annotated[
        str | None,
        typer.Option(
            "--initial-deflection",
            help="static (default): compliant meshes and springs start deflected under the "
            "loads of t = 0, so maxima describe the operation; none: they start undeflected, "
            "with the start-up impact.",
        ),
    ] = None,
    check_dt: CheckDtOption = False,
    check_window: CheckWindowOption = None,
    as_json: JsonOption = False,
) -> None:
    """Simulate a gearbox model, log it to MCAP, print speeds, mesh forces, bearing reactions."""
    import pinwind
    from pinwind.runs import scenario as sc
    from pinwind.runs.run import log_path

    _check_dt_options(check_dt, check_window, as_json, out)
    _check_log_options(no_log, out, log_rate, pose_rate, view_rate)
    values: dict[str, Any] = {"model": str(model), "duration": duration, "dt": dt}
    values |= load_values(torque, speed, speed_sine, initial_speed)
    optional = {
        "mesh": mesh_values(mesh),
        "position_error": position_error_values(position_error),
        "generator": generator_values(generator),
        "rotor": rotor_values(rotor),
        "wind": None if wind is None else number_or_text(wind),
        "hub_load": hub_load_values(hub_load),
        "rho_inf": rho_inf,
        "initial_deflection": initial_deflection,
        "log_rate": log_rate,
        "pose_rate": pose_rate,
        "view_rate": view_rate,
        "allow_large_log": allow_large_log or None,
        "keep": None if (kept := parse_keep(keep)) == "auto" else kept,
        "skip_start": skip_start,
    }
    values |= {k: v for k, v in optional.items() if v is not None and v != {}}
    scenario = sc.build(values, flags=FLAGS)
    window = None if check_window is None else parse_window(check_window)
    with warnings_as_lines():
        gearbox = pinwind.load(model)
    if check_dt:
        _check_dt_and_report(scenario, gearbox, str(model), window, progress=progress,
                             as_json=as_json)  # fmt: skip
        return
    log = None if no_log else log_path(out if out is not None else True, gearbox.name)
    command = shlex.join(["pinwind", *sys.argv[1:]])
    _run_and_report(
        scenario, gearbox, str(model), log, command, progress=progress, force=force,
        check_joints=False,
    )  # fmt: skip


def _run_and_report(
    scenario,
    gearbox,
    label: str,
    log: Path | None,
    command: str,
    *,
    progress,
    force,
    check_joints: bool = True,
) -> None:
    """Run a scenario and print its tables (``simulate`` and ``run``)."""
    import numpy as np

    from pinwind.analysis import load_sharing
    from pinwind.analysis.summary import row_table, summary_tables
    from pinwind.dynamics.dt_advice import dt_advice
    from pinwind.dynamics.integrator import Integrator
    from pinwind.runs import scenario as sc

    before = _stamp(log) if log is not None else None
    previous = signal.signal(signal.SIGTERM, raise_terminated)
    try:
        with warnings_as_lines():
            res = sc.run(
                scenario, gearbox=gearbox, out=log, no_log=log is None, force=force,
                command=command, progress=progress, check_joints=check_joints,
            )  # fmt: skip
    except (KeyboardInterrupt, PinwindError) as err:
        written = not isinstance(err, LogWriteFailed)  # that message says what the file holds
        if written and log is not None and _stamp(log) not in (None, before):
            err_console.print(
                f"the run stopped early; its log up to that point is in {escape(str(log))}"
            )
        if isinstance(err, Terminated):
            err_console.print(f"terminated ({escape(str(err))})")
            raise typer.Exit(code=143) from err
        raise
    finally:
        signal.signal(signal.SIGTERM, previous)
    dt = res.metadata["dt"]
    say(f"[bold]{escape(gearbox.name)}[/bold] from {escape(label)}")
    steps = res.metadata["samples_simulated"] - 1
    residual = res.constraint_residual.max()
    if res.statistics is not None:
        residual = res.statistics.row("run", "", "constraint residual").max
    say(
        f"{steps} steps of {dt:g} s in {res.metadata['wall_time_s']:.2f} s "
        f"({res.metadata['wall_time_s'] / max(steps, 1) * 1e6:.0f} µs/step); "
        f"max |J v| = {residual:.2e}"
    )
    if res.metadata.get("highest_mesh_mode_hz", 0.0) > 0.0:
        advice = dt_advice(
            res.metadata["highest_mesh_mode_hz"],
            dt,
            res.metadata.get("highest_mesh_mode_damping_ratio", 0.0),
            Integrator(rho_infinity=res.metadata["integrator"]["rho_infinity"]),
        )
        say(advice.text())
    stride = res.metadata.get("keep_stride", 1)
    if stride > 1:
        say(
            f"values at the end below are of the last sample; min / max / RMS are over every "
            f"one of the {res.metadata['samples_simulated']} samples, of which the result "
            f"keeps {len(res)} (every {stride}-th, --keep)"
            + ("; the log holds them all (pinwind report LOG)" if log is not None else "")
        )
    for table in summary_tables(res, plain=not console.is_terminal):
        console.print()
        console.print(table)
    rows = row_table(res, gearbox, plain=not console.is_terminal)
    if rows is not None:
        console.print()
        console.print(rows)
    compliant = {n for n, m in res.metadata.get("meshes", {}).items() if m["type"] != "rigid"}
    for sharing in load_sharing(res, gearbox):
        # Rigid planets share equally by construction (minimum-norm multipliers).
        if np.isfinite(sharing.factor_max) and compliant & set(sharing.meshes):
            say(
                f"load sharing at the {sharing.gear}: K_γ = {sharing.mean_share.max():.4f} "
                f"(mean loads), {sharing.factor_max:.4f} "
                f"(worst {'kept ' if stride > 1 else ''}sample)"
            )
    if log is not None:
        say(f"log: {escape(str(log))} ({log.stat().st_size / 1e6:.2f} MB)")


def _check_dt_options(
    check_dt: bool, check_window: str | None, as_json: bool, out: Path | None
) -> None:
    """Refuse the options that ``--check-dt`` takes without it, and ``--out`` with it.

    ``--check-window`` and ``--json`` only change the dt check (without it they were ignored);
    the dt check writes no log, so ``--out`` with it wrote nothing.
    """
    if not check_dt:
        for given, flag in ((check_window is not None, "--check-window"), (as_json, "--json")):
            if given:
                raise InputError(
                    f"{flag} goes with --check-dt (it changes the dt check), and there is none; "
                    f"add --check-dt, or leave out {flag}"
                )
    elif out is not None:
        raise InputError(
            f"--check-dt writes no log (it reruns the run at dt, dt/2 and dt/4 and compares "
            f"them), so --out {out} would stay unwritten; leave out --out, or run without "
            "--check-dt to log the run"
        )


def _check_log_options(
    no_log: bool, out: Path | None, log_rate: float | None, pose_rate: float, view_rate: float
) -> None:
    """Refuse a rate that is not a positive number, and ``--out`` or ``--log-rate`` with no log.

    ``--no-log`` writes no log. They were ignored: ``--log-rate -1 --no-log`` or ``--pose-rate
    nan --no-log`` ran without a word (the rates were checked only when a log is written).
    """
    for flag, rate in (("--log-rate", log_rate), ("--pose-rate", pose_rate),
                       ("--view-rate", view_rate)):  # fmt: skip
        if rate is not None and not 0.0 < rate < math.inf:
            raise InputError(f"{flag} {rate} Hz; give a positive number of samples per second")
    if not no_log:
        return
    for given, flag in ((out, "--out"), (log_rate, "--log-rate")):
        if given is not None:
            raise InputError(
                f"{flag} {given} sets the log, and --no-log writes none; leave out {flag}, or "
                "--no-log to log the run"
            )


#: Short names of the quantities in the --check-dt tables.
_SHORT = {
    "normal force RMS": "F_n RMS",
    "normal force max": "F_n max",
    "single-tooth force max": "F_1 max",
    "|force| RMS": "|F| RMS",
    "|force| max": "|F| max",
}


def _check_dt_and_report(
    scenario, gearbox, label: str, window, *, progress, as_json: bool, check_joints=False
) -> None:
    """Rerun a scenario at dt, dt/2 and dt/4 and print the convergence table (``--check-dt``)."""
    import json

    from pinwind.analysis.summary import PLAIN_BOX, TERMINAL_BOX
    from pinwind.runs.dt_check import check_dt

    if check_joints:
        scenario.check_joints(list(gearbox.joint_names), list(gearbox.locked_joints))
    kwargs = scenario.simulate_kwargs()
    dt = kwargs.pop("dt")
    previous = signal.signal(signal.SIGTERM, raise_terminated)
    try:
        with warnings_as_lines():
            check = check_dt(gearbox, dt=dt, window=window, progress=progress, **kwargs)
    except Terminated as err:
        err_console.print(f"terminated ({escape(str(err))})")
        raise typer.Exit(code=143) from err
    finally:
        signal.signal(signal.SIGTERM, previous)
    if as_json:
        print(json.dumps(check.as_dict(), indent=2))
        return
    start, end = check.window
    say(
        f"[bold]{escape(gearbox.name)}[/bold] from {escape(label)}: dt check over "
        f"{start:g}–{end:g} s at dt = {dt:g}, {dt / 2:g} and {dt / 4:g} s; converged: the value "
        f"at dt within {100 * check.tolerance:g} % of the one at dt/4"
    )
    plain = not console.is_terminal
    for group, title in (("mesh", "mesh forces"), ("bearing", "bearing forces")):
        rows = [row for row in check.rows if row.group == group]
        if not rows:
            continue
        table = Table(
            title=escape(f"{title} over the window [kN]"),  # rich read "[kN]" as markup
            box=PLAIN_BOX if plain else TERMINAL_BOX,
            title_style=None if plain else "bold",
            header_style=None if plain else "bold",
            show_edge=False,
            pad_edge=False,
            collapse_padding=True,
        )
        columns = (group, "", "dt", "dt/2", "dt/4", "Δ½ %", "Δ¼ %", "p", "off %", "verdict")
        for i, name in enumerate(columns):
            left = i in (0, 1, len(columns) - 1)
            table.add_column(
                name, justify="left" if left else "right", overflow="fold", no_wrap=i == 0
            )
        for row in rows:
            table.add_row(
                escape(row.element),
                _SHORT[row.quantity],
                *(f"{v / 1e3:.4g}" for v in row.values),
                f"{100 * row.change_half:+.2f}",
                f"{100 * row.change_quarter:+.2f}",
                "-" if math.isnan(row.order) else f"{row.order:.2f}",
                f"{100 * row.error:.2f}",
                "converged" if row.converged else "halve dt",
            )
        console.print()
        console.print(table)
    say(
        "; ".join(f"{short} = {long}" for long, short in _SHORT.items())
        + "; Δ½, Δ¼: changes dt → dt/2 → dt/4; p: observed order; off: |value at dt − value "
        f"at dt/4| / value at dt/4, converged when ≤ {100 * check.tolerance:g} %"
    )
    # The verdict of each quantity, in words, is in --json (and DtRow.verdict).
    bad = sum(not row.converged for row in check.rows)
    say(
        "every quantity is converged"
        if bad == 0
        else f"{bad} of {len(check.rows)} quantities are not converged: halve dt"
    )


@app.command("run")
def run_scenario(
    scenario_file: Annotated[
        Path | None, typer.Argument(help="Scenario file (TOML; keys named like simulate's flags).")
    ] = None,
    from_log: Annotated[
        Path | None,
        typer.Option("--from-log", help="Repeat the run a log holds, bit for bit."),
    ] = None,
    accept_changed_inputs: Annotated[
        bool,
        typer.Option(
            "--accept-changed-inputs",
            help="With --from-log: repeat the run even when a table it read (CSV, OpenFAST) "
            "has changed since; otherwise such a run is refused.",
        ),
    ] = False,
    out: Annotated[
        Path | None,
        typer.Option("--out", "-o", help="MCAP log to write (default: the scenario's out)."),
    ] = None,
    force: Annotated[bool, typer.Option("--force", help="Overwrite an existing log.")] = False,
    no_log: Annotated[bool, typer.Option("--no-log", help="Do not write a log.")] = False,
    progress: Annotated[
        bool | None, typer.Option("--progress/--no-progress", help="Progress bar.")
    ] = None,
    check_dt: CheckDtOption = False,
    check_window: CheckWindowOption = None,
    as_json: JsonOption = False,
) -> None:
    """Run a scenario file, or repeat a logged run with --from-log LOG."""
    import pinwind
    from pinwind.runs import scenario as sc
    from pinwind.runs.run import log_path

    if (scenario_file is None) == (from_log is None):
        raise InputError("give a scenario file or --from-log LOG (one of them)")
    _check_dt_options(check_dt, check_window, as_json, out)
    if accept_changed_inputs and from_log is None:
        raise InputError("--accept-changed-inputs goes with --from-log LOG only")
    with warnings_as_lines():
        if from_log is not None:
            scenario, gearbox = sc.from_log(from_log, accept_changed_inputs=accept_changed_inputs)
            label = f"the run logged in {from_log}"
            target = out if out is not None else True  # never the logged file itself
        else:
            # Exactly one of scenario_file and from_log is given (checked above).
            scenario = sc.load_scenario(cast(Path, scenario_file))
            path = scenario.model_path()
            if not path.is_file():
                raise scenario.fail(("model",), f"{path} does not exist")
            gearbox = pinwind.load(path)
            label = str(scenario_file)
            target = out if out is not None else scenario.values.get("out", True)
    if check_dt:
        window = None if check_window is None else parse_window(check_window)
        _check_dt_and_report(scenario, gearbox, label, window, progress=progress,
                             as_json=as_json, check_joints=True)  # fmt: skip
        return
    skip = no_log or (out is None and bool(scenario.values.get("no_log", False)))
    log = None if skip else log_path(target, gearbox.name)
    if from_log is not None and log is not None and log.resolve() == from_log.resolve():
        raise InputError(f"--out {log} is the log being repeated; choose another file")
    command = shlex.join(["pinwind", *sys.argv[1:]])
    _run_and_report(
        scenario, gearbox, label, log, command, progress=progress,
        force=force or bool(scenario.values.get("force", False)) and from_log is None,
    )  # fmt: skip
