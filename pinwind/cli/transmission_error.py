"""``pinwind te``: a mesh's loaded static transmission error over a range of torques."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer
from rich.markup import escape
from rich.table import Table

from pinwind.cli.app import app, console, say, warnings_as_lines
from pinwind.errors import InputError

#: Torque levels of ``--torque A:B`` without a count.
DEFAULT_LEVELS = 20


def torque_levels(text: str) -> np.ndarray:
    """``A``, ``A,B,...``, ``A:B`` (20 levels) or ``A:B:N`` as torques [N·m], each > 0.

    Raises:
        InputError: not numbers, a level ≤ 0 or not finite, fewer than 2 levels in a range.
    """
    try:
        if ":" in text:
            parts = text.split(":")
            if len(parts) not in (2, 3):
                raise ValueError
            count = int(parts[2]) if len(parts) == 3 else DEFAULT_LEVELS
            if count < 2:
                raise InputError(f"--torque {text}: a range needs at least 2 levels")
            levels = np.linspace(float(parts[0]), float(parts[1]), count)
        else:
            levels = np.array([float(x) for x in text.split(",")])
    except ValueError:
        raise InputError(
            f"--torque {text!r}: give N·m as A, A,B,C, A:B (20 levels) or A:B:N"
        ) from None
    if not (np.all(np.isfinite(levels)) and np.all(levels > 0.0)):
        raise InputError(
            f"--torque {text}: every torque must be a positive number of N·m (the TE of a "
            "loaded flank; the other flank is the same calculation with the gears swapped)"
        )
    return levels


@app.command()
def te(
    model: Annotated[Path, typer.Argument(help="Gearbox model file (URDF with <gearbox>).")],
    mesh: Annotated[str, typer.Option("--mesh", help="The mesh's name in the model.")],
    torque: Annotated[
        str,
        typer.Option(
            "--torque",
            help="Torque this mesh transmits on --gear [N·m]: A, A,B,C, A:B (20 levels) or "
            "A:B:N. A sun driving three planets gives each sun–planet mesh a third of its torque.",
        ),
    ],
    gear: Annotated[
        str | None,
        typer.Option("--gear", help="The gear the torque is on (default: the mesh's pinion)."),
    ] = None,
    misalignment_um: Annotated[
        float,
        typer.Option(
            "--misalignment-um",
            help="Mesh misalignment F_β across the face [µm], positive loading face side I.",
        ),
    ] = 0.0,
    slices: Annotated[
        int | None,
        typer.Option(
            "--slices",
            help="Slices of the face width (default 1 for an unmodified-lead spur pair, else 40).",
        ),
    ] = None,
    positions: Annotated[
        int, typer.Option("--positions", help="Roll positions per mesh cycle.")
    ] = 128,
    figures: Annotated[
        Path | None,
        typer.Option("--figures", help="Folder for te_cycle.png, te_map.png and te_harmonics.png."),
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of a table.")] = False,
) -> None:
    """The loaded static transmission error of one mesh at each torque, with its modifications.

    The tooth pairs in contact are springs (ISO 6336-1 stiffness) behind the gaps the gears'
    flank modifications in the model leave (tip and root relief, crowning, end relief, helix
    slope); TE along the line of action, over one mesh cycle. Prints the mean and peak-to-peak
    TE and the first three mesh harmonics per torque (the Harris map).
    """
    from pinwind.gears.gear_pair import GearPair
    from pinwind.gears.transmission_error import transmission_error_map
    from pinwind.model.gearbox import load

    levels = torque_levels(torque)
    if not math.isfinite(misalignment_um):
        raise InputError(f"--misalignment-um {misalignment_um}: give a finite number")
    with warnings_as_lines():
        gearbox = load(model)
        found = [m for m in gearbox.meshes if m.name == mesh]
        if not found:
            names = ", ".join(m.name for m in gearbox.meshes)
            raise InputError(f"{model}: no mesh named {mesh!r}; the meshes are {names}")
        pair = GearPair.from_mesh(found[0])
        specs = {g.name: g.spec for g in (found[0].gear_a, found[0].gear_b)}
        pinion, wheel = (specs[n] for n in pair.names)
        on = gear if gear is not None else pinion.name
        if on not in specs:
            raise InputError(
                f"--gear {on}: mesh {mesh} has gears {pinion.name} and {wheel.name}; name one"
            )
        geometry = pair.geometry
        radius = geometry.base_radius_1 if on == pinion.name else geometry.base_radius_2
        forces = levels / radius  # along the transverse line of action
        maps = transmission_error_map(
            pair, forces, gear_1=pinion.modification, gear_2=wheel.modification,
            misalignment=misalignment_um * 1e-6, positions=positions, slices=slices,
        )  # fmt: skip
    rows: list[dict[str, Any]] = [
        {
            "torque_Nm": float(t),
            "force_N": float(f),
            "mean_um": m.mean * 1e6,
            "peak_to_peak_um": m.peak_to_peak * 1e6,
            "harmonics_um": [float(a) * 1e6 for a in m.harmonics(3)],
        }
        for t, f, m in zip(levels, forces, maps, strict=True)
    ]
    if as_json:
        print(json.dumps({"mesh": mesh, "gear": on, "levels": rows}, indent=1))
    else:
        modified = [s.name for s in (pinion, wheel) if not s.modification.is_none]
        say(
            f"[bold]{escape(mesh)}[/bold] ({escape(pinion.name)}–{escape(wheel.name)}, ε_α "
            f"{pair.path.contact_ratio:.3f}, ε_β {pair.path.overlap_ratio:.3f}); torque on "
            f"{escape(on)}; flank modifications on: {escape(', '.join(modified) or 'none')}"
        )
        table = Table(
            title=escape("Loaded static transmission error along the line of action [µm]")
        )
        for head in ("torque [kN·m]", "F_bt [kN]", "mean", "peak-to-peak", "1×", "2×", "3×"):
            table.add_column(escape(head), justify="right")
        for r in rows:
            table.add_row(
                f"{r['torque_Nm'] / 1e3:.4g}", f"{r['force_N'] / 1e3:.4g}",
                f"{r['mean_um']:.3f}", f"{r['peak_to_peak_um']:.3f}",
                *(f"{a:.3f}" for a in r["harmonics_um"]),
            )  # fmt: skip
        console.print(table)
        say("1×, 2×, 3×: amplitudes of the mesh-frequency harmonics over one mesh cycle")
    if figures is not None:
        from pinwind.io.transmission_error_figures import plot_transmission_error

        about = f"mesh {mesh} of {gearbox.name}, torque on {on}"
        for path in plot_transmission_error(maps, levels, figures, about=about):
            if not as_json:
                say(f"wrote {escape(str(path))}")
