"""Where the scenes' defaults differ from the parameters of the paper (Lee et al. 2021), with
the reason and the effect: the table of the report (:mod:`ngincompat.studies.report`).

Each entry was found by reading the paper's sections 3.1-3.7 beside the scene's parameters
(``ngincompat list -v``). ``paper`` quotes the paper ("not given" where it names no value),
``ours`` is the scene's default, read from the scene class itself (so the table cannot
disagree with the code); the effect is measured where the documentation's measurement logs
or the accuracy studies measured it, otherwise said to be unmeasured.
"""

from __future__ import annotations

from dataclasses import dataclass

from ngincompat.scenes import (
    AtrophyScene,
    CubeScene,
    CylinderScene,
    DiscScene,
    FoldingScene,
    HemisphereScene,
    SkinExpansionScene,
)


@dataclass(frozen=True)
class Deviation:
    """One parameter of one section where the default is not the paper's."""

    section: str
    scene: type
    parameter: str
    paper: str
    reason: str
    effect: str

    @property
    def ours(self) -> str:
        """The scene's default of ``parameter`` with its unit (several: comma list)."""
        values = []
        for name in self.parameter.split(", "):
            default, _, unit = self.scene.parameters()[name]
            unit = self.scene.unit_of(unit) if unit else ""
            values.append(f"{name} = {default}{' ' + unit if unit else ''}")
        return ", ".join(values)


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
    Deviation("3.3", DiscScene, "mu, k1, k2, kappa",
              "GOH model, parameters not given",
              "the paper names no values: Holzapfel, Gasser & Ogden (2000) Table 1 (rabbit "
              "carotid artery), no dispersion",
              "the stresses scale with these moduli; the trends compared (fiber families) "
              "do not depend on them"),
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
    Deviation("3.7", FoldingScene, "order, maxh, cortex_maxh",
              "6,000 C3D8, 12,462 nodes (one element thick)",
              "the section in plane strain: quadratic triangles (two across the cortex)",
              "the same plane-strain solution as the one-element slab on half the unknowns; "
              "its convergence: docs/measurements/folding.md"),
)


def rows():
    """The table as dicts: section, scene, parameter, paper, ours, reason, effect."""
    return [{"section": d.section, "scene": d.scene.name, "parameter": d.parameter,
             "paper": d.paper, "ours": d.ours, "reason": d.reason, "effect": d.effect}
            for d in DEVIATIONS]
