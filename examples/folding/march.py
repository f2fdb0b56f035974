"""The folding scene's perfect branch and viscous march to t_end without the equilibrium and
the release (``python march.py axons=curved t_end=45``): per stage the wall time, steps, cut
tries, Newton iterations, tangents and the eigenpairs' calls and time; then the march's
records (time, theta_c, smallest eigenvalue, fold amplitude, top stretch)."""

import json
import sys
import time

from ngincompat.fem import buckling
from ngincompat.progress import Progress
from ngincompat.scenes.folding import FoldingScene
from ngincompat.workflow.pipeline import Solution, solve_stages

settings = dict(a.split("=") for a in sys.argv[1:])
scene = FoldingScene(**{k: v if k == "axons" else float(v) for k, v in settings.items()},
                     outputs="none")
case = scene.build()
print(f"dofs {case.problem.ndof}", flush=True)
calls = []
smallest_eigenpairs = buckling.smallest_eigenpairs


def timed_eigenpairs(*args, **kwargs):
    start = time.perf_counter()
    pairs = smallest_eigenpairs(*args, **kwargs)
    calls.append(time.perf_counter() - start)
    return pairs


buckling.smallest_eigenpairs = timed_eigenpairs
solution = Solution()


def report(stage):
    calls_before = len(calls)
    solve_stages([stage], Progress(), solution)
    h = solution.histories[stage.name]
    ok = [s for s in h.steps if s.converged]
    print(f"{stage.name}: {solution.timings[stage.name]:.0f} s, {len(ok)} steps, "
          f"{len(h.steps) - len(ok)} cut tries, {h.newton_iterations} Newton iterations, "
          f"{h.tangent_assemblies} tangents, eigenpairs {len(calls) - calls_before} calls "
          f"{sum(calls[calls_before:]):.0f} s", flush=True)


start = time.perf_counter()
stages = case.stages()
print(f"stages planned in {time.perf_counter() - start:.1f} s", flush=True)
for stage in stages:
    if case.mode is None:
        report(stage)
print("onset", case.noted, flush=True)
if case.mode is not None and scene.buckle and solution.converged:
    case.perturb()
    report(case.buckling_stage())
    print(json.dumps({k: [round(x, 5) for x in v] for k, v in case.series["buckling"].items()}))
print("status", solution.status, solution.error)
