"""The figures of ``ngincompat paper``, laid out as the paper's Figs. 1-7.

Per case, a field figure: colour maps on the deformed boundary
(:func:`ngincompat.workflow.surface.surface_figure`) of the fields the paper shows for its
scene (:data:`FIELDS`), the Burgers vectors b drawn as arrows over the maps of |b|, drawn
from the run's NGSolve fields as it ends (file ``fig<N>_<case>.png``). Per section, the
figures that compare cases, drawn from the profiles
in results.json (so a resumed job draws them too): Fig. 2g-h (the hemisphere's profiles,
with the 1-D radial solution beside the computed stresses of the symmetry case), Fig. 3e (the
disc's fiber families) and Fig. 7 (the folding fields of the three axon fields).
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from pathlib import Path

import numpy as np

from ngincompat.studies.sections import SECTIONS, Section
from ngincompat.workflow import plots, surface
from ngincompat.workflow.results import Results

#: Per scene: the paper's figure number, the camera (elevation, azimuth), and the panels as
#: (title with {L} length and {S} stress unit, field, signed, displacement field or None).
FIELDS = {
    "cube": ("1", (22, -58), (
        (r"(a) growth $\vartheta^g$ [-]", "theta", False, None),
        (r"(b) Curl $F^g$ : Curl $F^g$ [1/{L}$^2$]", "curlFg_sq", False, None),
        (r"(c) strain energy $\Psi$ [{S}]", "Psi", False, None),
        (r"(e) |b| on $\bar n_2$ [1/{L}]", "|b_n2|", False, None),
        (r"(f) $S_{{11}}$ [{S}]", "S11", True, None),
        (r"(f) $S_{{22}}$ [{S}]", "S22", True, None),
        (r"(f) $S_{{33}}$ [{S}]", "S33", True, None),
        (r"(e) |b| on $\bar n_3$ [1/{L}]", "|b_n3|", False, None))),
    "hemisphere": ("2", (20, -135), (
        (r"(a) growth $\vartheta^g$ [-]", "theta", False, None),
        (r"(b) |b| on $\bar n_\phi$ [1/{L}]", "|b_meridional|", False, None),
        (r"(c) |b| on $\bar n_\theta$ [1/{L}]", "|b_circumferential|", False, None),
        (r"(d, e) $\sigma_{{\theta\theta}}$ [{S}]", "sigma_thetatheta", True, None),
        (r"(d, e) $\sigma_{{\phi\phi}}$ [{S}]", "sigma_phiphi", True, None))),
    "disc": ("3", (35, -60), (
        (r"(a) growth $\vartheta^g$ [-]", "theta", False, None),
        (r"(b) |b| on $e_3$ [1/{L}]", "|b_e3|", False, None),
        (r"(c, d) $\sigma_r$ [{S}]", "sigma_r", True, None),
        (r"(c, d) $\sigma_\theta$ [{S}]", "sigma_theta", True, None),
        (r"(c, d) $\Psi$ [{S}]", "Psi", False, None))),
    "cylinder": ("4", (20, -60), (
        (r"(a) growth $\vartheta^g$ [-]", "theta", False, None),
        (r"(b) |b| on $e_3$ [1/{L}]", "|b_e3|", False, None),
        (r"(d) $\Psi$ [{S}]", "Psi", False, None),
        (r"(e) Curl $F^g$ : Curl $F^g$ [1/{L}$^2$]", "curlFg_sq", False, None),
        (r"$S_{{11}}$ [{S}]", "S11", True, None))),
    # growth and |b| drawn on the skin at the end of the hold (inflated over the expander),
    # the released stress on the released patch
    "skin": ("6", (55, -70), (
        (r"(a) area growth $\vartheta^g$, end of hold [-]", "theta", False, "u_end_of_hold"),
        (r"(b) |b| on $e_3$, end of hold [1/{L}]", "|b_e3|", False, "u_end_of_hold"),
        (r"(c) max principal stress, released [{S}]", "sigma_max_released", True,
         "u_released"))),
}


def _scene(label: str) -> str:
    return label.split("-")[0]


def case_files(label: str) -> list[str]:
    """The field figure of a case (none for a scene without one, nor for the hemisphere's
    symmetry case: a check, shown against its reference in ``fig2_radial_check.png``)."""
    scene = _scene(label)
    if scene not in FIELDS or label.endswith("-symmetry"):
        return []
    return [f"fig{FIELDS[scene][0]}_{label}.png"]


def _vector(key: str) -> str:
    """The vector field whose norm the field ``key`` is ("|b_e3|" -> "b_e3"; "" for any
    other): a panel of a Burgers vector's norm draws the vectors as arrows, as the paper
    draws them (Figs. 2b-c, 3b, 6b)."""
    return key[1:-1] if key.startswith("|b") and key.endswith("|") else ""


def case_figure(out: str | os.PathLike, label: str, results: Results, resolution: str) -> None:
    """Draw the field figure of the case ``label`` from its NGSolve fields, titled with the
    ``resolution`` it ran at (nothing for a scene without one, or a run without fields)."""
    scene = _scene(label)
    if not case_files(label) or results.domain is None:
        return
    number, view, spec = FIELDS[scene]
    f = results.fields
    L, S = results.units["length"], results.units.get("stress", "")
    panels = [surface.Panel(title.format(L=L, S=S) + (", arrows: b" if _vector(key) in f
                                                      else ""),
                            f[key], signed, u=f.get(disp) if disp else None,
                            arrows=f.get(_vector(key)))
              for title, key, signed, disp in spec
              if key in f and (disp is None or disp in f)]
    if not panels:
        return
    variant = label[len(scene) + 1:] or scene
    title = f"Fig. {number}: {scene}, {variant}".replace(f"{scene}, {scene}", scene)
    fig = surface.surface_figure(results.domain, f.get("u"), panels,
                                 f"{title} (deformed; {resolution} resolution)",
                                 L, view=view, ncols=5 if len(panels) <= 5 else 4)
    plots.save(fig, Path(out) / case_files(label)[0])


def section_files(number: str) -> list[str]:
    """The comparison figures of a section."""
    return {"3.2": ["fig2g_burgers.png", "fig2h_curl.png", "fig2_radial_check.png"],
            "3.3": ["fig3e_disc_stress.png"],
            "3.7": ["fig7_folding.png", "fig7_onset.png"]}.get(number, [])


def all_files(labels: Iterable[str]) -> list[str]:
    """Every figure the job may draw for the cases ``labels``."""
    return ([f for label in labels for f in case_files(label)]
            + [f for s in SECTIONS for f in section_files(s.number)])


def section_figures(out: str | os.PathLike, section: Section,
                    results: Mapping[str, Results]) -> None:
    """Draw the comparison figures of ``section`` from ``results`` (label -> Results) when
    every run they need finished."""
    out = Path(out)
    done = {k: r for k, r in results.items() if r.converged}
    if section.number == "3.2" and all(f"hemisphere-{p}" in done for p in PROFILES):
        _hemisphere(out, done)
    if section.number == "3.3" and {"disc-radial", "disc-circumferential"} <= set(done):
        _disc(out, done)
    if section.number == "3.7":
        _folding(out, {k: r for k, r in done.items() if k.startswith("folding-")})


#: The hemisphere's growth profiles, in the paper's order.
PROFILES = ("linear", "concave", "convex")


def _hemisphere(out: Path, results: Mapping[str, Results]) -> None:
    """Fig. 2g, 2h: |b| meridional and Curl Fg : Curl Fg against R per profile; and the
    symmetry case's stresses beside the 1-D radial solution it is checked against."""
    hemi = {p: results[f"hemisphere-{p}"].profile("line") for p in PROFILES}
    L = results["hemisphere-linear"].units["length"]
    R = hemi["linear"]["R"]
    plots.profiles(out / "fig2g_burgers.png", R,
                   {p: h["|b_meridional|"] for p, h in hemi.items()}, xlabel=f"R [{L}]",
                   ylabel=f"|b| on the meridional plane [1/{L}]",
                   title="Fig. 2g: hemisphere, three growth profiles")
    plots.profiles(out / "fig2h_curl.png", R, {p: h["curlFg_sq"] for p, h in hemi.items()},
                   xlabel=f"R [{L}]", ylabel=f"Curl $F^g$ : Curl $F^g$ [1/{L}$^2$]",
                   title="Fig. 2h: hemisphere, three growth profiles")
    sym = results.get("hemisphere-linear-symmetry")
    if sym is not None:
        _radial_check(out, sym)


