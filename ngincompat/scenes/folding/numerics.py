"""The folding scene's numerical settings: Newton's options in every stage, the march's
tolerances and steps, the relaxations' budget and the eigenpairs per record; and the
bifurcation analysis' onset that places the perfect branch's short steps. Why each value:
``docs/measurements/folding.md``."""

import functools
from typing import Any

from ngincompat.fem.solver import NewtonOptions
from ngincompat.references.bifurcation import Bilayer, onset

#: Eigenpairs computed per step: Lanczos asked for one alone can settle on another of the
#: cluster of nearly equal wrinkling modes and miss the smallest (seen: 10.8 after 3.5).
EIGENPAIRS = 6


#: The self-contact's pairs are sought within this many cortex thicknesses of a point. The
#: search costs about the number of boundary elements within reach per point, which on a
#: refined top is most of a step (``docs/measurements/folding.md``, "Past the creasing
#: threshold"). The walls of a sulcus approach by far less than a quarter thickness per step.
CONTACT_REACH = 0.25

#: Newton's linear solver in every stage (:class:`~ngincompat.fem.solver.NewtonOptions`): GMRES
#: preconditioned by the sparse Cholesky factorisation of the tangent's symmetric part. The
#: coupled tangent (growth condensed) is symmetric but for the stretch-driven axons' coupling
#: (small beside its norm); on the default bilayer GMRES takes a few iterations per direction
#: and a Newton step costs less than one with UMFPACK's LU, with the same residuals
#: (``docs/measurements/folding.md``, "Where the time goes").
#: At most ``KRYLOV_MAXITER`` iterations: where the preconditioner is poor the step is cut.
LINEAR_SOLVER = "symmetric-gmres"
KRYLOV_MAXITER = 100

#: Relative residual to which the viscous march's steps are solved: its states are a path
#: whose error in time (implicit Euler over steps of days) is far above this, and the
#: equilibrium at its end is solved to ``rtol`` without the viscosity. Against Newton's
#: 1e-9 it saves the last iteration of most steps, and starting each step from the
#: extrapolation of the last two saves more (``docs/measurements/folding.md``, "The
#: section").
MARCH_RTOL = 1e-6

#: The relaxations try Newton without the viscosity each time the flow's residual has fallen
#: this much (:class:`~ngincompat.fem.relaxation.RelaxationStage`'s ``switch``), within at most
#: ``RELAXATION_STEPS`` accepted pseudo-time steps of one Newton step each. The default
#: bilayer released at 75 days creeps toward its equilibrium along a soft mode: with a
#: tenfold fall asked for and 60 steps, Newton was never tried
#: (``docs/measurements/folding.md``, "The paper's 75 days"). The curved field with every
#: mesh size halved needed 174 steps, its step falling to a thousandth of a day and
#: doubling back up several times ("The release in contact").
RELAXATION_SWITCH = 0.3
RELAXATION_STEPS = 500


#: After a cut step, this many converged steps keep the step before it may double again
#: (:class:`~ngincompat.fem.solver.NewtonOptions`' ``step_hold``, also in the relaxations);
#: the viscous march gives a step up once its residual has stayed above its best for
#: ``STALL`` iterations (``stall``). The march meets short events where a fold snaps, which
#: only steps of a few thousandths of a day get through: doubling after each easy step
#: failed again at each, and each failed try cost the iterations of its cap
#: (docs/measurements/folding.md, "The march's failed steps").
STEP_HOLD = 2
STALL = 3

#: The viscous march hands a snap to a relaxation at held growth
#: (:class:`~ngincompat.fem.relaxation.SnappingMarch`) where its step is cut below this fraction
#: of its longest.
SNAP_STEP = 1 / 16


def newton(**settings: Any) -> NewtonOptions:
    """The Newton options of every stage: at most 12 iterations per step, the directions
    by :data:`LINEAR_SOLVER`, :data:`STEP_HOLD` steps held after a cut, and the stage's own
    ``settings`` (which may change those)."""
    return NewtonOptions(**{"max_iter": 12, "linear_solver": LINEAR_SOLVER,
                            "krylov_maxiter": KRYLOV_MAXITER, "step_hold": STEP_HOLD,
                            **settings})


@functools.lru_cache(maxsize=32)
def placing_onset(bilayer: Bilayer, length: float) -> float | None:
    """theta_c at the onset of the bifurcation analysis of ``bilayer`` with roller ends at
    ``length``, scanned in theta_c steps of 0.02 (it places the perfect branch's steps), or
    None if it finds none. Cached: it only depends on the bilayer (seconds per call), which
    the variants of a scene in time steps, axons or outputs share."""
    try:
        return onset(bilayer, length=length, resolution=0.02).growth
    except ValueError:
        return None

