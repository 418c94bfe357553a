"""001's CART 600 kW gearbox on a rigid and on a flexible support (its tower mode at 7.3 Hz).

IFToMM 2018 (MBDyn) runs NREL's CART 600 kW turbine with its gearbox
(Table 1: a compound planetary stage, ring 93, planets 22/103, sun 29, and a 57/23 parallel
stage) at 270 and 600 kW, once with the tower as a rigid support and once flexible, and finds the
tower's vibration at 7.3 Hz in every bearing's vertical force (its Figs. 4–7), the orbits of the
shafts in their bearings changed and the bearing loads up by about 10 %. Here the same
comparison on ``models/cart600_gearbox.urdf`` (Table 1's gearbox, the same file the other
examples use):

- meshes compliant, 1e8 N/m and 1e4 N·s/m (Table 1), constant stiffness along the path;
- the carrier, sun, planet and output (``stage1_pinion``) bearings compliant and linear, radial
  stiffness 1e9 N/m and damping 1e4 N·s/m, no clearance;
- 001's induction generator (Table 1) as Krause's dq model (``--generator steady``: its
  equivalent circuit's steady-state torque–slip curve) on its own rotor, 10 kg·m² (assumed: 001
  gives none), joined to the output shaft by a torsional spring-damper, 1e5 N·m/rad and
  100 N·m·s/rad (assumed), for 001's "viscous deformable joint"; the rotor torque P / ω on the
  carrier, from the ground (the air), at the speed where the generator takes P;
- flexible: the housing on a bedplate that carries one vertical tower mode, modal mass 10 t,
  damping ratio 1 %, tuned so that the tower with the gearbox on it vibrates at 001's 7.3 Hz:
  f_tower = 7.3 Hz · √((m + M)/m), M the gearbox's and the generator rotor's mass (the mode
  of ``pinwind modes``).

Prints per power and bearing the vertical force's mean and RMS, rigid and flexible, the RMS's
change beside 001's ≈ 10 %, the orbit (the body's mean offset in its bearing and the amplitude
about it), and the strongest peak of the vertical force's PSD. ``--figures DIR`` writes the
orbits (001 Figs. 4–7 left) and the PSDs (their right-hand sides).

Differences from 001, and why:

- Bearings: 001 uses Gargiulo's semi-empirical roller law (load-dependent stiffness) whose
  inputs (roller count, length, diameter) Table 1 does not give; here a linear law with an
  assumed 1e9 N/m (a large cylindrical roller bearing's order of magnitude) and 1e4 N·s/m (001's
  mesh damping, assumed). A rolling-bearing law in pinwind can replace it in ``BEARINGS``.
- The tower: 001's is a beam of five three-node elements under a nacelle on a yaw hinge; here
  one modal mass-spring-damper at the gearbox housing, vertical only (001 shows the vertical
  forces), whose frequency with the gearbox on it is 001's 7.3 Hz; its modal mass (10 t) and
  damping (1 %) are assumed (001 gives neither). The nacelle, the low-speed shaft and the rotor
  are not modelled: the housing is the bedplate's only load besides the modal mass.
- Excitation and start: 001's turbine is driven by aerodynamic blades on a teetering hub; here
  a constant rotor torque. The run starts as the machine runs (``simulate``'s static start,
  issue 36): the bedplate sagged under the weight on the tower, (m + M) g / k, the bearings
  and meshes deflected under the torque, the generator's rotor at the output shaft's speed
  across its coupling (only the carrier's speed is given). So the loads are the power's from
  the first sample: the carrier's vertical bearing force is 17.89 kN at 270 kW and 19.38 kN at
  600 kW (+8.3 %, the tooth forces' share), on the rigid and on the flexible support alike,
  and nothing rings the tower: the flexible support changes the bearing loads by 0.0 %. 001's
  ≈ 10 % comes from what excites its tower (turbulence, the rotor), which this example does
  not model; the table shows it for scale, not as something to reproduce. (An earlier version
  released the bedplate from its unloaded shape at t = 0: the ≈ 10 % RMS rise it printed was
  that start-up swing, not the power or the tower.)
- Which numbers are inputs and which are results: the tower's 7.3 Hz is an input (its
  stiffness is tuned so that the tower with the gearbox on it has 001's frequency; ``pinwind
  modes`` shows it); it is not in the PSDs, since nothing excites it. The means, RMS, orbits
  and the PSD peaks of the table are results: each bearing's strongest peak is either the
  turning of the carrier (0.76 Hz) and the planets, whose weights and tooth forces turn in
  world axes (≈ 1.1 and 2.3 Hz), or one of the train's lightly damped modes on its meshes and
  bearings (≈ 114 and 123 Hz, near the 119 and 130 Hz, ζ ≈ 1 %, of ``pinwind modes``, which
  leave out the generator's law).
- The generator's rotor and coupling: 001 gives neither the rotor's inertia nor the viscous
  joint's values. Without a rotor (the dq machine directly on the output pinion, 0.019 kg·m²)
  the run grows an oscillation of the output speed, measured at 54.9 Hz, σ = +6.42 1/s
  (ζ = −1.86 %), the same at dt = 4e-5, 2e-5 and 1e-5 s and at ρ∞ = 1 and 0.6: physical, not
  the step's. The machine's linearisation about its operating slip (−0.09 % at 600 kW) says
  why: in the synchronous frame its stator flux has a lightly damped mode at the grid's 60 Hz
  (eigenvalues −6.1 ± 376.9j 1/s), and near it the torque's response to the shaft speed,
  Re(∂T/∂ω) at 55 Hz, is +20.7 N·m·s/rad, a negative damper (it damps, +136 N·m·s/rad, at
  10 Hz, and +3.8 at 100 Hz). The linearised drivetrain (``pinwind.modes.linearisation``)
  with the machine's four flux states gives that mode at 55.5 Hz, σ = +6.1 1/s, the run's
  within 5 %. A rotor inertia J_g moves the electromechanical mode away from 60 Hz: joined
  rigidly to the pinion (no damper) it is unstable below J_g ≈ 0.8 kg·m² (−0.34 % at 0.5) and
  stable above (+0.22 % at 1 kg·m², +1.33 % at 77 Hz with 10 kg·m²). With this example's rotor
  and coupling its modes are at 15.6 Hz (ζ = 2.6 %, the rotor on the machine's flux) and 57.8 Hz
  (10.9 %, the coupling), and the least damped mode below 500 Hz is a purely mechanical one
  (119 Hz, 0.92 %): the oscillation decays (``tests/test_examples.py``). The rotor is a solid
  cylinder of radius 0.25 m (320 kg) on an ideal joint on the housing, so its weight is on the
  tower too (001's generator sits in the nacelle on the tower).
- The generator's stator reacts on the gearbox housing (pinwind's generators act between the
  shaft and the housing); 001's on the nacelle. The support here has no torque arms (no roll),
  so this does not change the housing's motion.
- Gravity along −y, shafts along z (the model file's frame).

    python examples/cart600_support.py --duration 4 --figures figures/cart600_support
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table
from scipy.optimize import brentq

import pinwind
from pinwind.analysis.spectrum import power_spectral_density, spectral_peaks
from pinwind.dynamics.elements import induction_torque
from pinwind.dynamics.ratios import train_speeds
from pinwind.loads.generator import InductionMachine
from pinwind.model.compliance import MeshCompliance
from pinwind.model.gearbox import Gearbox, loads

MODEL = Path(__file__).resolve().parent.parent / "models" / "cart600_gearbox.urdf"
#: 001 Table 1's mesh.
MESH = MeshCompliance(stiffness=1e8, damping=1e4, variation="constant")
#: The compliant bearings (assumed linear law, see the docstring).
BEARINGS = ("carrier", "sun", "planet1", "planet2", "planet3", "stage1_pinion")
BEARING_STIFFNESS = 1e9  # N/m
BEARING_DAMPING = 1e4  # N·s/m
#: The bearings whose orbits and forces 001 shows (Figs. 4–7): carrier, planet, sun, output.
SHOWN = ("carrier", "planet1", "sun", "stage1_pinion")
#: 001 §4: the frequency of the structure's vibration in the bearing forces [Hz].
TOWER_FREQUENCY = 7.3
TOWER_MASS = 10e3  # kg, assumed
TOWER_DAMPING = 0.01  # assumed
POWERS = (270e3, 600e3)  # W, 001 §4
#: 001 §5: "an increase of approximately 10 % of the load on the bearings".
PAPER_LOAD_CHANGE = 10.0  # %
#: The generator's rotor (001 gives no inertia; assumed: a 4-pole 600 kW induction machine's
#: rotor is of the order of 10 kg·m²) on its own joint, coaxial with the output shaft beyond it,
#: a solid cylinder of radius GENERATOR_RADIUS: mass 2 J / r².
GENERATOR_INERTIA = 10.0  # kg·m², assumed
GENERATOR_RADIUS = 0.25  # m, assumed
#: 001's "viscous deformable joint" between the output shaft and the generator, as a torsional
#: spring-damper (001 gives no values; assumed): 1e5 N·m/rad twists 1.8° under the 3.2 kN·m of
#: 600 kW, a flexible coupling's order, and 100 N·m·s/rad damps the coupling's mode by ≈ 11 %.
COUPLING_STIFFNESS = 1e5  # N·m/rad
COUPLING_DAMPING = 100.0  # N·m·s/rad
#: Time step [s]: 17 steps per period of the highest mode (≈ 1460 Hz, ``pinwind modes``).
DT = 4e-5
#: Kept samples: every 10th (2.5 kHz, far above the 7.3 Hz and the meshes' ≈ 70 Hz).
KEEP = 10
VERTICAL = 1  # world y: gravity is along −y


def model(*, flexible: bool) -> Gearbox:
    """The CART 600 gearbox with compliant bearings, on a rigid or a flexible support."""
    text = MODEL.read_text().replace("</robot>", generator_rotor() + "</robot>")
    extra = "".join(
        f'<bearing joint="{j}" radial_stiffness="{BEARING_STIFFNESS!r}" '
        f'radial_damping="{BEARING_DAMPING!r}"/>'
        for j in BEARINGS
    )
    extra += (
        f'<torsional_spring name="coupling" joint1="stage1_pinion" joint2="generator" '
        f'stiffness="{COUPLING_STIFFNESS!r}" damping="{COUPLING_DAMPING!r}"/>'
    )
    if flexible:
        mass = gearbox_mass(loads(text))
        tower_alone = TOWER_FREQUENCY * math.sqrt((TOWER_MASS + mass) / TOWER_MASS)
        extra += (
            f'<support housing="housing"><tower_mode direction="vertical" '
            f'frequency_hz="{tower_alone!r}" mass="{TOWER_MASS!r}" '
            f'damping_ratio="{TOWER_DAMPING!r}"/></support>'
        )
    head = '<gearbox gravity="0 -9.81 0">'
    return loads(text.replace(head, head + extra), path=str(MODEL))


def generator_rotor() -> str:
    """The generator's rotor: a link and its joint on the housing, on the output shaft's axis."""
    mass = 2.0 * GENERATOR_INERTIA / GENERATOR_RADIUS**2
    transverse = GENERATOR_INERTIA / 2.0  # a thin disc's: its tilt is held by an ideal joint
    return (
        f'<link name="generator"><inertial><origin xyz="0 0 0" rpy="0 0 0"/>'
        f'<mass value="{mass!r}"/><inertia ixx="{transverse!r}" ixy="0" ixz="0" '
        f'iyy="{transverse!r}" iyz="0" izz="{GENERATOR_INERTIA!r}"/></inertial></link>'
        f'<joint name="generator" type="continuous"><parent link="housing"/>'
        f'<child link="generator"/><origin xyz="0 0.22 0.9" rpy="0 0 0"/>'
        f'<axis xyz="0 0 1"/></joint>'
    )


def gearbox_mass(gearbox: Gearbox) -> float:
    """Every body's mass [kg] (the support's modal mass excluded)."""
    tower = [gearbox.model.getJointId(n) for n in gearbox.support_slides]
    return sum(
        gearbox.model.inertias[j].mass for j in range(1, gearbox.model.njoints) if j not in tower
    )


def operating_point(
    gearbox: Gearbox, machine: InductionMachine, power: float
) -> tuple[float, float]:
    """(carrier speed [rad/s], carrier torque [N·m]), signed, where the generator takes ``power``.

    The output turns positively (generating); the carrier the other way (the ratio is negative).
    """
    speed = brentq(
        lambda w: induction_torque(machine, w) * w - power,
        machine.sync_speed,
        1.05 * machine.sync_speed,
    )
    carrier = speed / output_ratio(gearbox)
    return carrier, power / carrier


def output_ratio(gearbox: Gearbox) -> float:
    """The output shaft's speed per carrier speed (negative: they turn opposite ways)."""
    speeds = train_speeds(gearbox, {"carrier": 1.0})
    return float(speeds[gearbox.v_index("stage1_pinion")])


