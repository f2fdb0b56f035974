"""The cost of the parts of one step of the folding scene's perfect branch on the default
bilayer (or another: ``python step_costs.py maxh=0.2``): residual, tangent assembly, the
factorisations, a solve, the eigenpairs and the samplings along the top. Minimum of repeats,
in milliseconds to four digits (a coarse bilayer's residual takes less than one)."""

import sys
import time

from ngincompat import config
from ngincompat.fem import buckling
from ngincompat.fem.solver import NewtonOptions, NewtonSolver
from ngincompat.scenes.folding import FoldingScene


def best(name, f, n=3):
    times = []
    for _ in range(n):
        start = time.perf_counter()
        f()
        times.append(time.perf_counter() - start)
    print(f"{name:40s} {1e3 * min(times):9.4g} ms")


scene = FoldingScene(**{k: float(v) for k, v in (a.split("=") for a in sys.argv[1:])})
case = scene.build()
p = case.problem
print(f"dofs {p.ndof}")
solver = NewtonSolver(p, NewtonOptions(line_search=False))
p.dt.Set(scene.onset_dt)
with config.task_manager():
    best("residual", solver.residual)
    best("tangent assembly", lambda: p.form.AssembleLinearization(p.state.vec))
    for inverse in ("umfpack", "sparsecholesky"):
        best(f"factorisation {inverse}", lambda i=inverse: p.form.mat.Inverse(p.freedofs,
                                                                             inverse=i), 2)
    solver.factorise()
    best("solve (UMFPACK's factors)", solver.direction)
    gmres = NewtonSolver(p, NewtonOptions(line_search=False, linear_solver="symmetric-gmres"))
    best("symmetric part + Cholesky + GMRES solve", lambda: (gmres.factorise(),
                                                               gmres.direction()), 2)
for count in (6, 1):
    best(f"eigenpairs ({count})", lambda c=count: buckling.smallest_eigenpairs(p, count=c), 2)
best("top_profile", lambda: case.top_profile(p.u))
best("top_stretch", lambda: case.top_stretch(p.u, 1.01))
