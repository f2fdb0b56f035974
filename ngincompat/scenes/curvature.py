"""What a scene reports of the curvature of its growth metric: the verdict and the figure.

The curvature itself is measured by :func:`ngincompat.incompatibility.curvature.measure_growth`
(numbers and fields); this module turns those numbers into the sentence and the figure a
reader sees.
"""

from collections.abc import Mapping

from ngincompat.scenes.base import Scene
from ngincompat.workflow.results import ProfileFigure, Results

#: Smallest range of the curvature axis of :func:`figure` [1/length^2]: the round-off of a
#: flat metric is drawn flat.
FIGURE_FLOOR = 1e-8


def verdict(metrics: Mapping[str, float]) -> str:
    """The one-line verdict on a run's curvature metrics: compatible when the measured
    ||Ein||_g does not exceed the estimate of its error."""
    value, error = metrics["einstein_norm_L2"], metrics["einstein_norm_L2_error"]
    if value <= error:
        return (f"compatible: a stress-free state exists (||Ein(Cg)||_L2 = {value:.3g} "
                f"<= its error {error:.3g})")
    return (f"incompatible: no stress-free state (||Ein(Cg)||_L2 = {value:.3g} > "
            f"its error {error:.3g})")


def figure(scene: Scene, coord: str, burgers: dict[str, str]) -> ProfileFigure:
    """The figure ``curvature.png`` of a scene: |Ein(Cg)|_g (profile key ``einstein_norm_g``)
    along a line with coordinate ``coord``, beside the Burgers vectors ``burgers`` (legend
    label -> profile key) on the right axis."""
    L = scene.units["length"]
    return ProfileFigure("curvature.png", coord, f"{coord} [{L}]",
                         {"|Ein(Cg)|_g": "einstein_norm_g"}, f"curvature [1/{L}$^2$]",
                         f"{scene.title()}: curvature of the growth metric",
                         right=burgers, right_label=f"|b| [1/{L}]", floor=FIGURE_FLOOR)


def report(scene: Scene, results: Results, coord: str, burgers: dict[str, str]) -> None:
    """Add the verdict (:func:`verdict`, when the curvature was measured) and the figure
    (:func:`figure`) to ``results``."""
    if "einstein_norm_L2" in results.metrics:
        results.verdicts.append(verdict(results.metrics))
    results.figures.append(figure(scene, coord, burgers))