def run(
    gearbox: Gearbox, power: float, *, duration: float, dt: float, dq: bool = False
) -> pinwind.Result:
    """One run at ``power`` [W], started as the machine runs (the tower sagged, module docstring).

    ``dq``: Krause's dq machine started at its steady state, else the steady-state curve; on
    the generator's rotor, which starts at the output shaft's speed (the carrier's speed
    carries across the gears and the coupling).
    """
    machine = InductionMachine.cart600(dynamic=dq, steady_start=dq)
    speed, torque = operating_point(gearbox, machine, power)
    return pinwind.simulate(
        gearbox,
        duration=duration,
        dt=dt,
        torques={"carrier": torque},
        generators={"generator": machine},
        initial_speeds={"carrier": speed},
        meshes={"all": MESH},
        keep=KEEP,
        statistics=False,
    )


def vertical_force(res: pinwind.Result, bearing: str) -> np.ndarray:
    """The bearing's vertical force on its body [N] (world y)."""
    return res.bearing(bearing).force[:, VERTICAL]


def orbit(res: pinwind.Result, bearing: str) -> tuple[float, float]:
    """(|mean offset|, max distance from it) of the body in its bearing [m], radial plane."""
    xy = res.bearing(bearing).displacement[:, :2]
    centre = xy.mean(axis=0)
    return float(np.linalg.norm(centre)), float(np.linalg.norm(xy - centre, axis=1).max())


