"""Skin expansion (section 3.6): inflation, a week of area growth, deflation and release.

Stages (lengths in cm, volumes in cm^3 = cc, stresses in MPa, time in days):

1. **inflation** to ``volume`` cc, volume-controlled: the expander pressure is the unknown
   conjugate to the volume under the footprint, so the target is met, not guessed;
2. **hold** for ``hold_days`` at that volume while the skin grows in area about its normal
   N0 = e3 (Hill law, eq. 46, implicit Euler, eq. 48);
3. **deflation**: the pressure is removed, the periphery still clamped: residual stress of the
   clamped patch;
4. **release**: the clamp is removed too (rigid-body constraints only): what stress remains is
   due to the incompatibility of the grown skin alone.

The patch lies on its base: outside the footprint the bottom face keeps X3 = 0 (it may slide),
which also keeps the footprint's edge in the plane, so the enclosed volume is exactly
int x3 det(dx_a/dX_b) dA over the footprint. The expander acts through a uniform pressure on
the footprint: its own shape and the skin-expander contact are not modelled.

Parameters and their sources:

* neo-Hookean skin with E = 0.5 MPa, nu = 0.4 (mu = 0.1786 MPa, lambda = 0.7143 MPa), the
  values of Buganza Tepole, Ploch, Wong, Gosain & Kuhl, J. Mech. Phys. Solids 59 (2011) 2177;
* Hill law k = 0.1 / day, K = 0.2, n = 2, theta_crit = 1.05: our choice; k lies in the range
  0.02-0.08 / hour calibrated on porcine expansion by Tac et al. (2022, Bayesian calibration
  of tissue expansion, PMC8678288) divided by a factor that accounts for the growth stimulus
  in that model being the full elastic area stretch, and gives area growth of tens of
  percent in a week, the range the paper reports.
"""

import logging
import time as _time
from dataclasses import dataclass
from pathlib import Path

import ngsolve as ngs
import numpy as np

from geometries import FOOTPRINTS, skin_patch

from .. import fields, io, plots, postprocess
from .. import incompatibility as inc
from ..errors import ConvergenceError, require
from ..growth import AreaGrowth
from ..growth_laws import HillLaw
from ..materials import NeoHookean
from ..problem import CoupledGrowth, GrowthMechanics
from ..solver import NewtonOptions, solve_coupled, solve_growth
from .base import Scene, param, timed

log = logging.getLogger(__name__)

CHECKPOINT = "checkpoint.npz"


@dataclass(frozen=True)
class SkinExpansionScene(Scene):
    """Tissue expansion of a 10 x 10 x 0.3 cm skin patch (section 3.6)."""

    name = "skin"
    summary = "section 3.6: skin expansion, inflation to 50 cc, 7 days of area growth"
    units = {"length": "cm", "stress": "MPa", "energy": "MPa cm^3 (J)", "volume": "cm^3",
             "time": "day"}

    order: int = param(2, "polynomial order of the displacement")
    maxh: float = param(1.0, "mesh size", "length")
    g_order: int = param(4, "order of the H1 space that Fg is projected into for Curl Fg")
    growth_order: int = param(3, "order of the (L2) growth field theta")
    footprint: str = param("rectangle", "expander base: " + ", ".join(FOOTPRINTS))
    footprint_size: float = param(7.0, "expander size: the square's side, the circle's "
                                       "diameter, the rectangle's long side", "length")
    volume: float = param(50.0, "expander volume at the end of inflation", "volume")
    inflation_steps: int = param(10, "initial number of inflation steps")
    hold_days: float = param(7.0, "duration of the hold", "time")
    dt: float = param(1.0, "time step of the hold (halved where Newton needs it)", "time")
    mu: float = param(0.1786, "shear modulus of skin", "stress")
    nu: float = param(0.4, "Poisson's ratio of skin")
    k: float = param(0.1, "Hill law: largest growth rate", "1/time")
    K: float = param(0.2, "Hill law: stimulus of half the largest rate")
    n: float = param(2.0, "Hill law exponent")
    theta_crit: float = param(1.05, "elastic area stretch below which skin does not grow")
    theta_max: float = param(3.0, "saturation of area growth")
    resume: bool = param(False, "continue an interrupted hold from the folder's checkpoint")

    def __post_init__(self):
        super().__post_init__()
        require(self.footprint in FOOTPRINTS, "footprint", self.footprint,
                ", ".join(FOOTPRINTS))
        require(self.volume > 0, "volume", self.volume, "> 0")
        require(self.hold_days >= 0, "hold_days", self.hold_days, ">= 0")
        require(self.dt > 0, "dt", self.dt, "> 0")
        require(self.inflation_steps >= 1, "inflation_steps", self.inflation_steps, ">= 1")
        NeoHookean.from_nu(self.mu, self.nu)
        self.law()

    def law(self):
        return HillLaw(self.k, self.K, self.n, self.theta_crit, self.theta_max)

    def run(self, out, quiet=True):
        with ngs.TaskManager():
            return _run(self, Path(out), quiet)


