"""PNG figures of a mesh's loaded static transmission error (``pinwind te --figures DIR``).

Three figures, each with its caption under the axes (`pinwind.io.figure_layout`): the TE over one
mesh cycle at a few of the torques, the peak-to-peak TE against the torque (the "Harris map"),
and the amplitudes of the first mesh harmonics against the torque. TE in µm along the line of
action, torques in kN·m on the gear the command names.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from pinwind.gears.transmission_error import TransmissionError
from pinwind.io.figure_layout import save_with_caption


def plot_transmission_error(
    maps: Sequence[TransmissionError],
    torques: Sequence[float] | np.ndarray,
    folder: Path,
    *,
    about: str,
    harmonics: int = 3,
) -> list[Path]:
    """Writes ``te_cycle.png``, ``te_map.png`` and ``te_harmonics.png`` into ``folder``.

    Args:
        maps: the TE at each torque, in the order of ``torques``.
        torques: the torques [N·m].
        about: the mesh, the gear the torque is on, the modifications: for the captions.
        harmonics: mesh harmonics drawn.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    kn_m = np.asarray(torques, dtype=float) / 1e3
    written = []

    fig, ax = plt.subplots(figsize=(7.5, 4.2), layout="constrained")
    shown = sorted({0, len(maps) // 2, len(maps) - 1})
    for i in shown:
        te = maps[i]
        cycle = te.roll / te.base_pitch
        ax.plot(cycle, te.approach * 1e6, label=f"{kn_m[i]:.4g} kN·m")
    ax.set_xlabel("roll over one mesh cycle [base pitches]")
    ax.set_ylabel("static TE along the line of action [µm]")
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    ax.grid(alpha=0.3)
    written.append(
        save_with_caption(
            fig,
            folder / "te_cycle.png",
            caption=f"Loaded static transmission error over one mesh cycle, {about}.\n"
            "The tooth pairs in contact as springs behind the gaps their flank modifications "
            "leave (ISO 6336-1 stiffness).",
        )
    )

    fig, ax = plt.subplots(figsize=(7.5, 4.2), layout="constrained")
    ax.plot(kn_m, [te.peak_to_peak * 1e6 for te in maps], "o-")
    ax.set_xlabel("torque [kN·m]")
    ax.set_ylabel("peak-to-peak static TE [µm]")
    ax.set_ylim(bottom=0.0)
    ax.grid(alpha=0.3)
    written.append(
        save_with_caption(
            fig,
            folder / "te_map.png",
            caption=f"Peak-to-peak static TE against torque (the Harris map), {about}.\n"
            "A tip relief flattens the TE at its design load: the minimum of the V.",
        )
    )

    fig, ax = plt.subplots(figsize=(7.5, 4.2), layout="constrained")
    amplitudes = np.array([te.harmonics(harmonics) for te in maps]) * 1e6
    for h in range(harmonics):
        ax.plot(kn_m, amplitudes[:, h], "o-", label=f"{h + 1} × mesh frequency")
    ax.set_xlabel("torque [kN·m]")
    ax.set_ylabel("TE harmonic amplitude [µm]")
    ax.set_ylim(bottom=0.0)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    ax.grid(alpha=0.3)
    written.append(
        save_with_caption(
            fig,
            folder / "te_harmonics.png",
            caption=f"Mesh-frequency harmonics of the static TE against torque, {about}.\n"
            "Amplitudes of the Fourier series over one mesh cycle.",
        )
    )
    return written
