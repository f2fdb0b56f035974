"""Where the scenes' settings differ from the parameters of the paper (Lee et al. 2021), or
choose what the paper does not state, with the reason and the effect: the table of the report
(:mod:`ngincompat.studies.report`).

Each entry was found by reading the paper's sections 3.1-3.7 beside the scene's parameters
(``ngincompat list -v``). ``paper`` quotes the paper ("not given" where it names no value);
``ours`` is the scene's default, read from the scene class itself (so the table cannot
disagree with the code), and :meth:`Deviation.as_run` the values of the runs a report was
made from (a preview run's presets, each with the default it replaces); the effect is
measured where the documentation's measurement logs or the accuracy studies measured it,
otherwise said to be unmeasured.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ngincompat.scenes import (
    AtrophyScene,
    CubeScene,
    CylinderScene,
    DiscScene,
    FoldingScene,
    HemisphereScene,
    SkinExpansionScene,
)
from ngincompat.scenes.base import Scene


@dataclass(frozen=True)
class Deviation:
    """One parameter of one section where the default is not the paper's."""

    section: str
    scene: type[Scene]
    parameter: str
    paper: str
    reason: str
    effect: str
    #: For a modelling choice no parameter sets (``parameter`` "(none)"): what it is.
    choice: str = ""

    @property
    def names(self) -> list[str]:
        """The parameters of the entry (none for a fixed modelling choice)."""
        return [] if self.choice else self.parameter.split(", ")

    def _unit(self, name: str) -> str:
        unit = self.scene.parameters()[name][2]
        unit = self.scene.unit_of(unit) if unit else ""
        return f" {unit}" if unit else ""

    @property
    def ours(self) -> str:
        """The scene's default of ``parameter`` with its unit (several: comma list)."""
        return self.choice or ", ".join(
            f"{name} = {self.scene.parameters()[name][0]}{self._unit(name)}"
            for name in self.names)

    def as_run(self, runs: Sequence[Mapping[str, Any]]) -> str:
        """The values of ``parameter`` in ``runs`` (the parameter dicts of this entry's
        scene's runs), each followed by "(default ...)" where it is not the default and
        listing the distinct values where the runs differ (variants); the defaults
        (:attr:`ours`) without runs."""
        if not runs or self.choice:
            return self.ours
        defaults = self.scene.typed_settings({k: v[0] for k, v in
                                              self.scene.parameters().items()})
        values = []
        for name in self.names:
            default = _text(defaults[name])
            seen = list(dict.fromkeys(_text(run[name]) for run in runs if name in run))
            text = " / ".join(seen) if seen else default
            note = f" (default {default})" if seen and seen != [default] else ""
            values.append(f"{name} = {text}{self._unit(name)}{note}")
        return ", ".join(values)


def _text(value: object) -> str:
    """A parameter's value as the table shows it: a list read back from results.json as the
    tuple it was."""
    return str(tuple(value) if isinstance(value, list) else value)


