"""A design sweep's rows (Saleh 2017 §3.2, §5): their kind, key, tables and eq. 41.

Rows are plain dicts, one per design, whatever the kind of stage (`StageDesign.columns`; the
kinds are `sweep_planetary` and `sweep_parallel`, told apart by the ``stage`` column). The sweep
that computes them is `pinwind.runs.sweep`; this module only reads and writes them:

- `design_key`: what identifies a design across runs (a re-run skips the rows it already has).
- `write_table` / `read_table`: CSV or Parquet, one column set per kind; `read_checkpoint`: the
  JSON lines a sweep appends as it goes.
- `query`: Saleh 2017 eq. 41 on the columns every kind has (centre distance, ratio, module, SF), and
  `best_found`: what each criterion finds on its own when no design meets them all.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Sequence
from dataclasses import asdict
from pathlib import Path

from pinwind.analysis.sweep_design import StageDesign, SweepSettings
from pinwind.analysis.sweep_parallel import ParallelDesign
from pinwind.analysis.sweep_planetary import PlanetaryDesign
from pinwind.errors import InputError

__all__ = [
    "STAGES",
    "best_found",
    "design_from_row",
    "design_key",
    "query",
    "read_checkpoint",
    "read_table",
    "settings_dict",
    "stage_of",
    "write_table",
]

#: Stage kinds by the value of a row's ``stage`` column.
STAGES: dict[str, type[StageDesign]] = {
    PlanetaryDesign.kind: PlanetaryDesign,
    ParallelDesign.kind: ParallelDesign,
}


def stage_of(row: dict) -> type[StageDesign]:
    """The kind of a row (tables written before the ``stage`` column are planetary)."""
    name = row.get("stage") or PlanetaryDesign.kind
    try:
        return STAGES[name]
    except KeyError:
        raise InputError(
            f'row #{row.get("number")}: unknown stage "{name}"; stages are {sorted(STAGES)}'
        ) from None


def design_key(row: dict) -> tuple:
    """What identifies a design across runs: its kind and ``KEY`` columns (lengths in µm).

    The key of a design is ``design_key(design.identity(settings))``, so the face width the
    settings give is part of it: a re-run with another width recomputes every design.
    """
    kind = stage_of(row)
    values: list = [kind.kind]
    for column in kind.KEY:
        value = row[column]
        if column.endswith("_mm"):
            values.append(round(float(value) * 1e3))
        elif column.endswith("_deg"):
            values.append(round(float(value) * 1e6))
        else:
            values.append(int(value))
    return tuple(values)


# --- tables -------------------------------------------------------------------------------------


def write_table(rows: Sequence[dict], path: Path) -> Path:
    """Write rows of one kind as CSV, or Parquet when the suffix is ``.parquet``.

    Raises:
        InputError: rows of more than one kind (write one table per stage kind).
    """
    import pyarrow as pa

    kinds = {stage_of(r) for r in rows} or {PlanetaryDesign}
    if len(kinds) > 1:
        raise InputError(
            f"rows of {len(kinds)} stage kinds ({', '.join(sorted(k.kind for k in kinds))}) in one "
            "table; write one table per kind"
        )
    columns = kinds.pop().columns()
    table = pa.Table.from_pylist([{c: r.get(c) for c in columns} for r in rows])
    path = Path(path)
    if path.suffix == ".parquet":
        import pyarrow.parquet as pq

        pq.write_table(table, path)
    else:
        import pyarrow.csv as pc

        pc.write_csv(table, path)
    return path


def read_table(path: Path) -> list[dict]:
    """Rows of a table written by `write_table` (CSV or Parquet)."""
    path = Path(path)
    if not path.exists():
        raise InputError(
            f"{path}: no such sweep table; run pinwind sweep planetary (or parallel) first"
        )
    import pyarrow as pa

    try:
        if path.suffix == ".parquet":
            import pyarrow.parquet as pq

            table = pq.read_table(path)
        else:
            import pyarrow.csv as pc

            table = pc.read_csv(path)
    except pa.ArrowInvalid as err:
        # An empty file (a sweep of no design wrote one) was pyarrow's "Empty CSV file" traceback.
        raise InputError(
            f"{path}: not a sweep table ({err}); remove it, or give another --output"
        ) from err
    rows = table.to_pylist()
    for row in rows:
        for k in ("reason", "findings"):
            if row.get(k) is None:
                row[k] = ""
    return rows


def read_checkpoint(path: Path) -> list[dict]:
    """Rows of a checkpoint (JSON lines); a torn last line is ignored."""
    rows: list[dict] = []
    if not Path(path).exists():
        return rows
    for line in Path(path).read_text(encoding="utf-8").splitlines():
        try:
            rows.append(json.loads(line))
        except json.JSONDecodeError:
            continue
    return rows


# --- eq. 41: picking designs ----------------------------------------------------------------------


def query(
    rows: Iterable[dict],
    *,
    centre_distance: float | None = None,
    ratio: float | None = None,
    ratio_tolerance: float = 0.05,
    module: float | None = None,
    min_sf: float | None = None,
    sf_column: str = "agma_SF_min",
    minimise: str | None = None,
) -> list[dict]:
    """Designs that satisfy every given criterion (Saleh 2017 eq. 41: a ∪ i ∪ m ∪ SF).

    Args:
        rows: sweep rows.
        centre_distance: required centre distance [m] (matched to the micrometre).
        ratio: required speed ratio, matched within ``ratio_tolerance`` (the paper's 6.3 picks
            6.32 and not 6.15).
        module: required module [m].
        min_sf: smallest acceptable safety factor: ``row[sf_column] > min_sf`` (the paper's
            "SF > 1"); failed designs never pass.
        sf_column: which safety factor (default the smallest AGMA one of the design).
        minimise: a column to minimise (``"centre_distance_mm"``, ``"module_mm"``, ...); only
            the designs at its smallest value are returned.

    Raises:
        InputError: ``sf_column`` or ``minimise`` is not a column of the table.
    """
    rows = list(rows)
    if min_sf is not None and rows and sf_column not in rows[0]:
        raise InputError(
            f'--sf "{sf_column}": not a column of the sweep table; safety-factor columns are '
            + ", ".join(c for c in rows[0] if "SF" in c or "_S_" in c)
        )
    keep = []
    for row in rows:
        if row.get("status") != "ok":
            continue
        if centre_distance is not None and round(float(row["centre_distance_mm"]) * 1e3) != round(
            centre_distance * 1e6
        ):
            continue
        if module is not None and round(float(row["module_mm"]) * 1e3) != round(module * 1e6):
            continue
        if ratio is not None and abs(float(row["ratio"]) - ratio) > ratio_tolerance:
            continue
        if min_sf is not None and not float(row[sf_column]) > min_sf:
            continue
        keep.append(row)
    if minimise and keep:
        if minimise not in keep[0]:
            raise InputError(
                f'--minimise "{minimise}": not a column; columns are {", ".join(keep[0])}'
            )
        best = min(float(r[minimise]) for r in keep)
        keep = [r for r in keep if float(r[minimise]) == best]
    return keep


def best_found(
    rows: Iterable[dict],
    *,
    centre_distance: float | None = None,
    ratio: float | None = None,
    ratio_tolerance: float = 0.05,
    module: float | None = None,
    min_sf: float | None = None,
    sf_column: str = "agma_SF_min",
) -> list[str]:
    """What each criterion of a ``query`` finds on its own, for a query no design meets.

    Per criterion given, over the designs that ran (status ok): the best value (the largest
    safety factor, the nearest centre distance, ratio or module), its design number, and how
    many designs meet that criterion alone. One line each, in the CLI's units and flags.
    """
    ok = [r for r in rows if r.get("status") == "ok"]
    if not ok:
        return ["no design of the table ran (none has status ok)"]

    def nearest(column: str, target: float) -> dict:
        return min(ok, key=lambda r: abs(float(r[column]) - target))

    lines = []
    if min_sf is not None:
        best = max(ok, key=lambda r: float(r[sf_column]))
        meet = sum(float(r[sf_column]) > min_sf for r in ok)
        lines.append(
            f"--min-sf {min_sf:g}: the largest {sf_column} is {float(best[sf_column]):.3f} "
            f"(#{int(best['number'])}); {meet} design(s) exceed {min_sf:g}"
        )
    if ratio is not None:
        best = nearest("ratio", ratio)
        meet = sum(abs(float(r["ratio"]) - ratio) <= ratio_tolerance for r in ok)
        lines.append(
            f"--ratio {ratio:g}: the nearest ratio is {float(best['ratio']):.4g} "
            f"(#{int(best['number'])}); {meet} design(s) within ±{ratio_tolerance:g}"
        )
    # Lengths: the table's columns are in mm; "at it" to the µm, as query matches them.
    for flag, column, length in (
        ("--center-distance", "centre_distance_mm", centre_distance),
        ("--module", "module_mm", module),
    ):
        if length is None:
            continue
        target = length * 1e3
        best = nearest(column, target)
        meet = sum(round(float(r[column]) * 1e3) == round(target * 1e3) for r in ok)
        lines.append(
            f"{flag} {target:g}: the nearest is {float(best[column]):g} mm "
            f"(#{int(best['number'])}); {meet} design(s) at it"
        )
    return lines


def design_from_row(row: dict) -> StageDesign:
    """The design of a row, of the row's kind."""
    return stage_of(row).from_row(row)


def settings_dict(settings: SweepSettings) -> dict:
    """Settings as plain values (for messages and metadata)."""
    return asdict(settings)
