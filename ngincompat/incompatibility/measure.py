"""The incompatibility of a growth field, measured once for every scene.

From Fg and the paper's planes of interest (label -> unit normal n):

* Curl Fg (eq. 7), by the exact path (symbolic gradient, analytic growth) or the projected
  path (the gradient of the H1 interpolant of ``order``, computed growth): see
  :mod:`ngincompat.incompatibility.operators`;
* G = (1/Jg) Fg Curl Fg (eq. 10);
* on each plane the Burgers vector density b = G^T n (eq. 11).

Its fields have one set of names in every scene: ``"G"``, ``"curlFg_sq"`` (Curl Fg : Curl
Fg), per plane ``"b_<label>"`` and ``"|b_<label>|"``, and ``"|b|"``, the largest |b| of the
planes at each point (the plane's own where there is one).
"""

from dataclasses import dataclass

import ngsolve as ngs

from ngincompat import sampling
from ngincompat.incompatibility import operators as inc
from ngincompat.incompatibility.operators import CF


@dataclass(eq=False)
class Incompatibility:
    """Curl Fg, G and the Burgers vectors of a growth field Fg on ``planes``.

    Build it with :meth:`exact` or :meth:`projected`.

    Attributes
    ----------
    Fg : CoefficientFunction
        The growth tensor (3 x 3).
    dFg : CoefficientFunction
        Its reference gradient, ``dFg[j, s, r] = d(Fg)_js / dX_r`` (exact or of Fg_h).
    Fg_h : CoefficientFunction or None
        The H1 interpolant that the projected path differentiates (None on the exact path).
    planes : dict
        label -> unit normal n of the planes b is measured on.
    """

    Fg: CF
    dFg: CF
    Fg_h: CF | None
    planes: dict

    @classmethod
    def exact(cls, Fg: CF, planes: dict) -> "Incompatibility":
        """The exact path: the gradient of an analytic Fg by symbolic differentiation."""
        return cls(Fg, inc.gradient_exact(Fg), None, dict(planes))

    @classmethod
    def projected(cls, Fg: CF, mesh: ngs.Mesh, order: int, planes: dict) -> "Incompatibility":
        """The projected path: the gradient of the H1(``order``) interpolant of Fg on
        ``mesh`` (G itself takes Fg, eq. 10)."""
        Fg_h, dFg = inc.project_tensor(Fg, mesh, order)
        return cls(Fg, dFg, Fg_h, dict(planes))

    @property
    def curl_Fg(self) -> CF:
        """Curl Fg (eq. 7)."""
        return inc.curl(self.dFg)

    @property
    def G(self) -> CF:
        """G = (1/Jg) Fg Curl Fg (eq. 10)."""
        return inc.incompatibility_tensor(self.Fg, self.curl_Fg)

    def burgers(self, label: str) -> CF:
        """b = G^T n on the plane ``label`` (eq. 11)."""
        return inc.burgers_vector(self.G, ngs.CF(self.planes[label]))

    def fields(self) -> dict[str, CF]:
        """G, Curl Fg : Curl Fg, and b, |b| per plane and the largest |b| (the module's
        names)."""
        G = self.G
        out = {"G": G, "curlFg_sq": inc.curl_norm_squared(self.curl_Fg)}
        largest = None
        for label, n in self.planes.items():
            b = inc.burgers_vector(G, ngs.CF(n))
            out[f"b_{label}"], out[f"|b_{label}|"] = b, ngs.Norm(b)
            norm = out[f"|b_{label}|"]
            largest = norm if largest is None else ngs.IfPos(largest - norm, largest, norm)
        if largest is not None:
            out["|b|"] = largest
        return out

    def burgers_max(self, mesh: ngs.Mesh) -> float:
        """The largest |b| of the planes over the mesh (the largest of each plane's maximum,
        :func:`~ngincompat.sampling.maximum`: every rank of a distributed mesh); 0 without
        planes."""
        return max((sampling.maximum(ngs.Norm(self.burgers(label)), mesh)
                    for label in self.planes), default=0.0)

    def norm_L2(self, mesh: ngs.Mesh, order: int, scale: float = 1.0) -> float:
        """||G||_L2 over ``mesh`` (integration ``order``; ``scale`` times the integral of
        G : G, e.g. the mirror images of a symmetric part)."""
        G = self.G
        return max(scale * ngs.Integrate(ngs.InnerProduct(G, G), mesh, order=order), 0.0) ** 0.5