DEVIATIONS = (
    Deviation("3.1", CubeScene, "elements, order, maxh",
              "1,000 C3D8 (trilinear hexahedra), 1,331 nodes",
              "tetrahedra of order 6 on a symmetric rule (the paper preset keeps hexahedra of "
              "order 4): the closed form of G (eq. 16) and the stresses converge at far fewer "
              "unknowns than trilinear elements",
              "G against eq. (16) to round-off; stresses converged "
              "(docs/measurements/paper-job.md)"),
    Deviation("3.2", HemisphereScene, "order, centre_maxh",
              "1,920 C3D8, 2,300 nodes, the whole half ball",
              "order 5, refined at the centre where theta has a cone point; ngincompat paper "
              "solves the quarter (model=quarter: mirror planes held, the same solution at "
              "a third of the unknowns)",
              "stresses within 1.7e-4 of the 1-D radial solution (symmetry case)"),
    Deviation("3.2", HemisphereScene, "profile",
              "\"other functions of theta(R) that are nonlinear, either concave or convex "
              "(Fig. 2f)\", no formula",
              "theta = 1 + f(R / R0) t / 4 with f(s) = s (linear), 2 s - s^2 (concave: "
              "growth rising fastest near the core) and s^2 (convex: fastest near the "
              "surface), the simplest f with f(0) = 0 and f(1) = 1 of each kind",
              "the section's findings compare the three profiles; other concave and convex "
              "shapes were not run"),
    Deviation("3.3", DiscScene, "mu, k1, k2, kappa",
              "GOH model, parameters not given",
              "the paper names no values: Holzapfel, Gasser & Ogden (2000) Table 1 (rabbit "
              "carotid artery), no dispersion",
              "the stresses scale with these moduli; the trends compared (fiber families) "
              "do not depend on them. The level does: the largest principal stress is "
              "0.81 kPa at the defaults (radial fibers), about 30 times below the stresses "
              "on Fig. 3e's axes as read off the figure; it is not compared"),
    Deviation("3.3", DiscScene, "order, maxh", "2,080 C3D8, 2,808 nodes",
              "tetrahedra of order 3", "sigma_r at the rim within 1e-2 of its largest"),
    Deviation("3.4", CylinderScene, "order, maxh", "960 C3D8, 1,243 nodes",
              "tetrahedra of order 3", "b against eq. (27) to round-off; stress-free to "
              "1e-3 mu"),
    Deviation("3.5", AtrophyScene, "geometry",
              "an anatomical brain (the models of refs. [85, 55])",
              "the idealized ellipsoid with a gray shell is the default; the anatomical "
              "hemisphere (geometry=fsaverage) needs the brain extra (nilearn) and minutes "
              "of meshing, which the main job does not assume",
              "the interface is a smooth shell: |b| and stress peaks sit on it, not in "
              "folded sulci; on fsaverage the stress still falls from the interface to the "
              "pial surface (ratio 1.39, docs/measurements/atrophy.md)"),
    Deviation("3.5", AtrophyScene, "theta_min",
              "\"the maximum volume loss is about 30%\" (a result, Fig. 5a)",
              "the atrophy law's floor: theta falls toward theta_min and never below it "
              "(exact update), set from the paper's own 30 %",
              "the largest loss is the cap wherever the protein has saturated: the 30 % "
              "finding is judged \"imposed\", not \"agrees\""),
    Deviation("3.5", AtrophyScene, "seed, seed_radius, c0, t_end",
              "not given (the models of refs. [85, 55])",
              "a Gaussian seed of radius 1 cm and concentration 0.1 (the 1-D test of "
              "Weickenmeier et al. 2019) at "
              "the idealized brain's basal pole, or in the entorhinal cortex on fsaverage; "
              "40 years",
              "where and how far the loss has spread; the sensitivity to these was not "
              "measured"),
    Deviation("3.5", AtrophyScene, "d_ext, alpha, rate_gray, rate_white, mu_gray, mu_white",
              "not given (refs. [85, 55])",
              "choices documented in the scene: rates that give about 30 % gray and "
              "almost no white loss in 40 years, mu = 1 kPa (stresses in units of mu)",
              "volume loss as the paper states; stress magnitudes are in units of mu"),
    Deviation("3.6", SkinExpansionScene, "mu",
              "the neo-Hookean model of ref. [77], no value in section 3.6; section 3.1 "
              "cites ref. [77] for mu = 0.55 MPa, nu = 0.4",
              "read as 3.1's values (the paper's, through its reference); until 2026-11-25 "
              "the default was mu = 0.1786 MPa (E = 0.5 MPa, nu = 0.4, Buganza Tepole et al. "
              "2011), --set mu=0.1786",
              "measured on the rectangle at the defaults (ngincompat run skin --set mu=...): "
              "growth and |b| unchanged to 0.2 % (mean theta over the footprint 1.3509 -> "
              "1.3504, largest |b| 0.724 -> 0.723 1/cm), every stress and energy about 3.1 "
              "times (released largest principal stress 136 -> 420 kPa, compression in the "
              "contact zone -111 -> -355 kPa, clamped energy 0.0545 -> 0.167 J): farther "
              "from the paper's 40 kPa; contact area 8.8 -> 11.8 cm^2"),
    Deviation("3.6", SkinExpansionScene, "k, K, n, theta_crit",
              "eq. (46) with the parameters of ref. [77], not given in the paper",
              "a Hill law calibrated to give tens of percent area growth in a week "
              "(documented in the scene)", "area growth of about 50 % as the paper states"),
    Deviation("3.6", SkinExpansionScene, "expander",
              "the expander of ref. [59] (shape not modelled in the text)",
              "a rigid dome in contact, volume-controlled to 50 cc",
              "growth peaks at the apex as in Fig. 6a; a uniform pressure puts it at the "
              "footprint's edge instead (docs/measurements/skin.md)"),
    Deviation("3.6", SkinExpansionScene, "footprint_area, volume",
              "four shapes inflated to 50 cc; their sizes not given",
              "every footprint has the same base area, 24.5 cm^2 (the rectangle 7 x 3.5 cm), "
              "under a dome phi = 1 - r^2 / R^2 (circle), (1 - x^2/A^2)(1 - y^2/B^2) "
              "(rectangle, square) or the product of the crescent's two arcs "
              "(ngincompat.fem.contact), raised to 50 cc",
              "the ranking of the shapes compares equal areas; under equal base sizes (7 cm "
              "wide) or a uniform pressure instead of the dome the order differs from the "
              "paper's too (ngincompat bench skin, on the validation page)"),
    Deviation("3.6", SkinExpansionScene, "(none)", "boundary conditions: not given",
              "a patch cut from a larger skin, held at its edge while the expander stretches "
              "it; the release shows what remains without that hold",
              "unmeasured: the clamped periphery carries the stress of the clamped state, "
              "the release removes it", choice="periphery clamped through inflation, "
              "growth and deflation; the base outside the footprint on X3 = 0, free to "
              "slide; then released to rigid-body constraints only"),
    Deviation("3.6", SkinExpansionScene, "order, maxh", "3,200 C3D8, 5,043 nodes",
              "quadratic tetrahedra of 1 cm", "not measured against the paper's mesh"),
    Deviation("3.7", FoldingScene, "cortex_rate",
              "0.008/hour", "read as 0.008 per day: per hour theta_c would reach 15.4 in 75 "
              "days, far past any folding model",
              "the onset falls within the run (docs/measurements/folding.md)"),
    Deviation("3.7", FoldingScene, "mu_white, lam_ratio",
              "mu_gray / mu_white = 3, no absolute values",
              "mu_white = 1 kPa (stresses in units of it), lambda / mu = 100 (nearly "
              "incompressible)", "onset and folds depend on the ratio only"),
    Deviation("3.7", FoldingScene, "axon_rate",
              "\"the growth rate between the two layers also differs, with theta_cortex_dot / "
              "theta_axon = 0.1\"",
              "read as the ratio of the cortex's rate to the axons' rate constant: G_axn = "
              "cortex_rate / 0.1 = 0.08 per day",
              "the axons' growth and so theta_a and the gradient at the interface scale with "
              "it; other readings were not run"),
    Deviation("3.7", FoldingScene, "stretch_crit",
              "the stretch-driven law of eq. (45), its threshold not given",
              "1: the axons grow wherever they are stretched beyond their grown length",
              "not measured"),
    Deviation("3.7", FoldingScene, "axons",
              "\"curved outward, concentric, and straight\"; the gradient is greater "
              "\"when the axons are normal to the cortex (second and third columns)\" than "
              "when they \"approach the interface tangentially (first column)\"",
              "straight: normal to the interface; curved: a radial fan from a focus 3 cm "
              "below the interface's middle (within 26.6 degrees of its normal on the 3 cm "
              "strip); concentric: arcs about that focus, parallel to the interface above "
              "it (ngincompat.mechanics.fields.axons)",
              "the field the paper calls tangential (curved) meets the interface nearly "
              "normally here, and concentric tangentially: 3.7 is judged under the paper's "
              "labels with both readings reported"),
    Deviation("3.7", FoldingScene, "viscosity, imperfection, contact_penalty",
              "Abaqus, quasi-static; no regularisation, imperfection or contact stated",
              "past the onset a viscous regularisation eta = 100 mu_white (per cm^2 and "
              "day) follows the folds, the onset's mode seeds them at 1 % of the cortex, "
              "and a penalty keeps the creased walls apart; the final equilibrium and the "
              "release are solved without the viscosity",
              "the grown state is an equilibrium without viscosity (residual <= 1e-6 of its "
              "start); penetration <= 1.3 % of the cortex at the defaults "
              "(docs/measurements/folding.md)"),
    Deviation("3.7", FoldingScene, "order, maxh, cortex_maxh",
              "6,000 C3D8, 12,462 nodes (one element thick)",
              "the section in plane strain: quadratic triangles (four across the cortex at "
              "the defaults, two at the preview, where the folds do not crease)",
              "the same plane-strain solution as the one-element slab on half the unknowns; "
              "its convergence: docs/measurements/folding.md"),
)


def rows(runs: Mapping[str, Sequence[Mapping[str, Any]]] | None = None) -> list[dict[str, str]]:
    """The table as dicts: section, scene, parameter, paper, ours, reason, effect. ``ours``
    is the defaults, or with ``runs`` (scene name -> the parameter dicts of its runs) the
    values as run (:meth:`Deviation.as_run`)."""
    return [{"section": d.section, "scene": d.scene.name, "parameter": d.parameter,
             "paper": d.paper,
             "ours": d.ours if runs is None else d.as_run(runs.get(d.scene.name, [])),
             "reason": d.reason, "effect": d.effect}
            for d in DEVIATIONS]
