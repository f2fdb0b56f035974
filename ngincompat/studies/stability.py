"""A numerical stress-test matrix: where does the growth solver converge, and at what cost?

Every :class:`Cell` is one traction-free solve of the unit cube, from t = 0 to 1, whose growth,
material and discretisation are parameters: shrinkage to theta = 0.5 and growth to 3 for every
growth kind, Poisson's ratios up to 0.499, steep tanh fronts, orders 1-8, one element and a
fine mesh, GOH fibers in compression with k2 up to 50, the full growth in one load step against
eight, and two inputs that must fail cleanly. :func:`run_cell` never raises; a cell ends as

* ``"converged"``: the growth reached t = 1 and the strain energy is finite,
* ``"error"``: a clean :class:`~ngincompat.errors.NgincompatError` (a parameter out of range,
  or the load step fell below ``min_step``), with its one-line message,
* ``"unexpected"``: any other exception, or a non-finite result: a bug of ngincompat (or an
  NGSolve failure that should become a clear error). The row keeps the traceback; the tests
  assert that no cell ends so.

Each cell reports the load steps attempted and converged, the Newton iterations of all attempted
steps (failed ones included), the wall time of the solve and the strain energy. The work of a
cell is bounded: at most 30 Newton iterations per load step (each with at most 30 halvings of
the line search), and no load step below 1e-3.

:func:`locking` shows volumetric locking at nu = 0.499 and its removal by the mixed
formulation: the cube's strain energy under p-refinement on 2 x 2 x 2 hexahedra, displacement
and mixed, next to displacement runs at nu = 0.3.

``ngincompat bench stability [--quick] [--threads N] [--out DIR]`` runs both; from Python::

    from ngincompat.studies import stability
    lines = stability.main(quick=True, out="results/stability")
"""

import contextlib
import logging
import math
import os
import time as _time
import traceback
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any, Literal

import ngsolve as ngs
import numpy as np

from geometries import cube
from ngincompat import config
from ngincompat.errors import NgincompatError
from ngincompat.fem.problem import GrowthMechanics
from ngincompat.fem.solver import NewtonOptions
from ngincompat.fem.stepping import solve_growth
from ngincompat.mechanics.expressions import parse_expression
from ngincompat.mechanics.fields import DirectionField, constant
from ngincompat.mechanics.growth import check_positive, make_growth
from ngincompat.mechanics.kinematics import deformation_gradient, elastic_part
from ngincompat.mechanics.materials import GOH, MaterialKind, NeoHookean, lame_lambda
from ngincompat.sampling import element_points
from ngincompat.workflow import io, tables

log = logging.getLogger(__name__)

#: Shear modulus of every cell [MPa] (the paper's idealized scenes).
MU = 0.55
#: Fiber stiffness k1 [MPa] of the GOH cells.
GOH_K1 = 1.0
#: Fiber dispersion kappa of the GOH cells: 0, aligned fibers (the Macaulay bracket acts on
#: the full fiber strain).
GOH_KAPPA = 0.0
#: The cube's growth: theta = 1 + X1 t / 4 (section 3.1).
CUBE_THETA = "1 + 0.25*X1*t"
#: Status of a cell that raised something other than an ngincompat error.
UNEXPECTED = "unexpected"


