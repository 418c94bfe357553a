"""PNG figures of a fatigue set's damage, like Jørgensen 2014's Figs. 14-15, and its load spectra.

Each figure has a caption under its axes (`pinwind.io.figure_layout.caption_below`): what is
plotted, the turbulence levels, the sources, and the set it comes from (``about``, which the
command gives); a figure of a short set (``pinwind fatigue --quick``) says so in its title
(``mark``). The caption and the mark are also the PNG's Description and Title.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from pinwind.io.figure_layout import save_with_caption
from pinwind.life.bearing_life import BearingLife
from pinwind.life.damage_ranking import RankedItem
from pinwind.life.load_spectrum import LoadSpectrum
from pinwind.life.set_damage import (
    JORGENSEN_2014_TABLE_8,
    PAPER,
    RANGE_EDGES,
    VARIANTS,
    SetDamage,
)


def plot_damage_vs_turbulence(
    damage: SetDamage, path: Path, *, about: str = "", mark: str = ""
) -> Path:
    """Total damage per gear kind against turbulence intensity (Jørgensen 2014 Fig. 15).

    Each S-N variant of each gear kind, and Jørgensen 2014's Table 8 dashed. ``about``: the set,
    for the caption; ``mark``: a title such as the quick set's.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    fig, ax = plt.subplots(figsize=(8.5, 4.5), layout="constrained")
    x = 100 * np.array(damage.intensities)
    colours: dict[str, Any] = {}
    for variant, style in zip(VARIANTS, ("o-", "s:", "^-."), strict=True):
        kinds: dict[str, list[float]] = {}
        for level in range(len(damage.levels)):
            for kind, (_, total) in damage.by_kind(variant, level).items():
                kinds.setdefault(kind, []).append(total)
        for kind, totals in kinds.items():
            line = ax.plot(x, totals, style, color=colours.get(kind), label=f"{kind} ({variant})")
            colours[kind] = line[0].get_color()
    paper = 100 * np.array(JORGENSEN_2014_TABLE_8["turbulence"])
    for kind in ("sun", "planet", "ring"):
        if kind in colours:
            ax.plot(paper, JORGENSEN_2014_TABLE_8[kind], "--", color=colours[kind],
                    label=f"{kind} ({PAPER} Table 8)")  # fmt: skip
    ax.axhline(1.0, color="k", lw=0.8)
    ax.set_xlabel("turbulence intensity [%]")
    ax.set_ylabel("damage over the design life [-]")
    values = np.concatenate([np.asarray(line.get_ydata(), dtype=float) for line in ax.get_lines()])
    threshold = damage_axis_threshold(values)
    ax.set_yscale("symlog", linthresh=threshold)
    top = 3.0 * max(float(np.nanmax(values, initial=1.0)), 1.0)
    ax.set_ylim(0.0, top)  # damage is never negative
    decades = np.arange(round(np.log10(threshold)), np.ceil(np.log10(top)))
    step = max(1, int(np.ceil(len(decades) / 12)))  # at most about 12 labelled decades
    ax.set_yticks([0.0, *(10.0 ** decades[::-1][::step])])
    ax.yaxis.set_minor_locator(matplotlib.ticker.NullLocator())
    # Beside the axes: a legend inside would hide the damages of some decade.
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    ax.grid(alpha=0.3)
    caption = (
        "Contact damage over the design life (Palmgren-Miner, worst tooth flank; planet = mean "
        "of the planets) per gear kind against turbulence, levels "
        f"{', '.join(damage.levels)}.\nS-N variants: limit = {PAPER} eq. 23 with its Table 5 "
        "endurance limits, no limit = the same line without them (an upper bound), iso 6336 = "
        "ISO 6336-2's curve of the gear's material.\n"
        f"Dashed: {PAPER} Table 8. Why they differ: docs/fatigue.md."
    )
    return _save(fig, path, caption=_with_set(caption, about), mark=mark)


def damage_axis_threshold(values: np.ndarray) -> float:
    """The symlog axis' linear range: the decade below the smallest non-zero damage (at most 1e-3).

    ISO 6336's curves give damages of 1e-8 to 1e-44 where the others give 0.1 to 1000: every
    non-zero value must be drawn on the logarithmic part, and zero on the linear part below it.
    """
    positive = values[np.isfinite(values) & (values > 0.0)]
    if positive.size == 0:
        return 1e-3
    return min(1e-3, 10.0 ** np.floor(np.log10(positive.min())))


