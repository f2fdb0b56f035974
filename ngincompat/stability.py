"""A numerical stress-test matrix: where does the growth solver converge, and at what cost?

Every :class:`Cell` is one solve of a cube whose growth, material and discretisation are given
by parameters: large shrinkage and growth for every growth kind, Poisson's ratios up to 0.499,
steep tanh fronts, polynomial orders 1-8, one element and a fine mesh, GOH fibers in
compression, and the full growth in one load step against many. :func:`run_cell` never raises:
a cell ends as

* ``"converged"``: the growth reached t = 1 and the strain energy is finite,
* ``"error"``: a clean :class:`~ngincompat.errors.NgincompatError` (a parameter out of range,
  or the load step fell below ``min_step``), with its one-line message,
* ``"unexpected"``: any other exception, or a non-finite result. This is a bug of ngincompat
  (or an NGSolve failure that should become a clear error); the tests assert that none occurs.

Each cell reports the load steps attempted and converged, the Newton iterations of all
attempted steps, the wall time of the solve and the strain energy. Nothing hangs: every cell
runs with at most 30 Newton iterations per load step and a smallest load step of 1e-3.

:func:`locking_table` shows volumetric locking at nu = 0.499: the cube's strain energy under
p-refinement on 2 x 2 x 2 hexahedra, where order 1 is far off and higher orders converge.

Command line (when wired into the CLI): ``stability [--quick] [--out FOLDER]``; from Python::

    from ngincompat import stability
    print("\\n".join(stability.main(stability.parse_args(["--quick"]))))
"""

import argparse
import logging
import math
import time as _time
from dataclasses import dataclass, fields

import ngsolve as ngs

from . import io
from .errors import NgincompatError
from .expressions import parse_expression
from .fields import constant
from .growth import check_positive, make_growth
from .materials import GOH, NeoHookean
from .problem import GrowthMechanics
from .solver import NewtonOptions, solve_growth

log = logging.getLogger(__name__)

#: Shear modulus of every cell [MPa] (the paper's idealized scenes).
MU = 0.55
#: Fiber stiffness k1 [MPa] and dispersion of the GOH cells (aligned fibers: the Macaulay
#: bracket acts on the full fiber strain).
GOH_K1 = 1.0
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
    maxh : float
        Element size of the mesh.
    elements : {"hex", "tet"}
    steps, max_iter, min_step :
        :class:`~ngincompat.solver.NewtonOptions`.
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
    maxh: float = 0.5
    elements: str = "hex"
    steps: int = 1
    max_iter: int = 30
    min_step: float = 1e-3

    def params(self):
        """The parameters that define the cell (without group and label)."""
        return {f.name: getattr(self, f.name) for f in fields(self)
                if f.name not in ("group", "label")}

    def build(self):
        """The problem and its time parameter (at t = 0), after checking theta > 0."""
        from geometries import cube

        time = ngs.Parameter(0.0)
        theta = parse_expression(self.theta, time, name="theta")
        direction = constant(self.direction) if self.direction else None
        growth = make_growth(self.kind, theta, direction)
        mesh = cube(maxh=self.maxh, elements=self.elements)
        check_positive(growth.theta, mesh, time)
        if self.material == "goh":
            nh = NeoHookean.from_nu(MU, self.nu)
            material = GOH(MU, nh.lam, GOH_K1, self.k2, GOH_KAPPA)
            fibers = (constant(self.fiber),)
        else:
            material = NeoHookean.from_nu(MU, self.nu)
            fibers = ()
        problem = GrowthMechanics(mesh, growth, material, order=self.order, fibers=fibers)
        return problem, time

    def options(self):
        return NewtonOptions(steps=self.steps, max_iter=self.max_iter, min_step=self.min_step)


def _one_line(err):
    return " ".join(str(err).split()) or type(err).__name__