@dataclass(frozen=True)
class Cell:
    """One solve of the unit cube [0, 1]^3 (mm), traction-free, from t = 0 to 1.

    Attributes
    ----------
    group, label : str
        Where the cell sits in the matrix and what it varies.
    theta : str
        Growth indicator theta(X1, X2, X3, t), parsed by :func:`parse_expression`.
    kind : {"isotropic", "area", "fiber"}
    direction : str or None
        N0 (area) or f0 (fiber) growth direction: "e1", "e2" or "e3".
    material : {"neo-hookean", "goh"}
    nu : float
        Poisson's ratio; lambda = 2 mu nu / (1 - 2 nu), mu = :data:`MU`.
    k2 : float
        GOH fiber nonlinearity (k1 = :data:`GOH_K1`, kappa = :data:`GOH_KAPPA`).
    fiber : str
        GOH fiber direction a0.
    order : int
        Polynomial order of the displacement.
    formulation : {"displacement", "mixed"}
        See :class:`~ngincompat.fem.problem.GrowthMechanics` (mixed: with a condensed pressure).
    maxh : float
        Element size of the mesh.
    elements : {"hex", "tet"}
    steps, max_iter, min_step :
        :class:`~ngincompat.fem.solver.NewtonOptions`.
    """

    group: str
    label: str
    theta: str = CUBE_THETA
    kind: str = "isotropic"
    direction: str | None = None
    material: str = "neo-hookean"
    nu: float = 0.4
    k2: float = 1.0
    fiber: str = "e1"
    order: int = 2
    formulation: Literal["displacement", "mixed"] = "displacement"
    maxh: float = 0.5
    elements: str = "hex"
    steps: int = 1
    max_iter: int = 30
    min_step: float = 1e-3

    def params(self) -> dict[str, Any]:
        """The parameters that define the cell (without group and label)."""
        return {f.name: getattr(self, f.name) for f in fields(self)
                if f.name not in ("group", "label")}

    def build(self) -> tuple[GrowthMechanics, ngs.Parameter]:
        """The problem and its time parameter (at t = 0), after checking theta > 0."""
        time = ngs.Parameter(0.0)
        theta = parse_expression(self.theta, time, name="theta")
        direction = constant(self.direction) if self.direction else None
        growth = make_growth(self.kind, theta, direction)
        mesh = cube(maxh=self.maxh, elements=self.elements)
        check_positive(growth.theta, mesh, time, expression=self.theta)
        if self.material == "goh":
            material: MaterialKind = GOH(MU, lame_lambda(MU, self.nu), GOH_K1, self.k2, GOH_KAPPA)
            fibers: tuple[DirectionField, ...] = (constant(self.fiber),)
        else:
            material = NeoHookean.from_nu(MU, self.nu)
            fibers = ()
        problem = GrowthMechanics(mesh, growth, material, order=self.order, fibers=fibers,
                                  formulation=self.formulation)
        return problem, time

    def options(self) -> NewtonOptions:
        return NewtonOptions(steps=self.steps, max_iter=self.max_iter, min_step=self.min_step)


def _one_line(err: BaseException) -> str:
    return " ".join(str(err).split()) or type(err).__name__


def run_cell(cell: Cell) -> dict[str, Any]:
    """Solve one cell; never raises. Returns a flat dict (see the module docstring)."""
    row = {"group": cell.group, "label": cell.label, "status": "error", "message": "",
           "ndof": None, "steps_attempted": 0, "steps_converged": 0, "newton": 0,
           "t_reached": 0.0, "seconds": 0.0, "strain_energy": None, "params": cell.params()}
    history = None
    try:
        problem, time = cell.build()
        row["ndof"] = problem.ndof
        start = _time.perf_counter()
        try:
            history = solve_growth(problem, time, cell.options())
        finally:
            row["seconds"] = _time.perf_counter() - start
        results = {"strain_energy": problem.strain_energy()}
        if cell.material == "goh":
            results.update(zip(("fiber_strain_min", "fiber_strain_max", "fiber_compressed"),
                               fiber_strain(problem), strict=True))
        for key, value in results.items():
            if not math.isfinite(value):
                raise FloatingPointError(f"{key} is {value} after convergence")
        row.update(status="converged", **results)
    except NgincompatError as err:
        row["message"] = f"{type(err).__name__}: {_one_line(err)}"
        if getattr(err, "history", None) is not None:
            history = err.history  # type: ignore[attr-defined]  # the getattr above
    except Exception as err:  # a cell never ends in a traceback; the row keeps it
        row.update(status=UNEXPECTED, message=f"{type(err).__name__}: {_one_line(err)}",
                   traceback=traceback.format_exc())
        log.warning("cell %s / %s: %s", cell.group, cell.label, row["message"])
    if history is not None:
        row["steps_attempted"] = len(history.steps)
        row["steps_converged"] = sum(s.converged for s in history.steps)
        row["newton"] = sum(s.iterations for s in history.steps)
        row["t_reached"] = history.t_reached
    log.info("%s / %s: %s %s", cell.group, cell.label, row["status"], row["message"])
    return row


