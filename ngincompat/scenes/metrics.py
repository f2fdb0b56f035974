"""The registry of the numbers a run reports: each metric declared once, with the quantity it
measures and what it means.

A scene lists its metrics (:attr:`ngincompat.scenes.base.Scene.metrics`) as a mapping of
names to :class:`Metric`; the units in results.json, the checks of a sweep's ``metrics``, the
tables of the studies and the docs page of every scene's metrics
(:doc:`/guide/metrics`) all read it. Metrics several scenes share are declared here once
(:data:`MECHANICS`, :data:`INCOMPATIBILITY`, :data:`CURVATURE`); a scene adds its own.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from types import MappingProxyType


@dataclass(frozen=True)
class Metric:
    """One number a run reports.

    Attributes
    ----------
    meaning : str
        What it measures, in a sentence a reader of results.json can check it against.
    quantity : str
        The quantity it measures, in the words of a scene's ``units`` ("length", "stress",
        "1/length", "stress length^2"), spelled in the scene's units by
        :meth:`~ngincompat.scenes.base.Scene.unit_of`; empty for a ratio or a count (its unit
        is "-").
    """

    meaning: str
    quantity: str = ""


def registry(*parts: Mapping[str, Metric], **metrics: Metric) -> Mapping[str, Metric]:
    """A read-only mapping of the metrics of ``parts`` (shared declarations, a parent
    scene's) and ``metrics``, in that order.

    Raises
    ------
    ValueError
        A name declared twice.
    """
    merged: dict[str, Metric] = {}
    for part in (*parts, metrics):
        twice = sorted(set(merged) & set(part))
        if twice:
            raise ValueError(f"metrics declared twice: {', '.join(twice)}")
        merged.update(part)
    return MappingProxyType(merged)


def select(names: Iterable[str], *sources: Mapping[str, Metric]) -> dict[str, Metric]:
    """The declarations of ``names`` from the first of ``sources`` that has each, for a scene
    that reports part of a shared set."""
    return {name: next(s[name] for s in sources if name in s) for name in names}


#: The mechanics of a solved body, reported by every scene that solves one.
MECHANICS = MappingProxyType({
    "strain_energy": Metric("the elastic energy stored in the grown body, the integral of the "
                            "strain energy density over the reference volume", "energy"),
    "max_principal_stress": Metric("the largest principal Cauchy stress over the body (its "
                                   "peak tension)", "stress"),
})

#: The incompatibility of the growth (eqs. 10-11), reported by every scene.
INCOMPATIBILITY = MappingProxyType({
    "burgers_max": Metric("the largest local Burgers vector |b| = |G^T n| (eq. 11) over the "
                          "body and the planes the scene measures", "1/length"),
    "G_norm_L2": Metric("the L2 norm of the incompatibility tensor G = (1/Jg) Fg Curl Fg "
                        "(eq. 10) over the body", "length^(1/2)"),
})

#: The curvature of the growth metric Cg = Fg^T Fg
#: (:func:`ngincompat.incompatibility.curvature.measure_growth`), with ``outputs=curvature``.
CURVATURE = MappingProxyType({
    "scalar_curvature_min": Metric("the smallest scalar curvature of the growth metric Cg "
                                   "over the body", "1/length^2"),
    "scalar_curvature_max": Metric("the largest scalar curvature of the growth metric Cg over "
                                   "the body", "1/length^2"),
    "einstein_norm_L2": Metric("the L2 norm of the Einstein tensor of Cg in the metric Cg: "
                               "zero when a stress-free state exists", "length^(-1/2)"),
    "einstein_norm_L2_error": Metric("the estimated discretisation error of "
                                     "einstein_norm_L2: the growth is called compatible when "
                                     "the norm does not exceed it", "length^(-1/2)"),
})
