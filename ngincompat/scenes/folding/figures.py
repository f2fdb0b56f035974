"""The folding scene's figures: Fig. 7 a-c on the deformed section, the profiles through
the middle, the perfect branch's eigenvalue, the folds' growth and the buckling mode."""


from collections.abc import Mapping
from typing import Any

from ngincompat.workflow.results import DeformedFigure, Figure, ProfileFigure

#: The panels of Fig. 7 a-c: label -> (field, the displacement it is drawn deformed by);
#: "{L}" and "{stress}" stand for the units. A panel is drawn when the run has its fields.
PANELS = {"axon growth theta_a [-]": ("theta_a", "u"),
          "|b| on the plane normal to e3 [1/{L}]": ("|b|", "u"),
          "max principal Cauchy stress [{stress}]": ("sigma_max", "u"),
          "after release: max principal Cauchy stress [{stress}]":
              ("sigma_max_released", "u_released")}

#: The fields sampled along the vertical through the middle (profile "depth").
DEPTH_FIELDS = ("theta_a", "|b|", "curlFg_sq", "sigma_max", "sigma_max_released")


def panels(scene: Any) -> dict[str, tuple[str, str]]:
    """``PANELS`` with the scene's units: label -> (field, displacement)."""
    units = {"L": scene.units["length"], "stress": scene.units["stress"]}
    return {label.format(**units): keys for label, keys in PANELS.items()}


def fields_figure(scene: Any, section: Mapping[str, Any]) -> DeformedFigure:
    """The figure of Fig. 7 a-c of one run: the panels whose fields ``section`` has."""
    L = scene.units["length"]
    present = {label: keys for label, keys in panels(scene).items()
               if all(k in section for k in keys)}
    return DeformedFigure("fields.png", "X1", f"X1 [{L}]",
                          {k: f for k, (f, _) in present.items()}, f"X2 [{L}]",
                          f"{scene.title()}: deformed state", profile="section", y="X2",
                          deform={k: d for k, (_, d) in present.items()},
                          floor=1e-3 * scene.mu_white)


def figures(scene: Any, profiles: Mapping[str, Mapping[str, Any]]) -> list[Figure]:
    """The figures of a run from its ``profiles``."""
    L, title = scene.units["length"], scene.title()
    stress = scene.units["stress"]
    stresses = {label: k for label, k in (("grown", "sigma_max"),
                                           ("released", "sigma_max_released"))
                if k in profiles["depth"]}
    return [
        fields_figure(scene, profiles["section"]),
        ProfileFigure("depth.png", "depth", f"depth below the top [{L}]",
                      {"|b| on the plane normal to e3": "|b|"}, f"|b| [1/{L}]",
                      f"{title}: through the middle", right={"axon growth theta_a": "theta_a"},
                      right_label="theta_a [-]", profile="depth"),
        ProfileFigure("stress_depth.png", "depth", f"depth below the top [{L}]",
                      stresses, f"max principal Cauchy stress [{stress}]",
                      f"{title}: through the middle", profile="depth",
                      floor=1e-3 * scene.mu_white),
        ProfileFigure("eigenvalue.png", "theta_c", "cortex growth theta_c [-]",
                      {"smallest eigenvalue": "eigenvalue"},
                      f"smallest tangent eigenvalue [{scene.units['stress']}/{L}^2]",
                      f"{title}: perfect branch", profile="perfect",
                      marks={"onset (the eigenvalue crosses zero): theta_c = {value:.4g}":
                      "onset_growth"}),
        ProfileFigure("folds.png", "theta_c", "cortex growth theta_c [-]",
                      {"fold amplitude": "amplitude"}, f"fold amplitude [{L}]",
                      f"{title}: after the onset", right={"smallest eigenvalue": "eigenvalue"},
                      right_label=f"smallest tangent eigenvalue [{scene.units['stress']}/{L}^2]",
                      profile="buckling"),
        ProfileFigure("mode.png", "X1", f"X1 [{L}]", {"u2 on top": "u2"}, "buckling mode u2 [-]",
                      f"{title}: first buckling mode", profile="mode"),
    ]