def fiber_strain(problem: GrowthMechanics) -> tuple[float, float, float]:
    """The GOH fiber strain E = kappa I1bar + (1 - 3 kappa) Cbar : a (x) a - 1 of the first
    fiber family (eq. 39) at the integration points and vertices of every element: returns
    (min, max, volume fraction with E < 0). Where E < 0 the fibers are compressed and the
    Macaulay bracket switches them off."""
    Fe = elastic_part(deformation_gradient(problem.u), problem.growth.Fg)
    C = Fe.trans * Fe
    Jm23 = ngs.Det(Fe) ** (-2.0 / 3.0)
    a = problem.fibers_intermediate()[0]
    kappa = problem.material.kappa  # type: ignore[attr-defined]  # a GOH cell's
    E = kappa * Jm23 * ngs.Trace(C) + (1 - 3 * kappa) * Jm23 * ngs.InnerProduct(a, C * a) - 1
    values = np.asarray(E(element_points(problem.mesh, 2 * problem.order))).ravel()
    order = 2 * problem.order + 2
    volume = ngs.Integrate(ngs.CF(1.0), problem.mesh, order=order)
    compressed = ngs.Integrate(ngs.IfPos(E, 0.0, 1.0), problem.mesh, order=order) / volume
    return float(values.min()), float(values.max()), float(compressed)


def _theta_to(theta_end: float, coordinate: str = "X1") -> str:
    """theta = 1 + (theta_end - 1) X t: from 1 at X = 0 to theta_end at X = 1 (and t = 1)."""
    return f"1 + ({theta_end - 1:g})*{coordinate}*t"


def _tanh_front(delta: float) -> str:
    """A growth front of width ``delta`` at X1 = 0.5: theta from 1 to 1.25."""
    return f"1 + 0.25*(1 + tanh((X1 - 0.5)/{delta:g}))/2*t"


def matrix(quick: bool = False) -> list[Cell]:
    """The cells of the stress-test matrix, in table order.

    ``quick``: a small corner for the default test suite (a few seconds on one thread): one or
    two cells per group, the hard growth to theta = 3 and the two designed errors.
    """
    errors = [
        Cell("errors", "theta <= 0 (rejected before the solve)", theta="1 - 2*X1*t"),
        Cell("errors", "max_iter = 1, min_step = 0.25 (must give up)", theta=_theta_to(3),
             max_iter=1, min_step=0.25),
    ]
    if quick:
        return [
            Cell("growth", "isotropic, theta -> 3", theta=_theta_to(3)),
            Cell("growth", "fiber e1, theta(X2) -> 0.5", theta=_theta_to(0.5, "X2"),
                 kind="fiber", direction="e1"),
            Cell("nu", "nu = 0.499", nu=0.499),
            Cell("nu", "nu = 0.499, mixed", nu=0.499, formulation="mixed"),
            Cell("gradient", "tanh front, delta = 0.01", theta=_tanh_front(0.01), maxh=0.25),
            Cell("order", "order 1, one hex", order=1, maxh=1.0),
            Cell("goh", "k2 = 50, shrink to 0.5, fibers e1", theta=_theta_to(0.5),
                 material="goh", k2=50.0),
            Cell("steps", "theta -> 3, order 3, steps = 1", theta=_theta_to(3), order=3),
            Cell("steps", "theta -> 3, order 3, steps = 8", theta=_theta_to(3), order=3,
                 steps=8),
            *errors,
        ]
    cells = []
    for kind, direction in (("isotropic", None), ("area", "e3"), ("fiber", "e1")):
        for theta_end in (0.5, 3.0):
            name = kind if direction is None else f"{kind} {direction}"
            cells.append(Cell("growth", f"{name}, theta -> {theta_end:g}",
                              theta=_theta_to(theta_end), kind=kind, direction=direction))
    # f0 = e1 with theta(X1) is compatible (Fg = Grad of a map): stress-free. With theta(X2)
    # the fibers of different length lie side by side: incompatible.
    for theta_end in (0.5, 3.0):
        cells.append(Cell("growth", f"fiber e1, theta(X2) -> {theta_end:g}",
                          theta=_theta_to(theta_end, "X2"), kind="fiber", direction="e1"))
    for nu in (0.3, 0.45, 0.49, 0.499):
        cells.append(Cell("nu", f"nu = {nu:g}", nu=nu))
    for nu in (0.49, 0.499):
        cells.append(Cell("nu", f"nu = {nu:g}, mixed", nu=nu, formulation="mixed"))
    for delta in (0.1, 0.03, 0.01):
        cells.append(Cell("gradient", f"tanh front, delta = {delta:g}",
                          theta=_tanh_front(delta), maxh=0.25, order=3))
    for order in range(1, 9):
        cells.append(Cell("order", f"order {order}, one hex", order=order, maxh=1.0))
    cells += [
        Cell("mesh", "one hex, order 2", maxh=1.0),
        Cell("mesh", "maxh 0.125 hex (512), order 2", maxh=0.125),
        Cell("mesh", "maxh 0.25 tet, order 2", maxh=0.25, elements="tet"),
    ]
    for k2 in (1.0, 10.0, 50.0):
        for theta_end in (0.5, 3.0):
            cells.append(Cell("goh", f"k2 = {k2:g}, theta -> {theta_end:g}, fibers e1",
                              theta=_theta_to(theta_end), material="goh", k2=k2))
    for steps in (1, 8):
        cells.append(Cell("steps", f"theta -> 3, order 4, steps = {steps}",
                          theta=_theta_to(3), order=4, steps=steps))
    for steps in (1, 8):
        cells.append(Cell("steps", f"nu = 0.499, order 3, steps = {steps}",
                          nu=0.499, order=3, steps=steps))
        cells.append(Cell("steps", f"nu = 0.499, order 3, mixed, steps = {steps}",
                          nu=0.499, order=3, steps=steps, formulation="mixed"))
    return cells + errors


