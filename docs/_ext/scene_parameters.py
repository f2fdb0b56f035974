"""The ``scene-parameters`` directive: every scene's parameters, from the scenes' own
declarations (:meth:`ngincompat.scenes.base.Scene.declarations`), so the page cannot drift
from the code.

One section per scene of :data:`ngincompat.scenes.SCENES` (label ``parameters-<scene>``):
its summary, units and presets, and a table of its parameters with the default, the values
of the ``preview`` and ``paper`` presets, the unit in the scene's units, the allowed values
as the error messages state them, and the help text. ``:scenes: cube disc`` restricts it.
"""

from docutils import nodes
from docutils.parsers.rst import directives
from sphinx.util.docutils import SphinxDirective

from ngincompat.scenes import SCENES

COLUMNS = ("parameter", "default", "preview", "paper", "unit", "allowed", "help")
WIDTHS = (12, 10, 9, 9, 7, 20, 33)


def value_text(parameter, value):
    """A value as the command line's ``--set`` takes it (tuples as "8.5,7,6")."""
    shown = parameter.to_json(value)
    if isinstance(shown, list):
        return ",".join(f"{v:g}" if isinstance(v, float) else str(v) for v in shown)
    if isinstance(shown, float):
        return f"{shown:g}"
    return str(shown)


def rows(cls):
    """The table's rows of the scene class ``cls``: one per parameter, as strings."""
    presets = {name: cls.typed_settings(cls.preset_settings(name))
               for name in ("preview", "paper") if name in cls.preset_names()}
    for name, parameter in cls.declarations().items():
        preset_values = [presets[p][name] if p in presets and name in presets[p] else ""
                         for p in ("preview", "paper")]
        yield (name, value_text(parameter, parameter.default),
               *[value_text(parameter, parameter.convert(v)) if v != "" else ""
                 for v in preset_values],
               cls.unit_of(parameter.unit) if parameter.unit else "-",
               parameter.allowed(), parameter.help)


def grid(columns, widths, rows, literal, name):
    """A docutils table with the header ``columns`` (relative ``widths``) and the string
    ``rows``, the cells of the columns indexed in ``literal`` set as code; ``name`` its
    class (for the stylesheet)."""
    group = nodes.tgroup(cols=len(columns))
    group += [nodes.colspec(colwidth=w) for w in widths]

    def row(cells, literal=()):
        line = nodes.row()
        for i, text in enumerate(cells):
            entry = nodes.entry()
            inline = nodes.literal(text=text) if i in literal and text else nodes.Text(text)
            entry += nodes.paragraph("", "", inline)
            line += entry
        return line

    head = nodes.thead()
    head += row(columns)
    body = nodes.tbody()
    body += [row(cells, literal=literal) for cells in rows]
    group += [head, body]
    return nodes.table("", group, classes=[name])


def table(cls):
    """The parameters of ``cls`` as a docutils table."""
    return grid(COLUMNS, WIDTHS, rows(cls), (0, 1, 2, 3), "scene-parameters")


def units_text(cls):
    """The scene's units in a phrase: "length in mm, stress in MPa, ..."."""
    return ", ".join(f"{quantity} in {symbol}" for quantity, symbol in cls.units.items())


class SceneTables(SphinxDirective):
    """A section per scene (``:scenes:`` a space-separated list; all by default), each
    labelled ``<kind>-<scene>``, titled with the scene's name and class, holding the
    paragraphs and the table of :meth:`body`."""

    option_spec = {"scenes": directives.unchanged}
    kind = ""

    def body(self, cls):
        """The nodes of the scene class ``cls``'s section below its title."""
        raise NotImplementedError

    def section(self, cls):
        ident = f"{self.kind}-{cls.name}"
        node = nodes.section(ids=[ident], names=[ident])
        node += nodes.title(text=f"{cls.name} ({cls.__name__})")
        node += self.body(cls)
        self.env.get_domain("std").note_hyperlink_target(
            ident, self.env.docname, ident, f"{self.kind} of the {cls.name} scene")
        return node

    def run(self):
        names = self.options.get("scenes", "").split() or list(SCENES)
        unknown = sorted(set(names) - set(SCENES))
        if unknown:
            raise self.error(f"unknown scenes {unknown}: allowed {', '.join(SCENES)}")
        return [self.section(SCENES[name]) for name in names]


class SceneParameters(SceneTables):
    """``.. scene-parameters::``: per scene its summary, units, presets and parameters."""

    kind = "parameters"

    def body(self, cls):
        return [nodes.paragraph(text=cls.summary),
                nodes.paragraph(text=f"Units: {units_text(cls)}. Presets: "
                                     f"{', '.join(cls.preset_names())} (the preview and paper "
                                     "columns show what each sets; the rest keep their "
                                     "defaults)."),
                table(cls)]


def setup(app):
    app.add_directive("scene-parameters", SceneParameters)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
