"""Load sharing between the planets of a stage: the mesh load factor K_γ (IEC 61400-4).

A gear that meshes with two or more others (a sun with its planets, a ring with its planets) shares
its load between those meshes. With perfect parts every planet carries the same; position errors
of the planet pins and the compliance of the meshes make the shares unequal. IEC 61400-4 rates
the stage with the mesh load factor

    K_γ = max_i F_i / mean_i F_i

over the planets i, taken here at every sample from the tooth normal forces, and over a run as
its largest value while the stage carries load.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pinwind.dynamics.result import Result
from pinwind.model.gearbox import Gearbox

#: Samples whose mean planet load is below this fraction of the run's largest mean are left out
#: of K_γ (a stage at rest shares nothing).
LOADED_FRACTION = 0.05


@dataclass(frozen=True)
class LoadSharing:
    """How the meshes of one central gear share its load over a run.

    Attributes:
        gear: the central gear (sun or ring).
        meshes: its meshes with the planets, in file order.
        share: (n, planets) each mesh's normal force over the mean of them.
        factor: (n,) K_γ at each sample (NaN where the stage carries no load).
    """

    gear: str
    meshes: list[str]
    share: np.ndarray
    factor: np.ndarray

    @property
    def factor_max(self) -> float:
        """K_γ of the run: the largest per-sample value while the stage is loaded."""
        return float(np.nanmax(self.factor)) if np.any(np.isfinite(self.factor)) else np.nan

    @property
    def mean_share(self) -> np.ndarray:
        """(planets,) each mesh's share averaged over the loaded samples."""
        loaded = np.isfinite(self.factor)
        return (
            self.share[loaded].mean(axis=0) if loaded.any() else np.full(len(self.meshes), np.nan)
        )


def load_sharing(
    result: Result, gearbox: Gearbox, *, skip_start: float | None = None
) -> list[LoadSharing]:
    """K_γ and the shares of every gear that meshes with two or more gears of equal size.

    Args:
        result: a run of ``gearbox``.
        gearbox: the model (for which meshes share a gear).
        skip_start: samples before this time [s] count as not loaded (NaN): a start-up span;
            default the run's ``metadata["statistics_from_s"]``, else none.
    """
    if skip_start is None:
        skip_start = float(result.metadata.get("statistics_from_s", 0.0))
    out = []
    for gear in gearbox.gears:
        meshes = [m for m in gearbox.meshes if gear in (m.gear_a.name, m.gear_b.name)]
        # Planets are the other gears; only gears of one size share a load equally.
        others = {(m.gear_b if m.gear_a.name == gear else m.gear_a).spec.teeth for m in meshes}
        if len(meshes) < 2 or len(others) != 1:
            continue
        index = [result.mesh_names.index(m.name) for m in meshes]
        force = result.mesh_normal[:, index]
        mean = force.mean(axis=1)
        after = result.time >= skip_start
        largest = float(mean[after].max(initial=0.0))
        loaded = after & (mean > LOADED_FRACTION * max(largest, 1e-300))
        share = np.full_like(force, np.nan)
        share[loaded] = force[loaded] / mean[loaded, None]
        factor = np.where(loaded, np.nanmax(np.where(loaded[:, None], share, 0.0), axis=1), np.nan)
        out.append(LoadSharing(gear, [m.name for m in meshes], share, factor))
    return out
