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


def table(cls):
    """The parameters of ``cls`` as a docutils table."""
    group = nodes.tgroup(cols=len(COLUMNS))
    group += [nodes.colspec(colwidth=w) for w in WIDTHS]

    def row(cells, literal=()):
        line = nodes.row()
        for i, text in enumerate(cells):
            entry = nodes.entry()
            inline = nodes.literal(text=text) if i in literal and text else nodes.Text(text)
            entry += nodes.paragraph("", "", inline)
            line += entry
        return line

    head = nodes.thead()
    head += row(COLUMNS)
    body = nodes.tbody()
    body += [row(cells, literal=(0, 1, 2, 3)) for cells in rows(cls)]
    group += [head, body]
    return nodes.table("", group, classes=["scene-parameters"])


def section(directive, cls):
    """The section of one scene: title, summary, units, presets and the table."""
    ident = f"parameters-{cls.name}"
    node = nodes.section(ids=[ident], names=[ident])
    node += nodes.title(text=f"{cls.name} ({cls.__name__})")
    node += nodes.paragraph(text=cls.summary)
    units = ", ".join(f"{quantity} in {symbol}" for quantity, symbol in cls.units.items())
    node += nodes.paragraph(text=f"Units: {units}. Presets: {', '.join(cls.preset_names())} "
                                 "(the preview and paper columns show what each sets; the "
                                 "rest keep their defaults).")
    node += table(cls)
    domain = directive.env.get_domain("std")
    domain.note_hyperlink_target(ident, directive.env.docname, ident,
                                 f"parameters of the {cls.name} scene")
    return node


class SceneParameters(SphinxDirective):
    """``.. scene-parameters::`` (``:scenes:`` a space-separated list; all by default)."""

    option_spec = {"scenes": directives.unchanged}

    def run(self):
        names = self.options.get("scenes", "").split() or list(SCENES)
        unknown = sorted(set(names) - set(SCENES))
        if unknown:
            raise self.error(f"unknown scenes {unknown}: allowed {', '.join(SCENES)}")
        return [section(self, SCENES[name]) for name in names]


def setup(app):
    app.add_directive("scene-parameters", SceneParameters)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
