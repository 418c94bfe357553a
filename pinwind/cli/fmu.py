"""``pinwind fmu``: a model or scenario as an FMI 2.0 or 3.0 co-simulation unit (``fmu_export``)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.markup import escape

from pinwind.cli.app import app, say, warnings_as_lines


@app.command()
def fmu(
    source: Annotated[Path, typer.Argument(help="Model file (.urdf) or scenario file (.toml).")],
    out: Annotated[Path, typer.Option("-o", "--out", help="The FMU file to write.")],
    inputs: Annotated[
        list[str] | None,
        typer.Option(
            "--inputs",
            help="An open input: torque.JOINT [N·m], speed.JOINT [rad/s] or wind [m/s]; "
            "repeatable. Default: a torque on every free joint the scenario leaves unloaded.",
        ),
    ] = None,
    outputs: Annotated[
        list[str] | None,
        typer.Option(
            "--outputs",
            help="An output SERIES.ELEMENT (speed.sun, mesh_normal.sun_planet1, "
            "bearing_force.carrier.x); repeatable. Default: speeds, angles, joint torques, "
            "mesh normal forces, bearing radial and axial loads, generator and rotor torques.",
        ),
    ] = None,
    dt: Annotated[float, typer.Option(help="Internal step [s] of a model file.")] = 1e-3,
    duration: Annotated[
        float, typer.Option(help="Longest run [s] of a model file (the master's stop time wins).")
    ] = 3600.0,
    fmi_version: Annotated[
        int,
        typer.Option(
            "--fmi-version",
            help="FMI version of the unit: 2 (PythonFMU) or 3 (PythonFMU3; the run lasts "
            "--duration or the scenario's, whatever the master's stop time).",
        ),
    ] = 2,
) -> None:
    """Write an FMI 2.0 (or 3.0) co-simulation FMU; it runs in this Python environment.

    Each communication step must be a whole number of internal steps dt; inputs are held over
    it. See docs/coupling.md.
    """
    from pinwind.runs.fmu_export import export_fmu

    with warnings_as_lines():
        written = export_fmu(source, out, inputs=inputs, outputs=outputs, dt=dt,
                             duration=duration, fmi_version=fmi_version)  # fmt: skip
    say(f"wrote {escape(str(written))}")