def _run(scene, out, quiet):
    timings = {}
    start = _time.perf_counter()
    mesh = skin_patch(footprint=scene.footprint, footprint_size=scene.footprint_size,
                      maxh=scene.maxh, curve_order=1)
    timings["mesh"] = _time.perf_counter() - start
    material = NeoHookean.from_nu(scene.mu, scene.nu)
    N0 = fields.constant("e3")
    clamp = dict(dirichlet="periphery", symmetry={"bottom": "z"})
    problem = CoupledGrowth(mesh, "area", N0, scene.law(), material, order=scene.order,
                            growth_order=scene.growth_order, volume="footprint", **clamp)
    results = {"scene": scene.name, "params": scene.settings(), "units": scene.units,
               **io.provenance(),
               "mesh": {"ne": mesh.ne, "nv": mesh.nv, "ndof": problem.ndof,
                        "order": scene.order, "maxh": scene.maxh},
               "solver": {}, "metrics": {}}
    metrics = results["metrics"]
    checkpoint = out / CHECKPOINT
    t_hold = _restore(problem, checkpoint) if scene.resume else None

    if t_hold is None:
        with timed(timings, "inflation"):
            def inflate(t):
                problem.dt.Set(0.0)
                problem.volume_target.Set(scene.volume * t)
            history = solve_coupled(problem, 1.0, 1.0 / scene.inflation_steps,
                                    schedule=inflate, quiet=quiet)
        results["solver"]["inflation"] = history.as_dict()
        t_hold = 0.0
    metrics["volume_inflated"] = problem.volume()
    metrics["volume_error_rel"] = abs(metrics["volume_inflated"] - scene.volume) / scene.volume
    metrics["pressure_inflated"] = problem.pressure()
    _save(problem, checkpoint, t_hold)

    def hold(t):
        problem.volume_target.Set(scene.volume)

    error = None
    with timed(timings, "hold"):
        try:
            history = solve_coupled(problem, scene.hold_days, scene.dt, t_start=t_hold,
                                    options=NewtonOptions(max_iter=20, max_step=scene.dt),
                                    schedule=hold, quiet=quiet,
                                    on_step=lambda t: _save(problem, checkpoint, t))
        except ConvergenceError as err:
            history, error = err.history, err
    results["solver"]["hold"] = history.as_dict()
    if error is not None:
        results["error"] = (f"{error} (the last converged state is in {CHECKPOINT}; run "
                            "again with --set resume=true)")
        io.write_json(out / "results.json", results)
        raise error
    metrics["pressure_end_of_hold"] = problem.pressure()

    theta = problem.theta
    footprint = mesh.Boundaries("footprint")
    area = ngs.Integrate(1, mesh, ngs.BND, definedon=footprint)
    metrics["theta_max"] = postprocess.maximum(theta, mesh)
    # an L2 field has no boundary trace: its continuous interpolant gives the footprint mean
    theta_h1 = ngs.GridFunction(ngs.H1(mesh, order=scene.growth_order))
    theta_h1.Set(theta)
    metrics["theta_mean_footprint"] = ngs.Integrate(theta_h1, mesh, ngs.BND,
                                                    definedon=footprint) / area
    growth = AreaGrowth(theta, N0)
    with timed(timings, "incompatibility"):
        curl_Fg, _ = inc.curl_projected(growth.Fg, mesh, scene.g_order)
        G = inc.incompatibility_tensor(growth.Fg, curl_Fg)
        b = inc.burgers_vector(G, N0.cf)
        metrics["burgers_max"] = postprocess.maximum(ngs.Norm(b), mesh)

    # The residual states are found by applying the grown field theta to the unloaded patch
    # (clamped, then free) in load steps from u = 0, the path the prescribed-growth solver is
    # built for; starting from the inflated dome instead, Newton could not find the released
    # state of the rectangular expander.
    ramp = ngs.Parameter(0.0)
    ramped = AreaGrowth(1 + (theta - 1) * ramp, N0)
    stresses, final = {}, {}
    for stage, kwargs in (("clamped", clamp), ("released", {})):
        with timed(timings, f"deflation_{stage}"):
            relaxed = GrowthMechanics(mesh, ramped, material, order=scene.order, **kwargs)
            ramp.Set(0.0)
            history = solve_growth(relaxed, ramp, NewtonOptions(max_iter=30), quiet=quiet)
            results["solver"][f"deflation_{stage}"] = history.as_dict()
            sigma = postprocess.stresses(relaxed.energy_density, relaxed.u)["sigma"]
            stresses[stage] = postprocess.principal_values(sigma)[2]
            metrics[f"max_principal_stress_{stage}"] = postprocess.maximum(stresses[stage],
                                                                           mesh)
            metrics[f"strain_energy_{stage}"] = relaxed.strain_energy()
            final[stage] = relaxed.u
    metrics.update(_where(mesh, theta, ngs.Norm(b)))

    line = ((-4.99, 0.0, 0.0), (4.99, 0.0, 0.0))
    s, values = postprocess.sample_line(
        mesh, {"theta": theta, "|b|": ngs.Norm(b), "sigma_max_clamped": stresses["clamped"],
               "sigma_max_released": stresses["released"]}, *line)
    results["profiles"] = {"line": {"X1": line[0][0] + s, **values}}
    with timed(timings, "output"):
        results["files"] = ["results.json"]
        wanted = scene.output_set()
        if "vtk" in wanted:
            io.write_vtk(out / "fields.vtu", mesh,
                         {"theta": theta, "b": b, "|b|": ngs.Norm(b),
                          "u_inflated": problem.u, "u_clamped": final["clamped"],
                          "u_released": final["released"],
                          "sigma_max_clamped": stresses["clamped"],
                          "sigma_max_released": stresses["released"]}, subdivision=1)
            results["files"].append("fields.vtu")
        if "figures" in wanted:
            p = results["profiles"]["line"]
            plots.profile_pair(out / "profile.png", p["X1"], ("area growth theta", p["theta"]),
                               ("|b| on e3 [1/cm]", p["|b|"]), xlabel="X1 [cm]",
                               title=f"skin, {scene.footprint} expander, bottom face")
            plots.profiles(out / "stress.png", p["X1"],
                           {"clamped": p["sigma_max_clamped"],
                            "released": p["sigma_max_released"]},
                           xlabel="X1 [cm]", ylabel="max principal stress [MPa]",
                           title="residual stress after deflation")
            results["files"] += ["profile.png", "stress.png"]
    results["timings"] = timings
    io.write_json(out / "results.json", results)
    return results


