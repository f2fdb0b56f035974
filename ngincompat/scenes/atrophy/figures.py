"""The atrophy scene's figures: the volumes over time, the depth profile of Fig. 5e and the
maps on the sections through the centre."""


from typing import Any

from ngincompat.scenes.atrophy.tissues import PLANES, TISSUES
from ngincompat.workflow.results import Figure, MapsFigure, ProfileFigure, SurfaceFigure


def figures(scene: Any, mechanics: bool) -> list[Figure]:
    """Time series, the profile along +X1 and the three sections (Fig. 5)."""
    L, stress, T = (scene.units[k] for k in ("length", "stress", "time"))
    title = scene.title()
    figures: list[Figure] = [
        ProfileFigure("spreading.png", "t", f"t [{T}]", {"int c dV": "c_integral"},
                      f"int c dV [{L}$^3$]", f"{title}: misfolded protein",
                      right={"front radius": "front_radius"} if scene.seed_centre() else {},
                      right_label=f"front radius (c >= 1/2) [{L}]", profile="series"),
        ProfileFigure("volume_theta.png", "t", f"t [{T}]",
                      {f"{k}": f"{k}_volume_loss_theta" for k in ("total", *TISSUES)},
                      "1 - int theta dV / V0 [-]", f"{title}: volume loss from theta",
                      profile="series"),
        ProfileFigure("profile.png", "R", f"X1 [{L}]", {"theta": "theta", "c": "c"}, "theta, c [-]",
                      f"{title}: from the centre along +X1",
                      right={"|b| (largest plane)": "burgers"}, right_label=f"|b| [1/{L}]"),
    ]
    if mechanics:
        figures += [
            ProfileFigure("volume_loss.png", "t", f"t [{T}]",
                          {k: f"{k}_volume_loss" for k in ("total", *TISSUES)},
                          "1 - int J dV / V0 [-]", f"{title}: volume loss", profile="snapshots"),
            ProfileFigure("stress.png", "R", f"X1 [{L}]",
                          {"sigma_rr": "sigma_rr", "sigma_thetatheta": "sigma_thetatheta",
                    "max principal": "sigma_max_principal"},
                          f"Cauchy stress [{stress}]", f"{title}: residual stress along +X1",
                          floor=1e-3 * min(scene.mu_gray, scene.mu_white)),
        ]
    if mechanics:
        figures.append(SurfaceFigure(
            "brain.png", "points", L, {"reference: c [-] at the end": "c",
                                        "atrophied: theta [-]": "theta",
                                        f"atrophied: max principal stress [{stress}]":
                                            "sigma_max_principal"},
            "", f"{title}: surface (Fig. 5)", profile="surface",
            deform={"atrophied: theta [-]": "u",
                    f"atrophied: max principal stress [{stress}]": "u"},
            view=(10.0, -90.0 if scene.hemisphere == "right" else 90.0)))
        figures.append(ProfileFigure(
            "depth.png", "xi", "depth xi [-] (0 surface, 1 gray/white interface)",
            {"max principal stress": "sigma_max_principal"},
            f"mean max principal stress [{stress}]", f"{title}: stress against depth (Fig. 5e)",
            right={"|b|": "|b|"}, right_label=f"mean |b| [1/{L}]", profile="depth"))
    labels = {"theta": "theta [-]", "|b|": f"|b| [1/{L}]",
              "sigma_max_principal": f"max principal stress [{stress}]"}
    keys = [k for k in labels if mechanics or k != "sigma_max_principal"]
    maps = {f"{labels[k]}, X{p[1]} through the centre": f"{p}_{k}"
            for p in PLANES for k in keys}
    figures.append(MapsFigure("sections.png", "e1_u", f"[{L}]", maps, f"[{L}]",
                              f"{title}: sections (Fig. 5; arrows: b = G^T e_k in the plane)",
                              profile="sections",
                              arrows={label: f"{key[:2]}_b_inplane"
                                      for label, key in maps.items() if key.endswith("|b|")}))
    return figures