def run_cell(cell):
    """Solve one cell; never raises. Returns a flat dict (see the module docstring)."""
    row = {"group": cell.group, "label": cell.label, "status": "error", "message": "",
           "ndof": None, "steps_attempted": 0, "steps_converged": 0, "newton": 0,
           "t_reached": 0.0, "seconds": 0.0, "strain_energy": None, "params": cell.params()}
    history = None
    start = None
    try:
        problem, time = cell.build()
        row["ndof"] = problem.ndof
        if cell.material == "goh":
            row["fiber_compressed"] = None
        start = _time.perf_counter()
        try:
            history = solve_growth(problem, time, cell.options())
        finally:
            row["seconds"] = _time.perf_counter() - start
        energy = problem.strain_energy()
        if not math.isfinite(energy):
            raise FloatingPointError(f"strain energy is {energy} after convergence")
        row.update(status="converged", strain_energy=energy)
        if cell.material == "goh":
            row["fiber_compressed"] = fiber_compressed_fraction(problem)
    except NgincompatError as err:
        row["message"] = f"{type(err).__name__}: {_one_line(err)}"
        history = getattr(err, "history", None) or history
    except Exception as err:  # noqa: BLE001 - a cell must never end in a traceback
        log.exception("cell %s/%s raised", cell.group, cell.label)
        row["status"] = UNEXPECTED
        row["message"] = f"{type(err).__name__}: {_one_line(err)}"
    if history is not None:
        row["steps_attempted"] = len(history.steps)
        row["steps_converged"] = sum(s.converged for s in history.steps)
        row["newton"] = sum(s.iterations for s in history.steps)
        row["t_reached"] = history.t_reached
    log.info("%s / %s: %s %s", cell.group, cell.label, row["status"], row["message"])
    return row


def fiber_compressed_fraction(problem):
    """Volume fraction of the body where the GOH fiber strain E = Cbar : H - 1 is negative
    (fibers in compression, cut off by the Macaulay bracket), for the first fiber family."""
    from .kinematics import deformation_gradient, elastic_part

    Fe = elastic_part(deformation_gradient(problem.u), problem.growth.Fg)
    C = Fe.trans * Fe
    Jm23 = ngs.Det(Fe) ** (-2.0 / 3.0)
    a = problem.fibers_intermediate()[0]
    kappa = problem.material.kappa
    E = kappa * Jm23 * ngs.Trace(C) + (1 - 3 * kappa) * Jm23 * ngs.InnerProduct(a, C * a) - 1
    mesh = problem.mesh
    order = 2 * problem.order + 2
    volume = ngs.Integrate(ngs.CF(1.0), mesh, order=order)
    return float(ngs.Integrate(ngs.IfPos(E, 0.0, 1.0), mesh, order=order)) / volume


def _theta_to(theta_end, coordinate="X1"):
    return f"1 + ({theta_end - 1:g})*{coordinate}*t"


def _tanh_front(delta):
    return f"1 + 0.25*(1 + tanh((X1 - 0.5)/{delta:g}))/2*t"


def matrix(quick=False):
    """The cells of the stress-test matrix; ``quick``: a small corner (~30 s on 2 cores)."""
    if quick:
        return [
            Cell("growth", "isotropic theta -> 3", theta=_theta_to(3)),
            Cell("growth", "fiber e1, theta(X2) -> 0.5", theta=_theta_to(0.5, "X2"),
                 kind="fiber", direction="e1"),
            Cell("nu", "nu = 0.499", nu=0.499),
            Cell("gradient", "tanh front delta = 0.03", theta=_tanh_front(0.03), maxh=0.25),
            Cell("order", "order 1, one hex", order=1, maxh=1.0),
            Cell("goh", "k2 = 50, shrink to 0.5", theta=_theta_to(0.5), material="goh",
                 k2=50.0),
            Cell("steps", "theta -> 3, order 3, 1 step", theta=_theta_to(3), order=3),
            Cell("input", "theta <= 0 (clean error)", theta="1 - 2*X1*t"),
        ]
    cells = []
    for kind, direction in (("isotropic", None), ("area", "e3"), ("fiber", "e1")):
        for theta_end in (0.5, 3.0):
            name = kind if direction is None else f"{kind} {direction}"
            cells.append(Cell("growth", f"{name}, theta -> {theta_end:g}",
                              theta=_theta_to(theta_end), kind=kind, direction=direction))
    for theta_end in (0.5, 3.0):   # f0 = e1 with theta(X1) is compatible: stress-free
        cells.append(Cell("growth", f"fiber e1, theta(X2) -> {theta_end:g}",
                          theta=_theta_to(theta_end, "X2"), kind="fiber", direction="e1"))
    for nu in (0.3, 0.45, 0.49, 0.499):
        cells.append(Cell("nu", f"nu = {nu:g}", nu=nu))
    for delta in (0.1, 0.03, 0.01):
        cells.append(Cell("gradient", f"tanh front delta = {delta:g}",
                          theta=_tanh_front(delta), maxh=0.25, order=3))
    for order in range(1, 9):
        cells.append(Cell("order", f"order {order}, one hex", order=order, maxh=1.0))
    cells += [
        Cell("mesh", "one hex, order 2", maxh=1.0),
        Cell("mesh", "maxh 0.125 hex, order 2", maxh=0.125),
        Cell("mesh", "maxh 0.25 tet, order 2", maxh=0.25, elements="tet"),
    ]
    for k2 in (1.0, 10.0, 50.0):
        cells.append(Cell("goh", f"k2 = {k2:g}, shrink to 0.5", theta=_theta_to(0.5),
                          material="goh", k2=k2))
        cells.append(Cell("goh", f"k2 = {k2:g}, grow to 2", theta=_theta_to(2.0),
                          material="goh", k2=k2))
    for steps in (1, 8):
        cells.append(Cell("steps", f"theta -> 3, order 4, steps = {steps}",
                          theta=_theta_to(3), order=4, steps=steps))
    return cells


