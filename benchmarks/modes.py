"""Cost of ``pinwind modes`` and of a Campbell diagram (issue 24: < 1 s and < 10 s).

- ``pinwind modes MODEL``, ``pinwind modes SCENARIO`` (the drivetrain its runs step: rotor, laws,
  drivers, loaded flanks; issue 36) and ``pinwind --version`` as a user runs them, a fresh process
  each time: median, best and worst wall time of ``--repeats`` runs, and the median CPU time (user
  + system, which depends less on what else the machine is doing), with the load average. From
  compiled modules, as an installed pinwind runs (one uncounted run writes the bytecode cache);
  ``--compile-each-run`` keeps PYTHONDONTWRITEBYTECODE, which this shared environment sets.
- In this process, what ``pinwind modes`` spends its time on, in the order the command meets it:
  typer and rich (the CLI library), ``import pinwind``, the CLI app with the modes verb alone
  (``pinwind/cli/__init__.py`` imports only the invoked verb's module; the verb modules import
  their heavy modules inside their commands: ``lazy_exports.py``), the modules of ``modes``
  (numpy, Pinocchio, the model, the linearisation), typer building the command from its
  signature, loading the model, linearising and solving; then the whole command once more in
  this process, everything imported (typer building the command and converting the arguments,
  without pydantic: ``cli/conversions.py``; the model, the modes, the table). Then whether
  pydantic or another verb's module was imported (neither should be).
- A Campbell diagram of ``--speeds`` input speeds: ``campbell`` itself (one linearisation at
  the top of the range: the modes of torsional coordinates do not change with speed), and the
  cost if every speed were linearised and solved (``linearise(speeds=...).modes()`` at each;
  a model whose gyroscopic terms act linearises once and solves at each of ``--points``
  speeds, cheaper than this); ``pinwind campbell`` as a process too.
- The cores this process gets asking for two (``machine.parallel_capacity``): below 2 while other
  work shares the machine, when wall times are longer than the CPU times.

    python benchmarks/modes.py [--model models/cart600_gearbox.urdf] [--repeats 10] [--speeds 100]
                               [--scenario scenarios/saleh2017_drivetrain.toml]
                               [--source OTHER_CHECKOUT] [--compile-each-run]

Measured 2026-11-27 06:09, ``python benchmarks/modes.py --repeats 9``, bytecode cached, on the
shared 2-core machine at load average 9.7-11.1 (0.23 cores of 2 given): ``pinwind modes
cart600_gearbox.urdf`` wall median 2.42 s (best 1.78), CPU median 0.81 s; ``pinwind --version``
0.90 s, CPU 0.30 s; in process (CPU): typer and rich 0.12 s, the app and the modes verb 0.04 s,
numpy, Pinocchio and the model 0.29 s, typer building the command 0.007 s, load 0.014 s,
linearise and solve 0.011 s, the whole command again 0.044 s (it was 0.16 s with pydantic and
every verb's command); pydantic and the other verbs not imported. Campbell 0-30 rpm 0.015 s CPU;
100 speeds each linearised 3.8 s wall (1.24 s CPU); ``pinwind campbell`` 2.6 s wall (0.90 s
CPU). Before/after in the same minutes (interleaved, 15 runs each, load 10.3-11.0): ``pinwind
modes`` CPU median 1.30 -> 0.86 s (best 0.92 -> 0.57), wall median 3.76 -> 2.43 s; summed
``-X importtime`` of the imports, best of 7, 1.42 -> 0.92 s. Wall times on this machine are 2-4x
the CPU times. On a quiet machine ``pinwind modes`` took 1.03-1.38 s before the lazy exports
(12-17 % less CPU) and this change (34 % less): about 0.6-0.8 s now, an estimate, as no quiet
period was available. benchmarks/README.md has the rest.

Measured 2027-01 (issue 36), ``python benchmarks/modes.py --repeats 5 --speeds 10``, load average
2.1-2.4 (0.77 cores of 2 given): ``pinwind modes saleh2017_drivetrain.toml`` wall median 0.466 s
(best 0.422), CPU 0.393 s; ``pinwind modes cart600_gearbox.urdf`` 0.433 s (CPU 0.333 s); in
process, reading the scenario and building its drivetrain 0.063 s, linearising it and its modes
0.012 s.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

from machine import parallel_capacity

ROOT = Path(__file__).resolve().parents[1]


def process_times(args: list[str], repeats: int, source: Path) -> tuple[list[float], list[float]]:
    """Wall and CPU times [s] of ``python -m pinwind ARGS``, ``repeats`` runs in ``source``."""
    walls, cpus = [], []
    for _ in range(repeats):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        subprocess.run(
            [sys.executable, "-m", "pinwind", *args], check=True, capture_output=True, cwd=source
        )
        walls.append(time.perf_counter() - start)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpus.append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
    return walls, cpus


def process_line(label: str, walls: list[float], cpus: list[float]) -> str:
    """Median, best and worst wall time and median CPU time of a command's runs."""
    return (
        f"{label}: wall median {statistics.median(walls):.3f} s (best {min(walls):.3f}, worst "
        f"{max(walls):.3f}), CPU median {statistics.median(cpus):.3f} s ({len(walls)} runs)"
    )


def load_average() -> str:
    """The 1-minute load average: how many processes wanted the machine's 2 cores."""
    return f"load average {os.getloadavg()[0]:.1f}"