def psd(res: pinwind.Result, bearing: str) -> tuple[np.ndarray, np.ndarray]:
    """(frequency [Hz], PSD [N²/Hz]) of the vertical force, Welch with half-run segments."""
    rate = 1.0 / float(res.time[1] - res.time[0])
    return power_spectral_density(
        vertical_force(res, bearing), sample_rate=rate, segment_samples=len(res.time) // 2
    )


def main(argv: list[str] | None = None) -> dict[str, dict[str, pinwind.Result]]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=2.0, help="simulated time [s]")
    parser.add_argument("--dt", type=float, default=DT, help="time step [s]")
    parser.add_argument("--figures", type=Path, help="write the orbit and PSD figures here")
    parser.add_argument(
        "--generator",
        choices=("steady", "dq"),
        default="dq",
        help="Krause's dq model (001's), or the machine's steady-state curve",
    )
    args = parser.parse_args(argv)

    gearboxes = {"rigid": model(flexible=False), "flexible": model(flexible=True)}
    results: dict[str, dict[str, pinwind.Result]] = {}
    started = time.perf_counter()
    for power in POWERS:
        key = f"{power / 1e3:g} kW"
        results[key] = {
            name: run(gb, power, duration=args.duration, dt=args.dt, dq=args.generator == "dq")
            for name, gb in gearboxes.items()
        }
    wall = time.perf_counter() - started

    console = Console(width=150)
    for key, pair in results.items():
        table = Table(
            title=f"{key}: vertical bearing force [kN], orbit [µm], PSD peak [Hz]; "
            f"001: ≈ {PAPER_LOAD_CHANGE:g} % more bearing load with the flexible tower"
        )
        for col in ("bearing", "mean rigid", "mean flex", "RMS rigid", "RMS flex", "RMS change",
                    "orbit rigid", "orbit flex", "PSD peak flex"):  # fmt: skip
            table.add_column(col, justify="left" if col == "bearing" else "right")
        for bearing in SHOWN:
            rigid, flex = (vertical_force(pair[n], bearing) for n in ("rigid", "flexible"))
            rms = [float(np.sqrt(np.mean(f**2))) for f in (rigid, flex)]
            orbits = [orbit(pair[n], bearing) for n in ("rigid", "flexible")]
            peaks = spectral_peaks(*psd(pair["flexible"], bearing), count=1)
            table.add_row(
                bearing,
                f"{rigid.mean() / 1e3:.2f}",
                f"{flex.mean() / 1e3:.2f}",
                f"{rms[0] / 1e3:.2f}",
                f"{rms[1] / 1e3:.2f}",
                f"{100 * (rms[1] / rms[0] - 1):+.1f} %",
                " ± ".join(f"{x * 1e6:.2f}" for x in orbits[0]),
                " ± ".join(f"{x * 1e6:.2f}" for x in orbits[1]),
                f"{peaks[0].frequency:.2f}" if peaks else "-",
            )
        console.print(table)
    runs = len(POWERS) * len(gearboxes)
    console.print(
        f"{runs} runs of {args.duration:g} s at dt = {args.dt:g} s in {wall:.1f} s wall; the "
        f"tower mode with the gearbox on it at {TOWER_FREQUENCY:g} Hz (f_tower alone "
        f"{TOWER_FREQUENCY * math.sqrt(1 + gearbox_mass(gearboxes['rigid']) / TOWER_MASS):.3f}"
        f" Hz, m = {TOWER_MASS:g} kg, M = {gearbox_mass(gearboxes['rigid']):.0f} kg); PSD "
        f"resolution {2.0 / args.duration:.2f} Hz",
        highlight=False,
    )
    if args.figures:
        for path in figures(results, args.figures):
            console.print(f"wrote {path}")
    return results


