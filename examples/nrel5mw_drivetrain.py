"""The NREL 5 MW drivetrain in 600 s of turbulent wind: bearing and tooth loads, 20-year ranking.

Runs ``scenarios/nrel5mw_turbulent.toml`` (its comment gives every choice and its source): the
Nejad et al. 2016 reference gearbox (13 compliant meshes, 16 rolling bearings as rows of their
shafts' compliant bearings) driven by the NREL 5 MW rotor (ROSCO's C_p and C_t tables) in 13 m/s
Kaimal wind (IEC 61400-1 class B turbulence, 16.5 %, seed 1, averaged over the 126 m disc),
held at 12.1 rpm by Jonkman's gain-scheduled PI blade-pitch controller, braked by Jonkman's
generator law with region 3 at constant torque (43.09 kN·m on the generator shaft, ROSCO's
default), with the rotor's thrust, weight (110 t, 5° shaft tilt) and wind-shear moment on the
main shaft's rotor end.

What the case is: above rated wind (11.4 m/s), region 3 of the power curve, where the rotor is
held at rated speed by pitching its blades (3-9° over the first 60 s) and the generator at rated
torque, with lulls into region 2½. What it leaves out: the generator's torque-rate limit and
speed filter, the pitch actuator's dynamics beyond its 8°/s limit, the rotor's 3P ripple and
imbalance, blade, tower and nacelle motion (the scenario's comment).

Printed:

1. the main shaft's rolling bearings (INP-A, INP-B and the carrier's PLC-A, PLC-B, rows of the
   `lss` bearing) and the planets' (PL-A/B, IMS-PL-A/B): radial and axial force and the row's own
   tilting moment, mean and max over the kept samples after the start;
2. every mesh's normal force (mean, max) and its largest single-tooth force, stage by stage;
3. a 20-year damage ranking of every gear (flank and root) and every bearing row (ISO 281 life
   consumption), as a table and ``vulnerability_map.png`` (like Nejad et al. 2016's
   vulnerability map).

The 20-year extrapolation (`FATIGUE`): the run is the one case of a fatigue set (``pinwind.life``:
its cycles and bearing sums, `set_damage`, `set_bearing_lives`) whose only wind bin is 12-14 m/s
of an IEC 61400-1 class I site (annual mean 10 m/s at hub height, Rayleigh: Weibull A =
10 / Γ(1.5) = 11.284 m/s, k = 2; ASSUMED, Nejad et al. 2016's site is not in the public data),
class B turbulence (the normal turbulence model at the bin's 13 m/s: 16.5 %, the scenario's),
20 years of 8760 h at availability 1: 18 958 h, 11 % of the life. The 600 s stand for those
hours; the other bins' damage is not in the numbers, so the ranking is that of this bin's share
of the life. Gears are
rated with ISO 6336's curves of 18CrNiMo7-6 (``iso 6336`` variant: σ_Hlim, σ_Flim with the
standard's line beyond the knee), bearings with ISO 281 L10 at each row's rating C (assumed by
the data's source, models/README.md). The planetary stages' spur teeth are rated along the path
of contact, tooth pair by tooth pair; stage 3 is helical (β = 10°, b = 360 mm, m_n = 14 mm:
overlap ratio ε_β = b sin β/(π m_n) = 1.42), so its teeth are rated as ISO 6336-2/-3 rate a
helical pair, from the whole mesh force, one cycle per tooth pass (`pinwind.life.tooth_damage`).

The case is reduced as it runs and the printout's statistics folded as it runs, over every
sample at the set's 1250 Hz, so the memory does not grow with ``--duration``; the returned
Result keeps ``--result-rate`` samples per second (10 Hz), a look at the run.

    python examples/nrel5mw_drivetrain.py [--duration 600] [--dt 1e-4] [--out nrel5mw_drivetrain/]
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np
from rich.console import Console
from rich.markup import escape
from rich.table import Table

import pinwind
from pinwind.analysis.bearing_rows import RowLoad, row_loads
from pinwind.errors import PinwindWarning
from pinwind.life.damage_ranking import RankedItem, damage_ranking
from pinwind.life.life_figures import plot_damage_ranking
from pinwind.life.set_bearing_life import set_bearing_lives
from pinwind.life.set_damage import set_damage
from pinwind.model.gearbox import load
from pinwind.runs.case_runner import CASE_SERIES, case_reducer, case_scenario, save_reduced_case
from pinwind.runs.fatigue_set_file import load_fatigue_set
from pinwind.runs.scenario import run

ROOT = Path(__file__).resolve().parent.parent
SCENARIO = ROOT / "scenarios" / "nrel5mw_turbulent.toml"
#: Weibull scale of an IEC 61400-1 class I site: annual mean 10 m/s, Rayleigh (k = 2) [m/s].
CLASS_I_SCALE = 10.0 / math.gamma(1.5)
#: The example's fatigue set (a ``[fatigue]`` table, pinwind.runs.fatigue_set_file): the
#: scenario's case as the one wind bin, 12-14 m/s of a class I site over 20 years (docstring).
FATIGUE: dict[str, Any] = {
    "duration": 600.0,
    "skip_start": 5.0,  # s: the start (static deflection, then the wind's first seconds)
    # Hz: the kept samples the tooth histories are read at, every 8th step at dt = 1e-4 s:
    # 2.7 samples per stage-3 mesh period (465 Hz at 12.1 rpm), about 8 per tooth engagement
    # (ε_γ = 2.88 base pitches); the teeth are tracked while the roll per sample stays below
    # half a base pitch (`tooth_damage.entering_teeth`, refused beyond it), up to 16 rpm of the
    # rotor, 30 % above rated (at 1 kHz: 13 rpm, within the gusts' reach at 13 m/s);
    # every series of 600 s at 1 kHz took 5.8 GB (benchmarks/README.md, with the figures at
    # 5 kHz against 1 kHz on a short window); the case is reduced as it runs (its memory does
    # not grow with the duration: docs/fatigue.md).
    "sample_rate": 1250.0,
    "seeds": [1],
    "turbulence": ["B"],
    "wind": "disc",
    "hub_height": 90.0,
    "site": {
        "scale": CLASS_I_SCALE,
        "shape": 2.0,
        "edges": [12.0, 14.0],
        "design_life_years": 20.0,
    },
    "sn_curve": {"preset": "iso6336"},
    # Every gear: the planetary stages' and the helical stage 3's wheel and pinion.
    "gears": [
        *(
            f"stage{s}_{g}"
            for s in (1, 2)
            for g in ("sun", "ring", "planet1", "planet2", "planet3")
        ),
        "stage3_wheel",
        "stage3_pinion",
    ],
}
#: Main-shaft rows (the `lss` bearing) and the planets' bearings whose rows are printed.
MAIN_SHAFT = "lss"
PLANET_PREFIXES = ("stage1_planet", "stage2_planet")


def fatigue_set(*, out: Path, duration: float, dt: float, sample_rate: float) -> Any:
    """The example's one-case fatigue set, its cases written into ``out``."""
    table = {
        **FATIGUE,
        "out": str(out.resolve()),
        "duration": duration,
        "skip_start": min(FATIGUE["skip_start"], duration / 4),
        "sample_rate": sample_rate,
    }
    fset = load_fatigue_set(SCENARIO, fatigue=table)
    return dataclasses.replace(fset, values={**fset.values, "dt": dt})


