"""The commands on models: ``info`` (check and list), ``view`` (look at it) and ``build``."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

import typer
from rich.markup import escape

from pinwind.cli.app import app, build_app, say, warnings_as_lines
from pinwind.cli.flags import GrpcPortOption, SaveOption, ServeOption, WebPortOption
from pinwind.errors import InputError


@app.command()
def info(model: Annotated[Path, typer.Argument(help="Gearbox model file.")]) -> None:
    """Load a model, check it, and list its bearings, gears and meshes."""
    import pinwind

    with warnings_as_lines():
        gb = pinwind.load(model)
    say(repr(gb))
    say("bearings (joints): " + ", ".join(gb.joint_names))
    if gb.locked_joints:
        say("locked (fixed mounts): " + ", ".join(gb.locked_joints))
    from pinwind.dynamics.ratios import speed_ratio

    free = [j for j in gb.joint_names if j not in gb.locked_joints]
    if free:
        try:
            ratios = {j: speed_ratio(gb, j, free[0]) for j in free}
        except InputError as err:
            say(f"speed ratios: {err}")
        else:
            say(
                f"speed ratios to {free[0]} (joint speeds, relative to the parent body): "
                + ", ".join(f"{j} {r:.6g}" for j, r in ratios.items())
            )
    for m in gb.meshes:
        a, b = m.gear_a.spec, m.gear_b.spec
        say(
            f"mesh {m.name}: {a.name} ({a.teeth}) – {b.name} ({b.teeth}"
            f"{', internal' if b.internal else ''}), a_w = {m.centre_distance * 1e3:.4f} mm, "
            f"α_w = {math.degrees(m.working_pressure_angle):.4f}°{_compliance_note(m)}"
        )


def _compliance_note(mesh) -> str:
    """The text ", compliant, N slices" of a compliant mesh (the rule's inputs if "auto")."""
    from pinwind.dynamics.compliant import auto_slices
    from pinwind.gears.face_load import AUTO_LINE_LOAD

    c = auto_slices(mesh).compliance
    if c is None:
        return ""
    note = f", compliant, {c.slices} slice{'s' if c.slices != 1 else ''}"
    if c.slice_rule is not None:
        misalignment, deflection = c.slice_rule
        note += (
            f' (slices="auto": ⌈10 F_β/δ_m⌉, F_β = {misalignment * 1e6:.4g} µm, δ_m = '
            f"{deflection * 1e6:.4g} µm at {AUTO_LINE_LOAD * 1e-3:g} N/mm)"
        )
    return note


@build_app.command("planetary")
def build_planetary(
    sun: Annotated[int, typer.Option(help="Sun teeth.")],
    planet: Annotated[int, typer.Option(help="Planet teeth.")],
    ring: Annotated[int, typer.Option(help="Ring teeth.")],
    planets: Annotated[int, typer.Option(help="Number of planets.")] = 3,
    module: Annotated[float, typer.Option(help="Module [mm].")] = 15.0,
    pressure_angle: Annotated[float, typer.Option(help="Pressure angle [deg].")] = 20.0,
    face_width: Annotated[float, typer.Option(help="Face width [mm].")] = 200.0,
    parallel: Annotated[
        list[str] | None,
        typer.Option(help="Parallel stage WHEEL/PINION teeth, e.g. 83/23 (repeatable)."),
    ] = None,
    parallel_module_mm: Annotated[
        list[float] | None,
        typer.Option(
            "--parallel-module-mm",
            help="Normal module of the parallel stages [mm]: once for all, or once per stage "
            "(default: sized from each stage's torque to the planetary's tooth load).",
        ),
    ] = None,
    parallel_face_width_mm: Annotated[
        list[float] | None,
        typer.Option(
            "--parallel-face-width-mm",
            help="Face width of the parallel stages [mm]: once for all, or once per stage "
            "(default: as many modules wide as the planetary).",
        ),
    ] = None,
    parallel_helix_deg: Annotated[
        list[float] | None,
        typer.Option(
            "--parallel-helix-deg",
            help="Helix angle of each parallel wheel [deg] (its pinion the opposite hand): once "
            "for all, or once per stage (default 0, spur).",
        ),
    ] = None,
    name: Annotated[str, typer.Option(help="Model name.")] = "planetary",
    output: Annotated[Path, typer.Option("--output", "-o", help="Output URDF file.")] = Path(
        "planetary.urdf"
    ),
) -> None:
    """Write a planetary stage (+ parallel stages) with inertias from steel geometry.

    Each parallel stage has its own module, face width and helix angle (--parallel-module-mm,
    --parallel-face-width-mm, --parallel-helix-deg: once for every stage or once per stage, in
    the order of --parallel).
    """
    from pinwind.model.builders import write_planetary

    stages = []
    for item in parallel or []:
        wheel, sep, pinion = item.partition("/")
        try:
            stages.append((int(wheel), int(pinion)))
        except ValueError as err:
            raise InputError(f'--parallel "{item}" must be WHEEL/PINION teeth, e.g. 83/23') from err
        if not sep:
            raise InputError(f'--parallel "{item}" must be WHEEL/PINION teeth, e.g. 83/23')
    with warnings_as_lines():  # the builder's warnings as one line each, not with its source
        path = write_planetary(
            output,
            sun=sun,
            planet=planet,
            ring=ring,
            planets=planets,
            module=module * 1e-3,
            pressure_angle=math.radians(pressure_angle),
            face_width=face_width * 1e-3,
            parallel=stages,
            parallel_module=_per_stage(
                "--parallel-module-mm", parallel_module_mm, 1e-3, len(stages)
            ),
            parallel_face_width=_per_stage(
                "--parallel-face-width-mm", parallel_face_width_mm, 1e-3, len(stages)
            ),
            parallel_helix_angle=_per_stage(
                "--parallel-helix-deg", parallel_helix_deg, math.pi / 180.0, len(stages)
            )
            or 0.0,
            name=name,
        )
    _check_loads(path, f"--module {module:g} mm, --face-width {face_width:g} mm")
    say(f"wrote {escape(str(path))}")


@build_app.command("stages")
def build_stages(
    stage_file: Annotated[
        Path,
        typer.Argument(
            help="Stage file (TOML): [[stage]] tables (planetary or parallel), their "
            "[[stage.bearing]] and [[end_body]] (rotor, generator); see "
            "pinwind.model.builders.stage_file."
        ),
    ],
    output: Annotated[Path | None, typer.Option("--output", "-o", help="Output URDF file.")] = None,
) -> None:
    """Write a gearbox of any sequence of stages joined by named shafts, from a stage file.

    Each stage has its own module, helix angle, face width, working centre distance, profile
    shifts (ISO 21771 sign) and tip alterations; its gears must mesh at that centre distance
    (ISO 21771 involute function). Output: the stage file's name with .urdf by default.
    """
    from pinwind.model.builders.stage_file import read_stage_file
    from pinwind.model.builders.stages import stages_urdf

    name, stages, bodies = read_stage_file(stage_file)
    path = output if output is not None else stage_file.with_suffix(".urdf")
    with warnings_as_lines():
        text = stages_urdf(
            stages, name=name, end_bodies=bodies, source=f"pinwind build stages {stage_file.name}"
        )
    try:
        path.write_text(text, encoding="utf-8")
    except OSError as err:
        raise InputError(
            f"cannot write the model to {path}: {err.strerror or err}; choose another --output "
            "or fix the folder's permissions"
        ) from err
    _check_loads(path, f"the values of {stage_file.name}")
    say(f"wrote {escape(str(path))}")


def _check_loads(path: Path, given: str) -> None:
    """Load the model just written; remove it and say so if pinwind refuses it.

    ``build planetary --module 1e30`` wrote a model of a 1.7e61 kg carrier that ``load`` then
    refused (``--module 1e-30``: no inertia about its axis), exit 0.

    Raises:
        InputError: the loader's message, naming the options that made the model.
    """
    import warnings

    import pinwind
    from pinwind.errors import PinwindError, PinwindWarning

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PinwindWarning)  # the builder has said its own
            pinwind.load(path)
    except PinwindError as err:
        path.unlink(missing_ok=True)
        raise InputError(
            f"the model built from {given} does not load, so {path} was not kept: {err}"
        ) from err


def _per_stage(
    option: str, values: list[float] | None, to_si: float, stages: int
) -> float | list[float] | None:
    """A repeated per-stage option in SI: None when not given, one value for all, or a list.

    Raises:
        InputError: neither one value nor one per stage.
    """
    if not values:
        return None
    if len(values) not in (1, stages):
        raise InputError(
            f"{option} given {len(values)} times for {stages} --parallel stage(s); give it once "
            "for every stage or once per stage, in the order of --parallel"
        )
    if len(values) == 1:
        return values[0] * to_si
    return [v * to_si for v in values]


@app.command()
def view(
    model: Annotated[Path, typer.Argument(help="Gearbox model file.")],
    save: SaveOption = None,
    serve: ServeOption = False,
    web_port: WebPortOption = None,
    grpc_port: GrpcPortOption = None,
) -> None:
    """Look at a model before simulating it: its bodies at rest and lines of action, in Rerun."""
    from pinwind.io.model_view import view_model

    with warnings_as_lines():
        out = view_model(
            model, save=save, serve=serve, web_port=web_port, grpc_port=grpc_port, announce=say
        )
    if out is not None:
        say(f"wrote {escape(str(out))}")
