"""``pinwind efficiency``: the efficiency map over input torques and speeds, as CSV and a figure."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich.markup import escape

from pinwind.cli.app import app, err_console, say, warnings_as_lines
from pinwind.errors import InputError


def _range(text: str, option: str) -> tuple[float, float]:
    """``A:B`` as two finite numbers A ≤ B (or one number: A = B)."""
    parts = text.split(":")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        values = []
    if len(values) == 1:
        values = values * 2
    if len(values) != 2 or not all(math.isfinite(v) for v in values) or values[0] > values[1]:
        raise InputError(f'{option} "{text}": give A:B, two numbers with A ≤ B (or one number)')
    return values[0], values[1]


@app.command()
def efficiency(
    model: Annotated[
        Path,
        typer.Argument(help="Gearbox model file (.urdf), or a scenario (.toml): its model."),
    ],
    input_joint: Annotated[
        str, typer.Option("--input", help="Joint the input torque acts on (the rotor's).")
    ],
    output_joint: Annotated[
        str, typer.Option("--output", help="Joint a speed driver holds (the generator's).")
    ],
    torque: Annotated[str, typer.Option(help="Input torques A:B [N·m].")],
    speed: Annotated[str, typer.Option(help="Input speeds C:D [rpm].")],
    points: Annotated[int, typer.Option(help="Points per axis (points × points runs).")] = 10,
    duration: Annotated[float, typer.Option(help="Each run's duration [s].")] = 0.02,
    dt: Annotated[float, typer.Option(help="Time step [s].")] = 1e-3,
    lubricant_vg: Annotated[
        int, typer.Option("--lubricant-vg", help="ISO 3448 viscosity grade of the gear oil.")
    ] = 320,
    oil_temperature: Annotated[
        float, typer.Option("--oil-temperature", help="Oil temperature [°C].")
    ] = 70.0,
    roughness: Annotated[
        float, typer.Option("--roughness", help="Flank roughness Ra = (Ra1 + Ra2)/2 [µm].")
    ] = 0.5,
    out: Annotated[Path, typer.Option(help="Folder for efficiency_map.csv and .png.")] = Path("."),
    workers: Annotated[int, typer.Option(help="Local worker processes.")] = 1,
    scheduler: Annotated[
        str | None, typer.Option(help="Dask scheduler address, e.g. tcp://head:8786.")
    ] = None,
) -> None:
    """Efficiency map: ISO/TR 14179-2's bearing and mesh losses over input torques and speeds.

    Each point is a short run with the torque on --input and --output held at the input speed
    times the train's ratio; its efficiency is 1 − losses / input power over the run's second
    half (docs/losses.md). No churning or windage: an upper bound. A scenario gives its model
    (its own loads and drivers are the map's points instead).
    """
    from pinwind.runs.efficiency_map import check_grade, draw, efficiency_map, write_csv

    check_grade(lubricant_vg, "--lubricant-vg")
    if model.suffix.lower() == ".toml":
        from pinwind.runs.scenario import load_scenario

        model = load_scenario(model).model_path()
    if points < 1:
        raise InputError(f"--points {points}: give at least 1")
    t_lo, t_hi = _range(torque, "--torque")
    n_lo, n_hi = _range(speed, "--speed")
    if n_lo <= 0.0:
        raise InputError(f'--speed "{speed}": the input speeds must be > 0 rpm')
    torques = np.linspace(t_lo, t_hi, points if t_hi > t_lo else 1)
    speeds = np.linspace(n_lo, n_hi, points if n_hi > n_lo else 1)
    out.mkdir(parents=True, exist_ok=True)
    with warnings_as_lines():
        rows, backend = efficiency_map(
            str(model), input_joint=input_joint, output_joint=output_joint,
            torques=list(torques), speeds_rpm=list(speeds), duration=duration, dt=dt,
            grade=lubricant_vg, temperature=oil_temperature + 273.15,
            roughness=roughness * 1e-6, workers=workers, scheduler=scheduler,
        )  # fmt: skip
    for note in sorted({n for r in rows for n in r["warnings"]}):
        err_console.print(f"[yellow]warning:[/yellow] {escape(note)}", highlight=False)
    write_csv(rows, out / "efficiency_map.csv")
    draw(rows, out / "efficiency_map.png", title=f"{model.stem}: efficiency (ISO/TR 14179-2)")
    best = max(rows, key=lambda r: r["efficiency"])
    say(
        f"{len(rows)} points on {backend}; efficiency {min(r['efficiency'] for r in rows):.4f}"
        f" … {best['efficiency']:.4f} (best at {best['torque_Nm']:g} N·m, "
        f"{best['speed_rpm']:g} rpm); wrote {out / 'efficiency_map.csv'} and "
        f"{out / 'efficiency_map.png'}"
    )
