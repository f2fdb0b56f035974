"""What the skin scene measures beyond the shared measures: growth and incompatibility at the
apex, and the compression left under the expander after the release (section 3.6)."""

import ngsolve as ngs
import numpy as np

from ngincompat.fem import contact


def compression(mesh: ngs.Mesh, term: contact.ExpanderContact, sigma_min: ngs.CoefficientFunction,
                spacing: float = 0.1) -> dict[str, float]:
    """The smallest principal Cauchy stress of the released patch over the former contact
    zone, the points of the lower surface (on a grid of ``spacing``) that the expander of
    the contact ``term`` pressed at the end of the hold: its smallest value and its mean
    there."""
    _, values = contact.sample(mesh, term.expander,
                               {"p": term.contact_pressure(), "s": sigma_min}, spacing)
    touched = values["s"][values["p"] > 0]
    if touched.size == 0:
        return {}
    return {"min_principal_stress_contact_zone": float(np.min(touched)),
            "min_principal_stress_contact_zone_mean": float(np.mean(touched))}


def apex(mesh: ngs.Mesh, theta: ngs.CoefficientFunction,
         b_norm: ngs.CoefficientFunction) -> dict[str, float]:
    """Growth and incompatibility at the apex (the centre of the bottom face)."""
    apex = mesh(1e-6, 1e-6, 1e-9)
    return {"theta_apex": float(theta(apex)), "burgers_apex": float(b_norm(apex))}
