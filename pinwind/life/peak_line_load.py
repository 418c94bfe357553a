"""The tooth stresses at the peak line load across the face: a run's K_Hβ(t) in the life code.

The life code rates a tooth pair's stress from its force spread evenly over the face width b
(`pinwind.life.contact_stress`, `pinwind.life.root_stress`: ISO's K_Hβ = K_Fβ = 1). A compliant
spur mesh cut into slices computes how the line load actually runs across the face, sample by
sample: ``mesh_face_load_factor`` K_Hβ(t) = w_max / w_m, the peak line load over the mean
(ISO 6336-1 §7; docs/flank_modifications.md "Sliced meshes"). Rated at the peak line load:

- the flank's Hertz contact, a line contact of load per unit length w = F/b, sees
  w_max = K_Hβ F/b: the contact stress of the force K_Hβ F on the same length (Jørgensen 2014
  eqs. 20-22; p_max ∝ √w);
- the root, whose stress spreads across the face more than the flank's, takes ISO 6336-1's
  K_Fβ = K_Hβ^N_F (`pinwind.gears.rating_iso.root_face_load_exponent`) on the force.

`force_factor` gives that factor per sample; the stress functions take the force times it.
The series is 0 at a sample where the mesh carries nothing (then the force is 0 too): such a
sample's factor is 1. `run_force_factor` reads it from a run, refusing a mesh the run did not
cut into slices (its series is 1 by construction, not by computation); the tooth histories
take it with ``face_load="run"`` (`FACE_LOADS`, `pinwind.life.tooth_damage.GearTeeth`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from pinwind.dynamics.compliant import unsliced_mesh
from pinwind.errors import FactorNotInRun, InputError
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.rating_iso import root_face_load_exponent

if TYPE_CHECKING:
    from pinwind.dynamics.result import Result

#: How the tooth histories spread a pair's force across the face: evenly (ISO's K_Hβ = 1), or
#: at the run's peak line load (``mesh_face_load_factor``, module docstring).
FACE_LOADS = ("uniform", "run")

#: The stresses a face load factor applies to, and how (module docstring).
STRESSES = ("contact", "root")


def force_factor(pair: GearPair, face_load_factor: npt.ArrayLike, *, stress: str) -> np.ndarray:
    """The factor on a tooth pair's force that rates it at the peak line load, per sample [-].

    Args:
        pair: the mesh's gears (its face width b and module give ISO's N_F).
        face_load_factor: K_Hβ per sample (``mesh_face_load_factor``), ≥ 1 where loaded, 0
            where the mesh carries nothing.
        stress: ``"contact"`` (K_Hβ) or ``"root"`` (K_Hβ^N_F).

    Raises:
        InputError: an unknown ``stress``, or a loaded factor below 1 or not finite.
    """
    if stress not in STRESSES:
        raise InputError(f'stress = "{stress}"; choose {" or ".join(STRESSES)}')
    k = np.asarray(face_load_factor, dtype=float)
    loaded = k != 0.0
    if not np.all(np.isfinite(k)) or np.any(k[loaded] < 1.0):
        low = float(np.min(np.where(np.isfinite(k) & loaded, k, -np.inf), initial=np.inf))
        raise InputError(
            f"face load factor K_Hβ {low:g} of {'–'.join(pair.names)}: K_Hβ = w_max/w_m is ≥ 1 "
            "where the mesh is loaded (0 where it is not); pass the run's "
            "mesh_face_load_factor"
        )
    k = np.where(loaded, k, 1.0)
    return k if stress == "contact" else k ** root_face_load_exponent(pair)


def require_sliced(result: Result, mesh: str) -> None:
    """Refuse to read the peak line load of ``mesh`` from a run that did not slice it.

    Raises:
        FactorNotInRun: the run modelled the mesh rigid or with one contact line
            (`unsliced_mesh`), naming it and the fix.
    """
    modelled = unsliced_mesh(result, mesh)
    if modelled is not None:
        raise FactorNotInRun(
            f'mesh "{mesh}": the tooth stresses at the run\'s peak line load (face_load = '
            f'"run") read its series mesh_face_load_factor, but the run modelled the mesh '
            f"{modelled}, whose K_Hβ is not computed; run it as a compliant mesh cut into "
            'slices (slices="8" on its <mesh>, or MeshCompliance(slices=8)), or spread the '
            'force evenly across the face (face_load = "uniform")'
        )


def run_force_factor(result: Result, index: int, pair: GearPair, *, stress: str) -> np.ndarray:
    """`force_factor` of mesh ``index`` of a run from its ``mesh_face_load_factor``, (n,).

    Args:
        result: the run (its ``metadata["meshes"]`` says how each mesh was modelled).
        index: the mesh's index in the run.
        pair: the mesh's gears.
        stress: ``"contact"`` or ``"root"``.

    Raises:
        FactorNotInRun: the run did not cut the mesh into slices (`require_sliced`).
        InputError: as `force_factor`.
    """
    require_sliced(result, result.mesh_names[index])
    return force_factor(pair, result.mesh_face_load_factor[:, index], stress=stress)
