"""PNG plots of a sweep against the module, like Saleh 2017 Figs. 14-19.

Which quantities are drawn is the stage kind's choice (`StageDesign.PLOTS`): Figs. 14-19's for a
planetary stage, the same family (centre distance, ratio, contact and bending SF) for a parallel
one.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

#: Labels of designs at one module closer than this fraction of the plot's y span would overprint
#: (a 6 pt label on a plot about 250 pt high): they are merged into one.
LABEL_GAP = 0.04


def _numbers_text(numbers: list[int]) -> str:
    """#11–#14 for consecutive design numbers, else #3, #7, #9."""
    numbers = sorted(numbers)
    if len(numbers) > 1 and numbers == list(range(numbers[0], numbers[-1] + 1)):
        return f"#{numbers[0]}–#{numbers[-1]}"
    return ", ".join(f"#{n}" for n in numbers)


def design_labels(
    numbers: Sequence[int], x: Sequence[float], y: Sequence[float]
) -> list[tuple[str, float, float]]:
    """(text, x, y) of the design labels of a plot, none overprinting another.

    Designs at the same x whose y values lie within ``LABEL_GAP`` of the y span of each other
    (in a chain) share one label, placed at the highest of them.
    """
    span = (max(y) - min(y)) if y else 0.0
    gap = LABEL_GAP * span if span > 0 else 0.0
    out = []
    for column in sorted(set(x)):
        points = sorted((b, n) for n, a, b in zip(numbers, x, y, strict=True) if a == column)
        group = [points[0]]
        for point in points[1:]:
            if point[0] - group[-1][0] <= gap:
                group.append(point)
                continue
            out.append((_numbers_text([n for _, n in group]), column, group[-1][0]))
            group = [point]
        out.append((_numbers_text([n for _, n in group]), column, group[-1][0]))
    return out


def plot_sweep(rows: list[dict], out_dir: Path) -> list[Path]:
    """One PNG per quantity against the module, workable designs labelled by number.

    Designs whose labels would overprint share one (``design_labels``: #11–#14).
    """
    import matplotlib

    from pinwind.analysis.sweep_table import stage_of

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    ok = [r for r in rows if r.get("status") == "ok"]
    plots = stage_of(rows[0]).PLOTS if rows else ()
    paths = []
    for stem, column, label, unity in plots:
        fig, ax = plt.subplots(figsize=(8, 4.5), layout="constrained")
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
        for text, a, b in design_labels([int(r["number"]) for r in ok], x, y):
            ax.annotate(text, (a, b), fontsize=6, xytext=(3, 2), textcoords="offset points")
        if unity:
            ax.axhline(1.0, color="grey", linewidth=0.8, linestyle="--")
        ax.set_xlabel("module [mm]")
        ax.set_ylabel(label)
        ax.set_title(f"{label} of the workable designs")
        ax.grid(True, linewidth=0.3)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
        path = out_dir / f"{stem}.png"
        fig.savefig(path, dpi=120)
        plt.close(fig)
        paths.append(path)
    return paths
