"""Rich tables of a `GearboxRating`: one row per gear of each mesh, stresses in MPa.

Four tables that fit 80 columns with no cell cut: ISO 6336, AGMA 2001 with Hertz, ISO's face
and transverse load factors with their sources, and the smallest safety factors per gear; the
mesh tables name the standard, its edition and method as ``gears/rating_iso.py`` and
``gears/rating_agma.py`` implement them, and the application factor, accuracy and reliability
used.
"""

from __future__ import annotations

from rich.table import Table

from pinwind.analysis.rating import GearboxRating

#: The standards, editions and methods of each table, as the rating modules implement them
#: (their docstrings give every factor and default).
ISO_METHOD = (
    "ISO 6336-2 (pitting) and ISO 6336-3 (tooth root), method B factors; K_v by "
    "ISO 6336-1:1996 method C; life, lubrication and roughness factors 1"
)
AGMA_METHOD = "AGMA 2001-D04 in SI units (Shigley 10th ed.)"
AGMA_DEFAULTS = (
    "Y_N = Z_N = 1; p_max: largest Hertz line-contact pressure along the path of contact"
)
#: Where AGMA's bending geometry factor J comes from, by ``AgmaFactors.geometry_factor``.
AGMA_J = {
    "agma908": "J by AGMA 908-B89 (internal gears: 1/(Y_F Y_S) of ISO 6336-3)",
    "iso": "J = 1/(Y_F Y_S) of ISO 6336-3",
}


def _iso_caption(rating: GearboxRating) -> str:
    """The ISO method and the choices of the first mesh (the command line's are every mesh's)."""
    if not rating.meshes:
        return ISO_METHOD
    f = rating.meshes[0].iso.factors
    return (
        f"{ISO_METHOD}; K_A = {f.K_A:g}, accuracy grade {f.accuracy_grade}, misalignment "
        f"F_βy = {f.misalignment * 1e6:g} µm"
    )


def _agma_caption(rating: GearboxRating) -> str:
    """The AGMA method and the choices of the first mesh."""
    if not rating.meshes:
        return f"{AGMA_METHOD}; {AGMA_DEFAULTS}"
    f = rating.meshes[0].agma.factors
    return (
        f"{AGMA_METHOD}; {AGMA_J[f.geometry_factor]}; {AGMA_DEFAULTS}; K_o = {f.K_o:g}, "
        f"Q_v = {f.quality}, reliability {f.reliability_percent:g} % (K_R = {f.K_R:.3g})"
    )


#: Safety factors at or above this print as ``>100``: a gear that carries almost nothing (a
#: stage the run leaves unloaded) has S in the thousands, which would widen the table past 80
#: columns and tell no more (``--json`` keeps the value).
LARGE_FACTOR = 100.0


def _factor(value: float) -> str:
    """A safety factor to 2 decimals, or ``>100`` from ``LARGE_FACTOR`` up."""
    return f"{value:.2f}" if value < LARGE_FACTOR else f">{LARGE_FACTOR:.0f}"


def _ok(passes: bool) -> str:
    return "[green]pass[/green]" if passes else "[bold red]FAIL[/bold red]"


def _table(title: str, caption: str, plain: bool) -> Table:
    """An empty table in the style of ``pinwind report``: no outer edge, a rule under the head."""
    from pinwind.analysis.summary import PLAIN_BOX, TERMINAL_BOX

    return Table(
        title=title,
        caption=caption,
        title_justify="left",
        caption_justify="left",
        box=PLAIN_BOX if plain else TERMINAL_BOX,
        show_edge=False,
        pad_edge=False,
        title_style=None if plain else "bold",
        header_style=None if plain else "bold",
    )


def _columns(table: Table, names: tuple[str, ...]) -> None:
    for name in names:
        # A cell too wide for the console folds onto a second line; none is cut to "…".
        table.add_column(
            name,
            justify="left" if name in ("mesh", "gear", "factor", "source") else "right",
            overflow="fold",
        )


def rating_tables(rating: GearboxRating, title: str = "", *, plain: bool = False) -> list[Table]:
    """The ISO 6336 and AGMA 2001/Hertz mesh tables, ISO's load factors, the smallest per gear.

    Each mesh table has a row per gear of each mesh (stresses in MPa; S = permissible / actual,
    ≥ 1 passes) and names the standard, edition, method and main factors in its caption; the
    load-factor table has a row per ISO K_Hβ and K_Hα of each mesh with where it came from
    (ISO 6336-1's form, given, the run's series, the loaded contact).

    Args:
        rating: the rating (``analysis.rating.rate``).
        title: what was rated (model, time), after each mesh table's standard.
        plain: ASCII rules and no styles, for pipes and files.
    """
    at = f" — {title}" if title else ""
    iso = _table(f"ISO 6336 mesh ratings{at}", _iso_caption(rating), plain)
    _columns(iso, ("mesh", "gear", "F_n kN", "v m/s", "σ_H MPa", "S_H", "σ_F MPa", "S_F"))
    agma = _table(f"AGMA 2001 and Hertz mesh ratings{at}", _agma_caption(rating), plain)
    _columns(agma, ("mesh", "gear", "σ_c MPa", "S_H", "σ MPa", "S_F", "p_max MPa", ""))
    for m in rating.meshes:
        for i, gear in enumerate(m.pair.names):
            first = i == 0
            iso.add_row(
                m.mesh if first else "",
                gear,
                f"{m.normal_force / 1e3:.1f}" if first else "",
                f"{m.load.pitch_line_speed:.2f}" if first else "",
                f"{m.iso.sigma_H[i] * 1e-6:.0f}",
                _factor(m.iso.S_H[i]),
                f"{m.iso.sigma_F[i] * 1e-6:.0f}",
                _factor(m.iso.S_F[i]),
            )
            agma.add_row(
                m.mesh if first else "",
                gear,
                f"{m.agma.contact_stress[i] * 1e-6:.0f}",
                _factor(m.agma.S_H[i]),
                f"{m.agma.bending_stress[i] * 1e-6:.0f}",
                _factor(m.agma.S_F[i]),
                f"{m.hertz_p_max * 1e-6:.0f}" if first else "",
                _ok(m.passes) if first else "",
            )
    factors = _table(
        f"ISO 6336 load factors{at}",
        "K_Fβ = K_Hβ^N_F (ISO 6336-1); with K_Hα from the loaded contact, K_Fα = K_Hα",
        plain,
    )
    _columns(factors, ("mesh", "factor", "value", "source"))
    for m in rating.meshes:
        f = m.iso.factors
        values = {"K_Hbeta": ("K_Hβ", f.K_Hbeta), "K_Halpha": ("K_Hα", f.K_Halpha)}
        for i, (key, (label, value)) in enumerate(values.items()):
            factors.add_row(
                m.mesh if i == 0 else "", label, f"{value:.4f}", m.factor_sources.get(key, "")
            )
    gears = _table(
        "smallest safety factors per gear", "S = permissible / actual, ≥ 1 passes", plain
    )
    _columns(gears, ("gear", "ISO S_H", "ISO S_F", "AGMA S_H", "AGMA S_F", "p_max MPa", ""))
    for g in rating.gears.values():
        gears.add_row(
            g.gear,
            _factor(g.S_H_iso),
            _factor(g.S_F_iso),
            _factor(g.S_H_agma),
            _factor(g.S_F_agma),
            f"{g.hertz_p_max * 1e-6:.0f}",
            _ok(g.passes),
        )
    return [iso, agma, factors, gears]
