"""PNG plots of a planetary sweep against the module, like 000_3b7c4a8fe52a6eee.txt Figs. 14-19."""

from __future__ import annotations

from pathlib import Path

#: (file stem, column, axis label, horizontal line at 1 for safety factors)
PLOTS = (
    ("fig14_centre_distance", "centre_distance_mm", "centre distance [mm]", False),
    ("fig15_speed_ratio", "ratio", "speed ratio [-]", False),
    ("fig16_contact_sf_sun_planet", "agma_SF_contact_sun_planet", "AGMA S_H sun/planet", True),
    ("fig17_contact_sf_planet_ring", "agma_SF_contact_planet_ring", "AGMA S_H planet/ring", True),
    ("fig18_bending_sf_min", "agma_SF_bending_min", "AGMA S_F, smallest of all gears", True),
    ("fig19_iso_sf_min", "iso_S_min", "ISO 6336 smallest S_H, S_F", True),
)


def plot_sweep(rows: list[dict], out_dir: Path) -> list[Path]:
    """One PNG per quantity against the module, workable designs labelled by number."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    ok = [r for r in rows if r.get("status") == "ok"]
    paths = []
    for stem, column, label, unity in PLOTS:
        fig, ax = plt.subplots(figsize=(7, 4.5))
        x = [float(r["module_mm"]) for r in ok]
        y = [float(r[column]) for r in ok]
        passes = [float(r["agma_SF_min"]) > 1.0 for r in ok]
        ax.scatter(
            [a for a, p in zip(x, passes, strict=True) if p],
            [b for b, p in zip(y, passes, strict=True) if p],
            marker="o", color="tab:blue", label="all AGMA SF > 1",
        )  # fmt: skip
        ax.scatter(
            [a for a, p in zip(x, passes, strict=True) if not p],
            [b for b, p in zip(y, passes, strict=True) if not p],
            marker="x", color="tab:red", label="some AGMA SF ≤ 1",
        )  # fmt: skip
        for r, a, b in zip(ok, x, y, strict=True):
            ax.annotate(f"#{int(r['number'])}", (a, b), fontsize=6, xytext=(3, 2),
                        textcoords="offset points")  # fmt: skip
        if unity:
            ax.axhline(1.0, color="grey", linewidth=0.8, linestyle="--")
        ax.set_xlabel("module [mm]")
        ax.set_ylabel(label)
        ax.set_title(f"{label} of the workable designs")
        ax.grid(True, linewidth=0.3)
        ax.legend(fontsize=7)
        fig.tight_layout()
        path = out_dir / f"{stem}.png"
        fig.savefig(path, dpi=120)
        plt.close(fig)
        paths.append(path)
    return paths
