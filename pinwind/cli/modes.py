"""``pinwind modes`` and ``pinwind campbell``: natural modes of a machine and its Campbell diagram.

Each takes a model file (the gearbox alone, unloaded) or a scenario file (TOML naming its model):
then the machine its runs step (``dynamics/drivetrain.py``), with the rotor's inertia, the
generator and rotor laws' slopes, the speed drivers held and the flanks its static load presses.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer
from rich import box
from rich.markup import escape
from rich.table import Table

from pinwind.cli.app import app, console, err_console, say, warnings_as_lines
from pinwind.cli.flags import mesh_values, parse_number, parse_pairs
from pinwind.errors import InputError
from pinwind.units import RAD_S_PER_RPM

if TYPE_CHECKING:
    import numpy as np

    from pinwind.dynamics.drivetrain import Drivetrain
    from pinwind.dynamics.normal_modes import Mode
    from pinwind.model.gearbox import Gearbox
    from pinwind.modes.linearisation import Linearisation

MachineArgument = Annotated[
    Path,
    typer.Argument(
        help="Model file (URDF with a <gearbox> element: the gearbox alone, unloaded), or "
        "scenario file (TOML naming its model: with its rotor, generator, drivers and loads)."
    ),
]

MeshOption = Annotated[
    list[str] | None,
    typer.Option(
        "--mesh",
        help="NAME=rigid|compliant (all for every mesh), repeatable. Default: all=compliant.",
    ),
]
HoldOption = Annotated[
    list[str] | None,
    typer.Option(
        "--hold",
        help="JOINT held at its speed (a speed driver, a stiff grid-connected generator); "
        "repeatable.",
    ),
]


def _meshes(*layers: dict[str, str] | None) -> dict[str, str]:
    """The mesh choice: every mesh compliant, then each layer's choices (a later one wins)."""
    out: dict[str, str] = {"all": "compliant"}
    for layer in layers:
        for key, value in (layer or {}).items():
            if key == "all":
                out = {}
            out[key] = value
    return out


def _machine(
    path: Path, mesh: list[str] | None, hold: list[str] | None
) -> tuple[Gearbox, Drivetrain]:
    """The gearbox and the machine to linearise, from a model file or a scenario file.

    A scenario's meshes are compliant unless it (or ``--mesh``) makes them rigid: a mesh a run
    takes rigid has no mode of its own.
    """
    import pinwind
    from pinwind.dynamics.drivetrain import drivetrain

    flags = mesh_values(mesh)
    if path.suffix.lower() == ".toml":
        from pinwind.runs.scenario import load_scenario

        scenario = load_scenario(path)
        gearbox = scenario.load_model()
        meshes = _meshes(dict(scenario.meshes), flags)
        return gearbox, scenario.drivetrain(gearbox, meshes=meshes, held=tuple(hold or ()))
    gearbox = pinwind.load(path)
    # The gearbox alone: no load presses a flank, not even its weight.
    train = drivetrain(gearbox, meshes=_meshes(flags), gravity=[0.0, 0.0, 0.0], held=hold or ())
    return gearbox, train


def _machine_lines(lin: Linearisation, at: np.ndarray, joint_names: list[str]) -> list[str]:
    """What the machine has besides the gearbox, and the flanks assumed without load."""
    lines = [
        f"rotor inertia on {name}: {value:.4g} kg·m²" for name, value in lin.added_inertia.items()
    ]
    if lin.law_damping:
        point = ", ".join(
            f"{name} {at[i] / RAD_S_PER_RPM:.4g} rpm"
            for i, name in enumerate(joint_names)
            if name in lin.law_damping
        )
        lines.append(
            "generator and rotor slopes as dampers: "
            + ", ".join(f"{n} {c:.4g} N·m·s/rad" for n, c in lin.law_damping.items())
            + f" (at {point})"
        )
    return lines + lin.flanks.notes()


def _shares(group: list[Mode], which: str, most: int = 3) -> str:
    """The largest shares of a group of modes (their mean) as ``name 52 %, ...``."""
    total: dict[str, float] = {}
    for mode in group:
        for name, value in getattr(mode, which).items():
            total[name] = total.get(name, 0.0) + value / len(group)
    ranked = sorted(total.items(), key=lambda kv: -abs(kv[1]))[:most]
    return ", ".join(f"{name} {100 * value:.0f} %" for name, value in ranked if abs(value) >= 0.01)


