"""``pinwind rate``: ISO 6336, AGMA 2001 and Hertz ratings from a short run's mesh forces."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated

import typer

from pinwind.cli.app import app, console, warnings_as_lines
from pinwind.cli.flags import (
    FLAGS,
    DurationOption,
    InitialSpeedOption,
    SpeedOption,
    StepOption,
    TorqueOption,
    check_reliability_percent,
    load_values,
    parse_pairs,
)
from pinwind.errors import InputError


@app.command()
def rate(
    model: Annotated[
        Path | None,
        typer.Argument(help="Gearbox model file (URDF with <gearbox>); not with --from-log."),
    ] = None,
    from_log: Annotated[
        Path | None,
        typer.Option(
            "--from-log",
            help="Rate the run a log holds (its model, its mesh forces) instead of running one.",
        ),
    ] = None,
    face_load_factor: Annotated[
        str,
        typer.Option(
            "--face-load-factor",
            help="ISO K_Hβ from: iso (ISO 6336-1 method C, F_βy 10 µm), run-max (largest "
            "mesh_face_load_factor of the run) or run-at (at the rated sample); run-* need "
            "meshes with slices.",
        ),
    ] = "iso",
    transverse_load_factor: Annotated[
        str,
        typer.Option(
            "--transverse-load-factor",
            help="ISO K_Hα, K_Fα from: iso (ISO 6336-1 method B; 1 without f_pb) or "
            "loaded-contact (largest tooth-pair load with the flank modifications over the "
            "ideal flanks', quasi-static loaded contact at the rated force).",
        ),
    ] = "iso",
    torque: TorqueOption = None,
    speed: SpeedOption = None,
    initial_speed: InitialSpeedOption = None,
    material: Annotated[
        list[str] | None,
        typer.Option(
            "--material",
            help="GEAR=NAME (18CrNiMo7-6, 42CrMo4, 34CrNiMo6; GEAR may be all); default "
            "18CrNiMo7-6.",
        ),
    ] = None,
    duration: DurationOption = 0.05,
    dt: StepOption = 1e-3,
    at: Annotated[str, typer.Option(help="Load level: last, max or mean of the run.")] = "last",
    application_factor: Annotated[
        float,
        typer.Option(
            "--application-factor",
            help="ISO K_A and AGMA K_o: the overload the run's forces do not hold [-].",
        ),
    ] = 1.0,
    accuracy_grade: Annotated[
        int, typer.Option("--accuracy-grade", help="ISO 1328 accuracy grade for ISO K_v (3…12).")
    ] = 6,
    quality: Annotated[
        int, typer.Option("--quality", help="AGMA transmission accuracy level Q_v for AGMA K_v.")
    ] = 10,
    reliability_percent: Annotated[
        float,
        typer.Option(
            "--reliability-percent",
            help="AGMA reliability R [%] for K_R (50 < R ≤ 99.99; 99: K_R = 1).",
        ),
    ] = 99.0,
    old_reliability: Annotated[
        float | None,
        typer.Option("--reliability", hidden=True, help="Replaced by --reliability-percent."),
    ] = None,
    geometry_factor: Annotated[
        str,
        typer.Option(
            "--geometry-factor",
            help="AGMA bending geometry factor J: agma908 (AGMA 908-B89; internal gears ISO's) "
            "or iso (1/(Y_F Y_S) of ISO 6336-3).",
        ),
    ] = "agma908",
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")] = False,
) -> None:
    """Rate every mesh (ISO 6336, AGMA 2001, Hertz) from the forces of a short simulation.

    The factors the command line sets are every mesh's; the others take their documented
    defaults (``IsoFactors``, ``AgmaFactors`` set them all from Python).
    """
    import pinwind
    from pinwind.analysis.rating import rate as rate_result
    from pinwind.analysis.rating_table import rating_tables
    from pinwind.gears.rating_agma import AgmaFactors
    from pinwind.gears.rating_iso import IsoFactors
    from pinwind.runs import scenario as sc

    _check_reliability(reliability_percent, old_reliability)
    if not (math.isfinite(application_factor) and application_factor >= 1.0):
        raise InputError(
            f"--application-factor {application_factor:g}: give a finite factor >= 1 "
            "(1: the run's forces are the actual loads; below 1 would rate the gears for less "
            "than the loads the run computed)"
        )
    if (model is None) == (from_log is None):
        raise InputError("give a MODEL to run or --from-log LOG to rate a logged run (one of them)")
    if from_log is not None and (torque or speed or initial_speed):
        raise InputError(
            "--from-log rates the logged run as it ran: drop --torque, --speed and "
            "--initial-speed (they set up a new run)"
        )
    scenario = None
    if from_log is not None:
        gearbox, res = _logged_run(from_log)
    elif model is not None:
        values = {"model": str(model), "duration": duration, "dt": dt}
        scenario = sc.build(values | load_values(torque, speed, None, initial_speed), flags=FLAGS)
        with warnings_as_lines():
            gearbox = pinwind.load(model)
    materials = parse_pairs(material, "--material")
    if "all" in materials:
        chosen = materials.pop("all")
        materials = {g: chosen for g in gearbox.gears} | materials
    with warnings_as_lines():
        if scenario is not None:
            res = sc.run(scenario, gearbox=gearbox, no_log=True, check_joints=False)
        rating = rate_result(
            gearbox,
            res,
            at=at,
            materials=materials,
            iso=IsoFactors(K_A=application_factor, accuracy_grade=accuracy_grade),
            agma=AgmaFactors(
                K_o=application_factor,
                quality=quality,
                reliability_percent=reliability_percent,
                geometry_factor=geometry_factor,
            ),
            face_load=face_load_factor,
            transverse_load=transverse_load_factor,
        )
    if as_json:
        print(json.dumps(rating.as_dict(), indent=1))
        return
    title = f"{gearbox.name} at t = {res.time[-1]:g} s"
    for table in rating_tables(rating, title=title, plain=not console.is_terminal):
        console.print()
        console.print(table)
    console.print("all meshes pass" if rating.passes else "[bold red]some meshes fail[/bold red]")


def _logged_run(path: Path):
    """(gearbox, result) of the run a log holds, the model rebuilt from the log's copy."""
    from pinwind.io.log_reader import LogReader
    from pinwind.model.gearbox import loads

    with warnings_as_lines():
        with LogReader(path) as reader:
            res = reader.read()
            text, problem = reader.model_text, reader.model_problem
        if not text:
            raise InputError(f"{path}: {problem}; rate the model with a new run (MODEL) instead")
        return loads(text, path=f"{path} (its model)"), res


def _check_reliability(percent: float, old: float | None) -> None:
    """``--reliability-percent`` in AGMA's K_R range; the old fraction ``--reliability`` refused.

    ``rate --reliability`` took a fraction (0.99) where ``pinwind life --reliability`` takes a
    percent (99): the one spelling in two units is refused here, with the percent to give.
    """
    from pinwind.gears.rating_agma import RELIABILITY_PERCENT_RANGE

    if old is not None:
        hint = f" (--reliability-percent {100 * old:g})" if 0.0 < old <= 1.0 else ""
        raise InputError(
            f"--reliability {old:g}: rate takes the AGMA reliability in percent, as "
            f"pinwind life does: give --reliability-percent R{hint}, "
            f"{RELIABILITY_PERCENT_RANGE[0]:g} < R ≤ {RELIABILITY_PERCENT_RANGE[1]:g}"
        )
    check_reliability_percent(percent, *RELIABILITY_PERCENT_RANGE, open_low=True)
