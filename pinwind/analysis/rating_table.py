"""Rich tables of a `GearboxRating`: one row per mesh and gear, stresses in MPa."""

from __future__ import annotations

from rich.table import Table

from pinwind.analysis.rating import GearboxRating


def _ok(passes: bool) -> str:
    return "[green]pass[/green]" if passes else "[bold red]FAIL[/bold red]"


def rating_tables(rating: GearboxRating, title: str = "") -> list[Table]:
    """A mesh table (one row per gear of each mesh) and a table of the smallest factors per gear."""
    meshes = Table(title=f"mesh ratings {title}".strip(), title_justify="left")
    for column in (
        "mesh", "gear", "F_n kN", "v m/s", "ISO σ_H", "S_H", "ISO σ_F", "S_F",
        "AGMA σ_c", "S_H", "AGMA σ", "S_F", "Hertz p_max", "",
    ):  # fmt: skip
        meshes.add_column(column, justify="left" if column in ("mesh", "gear") else "right")
    for m in rating.meshes:
        for i, gear in enumerate(m.pair.names):
            first = i == 0
            meshes.add_row(
                m.mesh if first else "",
                gear,
                f"{m.normal_force / 1e3:.1f}" if first else "",
                f"{m.load.pitch_line_speed:.2f}" if first else "",
                f"{m.iso.sigma_H[i] * 1e-6:.0f}",
                f"{m.iso.S_H[i]:.2f}",
                f"{m.iso.sigma_F[i] * 1e-6:.0f}",
                f"{m.iso.S_F[i]:.2f}",
                f"{m.agma.contact_stress[i] * 1e-6:.0f}",
                f"{m.agma.S_H[i]:.2f}",
                f"{m.agma.bending_stress[i] * 1e-6:.0f}",
                f"{m.agma.S_F[i]:.2f}",
                f"{m.hertz_p_max * 1e-6:.0f}" if first else "",
                _ok(m.passes) if first else "",
            )
    meshes.caption = "stresses in MPa; S = permissible (allowable) / actual, ≥ 1 passes"
    gears = Table(title="smallest safety factors per gear", title_justify="left")
    for column in ("gear", "ISO S_H", "ISO S_F", "AGMA S_H", "AGMA S_F", "Hertz p_max MPa", ""):
        gears.add_column(column, justify="left" if column == "gear" else "right")
    for g in rating.gears.values():
        gears.add_row(
            g.gear,
            f"{g.S_H_iso:.2f}",
            f"{g.S_F_iso:.2f}",
            f"{g.S_H_agma:.2f}",
            f"{g.S_F_agma:.2f}",
            f"{g.hertz_p_max * 1e-6:.0f}",
            _ok(g.passes),
        )
    return [meshes, gears]