#: The series the run's Result keeps, at `RESULT_RATE` (its log has them all, at the log rate):
#: the fatigue reduction's, and the generator's and the rotor's the test reads.
KEPT_SERIES = (
    *CASE_SERIES, "generator_torque", "rotor_tip_speed_ratio", "rotor_thrust",
    "rotor_thrust_coefficient", "rotor_power", "rotor_wind_speed", "rotor_pitch",
)  # fmt: skip
#: Samples per second the returned Result keeps [Hz]: a look at the run. The printout and the
#: reduction read every sample at the set's sample rate as the run goes, so that the memory
#: does not grow with the duration (600 s of these series at 1250 Hz took 2.2 GB).
RESULT_RATE = 10.0


class Printout:
    """The printout's statistics over the kept samples from ``skip_start`` on, block by block.

    Each quantity's mean, min and max over the blocks a run hands on
    (``pinwind.runs.kept_blocks``): the main shaft's and the planets' rows' radial force, axial
    force and own tilting moment, every mesh's normal and single-tooth force, the rotor's speed
    [rpm] and pitch [°] and the generator's power.
    """

    def __init__(self, gearbox: Any) -> None:
        self.gearbox = gearbox
        self.folded: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray, int]] = {}
        self.rows: list[tuple[str, str]] = []
        self.meshes: list[str] = []

    def add(self, block: pinwind.Result) -> None:
        rows = bearing_rows(block, self.gearbox)
        self.rows = [(row.bearing, row.name) for row in rows]
        self.meshes = list(block.mesh_names)
        self._fold("radial", np.column_stack([row.radial_magnitude for row in rows]))
        self._fold("axial", np.column_stack([np.abs(row.axial) for row in rows]))
        self._fold("tilt", np.column_stack([np.hypot(*row.tilting.T) for row in rows]))
        self._fold("normal", block.mesh_normal)
        self._fold("single", block.mesh_single_tooth_force)
        self._fold("rotor", block.joint("rotor").speed[:, None] * 60 / (2 * math.pi))
        self._fold("pitch", np.degrees(block.rotor("rotor").pitch)[:, None])
        torque = block.generator("generator").torque * block.joint("generator").speed
        self._fold("power", np.abs(torque)[:, None])

    def _fold(self, name: str, values: np.ndarray) -> None:
        columns = values.shape[1]
        total, low, high, count = self.folded.get(
            name, (np.zeros(columns), np.full(columns, np.inf), np.full(columns, -np.inf), 0)
        )
        self.folded[name] = (
            total + values.sum(axis=0), np.minimum(low, values.min(axis=0)),
            np.maximum(high, values.max(axis=0)), count + len(values),
        )  # fmt: skip

    def mean(self, name: str) -> np.ndarray:
        total, _, _, count = self.folded[name]
        return total / count

    def low(self, name: str) -> np.ndarray:
        return self.folded[name][1]

    def high(self, name: str) -> np.ndarray:
        return self.folded[name][2]


