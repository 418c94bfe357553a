"""Gear materials: elastic constants and the fatigue strengths the ratings need (SI units).

Every value is a representative one for the named steel and heat treatment, to be overridden by a
supplier's data: `Material` is a frozen dataclass, so ``dataclasses.replace(MATERIALS[...],
sigma_H_lim=...)`` gives a variant.

ISO 6336-5 strengths are for material quality MQ; AGMA 2001 allowable numbers (s_ac, s_at) are
AGMA 2001-D04 Tables 3-4 / Figs. 3-4 (as quoted in Shigley's Mechanical Engineering Design,
10th ed., Tables 14-3, 14-6 and Figs. 14-2 to 14-5), 10⁷ cycles and 99 % reliability.

| key | treatment | σ_Hlim | σ_Flim | s_ac | s_at |
|---|---|---|---|---|---|
| ``18CrNiMo7-6`` | carburised, 58-62 HRC | 1500 | 500 | 1550 (225 ksi, gr. 2) | 448 (65 ksi) |
| ``42CrMo4`` | through hardened, 300 HB | 770 | 310 | 867 (2.22 HB + 200) | 248 (0.533 HB + 88.3) |
| ``34CrNiMo6`` | nitrided, 300 HB core | 1000 | 370 | 1034 (150 ksi) | 254 (0.568 HB + 83.8) |

(MPa.) The ISO values read the MQ lines of ISO 6336-5 Figs. for case-hardened wrought steel
(σ_Hlim 1500, σ_Flim 500), through-hardened alloy steel at 300 HB and nitrided through-hardening
steel; they are chart readings, good to a few per cent.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pinwind.errors import InputError

MPA = 1e6
KSI = 6.894757e6


@dataclass(frozen=True)
class Material:
    """A gear steel and its heat treatment.

    Attributes:
        name: designation, e.g. ``"18CrNiMo7-6"``.
        treatment: ``"case_carburised"``, ``"through_hardened"`` or ``"nitrided"``.
        youngs_modulus: E [Pa].
        poisson_ratio: ν [-].
        density: ρ [kg/m³].
        brinell_hardness: core (through-hardened) hardness HB [-], used by AGMA C_H.
        sigma_H_lim: ISO 6336-5 endurance limit for contact stress σ_Hlim [Pa].
        sigma_F_lim: ISO 6336-5 nominal stress number for bending σ_Flim [Pa] (σ_FE = 2 σ_Flim).
        agma_contact_allowable: AGMA allowable contact stress number s_ac [Pa].
        agma_bending_allowable: AGMA allowable bending stress number s_at [Pa].
    """

    name: str
    treatment: str
    youngs_modulus: float
    poisson_ratio: float
    density: float
    brinell_hardness: float
    sigma_H_lim: float
    sigma_F_lim: float
    agma_contact_allowable: float
    agma_bending_allowable: float

    @property
    def case_hardened(self) -> bool:
        """True for surface-hardened teeth (carburised or nitrided)."""
        return self.treatment in ("case_carburised", "nitrided")


MATERIALS: dict[str, Material] = {
    "18CrNiMo7-6": Material(
        name="18CrNiMo7-6",
        treatment="case_carburised",
        youngs_modulus=206e9,
        poisson_ratio=0.3,
        density=7850.0,
        brinell_hardness=600.0,
        sigma_H_lim=1500 * MPA,
        sigma_F_lim=500 * MPA,
        agma_contact_allowable=225 * KSI,
        agma_bending_allowable=65 * KSI,
    ),
    "42CrMo4": Material(
        name="42CrMo4",
        treatment="through_hardened",
        youngs_modulus=206e9,
        poisson_ratio=0.3,
        density=7850.0,
        brinell_hardness=300.0,
        sigma_H_lim=770 * MPA,
        sigma_F_lim=310 * MPA,
        agma_contact_allowable=(2.22 * 300 + 200) * MPA,
        agma_bending_allowable=(0.533 * 300 + 88.3) * MPA,
    ),
    "34CrNiMo6": Material(
        name="34CrNiMo6",
        treatment="nitrided",
        youngs_modulus=206e9,
        poisson_ratio=0.3,
        density=7850.0,
        brinell_hardness=300.0,
        sigma_H_lim=1000 * MPA,
        sigma_F_lim=370 * MPA,
        agma_contact_allowable=150 * KSI,
        agma_bending_allowable=(0.568 * 300 + 83.8) * MPA,
    ),
}

#: Material of every gear unless told otherwise: wind-turbine gears are case carburised.
DEFAULT_MATERIAL = "18CrNiMo7-6"


def material(name: str | Material) -> Material:
    """Look a material up by name (a `Material` passes through)."""
    if isinstance(name, Material):
        return name
    try:
        return MATERIALS[name]
    except KeyError as err:
        raise InputError(
            f'unknown gear material "{name}"; materials are: {", ".join(MATERIALS)}'
        ) from err


def elastic_coefficient(first: Material, second: Material) -> float:
    """Z_E = C_p = sqrt(1 / (π ((1 − ν1²)/E1 + (1 − ν2²)/E2))) [√Pa] (ISO 6336-2, AGMA 2001).

    189.8 √MPa (2300 √psi) for two steels with E = 206 GPa, ν = 0.3.
    """
    compliance = (1.0 - first.poisson_ratio**2) / first.youngs_modulus + (
        1.0 - second.poisson_ratio**2
    ) / second.youngs_modulus
    return math.sqrt(1.0 / (math.pi * compliance))