def _radial_check(out: Path, results: Results) -> None:
    """The symmetry case's stresses along its ray beside the 1-D radial solution
    (:mod:`ngincompat.references.radial`) they are checked against."""
    from ngincompat.references.radial import solve_radial
    from ngincompat.scenes.hemisphere import PROFILES as GROWTH
    from ngincompat.scenes.hemisphere import HemisphereScene
    scene = HemisphereScene.from_settings(results.params)
    material = scene.make_material()
    f = GROWTH[scene.profile][1]
    reference = solve_radial(lambda r: 1 + f(r / scene.R0) / 4,
                             material.mu, material.lam,
                             R0=scene.R0)
    p = results.profile("line")
    R = p["R"]
    inner = R >= 0.05 * scene.R0          # the centre is a cone point of the growth
    srr, stt = reference.cauchy(R[inner])
    L, S = results.units["length"], results.units["stress"]
    fig = plots.curves_figure(
        {r"$\sigma_{rr}$, 3-D (symmetry face)": (R, p["sigma_rr"]),
         r"$\sigma_{rr}$, 1-D radial solution": (R[inner], srr),
         r"$\sigma_{\theta\theta}$, 3-D": (R, p["sigma_thetatheta"]),
         r"$\sigma_{\theta\theta}$, 1-D radial solution": (R[inner], stt)},
        f"R [{L}]", f"Cauchy stress [{S}]",
        "Hemisphere, linear profile: 3-D against the 1-D radial solution", markevery=10,
        colours=["tab:blue", "tab:blue", "tab:red", "tab:red"])
    plots.save(fig, out / "fig2_radial_check.png")