def plot_range_cycles(
    damage: SetDamage,
    path: Path,
    *,
    level: int = 0,
    gear: str | None = None,
    about: str = "",
    mark: str = "",
) -> Path:
    """Cycles per tooth over the life above each stress range, one line per wind bin.

    As Jørgensen 2014's Fig. 14b, of one gear (the first rated) at one turbulence level.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    gear = gear or damage.gears[0]
    fig, ax = plt.subplots(figsize=(8.5, 4.5), layout="constrained")
    for speed, bins in zip(damage.speeds, damage.range_cycles[level], strict=True):
        counts = bins.get(gear)
        if counts is None or not np.any(counts):
            continue
        above = np.cumsum(counts[::-1])[::-1]  # cycles with a range at or above each edge
        ax.step(RANGE_EDGES[:-1] / 1e6, above, where="post", label=f"{speed:g} m/s")
    counted = [c for b in damage.range_cycles[level] for g, c in b.items() if g == gear]
    reached = np.flatnonzero(np.sum(counted, axis=0)) if counted else np.zeros(0, dtype=int)
    if reached.size:
        ax.set_xlim(0.0, 1.1 * RANGE_EDGES[reached[-1] + 1] / 1e6)
    ax.set_xlabel("von Mises contact-stress range [MPa]")
    ax.set_ylabel("cycles per tooth over the bin's hours, range ≥ x [-]")
    ax.set_yscale("log")
    ax.set_title(f"{gear}, turbulence {damage.levels[level]}")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    ax.grid(alpha=0.3)
    caption = (
        f"Rainflow cycles per tooth of {gear} over each wind bin's hours with a von Mises contact-"
        f"stress range at or above x (ASTM E1049-85), turbulence {damage.levels[level]}, one "
        f"line per bin.\nAs {PAPER} Fig. 14b."
    )
    return _save(fig, path, caption=_with_set(caption, about), mark=mark)


def plot_load_spectra(
    spectra: list[LoadSpectrum], path: Path, *, title: str = "", about: str = "", mark: str = ""
) -> Path:
    """LDD (hours) and LRD (revolutions) against torque, one line per shaft (IEC 61400-4).

    ``title``: the axes' (e.g. the turbulence level); ``about``, ``mark`` as the other figures'.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ldd, lrd) = plt.subplots(1, 2, figsize=(11, 4.2), layout="constrained")
    for spectrum in spectra:
        if not np.any(spectrum.revolutions):  # a shaft that does not turn has no spectrum
            continue
        torque = spectrum.levels / 1e3
        ldd.step(torque, spectrum.time / 3600.0, where="mid", label=spectrum.joint)
        lrd.step(torque, spectrum.revolutions, where="mid", label=spectrum.joint)
    ldd.set_ylabel("time at the torque level [h]")
    lrd.set_ylabel("revolutions at the torque level [-]")
    for ax, name in ((ldd, "LDD"), (lrd, "LRD")):
        ax.set_xlabel("shaft torque [kN·m]")
        ax.set_yscale("log")
        ax.set_title(f"{name} {title}".strip())
        ax.grid(alpha=0.3)
    # one legend for both (the same shafts), beside the axes: inside it would hide a step
    lrd.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
    caption = (
        "Load duration (LDD: hours at each torque level) and load revolution distribution (LRD: "
        "revolutions at each) of every turning shaft over the site's life"
        + (f", {title}" if title else "")
        + " (IEC 61400-4)."
    )
    return _save(fig, path, caption=_with_set(caption, about), mark=mark)


