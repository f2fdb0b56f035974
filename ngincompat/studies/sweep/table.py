"""The table of a sweep: one row per finished case, written, read back and drawn.

The table has the columns ``case, status, <varied parameters>, <metrics>, seconds, error``, in
case order. ``status`` is "done", "not converged" (the metrics are those of the last
converged state) or "failed" (no metrics: the scene rejected a value, or the run raised).
:func:`write_table` writes it as the summary table ``sweep`` (``sweep.md``, ``sweep.csv``,
``sweep.json``, by :func:`ngincompat.workflow.tables.write`: headers with units) and as
``sweep.parquet`` when pyarrow is installed; sweep.json also records the sweep and its cases.
:func:`read_table` reads it back, :func:`plot_sweep` draws a metric against a parameter.

Units: a parameter's from the scene's parameter metadata (:meth:`Scene.parameters`,
:meth:`Scene.unit_of`), a metric's from :meth:`Scene.metric_unit`.
"""

import dataclasses
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from matplotlib.figure import Figure

from ngincompat.atomic import atomic_path
from ngincompat.errors import ParameterError
from ngincompat.scenes.base import Scene
from ngincompat.studies.sweep.spec import Sweep
from ngincompat.workflow import io, plots, tables

NAME = "sweep"
PARQUET = f"{NAME}.parquet"
RECORD = f"{NAME}.json"
#: One line per case finished since the table was last written (see the runner).
JOURNAL = f"{NAME}.journal.jsonl"
FIXED_COLUMNS = ("case", "status", "warnings", "seconds", "error")


def column_units(scene_class: type[Scene], columns: Iterable[str]) -> dict[str, str]:
    """Column -> unit of a sweep of ``scene_class``: parameters with a unit, every metric,
    and the seconds."""
    parameters = scene_class.parameters()
    units = {}
    for column in columns:
        if column in parameters:
            unit = parameters[column][2]
            if unit:
                units[column] = scene_class.unit_of(unit)
        elif column == "seconds":
            units[column] = "s"
        elif column not in FIXED_COLUMNS:
            units[column] = scene_class.metric_unit(column)
    return units


@dataclasses.dataclass
class SweepTable:
    """The table of a sweep.

    Attributes
    ----------
    scene : str
        Name of the scene.
    varied : list of str
        The varied parameters (columns of the table).
    columns : list of str
    units : dict
        Column -> unit.
    rows : list of dict
        One per finished case, in case order; missing values are None.
    """

    scene: str
    varied: list
    columns: list
    units: dict
    rows: list

    def label(self, column: str) -> str:
        """An axis label: the column with its unit, ``"a [1/mm]"``."""
        return tables.header(column, self.units)


def make_table(sweep: Sweep, outcomes: Mapping[int, Mapping[str, Any]]) -> SweepTable:
    """The table of ``sweep`` from the outcomes of its finished cases.

    Parameters
    ----------
    sweep : Sweep
    outcomes : dict
        Case index -> dict with ``status``, ``warnings`` (how many the run gave; absent for
        a case that failed), ``varied`` (the case's varied parameters), ``metrics``,
        ``seconds`` and ``error``.

    Returns
    -------
    SweepTable
        With the sweep's metrics, or (none named) every metric a case reported.
    """
    ordered = [{"case": index, **outcomes[index]} for index in sorted(outcomes)]
    if sweep.metrics is not None:
        metrics = list(sweep.metrics)
    else:
        metrics = list(dict.fromkeys(m for o in ordered for m in o["metrics"]))
    columns = ["case", "status", "warnings", *sweep.varied, *metrics, "seconds", "error"]
    rows = [{"case": o["case"], "status": o["status"], "warnings": o.get("warnings"),
             **o["varied"],
             **{m: o["metrics"].get(m) for m in metrics},
             "seconds": o["seconds"], "error": o["error"]} for o in ordered]
    return SweepTable(sweep.scene, sweep.varied, columns,
                      column_units(sweep.scene_class, columns), rows)


def write_table(out: str | os.PathLike, table: SweepTable,
                record: Mapping[str, Any]) -> list[str]:
    """Write ``table`` into the folder ``out`` (atomically), with ``record`` (the sweep, see
    :meth:`Sweep.record`) in sweep.json; returns the names of the files written."""
    files = tables.write(out, NAME, table.rows, table.columns, table.units, **record)
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        return files
    arrays = {}
    for column in table.columns:
        values = [row[column] for row in table.rows]
        try:
            arrays[column] = pa.array(values)
        except (pa.ArrowInvalid, pa.ArrowTypeError):  # mixed types: as text
            arrays[column] = pa.array([None if v is None else str(v) for v in values])
    units = {column.encode(): unit.encode() for column, unit in table.units.items()}
    with atomic_path(Path(out) / PARQUET) as tmp:
        pq.write_table(pa.table(arrays).replace_schema_metadata(units), str(tmp))
    return [*files, PARQUET]


