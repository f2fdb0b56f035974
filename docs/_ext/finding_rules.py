"""The ``finding-rules`` directive: the rules by which ``ngincompat paper``'s report judges the
paper's findings, one row per rule, made from :func:`ngincompat.studies.findings.rules` when
the site is built (and again whenever a module of it changes), so the page cannot drift from the
code.

Columns: the section and figure, the paper's words (quoted), the measure (what is computed
from which case), the thresholds that give each verdict with their sources, and the verdicts
the rule can give.
"""

from pathlib import Path

from docutils import nodes
from sphinx.util.docutils import SphinxDirective

from ngincompat.studies import findings
from ngincompat.studies.findings import RULE_COLUMNS, rules

WIDTHS = (5, 5, 25, 22, 36, 7)


def cell(content):
    """A table entry: a paragraph, or a bulleted list for a list of strings."""
    entry = nodes.entry()
    if isinstance(content, list):
        items = nodes.bullet_list()
        for text in content:
            item = nodes.list_item()
            item += nodes.paragraph(text=text)
            items += item
        entry += items
    else:
        entry += nodes.paragraph(text=content)
    return entry


class FindingRules(SphinxDirective):
    """``.. finding-rules::``: the table of every rule."""

    def run(self):
        # the page is read again when the rules change (any module of the package)
        for module in sorted(Path(findings.__file__).parent.glob("*.py")):
            self.env.note_dependency(str(module))
        group = nodes.tgroup(cols=len(RULE_COLUMNS))
        group += [nodes.colspec(colwidth=w) for w in WIDTHS]
        head = nodes.thead()
        line = nodes.row()
        line += [cell(name) for name in RULE_COLUMNS]
        head += line
        body = nodes.tbody()
        for row in rules():
            line = nodes.row()
            line += [cell(content) for content in row]
            body += line
        group += [head, body]
        return [nodes.table("", group, classes=["finding-rules"])]


def setup(app):
    app.add_directive("finding-rules", FindingRules)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