def run_matrix(cells):
    """Run every cell in order; returns the rows."""
    return [run_cell(cell) for cell in cells]


def _fmt(value, spec):
    return "" if value is None else format(value, spec)


def format_table(rows):
    """The rows as a markdown table."""
    lines = ["| group | cell | status | ndof | load steps (conv./att.) | Newton | t reached | "
             "solve [s] | strain energy [N mm] | message |",
             "|" + "---|" * 10]
    for r in rows:
        message = r["message"]
        if r.get("fiber_compressed") is not None:
            message = f"fibers compressed in {100 * r['fiber_compressed']:.0f} % of the volume"
        lines.append(
            f"| {r['group']} | {r['label']} | {r['status']} | {_fmt(r['ndof'], 'd')} | "
            f"{r['steps_converged']}/{r['steps_attempted']} | {r['newton']} | "
            f"{r['t_reached']:.4g} | {r['seconds']:.2f} | {_fmt(r['strain_energy'], '.6e')} | "
            f"{message.replace('|', '/')} |")
    return "\n".join(lines)


def locking(orders=(1, 2, 3, 4, 5), nu=0.499, maxh=0.5):
    """The cube (theta = 1 + X1 t / 4) at ``nu`` on hexahedra of size ``maxh`` for each order.

    Returns rows with the strain energy and its relative change from the previous order and
    relative difference to the highest order.
    """
    rows = [run_cell(Cell("locking", f"order {p}", nu=nu, order=p, maxh=maxh))
            for p in orders]
    best = rows[-1]["strain_energy"]
    previous = None
    for r in rows:
        energy = r["strain_energy"]
        ok = energy is not None
        r["change"] = abs(energy - previous) / abs(energy) if ok and previous else None
        r["vs_highest"] = abs(energy - best) / abs(best) if ok and best else None
        previous = energy
    return rows


def locking_table(rows=None):
    """The locking study as a markdown table (runs :func:`locking` unless ``rows`` given)."""
    rows = locking() if rows is None else rows
    nu = rows[0]["params"]["nu"]
    lines = [f"| order (nu = {nu:g}) | ndof | status | Newton | solve [s] | "
             "strain energy [N mm] | change from previous order | difference to highest order |",
             "|" + "---|" * 8]
    for r in rows:
        lines.append(f"| {r['params']['order']} | {r['ndof']} | {r['status']} | {r['newton']} | "
                     f"{r['seconds']:.2f} | {_fmt(r['strain_energy'], '.6e')} | "
                     f"{_fmt(r['change'], '.1e')} | {_fmt(r['vs_highest'], '.1e')} |")
    return "\n".join(lines)


def add_arguments(parser):
    parser.add_argument("--quick", action="store_true",
                        help="only a small corner of the matrix (about 30 s)")
    parser.add_argument("--out", default=None, help="folder for stability.json")


def parse_args(argv=()):
    parser = argparse.ArgumentParser(prog="stability", description=__doc__.splitlines()[0])
    add_arguments(parser)
    return parser.parse_args(list(argv))


def main(args):
    """Run the matrix and the locking study; returns the lines to print."""
    start = _time.perf_counter()
    rows = run_matrix(matrix(quick=args.quick))
    lock = locking(orders=(1, 3, 4) if args.quick else (1, 2, 3, 4, 5))
    seconds = _time.perf_counter() - start
    counts = {s: sum(r["status"] == s for r in rows) for s in ("converged", "error", UNEXPECTED)}
    summary = (f"{len(rows)} cells: {counts['converged']} converged, {counts['error']} error, "
               f"{counts[UNEXPECTED]} unexpected; {seconds:.0f} s")
    if args.out:
        io.write_json(f"{args.out}/stability.json",
                      {"quick": args.quick, "rows": rows, "locking": lock, "seconds": seconds,
                       **io.provenance()})
    return [format_table(rows), "", locking_table(lock), "", summary]


__all__ = ["Cell", "run_cell", "matrix", "run_matrix", "format_table", "locking",
           "locking_table", "add_arguments", "main"]