def plot_bearing_lives(
    lives: list[BearingLife],
    path: Path,
    *,
    hours: float,
    title: str = "",
    about: str = "",
    mark: str = "",
) -> Path:
    """Each rated bearing's and row's three lives [h] as horizontal bars on a log scale.

    ISO 281 basic L10h and modified L_nmh (90 %), ISO/TS 16281 reference L10rh, over the site's
    operating ``hours`` (drawn as a line: a life left of it is used up within the design life);
    a life not computed has no bar and is said in the caption. ``title``: the axes' (e.g. the
    turbulence level); ``about``, ``mark`` as the other figures'.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    rated = [life for life in lives if life.rated and not life.refused]
    kinds = (("l10h", "L10h (ISO 281)", "tab:blue"),
             ("lnmh", "L_nmh (ISO 281, 90 %)", "tab:orange"),
             ("l10rh", "L10rh (ISO/TS 16281)", "tab:green"))  # fmt: skip
    fig, ax = plt.subplots(figsize=(9.0, 1.6 + 0.42 * max(len(rated), 1)), layout="constrained")
    values = np.array([[getattr(life, k) for k, _, _ in kinds] for life in rated]).reshape(-1, 3)
    finite = values[np.isfinite(values) & (values > 0.0)]
    floor = (
        10.0 ** np.floor(np.log10(min(float(finite.min()), hours) / 3.0)) if finite.size else 1.0
    )
    y = np.arange(len(rated))[::-1]
    height = 0.27
    missing: list[str] = []
    for j, (_, label, colour) in enumerate(kinds):
        shown = np.isfinite(values[:, j]) & (values[:, j] > 0.0)
        rows = y[shown] + (1 - j) * height
        ax.barh(rows, values[shown, j] - floor, left=floor, height=height, label=label,
                color=colour)  # fmt: skip
        lacking = [rated[i].joint for i in np.flatnonzero(~shown)]
        if len(lacking) > 4:
            missing.append(f"{label.split()[0]} of {len(lacking)} of the {len(rated)}")
        elif lacking:
            missing.append(f"{label.split()[0]} of {', '.join(lacking)}")
    ax.set_yticks(y, [life.joint for life in rated], fontsize=7)
    ax.set_xscale("log")
    ax.set_xlim(left=floor)
    ax.axvline(hours, color="k", lw=0.8)
    ax.set_xlabel("life [h of operation]")
    ax.set_title(title, fontsize=9)
    ax.grid(axis="x", alpha=0.3)
    handles: list[Any] = [Patch(color=colour, label=label) for _, label, colour in kinds]
    handles.append(Line2D([], [], color="k", lw=0.8, label=f"site's {hours:.0f} h of operation"))
    ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0),
              borderaxespad=0)  # fmt: skip
    caption = (
        "Each rated bearing's and row's lives over the site's wind bins: ISO 281 basic L10h and "
        "modified L_nmh (a_ISO from the lubricant, cleanliness and fatigue load limit), ISO/TS "
        "16281 reference L10rh (from the internal load distribution), the loads of each "
        "revolution-weighted over the bins (Palmgren-Miner), in hours at the mean speed."
        + (f"\nNot computed (no size_mm, C_u or C₀ in the model, or a single angular row that "
           f"needs its pair): {'; '.join(missing)}."
           if missing else "")
    )  # fmt: skip
    return _save(fig, path, caption=_with_set(caption, about), mark=mark)


def _with_set(caption: str, about: str) -> str:
    """A figure's caption, and the set it comes from on its own line."""
    return f"{caption}\n{about}" if about else caption


def plot_damage_ranking(items: list[RankedItem], path: Path, *, title: str) -> Path:
    """The ranked gears and bearings as horizontal bars on a log scale, the most damaged on top.

    Like Nejad et al. 2016's vulnerability map: one bar per gear flank, gear root and bearing
    (`pinwind.life.damage_ranking`), coloured by kind; items without damage (0 or NaN) are
    listed on the axis without a bar. A line marks 1 (the life used up).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch

    colours = {"flank": "tab:blue", "root": "tab:orange", "bearing": "tab:green"}
    shown = [i for i in items if np.isfinite(i.damage) and i.damage > 0.0]
    floor = min((i.damage for i in shown), default=1e-12) / 10.0
    fig, ax = plt.subplots(figsize=(9.0, 1.2 + 0.22 * len(items)), layout="constrained")
    y = np.arange(len(items))[::-1]
    for item, row in zip(items, y, strict=True):
        if item in shown:
            ax.barh(row, item.damage - floor, left=floor, color=colours[item.kind])
    ax.set_yticks(y, [f"{i.name} ({i.kind})" for i in items], fontsize=7)
    ax.set_xscale("log")
    ax.set_xlim(left=floor)
    ax.axvline(1.0, color="k", lw=0.8)
    handles = [Patch(color=colour, label=kind) for kind, colour in colours.items()]
    ax.legend(handles=handles, fontsize=8, loc="lower right")
    ax.set_xlabel("damage over the design life [-] (bearings: revolutions / L10)")
    ax.set_title(title, fontsize=9)
    ax.grid(axis="x", alpha=0.3)
    caption = (
        "Each gear's contact (flank) and root damage, its worst tooth flank's Palmgren-Miner sum, "
        "and each rated bearing row's ISO 281 life consumption (revolutions / L10), over the "
        "design life; most damaged on top.\nAs Nejad et al. 2016's vulnerability map; the damages "
        "of different kinds use different curves and failure probabilities."
    )
    return _save(fig, path, caption=caption)


def _save(fig: Any, path: Path, *, caption: str, mark: str = "") -> Path:
    """Writes a figure with its caption and mark (`figure_layout.save_with_caption`)."""
    return Path(save_with_caption(fig, path, caption=caption, mark=mark))