def _disc(out: Path, results: Mapping[str, Results]) -> None:
    """Fig. 3e: sigma_r and sigma_theta against R for both fiber families."""
    curves = {}
    for family in ("radial", "circumferential"):
        p = results[f"disc-{family}"].profile("line")
        curves[rf"$\sigma_r$, {family} fibers"] = p["sigma_r"]
        curves[rf"$\sigma_\theta$, {family} fibers"] = p["sigma_theta"]
    r = results["disc-radial"]
    plots.profiles(out / "fig3e_disc_stress.png", r.profile("line")["R"], curves,
                   xlabel=f"R [{r.units['length']}]",
                   ylabel=f"Cauchy stress [{r.units['stress']}]",
                   title="Fig. 3e: disc, two GOH fiber families")


def _folding(out: Path, results: Mapping[str, Results]) -> None:
    """Fig. 7: the folding fields of every axon field that ran (one row each)."""
    from ngincompat.scenes.folding import FoldingScene, panels
    rows = {k.split("-", 1)[1]: r.profiles["section"] for k, r in results.items()
            if "section" in r.profiles}
    if not rows:
        return
    scene = FoldingScene.from_settings(next(iter(results.values())).params)
    L = scene.units["length"]
    fig = plots.deformed_figure(rows, panels(scene), ("X1", "X2"), f"X1 [{L}]", f"X2 [{L}]",
                                "Fig. 7: cortical folding, one row per axon field",
                                floor=1e-3 * scene.mu_white)
    plots.save(fig, out / "fig7_folding.png")
    perfect = {k.split("-", 1)[1]: r for k, r in results.items() if "perfect" in r.profiles}
    if perfect:
        stress = scene.units["stress"]
        curves = {axons: (r.profiles["perfect"]["theta_c"], r.profiles["perfect"]["eigenvalue"])
                  for axons, r in perfect.items()}
        onsets = {f"onset, {axons}: theta_c = {r.metrics['onset_growth']:.4g}":
                  r.metrics["onset_growth"] for axons, r in perfect.items()
                  if np.isfinite(r.metrics.get("onset_growth", np.nan))}
        plots.save(plots.curves_figure(
            curves, "cortex growth theta_c [-]",
            f"smallest tangent eigenvalue [{stress}/{L}$^2$]",
            "The perfect branch: the smallest eigenvalue crosses zero at the onset of folding",
            vlines=onsets), out / "fig7_onset.png")
