"""ISO 6336 load factors computed by pinwind instead of taken from ISO's empirical forms.

ISO 6336-1 rates a mesh with a face load factor K_Hβ (the load across the face width) and a
transverse load factor K_Hα (the load between the tooth pairs in contact), and gives empirical
forms for both (`pinwind.gears.rating_iso`: K_Hβ from an effective misalignment F_βy, K_Hα by
method B from a base pitch deviation f_pb). ISO 6336-1 §4.1 ranks above them a "method A"
value from a comprehensive analysis of the loaded mesh; this module gives two such values:

- **K_Hβ from a run** (``face_load`` in `pinwind.analysis.rating.rate`): the series
  ``mesh_face_load_factor`` of a compliant spur mesh cut into slices across the face
  (docs/flank_modifications.md "Sliced meshes"), K_Hβ(t) = N max_s F_s / Σ_s F_s, ISO 6336-1
  §7's definition (the peak line load over the mean) at each sample. The rating takes one
  number from it (`FACE_LOAD_STATISTICS`): its largest value over the loaded samples
  (``"run-max"``), or its value at the sample the rating's force comes from (``"run-at"``;
  for the rating's ``at="mean"`` its mean over the loaded samples). A mesh run with one
  contact line has K_Hβ = 1 by construction, not by computation: asking it is refused.
- **K_Hα from the loaded contact** (``transverse_load="loaded-contact"``): ISO 6336-1 §8
  defines K_Hα as the factor on the load of the most loaded tooth pair for the uneven
  sharing of the transverse load between the pairs in contact; the standard's rating (Z_B,
  Z_D, Z_ε) assumes the sharing of ideal involute flanks of the same stiffness. So

      K_Hα = max over the mesh cycle of the largest pair load, flanks as modified
             / the same, ideal flanks (no modification)

  from the quasi-static loaded contact (`pinwind.gears.transmission_error`: every tooth pair a
  spring of ISO 6336-1's pair stiffness behind the gap its profile and lead modifications
  leave) at the rated force along the transverse line of action, limited below by 1 as
  ISO 6336-1 limits method B's. It is 1 for ideal flanks and for a spur pair of ε_α < 2 (the
  single-pair zone carries the whole force with or without relief: a tip relief does not raise
  ISO's rated load, it reshapes the load and stress along the flank near the ends of the path,
  which the life code sees), above 1 where modifications or misalignment push more than the
  ideal peak onto one pair (helical pairs, ε_γ > 2). K_Fα takes the same value (ISO 6336-1
  method B has K_Fα = K_Hα below their limits).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from pinwind.dynamics.compliant import unsliced_mesh
from pinwind.errors import FactorNotInRun, InputError
from pinwind.gears.flank_modification import UNMODIFIED, FlankModification
from pinwind.gears.transmission_error import static_transmission_error

if TYPE_CHECKING:
    from pinwind.dynamics.result import Result
    from pinwind.gears.gear_pair import GearPair

#: Where K_Hβ comes from: ISO 6336-1's closed form, or the run's series (module docstring).
FACE_LOAD_SOURCES = ("iso", "run-max", "run-at")
#: Where K_Hα and K_Fα come from: ISO 6336-1 method B, or the quasi-static loaded contact.
TRANSVERSE_LOAD_SOURCES = ("iso", "loaded-contact")
#: Roll positions per mesh cycle of the loaded contact behind K_Hα.
TRANSVERSE_POSITIONS = 256


def run_face_load_factor(
    result: Result, mesh: str, source: str, *, sample: int | None
) -> tuple[float, str]:
    """(K_Hβ, where it came from) of one mesh of a run, from ``mesh_face_load_factor``.

    Args:
        result: the run (its ``metadata["meshes"]`` says how each mesh was modelled).
        mesh: the mesh's name.
        source: ``"run-max"`` (largest over the loaded samples) or ``"run-at"`` (at
            ``sample``; the mean over the loaded samples when ``sample`` is None).
        sample: the rated sample's index, or None for a rating of the run's mean.

    Raises:
        FactorNotInRun: the mesh was rigid or had one contact line in the run (its K_Hβ is 1
            by construction), or carried no load.
        InputError: an unknown source.
    """
    if source not in ("run-max", "run-at"):
        raise InputError(f'face load factor source "{source}"; choose run-max or run-at')
    modelled = unsliced_mesh(result, mesh)
    if modelled is not None:
        raise FactorNotInRun(
            f'mesh "{mesh}": K_Hβ from the run ({source}) reads its series '
            f"mesh_face_load_factor, but the run modelled the mesh {modelled}, whose K_Hβ is "
            'not computed; run it as a compliant mesh cut into slices (slices="8" on its '
            "<mesh>, or MeshCompliance(slices=8)), or take ISO's K_Hβ (--face-load-factor iso)"
        )
    series = result.mesh(mesh)
    factor, loaded = series.face_load_factor, series.normal > 0.0
    if not np.any(loaded):
        raise FactorNotInRun(f'mesh "{mesh}" carries no load in the run: it has no K_Hβ to read')
    if source == "run-max":
        return float(np.max(factor[loaded])), "run: mesh_face_load_factor max"
    if sample is None:
        return float(np.mean(factor[loaded])), "run: mesh_face_load_factor mean"
    if not loaded[sample]:
        raise FactorNotInRun(
            f'mesh "{mesh}" carries no load at t = {result.time[sample]:g} s, the rated sample: '
            "it has no K_Hβ there; rate another sample or take run-max"
        )
    return (
        float(factor[sample]),
        f"run: mesh_face_load_factor at t = {result.time[sample]:g} s",
    )


def loaded_contact_transverse_factor(
    pair: GearPair,
    force: float,
    *,
    gear_1: FlankModification = UNMODIFIED,
    gear_2: FlankModification = UNMODIFIED,
    misalignment: float = 0.0,
) -> float:
    """K_Hα of ``pair`` under ``force`` from its quasi-static loaded contact (module docstring).

    Args:
        pair: pinion first (`GearPair.from_mesh`).
        force: F_bt, the mesh force along the transverse line of action [N].
        gear_1, gear_2: the flank modifications of pinion and wheel.
        misalignment: F_β across the face [m] (`static_transmission_error`).

    Raises:
        InputError: a non-positive force.
    """
    if not (np.isfinite(force) and force > 0.0):
        raise InputError(f"K_Hα of {'–'.join(pair.names)} at {force} N: give a load > 0")
    modified = static_transmission_error(
        pair,
        force,
        gear_1=gear_1,
        gear_2=gear_2,
        misalignment=misalignment,
        positions=TRANSVERSE_POSITIONS,
    )
    ideal = static_transmission_error(
        pair, force, misalignment=misalignment, positions=TRANSVERSE_POSITIONS
    )
    return max(1.0, float(np.max(modified.pair_forces) / np.max(ideal.pair_forces)))