def simulate(
    fset: Any, *, progress: bool = True, result_rate: float = RESULT_RATE
) -> tuple[pinwind.Result, Any, float, Printout]:
    """Run the set's case with a progress bar, reduced as it runs, its reduction saved.

    (result, gearbox, wall, printout): the Result at ``result_rate`` [Hz]; the printout's
    statistics, as the case's reduction, from every sample at the set's sample rate. The
    reduction is not returned: the set's rating reads it from its file, and two copies of its
    cycles (25 700 a simulated second, 20 bytes each) would be the memory that grows with the
    duration.
    """
    (case,) = fset.cases()
    scenario = case_scenario(case, fset)
    gearbox = load(scenario.model_path())
    fset.out.mkdir(parents=True, exist_ok=True)
    printout = Printout(gearbox)
    extra = ("generator_torque", "rotor_pitch")
    reduction, observer = case_reducer(case, fset, gearbox, printout, series=extra)
    keep = max(1, round(1.0 / (result_rate * fset.values["dt"])))
    started = time.perf_counter()
    with warnings.catch_warnings():
        # dt = 1e-4 s does not resolve the highest mesh mode's period (StepTooCoarse): the
        # single-tooth forces converge anyway (benchmarks/README.md, nrel5mw_step.py).
        warnings.simplefilter("ignore", PinwindWarning)
        result = run(scenario, gearbox=gearbox, progress=progress, statistics=False,
                     keep=keep, keep_series=KEPT_SERIES, observer=observer)  # fmt: skip
    wall = time.perf_counter() - started
    save_reduced_case(case, fset, reduction, wall_time=wall)
    return result, gearbox, wall, printout


def bearing_rows(result: pinwind.Result, gearbox: Any) -> list[RowLoad]:
    """The main shaft's and the planets' rows."""
    return [
        row
        for row in row_loads(result, gearbox)
        if row.bearing == MAIN_SHAFT or row.bearing.startswith(PLANET_PREFIXES)
    ]