@contextlib.contextmanager
def ngsolve_threads(threads: int | None = None) -> Iterator[None]:
    """Run the block with ``threads`` NGSolve threads (None: leave them as they are).

    Afterwards the threads configured before are restored (:func:`ngincompat.config.threads`).
    """
    if threads is None:
        yield
        return
    with config.using(threads=int(threads)):
        yield


def run_matrix(cells: Iterable[Cell], threads: int | None = None) -> list[dict[str, Any]]:
    """Run every cell in order (with ``threads`` NGSolve threads); returns the rows."""
    with ngsolve_threads(threads):
        return [run_cell(cell) for cell in cells]


def _fmt(value: Any, spec: str) -> str:
    return "" if value is None else format(value, spec)


def _note(row: Mapping[str, Any]) -> str:
    if row.get("fiber_compressed") is not None:
        return (f"fiber strain in [{row['fiber_strain_min']:.3f}, "
                f"{row['fiber_strain_max']:.3f}], compressed in "
                f"{100 * row['fiber_compressed']:.0f} % of the volume")
    return row["message"].replace("|", "/")


#: Columns of the matrix's table and their units.
COLUMNS = ("group", "cell", "status", "ndof", "load steps conv./att.", "newton", "t_reached",
           "seconds", "strain_energy", "note")
UNITS = {"seconds": "s", "strain_energy": "N mm"}


def format_table(rows: Iterable[Mapping[str, Any]]) -> str:
    """The rows of :func:`run_matrix` as a markdown table."""
    shown = [{**r, "cell": r["label"], "note": _note(r),
              "load steps conv./att.": f"{r['steps_converged']}/{r['steps_attempted']}"}
             for r in rows]
    return tables.markdown(shown, list(COLUMNS), UNITS)


def _relative(a: float | None, b: float | None) -> float | None:
    """|a - b| / |b|, None if either is missing or b is zero."""
    if a is None or b is None or b == 0:
        return None
    return abs(a - b) / abs(b)


def locking(orders: Iterable[int] = (1, 2, 3, 4, 5), nu: float = 0.499, maxh: float = 0.5,
            reference_nu: float | None = 0.3, threads: int | None = None) -> list[dict[str, Any]]:
    """Volumetric locking: the cube (theta = 1 + X1 t / 4) on hexahedra of size ``maxh`` at
    ``nu`` for each order, in the displacement and the mixed formulation (orders >= 2), next
    to displacement runs at the compressible ``reference_nu``.

    Returns one row per order: the displacement row at ``nu``, with ``mixed`` (the mixed row,
    None at order 1) and ``reference`` (the row at ``reference_nu``). Every row carries
    ``change`` (relative change from the previous order of its series) and ``vs_highest``
    (relative difference to the highest order of the mixed series, the most accurate value at
    ``nu``; for the reference series, to its own highest order). Locking shows as a far larger
    error of the low orders at ``nu`` than at ``reference_nu``; the mixed series removes it.
    """
    orders = sorted(orders)

    def series(nu_: float, formulation: Literal["displacement", "mixed"],
               wanted: Iterable[int]) -> list[dict[str, Any]]:
        return [run_cell(Cell("locking", f"order {p}", nu=nu_, order=p, maxh=maxh,
                              formulation=formulation)) for p in wanted]

    with ngsolve_threads(threads):
        rows = series(nu, "displacement", orders)
        mixed = series(nu, "mixed", [p for p in orders if p >= 2])
        refs = series(reference_nu, "displacement", orders) if reference_nu is not None else []
    best_mixed = mixed[-1]["strain_energy"] if mixed else rows[-1]["strain_energy"]
    for line, best in ((rows, best_mixed), (mixed, best_mixed),
                       (refs, refs[-1]["strain_energy"] if refs else None)):
        previous = None
        for r in line:
            r["order"] = r["params"]["order"]
            r["change"] = _relative(previous, r["strain_energy"])
            r["vs_highest"] = _relative(r["strain_energy"], best)
            previous = r["strain_energy"]
    by_order = {r["order"]: r for r in mixed}
    for i, r in enumerate(rows):
        r["mixed"] = by_order.get(r["order"])
        r["reference"] = refs[i] if refs else None
    return rows