def _where(mesh, theta, b_norm):
    """Where growth and incompatibility sit: at the apex (centre of the bottom face) and the
    largest |b| with its distance from the centre."""
    pts = np.array([v.point for v in mesh.vertices])
    bottom = pts[np.abs(pts[:, 2]) < 1e-9]
    values = np.array([b_norm(mesh(*p)) for p in bottom])
    i = int(np.argmax(values))
    apex = mesh(1e-6, 1e-6, 1e-9)
    return {"theta_apex": float(theta(apex)), "burgers_apex": float(b_norm(apex)),
            "burgers_max_radius": float(np.hypot(*bottom[i, :2]))}


def _save(problem, path, t):
    """Write the state of the hold atomically (the last converged step)."""
    with io.atomic_path(path) as tmp:
        with open(tmp, "wb") as f:
            np.savez(f, t=t, state=problem.state.vec.FV().NumPy(),
                     theta_old=problem.theta_old.vec.FV().NumPy())


def _restore(problem, path):
    """Load a checkpoint into the problem; returns its time, or None if there is none."""
    if not path.is_file():
        return None
    data = np.load(path)
    if data["state"].shape != problem.state.vec.FV().NumPy().shape:
        raise ConvergenceError(f"{path} does not fit this mesh and order: cannot resume")
    problem.state.vec.FV().NumPy()[:] = data["state"]
    problem.theta_old.vec.FV().NumPy()[:] = data["theta_old"]
    log.info("resuming the hold at t = %g days", float(data["t"]))
    return float(data["t"])


def summary(out, footprints=FOOTPRINTS, quiet=True, **settings):
    """Run every expander into ``out/<footprint>``; returns the summary rows.

    ``settings`` are scene parameters by name (strings are converted as on the command line).
    """
    rows = []
    for footprint in footprints:
        start = _time.perf_counter()
        scene = SkinExpansionScene.from_settings({**settings, "footprint": footprint})
        r = scene.run(Path(out) / footprint, quiet=quiet)
        m = r["metrics"]
        rows.append({"footprint": footprint, "ndof": r["mesh"]["ndof"],
                     "seconds": round(_time.perf_counter() - start, 1),
                     **{k: m[k] for k in ("volume_inflated", "pressure_inflated", "theta_max",
                                          "theta_mean_footprint", "theta_apex",
                                          "burgers_max", "burgers_apex", "burgers_max_radius",
                                          "max_principal_stress_clamped",
                                          "max_principal_stress_released")}})
    io.write_json(Path(out) / "summary.json", {"rows": rows, **io.provenance()})
    return rows