@app.command()
def modes(
    model: MachineArgument,
    mesh: MeshOption = None,
    hold: HoldOption = None,
    speed: Annotated[
        list[str] | None,
        typer.Option(
            "--speed",
            help="JOINT=RPM operating speed (≥ 0; the other joints through the gear ratios), "
            "repeatable. Default: at rest.",
        ),
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of a table.")] = False,
    animate: Annotated[
        int | None,
        typer.Option(
            "--animate",
            help="Animate mode N (its number in the list) in a Rerun recording; with --save.",
        ),
    ] = None,
    save: Annotated[
        Path | None, typer.Option("--save", help="Write the --animate recording (.rrd) here.")
    ] = None,
) -> None:
    """Natural frequencies, damping ratios and energy shares of a machine's modes.

    Linearised at the reference pose and the operating speed: compliant meshes at their mean
    stiffness on the flanks the static load presses, torsional springs, compliant bearings,
    bearing damping, and at speed the gyroscopic and centrifugal terms; rigid meshes, held
    joints and locked bearings as constraints. From a scenario also the rotor's inertia, the
    generator and rotor laws' slopes (dampers, at the scenario's start speeds) and its speed
    drivers (held). A repeated frequency is one row (its modes' mean shares); with a planetary
    stage, each mode's class (Lin & Parker 1999: rotational, translational, planet); at speed,
    a spinning body's orbit in its bearing whirls forward or backward.
    """
    from pinwind.dynamics.normal_modes import repeated_groups
    from pinwind.modes.linearisation import linearise

    speeds = {
        name: parse_number(value, "--speed", "rpm") * RAD_S_PER_RPM
        for name, value in parse_pairs(speed, "--speed").items()
    }
    if (animate is None) != (save is None):
        raise InputError("--animate N and --save FILE.rrd go together (open it with: rerun FILE)")
    with warnings_as_lines():
        gearbox, train = _machine(model, mesh, hold)
        lin = linearise(train, speeds=speeds)
        found = lin.modes()
    if animate is not None and not 1 <= animate <= len(found):
        raise InputError(f"--animate {animate}: {gearbox.name} has modes 1 to {len(found)}")
    at = lin.speed if speeds else train.operating_speed()
    notes = _machine_lines(lin, at, lin.joint_names)
    if as_json:
        for line in notes:  # stdout keeps the JSON alone
            err_console.print(line, soft_wrap=True, highlight=False)
        print(json.dumps([
            {"frequency_hz": m.frequency, "damping_ratio": m.damping_ratio, "kind": m.kind,
             "whirl": m.whirl, "kinetic_share": m.kinetic_share, "strain_share": m.strain_share}
            for m in found
        ], indent=1))  # fmt: skip
        _animate(gearbox, found, animate, save, quiet=True)
        return
    plain = not console.is_terminal
    given = ", ".join(f"{name} {value}" for name, value in parse_pairs(speed, "--speed").items())
    table = Table(
        title=f"natural modes of {escape(gearbox.name)}"
        + (f" at {escape(given)} rpm" if given else ""),
        box=box.ASCII if plain else box.SIMPLE,
    )
    kinds = any(m.kind for m in found)
    whirls = any(m.whirl for m in found)
    columns = ["#", "f [Hz]", "ζ [%]", *(["kind"] if kinds else []), *(["whirl"] if whirls else [])]
    columns.append("moves (kinetic energy)")
    for column in [*columns, "works (strain energy)"]:
        table.add_column(column, justify="right" if column in ("#", "f [Hz]", "ζ [%]") else "left")
    first = 1
    for group in repeated_groups(found):
        m, last = group[0], first + len(group) - 1
        number = str(first) if last == first else f"{first}-{last}"
        first = last + 1
        kind = [f"{m.kind} ×{len(group)}" if len(group) > 1 else m.kind] if kinds else []
        kind += [" / ".join(sorted({x.whirl or "-" for x in group}))] if whirls else []
        if m.rigid:
            row = [number, "0 (rigid)", "-", *kind, _shares(group, "kinetic_share"), "-"]
        else:
            zeta = sum(x.damping_ratio for x in group) / len(group)
            row = [number, f"{m.frequency:.5g}", f"{100 * zeta:.3g}", *kind]
            row += [_shares(group, "kinetic_share"), _shares(group, "strain_share")]
        table.add_row(*(escape(cell) for cell in row))
    console.print(table)
    for line in notes:
        say(escape(line))
    _animate(gearbox, found, animate, save)


def _animate(
    gearbox: Gearbox, found: list[Mode], number: int | None, save: Path | None, quiet: bool = False
) -> None:
    """Write mode ``number``'s animation to ``save`` (``modes/mode_animation.py``) when asked."""
    if number is None or save is None:
        return
    from pinwind.modes.mode_animation import save_mode_animation

    path = save_mode_animation(gearbox, found[number - 1], save, number=number)
    if not quiet:
        say(f"wrote {escape(str(path))}")


@app.command()
def campbell(
    model: MachineArgument,
    joint: Annotated[str, typer.Option(help="Input joint whose speed the diagram runs over.")],
    speed_range: Annotated[
        str, typer.Option("--speed-range", help="A:B input speed range [rpm], e.g. 0:20.")
    ],
    mesh: MeshOption = None,
    hold: HoldOption = None,
    harmonics: Annotated[int, typer.Option(help="Mesh-frequency harmonics drawn.")] = 3,
    points: Annotated[
        int,
        typer.Option(
            help="Speeds sampled across the range when the modes change with speed "
            "(gyroscopic terms)."
        ),
    ] = 101,
    png: Annotated[Path | None, typer.Option("--png", help="Write the diagram here.")] = None,
    csv_out: Annotated[
        Path | None, typer.Option("--csv", help="Write the crossings as CSV here.")
    ] = None,
) -> None:
    """Natural frequencies against the input speed with the mesh and shaft orders; crossings.

    Lists every speed inside the range where an excitation (a mesh frequency or its harmonic,
    a shaft's order 1) meets a natural frequency, with the mode's whirl there when a spinning
    body's gyroscopic terms move the modes with speed.
    """
    from pinwind.dynamics.normal_modes import repeated_groups
    from pinwind.modes.campbell import campbell as diagram_of
    from pinwind.modes.campbell import write_figure

    low, sep, high = speed_range.partition(":")
    try:
        bounds = (float(low) * RAD_S_PER_RPM, float(high) * RAD_S_PER_RPM)
    except ValueError as err:
        raise InputError(f'--speed-range "{speed_range}": give A:B in rpm, e.g. 0:20') from err
    if not sep:
        raise InputError(f'--speed-range "{speed_range}": give A:B in rpm, e.g. 0:20')
    with warnings_as_lines():
        _, train = _machine(model, mesh, hold)
        diagram = diagram_of(train, joint, bounds, harmonics=harmonics, points=points)
    rpm = 1.0 / RAD_S_PER_RPM
    plain = not console.is_terminal
    table = Table(
        title=f"crossings for {escape(joint)} at {speed_range} rpm",
        box=box.ASCII if plain else box.SIMPLE,
    )
    whirls = any(c.whirl for c in diagram.crossings)
    for column in ("speed [rpm]", "mode [Hz]", *(["whirl"] if whirls else []), "excitation"):
        # escaped: rich took "[rpm]" for markup and printed the header "speed"
        table.add_column(
            escape(column), justify="right" if column in ("speed [rpm]", "mode [Hz]") else "left"
        )
    for c in diagram.crossings:
        whirl = [c.whirl or "-"] if whirls else []
        repeated = f" ×{c.multiplicity}" if c.multiplicity > 1 else ""
        table.add_row(
            f"{c.speed * rpm:.4g}",
            f"{c.frequency:.5g}{repeated}",
            *whirl,
            escape(c.excitation.label),
        )
    top = f" at {float(high):g} rpm" if len(diagram.speed_grid) > 1 else ""
    say(
        f"natural frequencies [Hz]{top}: "
        + ", ".join(
            f"{group[0].frequency:.5g}" + (f" ×{len(group)}" if len(group) > 1 else "")
            for group in repeated_groups(diagram.modes)
        )
        + f"; {len(diagram.crossings)} crossings in the range"
    )
    if diagram.crossings:
        console.print(table)
    if csv_out is not None:
        with open(csv_out, "w", newline="", encoding="utf-8") as f:
            writer = csv.writer(f)
            writer.writerow(
                ["speed_rpm", "mode_hz", "excitation", "harmonic", "whirl", "multiplicity"]
            )
            for c in diagram.crossings:
                writer.writerow(
                    [
                        c.speed * rpm,
                        c.frequency,
                        c.excitation.label,
                        c.excitation.harmonic,
                        c.whirl,
                        c.multiplicity,
                    ]
                )
        say(f"wrote {escape(str(csv_out))}")
    if png is not None:
        write_figure(diagram, str(png))
        say(f"wrote {escape(str(png))}")
