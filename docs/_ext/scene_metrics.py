"""The ``scene-metrics`` directive: every scene's metrics, from the scenes' own registry
(:attr:`ngincompat.scenes.base.Scene.metrics`), so the page cannot drift from the code.

One section per scene of :data:`ngincompat.scenes.SCENES` (label ``metrics-<scene>``): a
table of its metrics with the unit in the scene's units and the meaning. ``:scenes: cube
disc`` restricts it.
"""

from docutils import nodes
from scene_parameters import SceneTables, grid, units_text

COLUMNS = ("metric", "unit", "meaning")
WIDTHS = (16, 8, 60)


def rows(cls):
    """The table's rows of the scene class ``cls``: one per metric, as strings."""
    for name, metric in cls.metrics.items():
        yield name, cls.metric_unit(name), metric.meaning


def table(cls):
    """The metrics of ``cls`` as a docutils table."""
    return grid(COLUMNS, WIDTHS, rows(cls), (0,), "scene-metrics")


class SceneMetrics(SceneTables):
    """``.. scene-metrics::``: per scene its units and metrics."""

    kind = "metrics"

    def body(self, cls):
        return [nodes.paragraph(text=f"Units: {units_text(cls)}; '-' marks a ratio or a "
                                     "count."),
                table(cls)]


def setup(app):
    app.add_directive("scene-metrics", SceneMetrics)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