class Steps:
    """Wall and CPU time [s] of consecutive steps in this process."""

    def __init__(self) -> None:
        self.rows: list[tuple[str, float, float]] = []
        self.wall, self.cpu = time.perf_counter(), time.process_time()

    def done(self, label: str) -> None:
        """Close the step that started at the previous ``done`` (or at creation)."""
        wall, cpu = time.perf_counter(), time.process_time()
        self.rows.append((label, wall - self.wall, cpu - self.cpu))
        self.wall, self.cpu = wall, cpu

    def print(self) -> None:
        """One line per step, then the total."""
        for label, wall, cpu in self.rows:
            print(f"  {label:<54} {wall:7.3f} s (CPU {cpu:.3f} s)")
        wall = sum(row[1] for row in self.rows)
        cpu = sum(row[2] for row in self.rows)
        print(f"  {'total':<54} {wall:7.3f} s (CPU {cpu:.3f} s)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--model", default=str(ROOT / "models" / "cart600_gearbox.urdf"))
    parser.add_argument(
        "--scenario",
        default=str(ROOT / "scenarios" / "saleh2017_drivetrain.toml"),
        help="scenario file timed as `pinwind modes SCENARIO` (issue 36: < 1 s)",
    )
    parser.add_argument("--joint", default="carrier")
    parser.add_argument("--rpm", type=float, default=30.0, help="top of the Campbell range")
    parser.add_argument("--repeats", type=int, default=10)
    parser.add_argument("--speeds", type=int, default=100)
    parser.add_argument(
        "--source",
        type=Path,
        default=ROOT,
        help="the pinwind tree to time (default this checkout; another checkout, e.g. a `git "
        "archive` of main with its _native module copied in, compares before and after)",
    )
    parser.add_argument(
        "--compile-each-run",
        action="store_true",
        help="keep PYTHONDONTWRITEBYTECODE as set (default: unset, as an installed pinwind runs "
        "from its compiled modules)",
    )
    args = parser.parse_args()
    source = args.source.resolve()
    if not args.compile_each_run:
        os.environ.pop("PYTHONDONTWRITEBYTECODE", None)
    os.environ["PYTHONPATH"] = os.pathsep.join([str(source), os.environ.get("PYTHONPATH", "")])
    sys.path.insert(0, str(source))

    cache = "compiled each run" if os.environ.get("PYTHONDONTWRITEBYTECODE") else "bytecode cached"
    print(
        f"{source} ({cache}): cores given when asking for two: {parallel_capacity():.2f}, "
        f"{load_average()}"
    )
    for label, command in (
        (f"pinwind modes {Path(args.model).name}", ["modes", args.model]),
        (f"pinwind modes {Path(args.scenario).name}", ["modes", args.scenario]),
        ("pinwind --version", ["--version"]),
    ):
        walls, cpus = process_times(command, args.repeats, source)
        print(process_line(label, walls, cpus) + f"; {load_average()}")

    print("in process, what pinwind modes spends its time on:")
    steps = Steps()
    import rich.table  # noqa: F401
    import typer.main

    steps.done("import typer, rich (the CLI library)")
    import pinwind

    steps.done("import pinwind")
    import pinwind.cli.modes  # noqa: F401
    from pinwind.cli.app import app

    steps.done("import pinwind.cli.modes (the app, the modes verb)")
    from pinwind.modes.linearisation import linearise

    steps.done("import the modes modules (numpy, Pinocchio, model)")
    typer.main.get_command(app)
    steps.done("typer builds the click command of modes")
    gearbox = pinwind.load(args.model)
    steps.done("load the model")
    modes = linearise(gearbox, meshes={"all": "compliant"}).modes()
    steps.done(f"linearise + modes ({len(modes)} modes)")
    from pinwind.cli import main as pinwind_main

    sys.argv = ["pinwind", "modes", args.model]
    with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):
        pinwind_main()
    steps.done("whole command again, all imported (typer, work, table)")
    from pinwind.runs.scenario import load_scenario

    scenario = load_scenario(args.scenario)
    machine = scenario.drivetrain(scenario.load_model(), meshes={"all": "compliant"})
    steps.done("read the scenario, load its model, build its drivetrain")
    modes = linearise(machine).modes()
    steps.done(f"linearise the drivetrain + modes ({len(modes)} modes)")
    steps.print()
    from pinwind.cli import VERB_MODULES

    others = {f"pinwind.cli.{name}" for name in VERB_MODULES.values()} - {"pinwind.cli.modes"}
    print(
        f"  imported: pydantic {'yes' if 'pydantic' in sys.modules else 'no'}, other verb "
        f"modules {sorted(others & set(sys.modules)) or 'none'}"
    )

    from pinwind.modes.campbell import campbell

    top = args.rpm * 2 * 3.141592653589793 / 60
    start, cpu = time.perf_counter(), time.process_time()
    diagram = campbell(gearbox, args.joint, (0.0, top), meshes={"all": "compliant"})
    once, once_cpu = time.perf_counter() - start, time.process_time() - cpu
    start, cpu = time.perf_counter(), time.process_time()
    for k in range(args.speeds):
        speed = top * k / (args.speeds - 1)
        linearise(gearbox, meshes={"all": "compliant"}, speeds={args.joint: speed}).modes()
    each, each_cpu = time.perf_counter() - start, time.process_time() - cpu
    print(
        f"campbell 0-{args.rpm:g} rpm on {args.joint}: {once:.4f} s (CPU {once_cpu:.4f} s, "
        f"{len(diagram.crossings)} crossings); {args.speeds} speeds each linearised: "
        f"{each:.3f} s (CPU {each_cpu:.3f} s)"
    )
    walls, cpus = process_times(
        ["campbell", args.model, "--joint", args.joint, "--speed-range", f"0:{args.rpm:g}"],
        args.repeats,
        source,
    )
    print(process_line("pinwind campbell", walls, cpus) + f"; {load_average()}")


if __name__ == "__main__":
    main()
