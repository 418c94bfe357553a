"""PNG plots of a sweep against the module, like 000_3b7c4a8fe52a6eee.txt Figs. 14-19.

Which quantities are drawn is the stage kind's choice (`StageDesign.PLOTS`): Figs. 14-19's for a
planetary stage, the same family (centre distance, ratio, contact and bending SF) for a parallel
one.
"""

from __future__ import annotations

from pathlib import Path


def plot_sweep(rows: list[dict], out_dir: Path) -> list[Path]:
    """One PNG per quantity against the module, workable designs labelled by number."""
    import matplotlib

    from pinwind.analysis.sweep import stage_of

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    ok = [r for r in rows if r.get("status") == "ok"]
    plots = stage_of(rows[0]).PLOTS if rows else ()
    paths = []
    for stem, column, label, unity in plots:
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