def figures(results: dict[str, dict[str, pinwind.Result]], folder: Path) -> list[Path]:
    """The orbits (001 Figs. 4–7, left) and the vertical forces' PSDs (right), one file each."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    folder.mkdir(parents=True, exist_ok=True)
    out = []
    for what in ("orbits", "psd"):
        fig, axes = plt.subplots(2, 2, figsize=(11, 8), layout="constrained")
        for ax, bearing in zip(axes.flat, SHOWN, strict=True):
            for key, pair in results.items():
                for name, res in pair.items():
                    style = "-" if name == "flexible" else "--"
                    label = f"{key} {name}"
                    if what == "orbits":
                        xy = res.bearing(bearing).displacement[:, :2] * 1e6
                        ax.plot(xy[:, 0], xy[:, 1], style, lw=0.7, label=label)
                        ax.set_xlabel("x [µm]")
                        ax.set_ylabel("y [µm]")
                        ax.set_aspect("equal", adjustable="datalim")
                    else:
                        freq, density = psd(res, bearing)
                        ax.semilogy(freq, density, style, lw=0.8, label=label)
                        ax.set_xlim(0.0, 50.0)
                        ax.set_xlabel("frequency [Hz]")
                        ax.set_ylabel("PSD of the vertical force [N²/Hz]")
            ax.set_title(bearing)
        # One legend for the four panels (the same runs in each), beside them: inside a panel
        # it would hide the orbits; the constrained layout makes room for it.
        handles, labels = axes.flat[0].get_legend_handles_labels()
        fig.legend(handles, labels, fontsize=7, loc="outside right upper")
        path = folder / f"cart600_support_{what}.png"
        fig.savefig(path, dpi=120)
        plt.close(fig)
        out.append(path)
    return out


if __name__ == "__main__":
    main()
