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
    load_values,
    parse_pairs,
)
from pinwind.errors import InputError


@app.command()
def rate(
    model: Annotated[Path, typer.Argument(help="Gearbox model file (URDF with <gearbox>).")],
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
    reliability: Annotated[
        float,
        typer.Option("--reliability", help="AGMA reliability for K_R (0.5 … 0.9999)."),
    ] = 0.99,
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

    if not (math.isfinite(application_factor) and application_factor > 0):
        raise InputError(
            f"--application-factor {application_factor:g}: give a finite factor > 0 "
            "(1: the run's forces are the actual loads)"
        )
    values = {"model": str(model), "duration": duration, "dt": dt}
    scenario = sc.build(values | load_values(torque, speed, None, initial_speed), flags=FLAGS)
    with warnings_as_lines():
        gearbox = pinwind.load(model)
    materials = parse_pairs(material, "--material")
    if "all" in materials:
        chosen = materials.pop("all")
        materials = {g: chosen for g in gearbox.gears} | materials
    with warnings_as_lines():
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
                reliability=reliability,
                geometry_factor=geometry_factor,
            ),
        )
    if as_json:
        print(json.dumps(rating.as_dict(), indent=1))
        return
    title = f"{gearbox.name} at t = {res.time[-1]:g} s"
    for table in rating_tables(rating, title=title, plain=not console.is_terminal):
        console.print()
        console.print(table)
    console.print("all meshes pass" if rating.passes else "[bold red]some meshes fail[/bold red]")
