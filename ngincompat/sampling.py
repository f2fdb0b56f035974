"""Points at which fields are checked or maximised: integration points and vertices."""

import ngsolve as ngs

_VERTICES = {
    ngs.ET.TET: [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)],
    ngs.ET.HEX: [(a, b, c) for a in (0, 1) for b in (0, 1) for c in (0, 1)],
    ngs.ET.PRISM: [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (0, 1, 1)],
    ngs.ET.PYRAMID: [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1)],
}


def element_points(mesh, order=4):
    """The points of an integration rule of ``order`` plus the vertices, in every volume element.

    Returns the mapped points (evaluate a CoefficientFunction ``cf`` there with ``cf(points)``).
    """
    rules = {}
    for et in {el.type for el in mesh.Elements(ngs.VOL)}:
        ir = ngs.IntegrationRule(et, order)
        verts = _VERTICES[et]
        rules[et] = ngs.IntegrationRule([tuple(p) for p in ir.points] + verts,
                                        list(ir.weights) + [0.0] * len(verts))
    return mesh.MapToAllElements(rules, ngs.VOL)