def locking_table(rows: list[dict[str, Any]] | None = None) -> str:
    """The locking study as a markdown table (runs :func:`locking` unless ``rows`` given)."""
    rows = locking() if rows is None else rows
    nu = rows[0]["params"]["nu"]
    ref = rows[0].get("reference")
    head = (f"| order | ndof | Newton | solve [s] | strain energy, nu = {nu:g} [N mm] | change "
            "from previous order | difference to highest mixed | mixed: ndof | Newton | "
            "solve [s] | strain energy | change | difference to highest mixed |")
    if ref:
        head += f" strain energy, nu = {ref['params']['nu']:g} | its difference to highest |"
    lines = [head, "|" + "---|" * (15 if ref else 13)]

    def cells(r: Mapping[str, Any] | None) -> list[str]:
        if r is None:
            return ["", "", "", "", "", ""]
        return [_fmt(r["ndof"], "d"), str(r["newton"]), f"{r['seconds']:.2f}",
                _fmt(r["strain_energy"], ".6e"), _fmt(r["change"], ".1e"),
                _fmt(r["vs_highest"], ".1e")]

    for r in rows:
        parts = [str(r["order"]), *cells(r), *cells(r.get("mixed"))]
        if ref:
            parts += [_fmt(r["reference"]["strain_energy"], ".6e"),
                      _fmt(r["reference"]["vs_highest"], ".1e")]
        line = "| " + " | ".join(parts) + " |"
        bad = [x for x in (r, r.get("mixed")) if x is not None and x["status"] != "converged"]
        line += "".join(f" {x['status']}: {x['message']}" for x in bad)
        lines.append(line)
    return "\n".join(lines)


#: Orders of the locking study.
LOCKING_ORDERS = (1, 2, 3, 4, 5)
#: Orders of the locking study with ``--quick``.
LOCKING_ORDERS_QUICK = (1, 2, 3)


def main(quick: bool = False, threads: int | None = 1,
         out: str | os.PathLike | None = None) -> list[str]:
    """Run the matrix and the locking study; returns the lines to print.

    Parameters
    ----------
    quick : bool
        Only a small corner of the matrix (:func:`matrix`) and the locking orders
        :data:`LOCKING_ORDERS_QUICK`.
    threads : int or None
        NGSolve threads (default 1: the cells are small, and times on a shared machine stay
        comparable); None leaves NGSolve's setting.
    out : path-like, optional
        Folder of ``stability.json`` (the rows of both) and of the two tables as markdown,
        ``stability.md`` and ``locking.md``, written atomically.

    Returns
    -------
    list of str
    """
    start = _time.perf_counter()
    rows = run_matrix(matrix(quick=quick), threads=threads)
    lock = locking(LOCKING_ORDERS_QUICK if quick else LOCKING_ORDERS, threads=threads)
    seconds = _time.perf_counter() - start
    counts = {s: sum(r["status"] == s for r in rows) for s in ("converged", "error", UNEXPECTED)}
    summary = (f"{len(rows)} cells: {counts['converged']} converged, {counts['error']} error, "
               f"{counts[UNEXPECTED]} unexpected; matrix and locking study {seconds:.0f} s")
    lines = [format_table(rows), "", locking_table(lock), "", summary]
    if out is not None:
        path = io.write_json(Path(out) / "stability.json",
                             {"quick": quick, "threads": threads, "seconds": seconds,
                              "rows": rows, "locking": lock, **io.provenance()})
        tables.write_markdown(Path(out) / "stability.md", f"{lines[0]}\n\n{summary}")
        tables.write_markdown(Path(out) / "locking.md", lines[2])
        lines.append(f"written to {path} (and stability.md, locking.md)")
    return lines