def row_table(printout: Printout) -> Table:
    table = Table(title="Main-shaft and planet bearing rows (on the shaft, its bearing's frame)")
    for col in ("bearing", "row", "radial mean", "radial max", "axial mean", "axial max",
                "tilt mean", "tilt max"):  # fmt: skip
        table.add_column(col, justify="left" if col in ("bearing", "row") else "right")
    for i, (bearing, name) in enumerate(printout.rows):
        radial, axial, tilt = (
            (printout.mean(q)[i] / 1e3, printout.high(q)[i] / 1e3)
            for q in ("radial", "axial", "tilt")
        )
        table.add_row(
            bearing, name,
            f"{radial[0]:.1f}", f"{radial[1]:.1f}", f"{axial[0]:.1f}",
            f"{axial[1]:.1f}", f"{tilt[0]:.2f}", f"{tilt[1]:.2f}",
        )  # fmt: skip
    table.caption = escape("forces [kN], the row's own tilting moment [kN·m]")
    return table


def tooth_table(printout: Printout) -> Table:
    table = Table(title=escape("Tooth forces per mesh, stage by stage [kN]"))
    for col in ("stage", "mesh", "normal mean", "normal max", "1 tooth max"):
        table.add_column(col, justify="left" if col in ("stage", "mesh") else "right")
    for i, name in enumerate(printout.meshes):
        table.add_row(
            name.split("_")[0], name, f"{printout.mean('normal')[i] / 1e3:.1f}",
            f"{printout.high('normal')[i] / 1e3:.1f}", f"{printout.high('single')[i] / 1e3:.1f}",
        )  # fmt: skip
    return table


def ranking_table(items: list[RankedItem], hours: float) -> Table:
    table = Table(title=f"Damage ranking over 20 years ({hours:.0f} h in this bin)")
    for col in ("rank", "item", "kind", "damage", "from"):
        table.add_column(col, justify="right" if col in ("rank", "damage") else "left")
    for rank, item in enumerate(items, start=1):
        table.add_row(str(rank), item.name, item.kind, f"{item.damage:.3e}", item.detail)
    return table


def main(argv: list[str] | None = None) -> dict[str, Any]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=600.0, help="simulated time [s]")
    parser.add_argument("--dt", type=float, default=1e-4, help="time step [s]")
    parser.add_argument(
        "--out", type=Path, default=Path("nrel5mw_drivetrain"), help="folder for log and figure"
    )
    parser.add_argument(
        "--sample-rate", type=float, default=FATIGUE["sample_rate"],
        help="kept samples per second, the tooth histories' rate [Hz]",
    )  # fmt: skip
    parser.add_argument(
        "--result-rate", type=float, default=RESULT_RATE,
        help="samples per second the returned Result keeps [Hz] (its memory grows with it)",
    )  # fmt: skip
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    args = parser.parse_args(argv)

    fset = fatigue_set(
        out=args.out, duration=args.duration, dt=args.dt, sample_rate=args.sample_rate
    )
    result, gearbox, wall, printout = simulate(
        fset, progress=not args.no_progress, result_rate=args.result_rate
    )
    damage = set_damage(fset)
    lives = set_bearing_lives(fset)
    items = damage_ranking(damage, lives, variant="iso 6336")

    console = Console(width=140)
    console.print(
        f"{args.duration:g} s at dt = {args.dt:g} s in {wall:.0f} s wall "
        f"({wall / args.duration:.2f} s per simulated second); rotor "
        f"{printout.low('rotor')[0]:.2f}-{printout.high('rotor')[0]:.2f} rpm, pitch "
        f"{printout.low('pitch')[0]:.1f}-{printout.high('pitch')[0]:.1f}°, generator power "
        f"{printout.mean('power')[0] / 1e6:.2f} MW mean, "
        f"{printout.high('power')[0] / 1e6:.2f} MW max; statistics from t = "
        f"{fset.skip_start:g} s over "
        f"the kept samples ({fset.sample_rate:g} Hz)",
        highlight=False,
    )
    console.print(row_table(printout))
    console.print(tooth_table(printout))
    console.print(ranking_table(items, float(fset.site.total_hours)))
    figure = plot_damage_ranking(
        items,
        args.out / "vulnerability_map.png",
        title=f"NREL 5 MW gearbox, 20 years: the 12-14 m/s bin of a class I site "
        f"({fset.site.total_hours:.0f} h) from {args.duration:g} s at 13 m/s, class B",
    )
    console.print(f"figure: {figure}")
    return {"result": result, "gearbox": gearbox, "fatigue": fset, "damage": damage,
            "lives": lives, "ranking": items, "figure": figure, "wall": wall,
            "printout": printout}  # fmt: skip


if __name__ == "__main__":
    main()