def read_table(sweep_dir: str | os.PathLike) -> SweepTable:
    """The table of a sweep folder (from its sweep.json, values with their types).

    Parameters
    ----------
    sweep_dir : path-like
        The ``out`` folder of a sweep run.

    Returns
    -------
    SweepTable

    Raises
    ------
    ParameterError
        The folder holds no table of a sweep.
    """
    path = Path(sweep_dir) / RECORD
    try:
        data = io.read_json(path)
        return SweepTable(data["scene"], list(data["varied"]), list(data["columns"]),
                          dict(data["units"]), list(data["rows"]))
    except FileNotFoundError:
        raise ParameterError(f"{sweep_dir}: no {RECORD} (is it the --out of a sweep "
                             "run?)") from None
    except (OSError, ValueError, KeyError, TypeError) as err:
        raise ParameterError(f"{path} is not the table of a sweep ({err})") from None


def _parse(text: str) -> int | float | str:
    """A --where value as the table holds it: int, float or text."""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def sweep_figure(table: SweepTable, metric: str, x: str, hue: str | None = None,
                 where: Mapping[str, Any] | None = None, logx: bool = False,
                 logy: bool = False) -> Figure:
    """A metric against a varied parameter, one curve per value of another.

    Parameters
    ----------
    table : SweepTable
    metric : str
        Column on the y axis.
    x : str
        Parameter on the x axis.
    hue : str, optional
        Parameter with one curve per value.
    where : dict, optional
        Column -> value: keep only these rows (a text value is compared as the number it
        spells, if it spells one).
    logx, logy : bool
        Logarithmic axes.

    Returns
    -------
    matplotlib.figure.Figure
        Axes labelled with the columns' units; only the cases that are done are drawn.

    Raises
    ------
    ParameterError
        A column that the table does not have, no case with a value, or several cases at
        one point of a curve (a varied parameter neither on the axes nor fixed by ``where``).
    """
    allowed = ", ".join(c for c in table.columns if c not in FIXED_COLUMNS)
    for role, name in (("metric", metric), ("x", x), ("hue", hue)):
        if name is not None and name not in table.columns:
            raise ParameterError(f"{role} {name!r} is not a column of the sweep: allowed "
                                 f"{allowed}")
    rows = [r for r in table.rows if r["status"] == "done" and r[metric] is not None]
    for key, value in (where or {}).items():
        if key not in table.columns:
            raise ParameterError(f"where {key}={value}: {key!r} is not a column of the sweep: "
                                 f"allowed {allowed}")
        wanted = _parse(value) if isinstance(value, str) else value
        rows = [r for r in rows if r[key] == wanted]
    if not rows:
        raise ParameterError(f"metric {metric!r}: no finished case has a value")
    groups: dict[Any, list[dict[str, Any]]] = {}
    for r in rows:
        groups.setdefault(r[hue] if hue else None, []).append(r)
    curves = {}
    for value in sorted(groups, key=_sort_key):
        group = sorted(groups[value], key=lambda r: _sort_key(r[x]))
        xs = [r[x] for r in group]
        if len(set(xs)) < len(xs):
            others = [v for v in table.varied if v not in (x, hue)]
            raise ParameterError(
                f"several cases share {x} = {xs[0]!r}"
                + (f" and {hue} = {value!r}" if hue else "")
                + f": fix the other varied parameters ({', '.join(others) or 'none'}) with "
                  "where KEY=VALUE or choose one as hue")
        label = f"{hue} = {_text(value)}" if hue else ""
        curves[label] = (xs, [r[metric] for r in group])
    return plots.curves_figure(curves, table.label(x), table.label(metric),
                               title=f"{table.scene}: {metric} against {x}", logx=logx,
                               logy=logy)


def plot_sweep(sweep_dir: str | os.PathLike, metric: str, x: str, out: str | os.PathLike,
               hue: str | None = None, where: Mapping[str, Any] | None = None,
               logx: bool = False, logy: bool = False) -> Path:
    """Draw :func:`sweep_figure` of the sweep in ``sweep_dir`` into the PNG file ``out``
    (atomically); returns its path."""
    plots.save(sweep_figure(read_table(sweep_dir), metric, x, hue=hue, where=where, logx=logx,
                            logy=logy), out)
    return Path(out)


def _sort_key(value: object) -> tuple[int, Any, str]:
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return (0, value, "")
    return (1, 0, str(value))


def _text(value: object) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)
