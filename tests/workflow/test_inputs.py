"""User inputs: mesh files (Netgen .vol; Gmsh, VTK, Abaqus, MEDIT through meshio) and growth
fields given as data."""

import gzip
import itertools
import json

import meshio
import ngsolve as ngs
import numpy as np
import pytest
from conftest import random_points, values_at
from netgen.csg import CSGeometry, OrthoBrick, Pnt
from netgen.geom2d import unit_square

from geometries import cylinder
from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.workflow import inputs


def write_box_msh(path, n=(2, 2, 2), size=(2.0, 1.0, 1.0), version="2.2 0 8"):
    """A box [0, a] x [0, b] x [0, c] in Gmsh ASCII format 2.2.

    Structured cells split into 6 tetrahedra each (a conforming Kuhn split), two volume
    regions ``soft`` (x < a/2) and ``stiff`` and three boundary surfaces ``fixed`` (x = 0),
    ``loaded`` (x = a) and ``sides``. Returns the number of tetrahedra and the node
    coordinates in file order.
    """
    nx, ny, nz = n
    a, b, c = size

    def node(i, j, k):
        return 1 + i + (nx + 1) * (j + (ny + 1) * k)

    xyz = {node(i, j, k): (a * i / nx, b * j / ny, c * k / nz)
           for k in range(nz + 1) for j in range(ny + 1) for i in range(nx + 1)}
    tets = []
    for i, j, k in itertools.product(range(nx), range(ny), range(nz)):
        region = 1 if i < nx / 2 else 2
        for axes in itertools.permutations(range(3)):
            p = [i, j, k]
            tet = [node(*p)]
            for ax in axes:
                p[ax] += 1
                tet.append(node(*p))
            e = np.array([xyz[v] for v in tet])
            if np.linalg.det(e[1:] - e[0]) < 0:       # Gmsh wants positive orientation
                tet[1], tet[2] = tet[2], tet[1]
            tets.append((region, tet))

    def quads(fixed_axis, value):
        """The boundary quads on the plane x_fixed_axis = value, as lists of nodes."""
        m = [nx, ny, nz]
        u, v = [ax for ax in range(3) if ax != fixed_axis]
        for s, t in itertools.product(range(m[u]), range(m[v])):
            corners = []
            for ds, dt in ((0, 0), (1, 0), (1, 1), (0, 1)):
                p = [0, 0, 0]
                p[fixed_axis], p[u], p[v] = value, s + ds, t + dt
                corners.append(node(*p))
            yield corners

    tris = []
    for axis, (lo, hi) in enumerate(((0, nx), (0, ny), (0, nz))):
        for value, tag in ((lo, 11 if axis == 0 else 13), (hi, 12 if axis == 0 else 13)):
            outward = np.eye(3)[axis] * (1 if value else -1)
            for q in quads(axis, value):
                e = np.array([xyz[v] for v in q[:3]])
                if np.cross(e[1] - e[0], e[2] - e[0]) @ outward < 0:
                    q[1], q[3] = q[3], q[1]     # the other way round, same diagonal
                tris += [(tag, [q[0], q[1], q[2]]), (tag, [q[0], q[2], q[3]])]
    lines = ["$MeshFormat", version, "$EndMeshFormat", "$PhysicalNames", "5",
             '2 11 "fixed"', '2 12 "loaded"', '2 13 "sides"', '3 1 "soft"', '3 2 "stiff"',
             "$EndPhysicalNames", "$Nodes", str(len(xyz))]
    lines += [f"{t} {x!r} {y!r} {z!r}" for t, (x, y, z) in xyz.items()]
    lines += ["$EndNodes", "$Elements", str(len(tris) + len(tets))]
    elements = [(2, tag, t) for tag, t in tris] + [(4, tag, t) for tag, t in tets]
    for number, (etype, tag, vertices) in enumerate(elements, start=1):
        lines.append(f"{number} {etype} 2 {tag} {tag} " + " ".join(map(str, vertices)))
    lines.append("$EndElements")
    path.write_text("\n".join(lines) + "\n")
    return len(tets), np.array(list(xyz.values()))


def write_gmsh4(path, source, names, binary):
    """Write the mesh of the Gmsh file ``source`` as Gmsh 4.1 with meshio.

    Each cell block of one type and physical tag becomes an entity with that tag;
    ``names`` is {name: (tag, dimension)} ($PhysicalNames). meshio's writer takes the
    entities of $Entities from the nodes' entities and writes the nodes grouped by entity
    in the order of (dimension, tag): the first nodes are given one entity each in that
    order, the others the last one, so that the nodes keep their order."""
    mesh = meshio.read(source)
    cells, tags = [], []
    for block, physical in zip(mesh.cells, mesh.cell_data["gmsh:physical"], strict=True):
        for tag in np.unique(physical):
            cells.append(meshio.CellBlock(block.type, block.data[physical == tag]))
            tags.append(np.full(int((physical == tag).sum()), tag))
    entities = sorted({(block.dim, int(tag[0])) for block, tag in zip(cells, tags, strict=True)})
    dim_tags = np.array(entities + entities[-1:] * (len(mesh.points) - len(entities)))
    meshio.write(path, meshio.Mesh(
        mesh.points, cells, point_data={"gmsh:dim_tags": dim_tags},
        cell_data={"gmsh:physical": tags, "gmsh:geometrical": tags},
        field_data={name: np.array(td) for name, td in names.items()}),
        file_format="gmsh", binary=binary)


def round_vol_points(path):
    """Write the point coordinates of a .vol file as Netgen's Gmsh export does ("%f"), so that
    the .vol and the exported file describe the same vertices to the last bit."""
    head, rest = path.read_text().split("\npoints\n", 1)
    count, rest = rest.split("\n", 1)
    rows = rest.split("\n")
    rows[:int(count)] = [" ".join(f"{float(v):f}" for v in row.split())
                         for row in rows[:int(count)]]
    path.write_text(head + "\npoints\n" + count + "\n" + "\n".join(rows))


#: The physical names the Gmsh 4 files of :func:`box_files` carry.
BOX_NAMES = {"soft": (100001, 3), "stiff": (100002, 3),
             **{f"face{k}": (k, 2) for k in range(1, 12)}}


def write_box_files(folder):
    """Two unit cubes side by side meshed by Netgen (regions soft and stiff, 11 faces with
    the interface), as ``.vol`` and in the formats read through meshio, into ``folder``: the
    Gmsh 2 file exactly as ``ngmesh.Export(..., "Gmsh2 Format")`` writes it (no physical
    names) and, written by meshio from it, Gmsh 4.1 ASCII and binary (named), Gmsh 2.2
    binary, VTU, VTK, Abaqus (element sets soft and stiff) and MEDIT (the fixture
    ``box_files`` of tests/workflow/conftest.py)."""
    geo = CSGeometry()
    geo.Add(OrthoBrick(Pnt(0, 0, 0), Pnt(1, 1, 1)).mat("soft").bc("outer"))
    geo.Add(OrthoBrick(Pnt(1, 0, 0), Pnt(2, 1, 1)).mat("stiff").bc("outer"))
    ngmesh = geo.GenerateMesh(maxh=0.4)
    ngmesh.Save(str(folder / "box.vol"))
    round_vol_points(folder / "box.vol")
    ngmesh.Export(str(folder / "netgen2.msh"), "Gmsh2 Format")
    source = folder / "netgen2.msh"
    write_gmsh4(folder / "ascii4.msh", source, BOX_NAMES, binary=False)
    write_gmsh4(folder / "binary4.msh", source, BOX_NAMES, binary=True)
    mesh = meshio.read(source)
    meshio.write(folder / "binary22.msh", mesh, file_format="gmsh22", binary=True)
    for name in ("box.vtu", "box.vtk", "box.mesh"):
        meshio.write(folder / name, mesh)
    physical = mesh.cell_data["gmsh:physical"]
    sets = {name: [np.flatnonzero((p == tag) & (c.dim == 3)) for c, p in zip(mesh.cells, physical,
                                                                        strict=True)]
            for name, tag in (("soft", 100001), ("stiff", 100002))}
    meshio.write(folder / "box.inp", meshio.Mesh(mesh.points, mesh.cells, cell_sets=sets))
    return folder


@pytest.fixture(scope="module")
def cube_vol(tmp_path_factory, unit_cube_tet):
    """``cube(maxh=0.5, elements="tet")`` written as a .vol file, and that mesh."""
    path = tmp_path_factory.mktemp("mesh") / "cube.vol"
    unit_cube_tet.ngmesh.Save(str(path))
    return path, unit_cube_tet


# --- meshes ----------------------------------------------------------------------------------

@pytest.mark.parametrize("name", ["cube.vol", "cube.vol.gz"])
def test_vol_keeps_elements_and_names(tmp_path, unit_cube_tet, name):
    original = unit_cube_tet
    path = inputs.save_mesh(tmp_path / name, original)
    assert [p.name for p in tmp_path.iterdir()] == [name]
    if name.endswith(".gz"):
        assert path.read_bytes()[:2] == b"\x1f\x8b"
    mesh = inputs.load_mesh(path)
    assert (mesh.ne, mesh.nv) == (original.ne, original.nv)
    assert mesh.GetMaterials() == original.GetMaterials() == ("tissue",)
    assert mesh.GetBoundaries() == original.GetBoundaries()
    assert set(mesh.GetBoundaries()) == {"left", "right", "front", "back", "bottom", "top"}
    assert inputs.describe_mesh(mesh) == inputs.describe_mesh(original)


def test_describe_mesh(cube_vol):
    d = inputs.describe_mesh(inputs.load_mesh(cube_vol[0]))
    assert d["dim"] == 3 and d["ne"] == cube_vol[1].ne and d["nv"] == cube_vol[1].nv
    assert d["nse"] > 0 and d["materials"] == ["tissue"] and len(d["boundaries"]) == 6
    np.testing.assert_allclose(d["bounding_box"], [[0, 0, 0], [1, 1, 1]], atol=1e-12)
    assert set(d["fingerprint"]) == {"nv", "ne", "elements_sha256", "vertices_sha256"}


def test_curved_vol_reads_back_curved_and_recurves_with_its_geometry(tmp_path):
    mesh = cylinder(maxh=0.5, curve_order=1)
    straight_volume = ngs.Integrate(1, mesh)
    inputs.save_mesh(tmp_path / "straight.vol", mesh)
    mesh.Curve(3)
    volume = ngs.Integrate(1, mesh)
    assert volume - straight_volume > 0.01
    inputs.save_mesh(tmp_path / "curved.vol", mesh)
    # the curved elements are in the file; the text format keeps them to about 1e-9
    mesh = inputs.load_mesh(tmp_path / "curved.vol")
    assert inputs.describe_mesh(mesh)["curve_order"] == 3
    assert ngs.Integrate(1, mesh) == pytest.approx(volume, rel=1e-8)
    flat = inputs.load_mesh(tmp_path / "curved.vol", curve_order=1)
    assert ngs.Integrate(1, flat) == pytest.approx(straight_volume, rel=1e-12)
    # the OCC geometry is in the file too: a straight mesh is curved with it
    assert ngs.Integrate(1, inputs.load_mesh(tmp_path / "straight.vol")) == pytest.approx(
        straight_volume, rel=1e-12)
    recurved = inputs.load_mesh(tmp_path / "straight.vol", curve_order=3)
    assert ngs.Integrate(1, recurved) == pytest.approx(volume, rel=1e-12)
    write_box_msh(tmp_path / "box.msh")
    with pytest.raises(ParameterError, match=r"box\.msh.*no geometry"):
        inputs.load_mesh(tmp_path / "box.msh", curve_order=2)


# --- the command line on mesh files ----------------------------------------------------------

#: A run of the custom scene on a mesh file: theta = 1 + X1 t / 10.
RUN = ["--set", "theta=1+0.1*X1*t", "--set", "order=2", "-q"]


def run_custom(out, mesh):
    assert main(["run", "custom", "--out", str(out), "--set", f"mesh={mesh}", *RUN]) == 0
    return json.loads((out / "results.json").read_text())


@pytest.fixture(scope="module")
def vol_run(box_files, tmp_path_factory):
    return run_custom(tmp_path_factory.mktemp("run"), box_files / "box.vol")


def assert_same_run(results, reference):
    """The same growth on the same mesh: the same metrics, to round-off."""
    assert results["status"] == "done" and results["mesh"] == reference["mesh"]
    assert set(results["metrics"]) == set(reference["metrics"])
    for key, value in reference["metrics"].items():
        if value is None:
            assert results["metrics"][key] is None, key
        else:
            assert results["metrics"][key] == pytest.approx(value, rel=1e-9, abs=1e-15), key


def test_cli_runs_on_a_vol_file(vol_run, box_files):
    assert vol_run["status"] == "done"
    assert vol_run["mesh"]["ne"] == inputs.load_mesh(box_files / "box.vol").ne
    # eq. (16): |b| on n2 is |grad theta| / (3 theta^(4/3)), largest where theta = 1
    assert vol_run["metrics"]["burgers_max"] == pytest.approx(0.1 / 3, rel=1e-5)


def test_cli_runs_on_a_gmsh4_ascii_file(tmp_path, box_files, vol_run):
    assert_same_run(run_custom(tmp_path, box_files / "ascii4.msh"), vol_run)


def test_cli_runs_on_a_gmsh4_binary_file(tmp_path, box_files, vol_run):
    assert_same_run(run_custom(tmp_path, box_files / "binary4.msh"), vol_run)


def test_cli_runs_on_a_gmsh2_file_as_netgen_exports_it(tmp_path, box_files, vol_run):
    assert_same_run(run_custom(tmp_path, box_files / "netgen2.msh"), vol_run)


# --- growth data -----------------------------------------------------------------------------

def test_growth_round_trip_on_the_same_mesh_file(tmp_path, cube_vol):
    path, _ = cube_vol
    theta = 1 + 0.25 * ngs.x + 0.1 * ngs.y * ngs.z
    written_on = inputs.load_mesh(path)
    growth = inputs.save_growth(tmp_path / "growth.npz", written_on, theta, order=3)
    assert [p.name for p in tmp_path.iterdir()] == ["growth.npz"]
    mesh = inputs.load_mesh(path)
    gf = inputs.load_growth(growth, mesh)
    assert gf.space.globalorder == 3
    reference = ngs.GridFunction(ngs.H1(written_on, order=3))
    reference.Set(theta, dual=True)
    np.testing.assert_allclose(gf.vec.FV().NumPy(), reference.vec.FV().NumPy(), rtol=0,
                               atol=1e-14)
    pts = random_points(10)
    np.testing.assert_allclose(values_at(gf, mesh, pts).ravel(),
                               1 + 0.25 * pts[:, 0] + 0.1 * pts[:, 1] * pts[:, 2], atol=1e-12)
    with np.load(growth) as data:
        coords = np.array([v.point for v in mesh.vertices])
        np.testing.assert_allclose(data["vertices"], coords, atol=1e-15)
        np.testing.assert_allclose(data["vertex_values"],
                                   1 + 0.25 * coords[:, 0] + 0.1 * coords[:, 1] * coords[:, 2],
                                   atol=1e-14)


def test_growth_of_a_run_reads_back_on_its_saved_mesh(tmp_path, cube_vol):
    """What a run writes (its mesh in memory, a GridFunction) and a later run reads."""
    path, original = cube_vol
    field = ngs.GridFunction(ngs.H1(original, order=2))
    field.Set(1 + 0.3 * ngs.x * ngs.x)
    inputs.save_growth(tmp_path / "growth.npz", original, field, order=2)
    gf = inputs.load_growth(tmp_path / "growth.npz", inputs.load_mesh(path))
    np.testing.assert_allclose(gf.vec.FV().NumPy(), field.vec.FV().NumPy(), atol=1e-13)


def test_growth_on_another_mesh_is_refused(tmp_path, cube_vol, unit_cube_hex):
    inputs.save_growth(tmp_path / "growth.npz", inputs.load_mesh(cube_vol[0]), 1 + ngs.x, 2)
    with pytest.raises(ParameterError, match=rf"growth\.npz': was written on a mesh with "
                                             rf"{cube_vol[1].nv} vertices, this one has "
                                             rf"{unit_cube_hex.nv}"):
        inputs.load_growth(tmp_path / "growth.npz", unit_cube_hex)
    moved = ngs.Mesh(cube_vol[1].ngmesh.Copy())
    moved.ngmesh.Scale(2.0)
    moved = ngs.Mesh(moved.ngmesh)
    with pytest.raises(ParameterError, match=r"growth\.npz': was written on a mesh with vertex"):
        inputs.load_growth(tmp_path / "growth.npz", moved)


def test_growth_with_other_dofs_is_refused(tmp_path, cube_vol):
    """The stored field values per element catch dofs that no longer mean the same field."""
    mesh = inputs.load_mesh(cube_vol[0])
    path = inputs.save_growth(tmp_path / "growth.npz", mesh, 1 + 0.1 * ngs.x * ngs.y, order=3)
    with np.load(path) as data:
        arrays = dict(data)
    arrays["dofs"][mesh.nv:] = arrays["dofs"][mesh.nv:][::-1]    # higher-order dofs shuffled
    np.savez(path, **arrays)
    with pytest.raises(ParameterError, match=r"growth\.npz': its dofs do not give back"):
        inputs.load_growth(path, mesh)


@pytest.mark.parametrize("name,header", [("theta.csv", "theta\n"), ("theta.txt", "# theta\n")])
def test_vertex_values_from_a_table(tmp_path, cube_vol, name, header):
    mesh = inputs.load_mesh(cube_vol[0])
    values = 1 + np.random.default_rng(1).uniform(0, 0.5, mesh.nv)
    (tmp_path / name).write_text(header + "\n".join(repr(float(v)) for v in values))
    gf = inputs.load_growth(tmp_path / name, mesh)
    assert gf.space.globalorder == 1
    np.testing.assert_array_equal(gf.vec.FV().NumPy(), values)
    corners = np.array([v.point for v in mesh.vertices])
    np.testing.assert_allclose(values_at(gf, mesh, corners).ravel(), values, atol=1e-12)


def test_vertex_values_from_npz(tmp_path, cube_vol):
    mesh = inputs.load_mesh(cube_vol[0])
    values = np.linspace(1, 2, mesh.nv)
    np.savez(tmp_path / "theta.npz", theta=values, other=np.zeros(3))
    np.testing.assert_array_equal(
        inputs.load_growth(tmp_path / "theta.npz", mesh).vec.FV().NumPy(), values)


def test_ramped_growth(cube_vol):
    mesh = inputs.load_mesh(cube_vol[0])
    data = ngs.GridFunction(ngs.H1(mesh, order=1))
    data.Set(1 + ngs.x)
    t = ngs.Parameter(0.0)
    theta = inputs.ramped_growth(data, t)
    p = mesh(0.5, 0.5, 0.5)
    assert theta(p) == pytest.approx(1.0)
    t.Set(1.0)
    assert theta(p) == pytest.approx(1.5)
    t.Set(0.5)
    assert theta(p) == pytest.approx(1.25)


# --- bad inputs ------------------------------------------------------------------------------

def _bad_mesh_files(tmp_path, cube_vol, box_files):
    """file -> the reason the error must give."""
    text = cube_vol[0].read_text()
    (tmp_path / "dir.vol").mkdir()
    (tmp_path / "mesh.stl").write_text("solid x\n")
    (tmp_path / "junk.vol").write_text("hello\n")
    (tmp_path / "truncated.vol").write_text(text[:len(text.split("points")[0]) + 200])
    (tmp_path / "noend.vol").write_text(text[:text.index("endmesh")])
    (tmp_path / "broken.vol.gz").write_bytes(gzip.compress(text.encode())[:300])
    rows = text.split("\nvolumeelements\n")[1].split("\n")
    (tmp_path / "badpoint.vol").write_text(text.replace(rows[1], " 1 4 1 2 3 999", 1))
    (tmp_path / "flat.vol").write_text(text.replace("dimension\n3", "dimension\n2", 1))
    before, after = text.split("\nvolumeelements\n")
    (tmp_path / "novolume.vol").write_text(before + "\npoints\n" + after.split("\npoints\n")[1])
    box = (box_files / "netgen2.msh").read_text()
    (tmp_path / "truncated.msh").write_text(box[:box.index("$Elements") + 200])
    binary = (box_files / "binary4.msh").read_bytes()
    (tmp_path / "truncated4.msh").write_bytes(binary[:len(binary) // 2])
    mesh = meshio.read(box_files / "netgen2.msh")
    triangles = [c for c in mesh.cells if c.type == "triangle"]
    meshio.write(tmp_path / "surface.msh", meshio.Mesh(mesh.points, triangles),
                 file_format="gmsh22")
    meshio.write(tmp_path / "stray.msh", meshio.Mesh(mesh.points, [
        *mesh.cells, ("triangle", np.array([[0, 1, len(mesh.points) - 1]]))]),
        file_format="gmsh22")
    square = unit_square.GenerateMesh(maxh=0.5)
    square.Export(str(tmp_path / "square.msh"), "Gmsh2 Format")
    corners = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [0, 0, 1]], float)
    meshio.write(tmp_path / "degenerate.vtu", meshio.Mesh(corners, [("tetra", [[0, 1, 2, 3]])]))
    cube = np.array(list(itertools.product((0, 1), repeat=3)), float)[:, ::-1]
    meshio.write(tmp_path / "tangled.vtu", meshio.Mesh(cube, [("hexahedron",
                                                                [[0, 1, 3, 2, 4, 5, 6, 7]])]))
    meshio.write(tmp_path / "polygons.vtu", meshio.Mesh(corners, [("polygon", [[0, 1, 3, 2]])]))
    allowed = ".vol, .vol.gz, .msh, .vtu, .vtk, .inp, .mesh"
    return {
        "missing.vol": "does not exist",
        "dir.vol": "is a directory",
        "mesh.stl": f"unknown extension '.stl'; allowed: {allowed}",
        "junk.vol": "not a Netgen mesh",
        "truncated.vol": "truncated",
        "noend.vol": "truncated",
        "broken.vol.gz": "damaged gzip data",
        "badpoint.vol": "an element uses point 999 but the file has",
        "flat.vol": "not a 3-D mesh",
        "novolume.vol": "no volume elements",
        "truncated.msh": "cannot be read as a gmsh file (truncated or damaged?)",
        "truncated4.msh": "cannot be read as a gmsh file (truncated or damaged?)",
        "surface.msh": "is a surface mesh (triangles and quadrilaterals only): a 3-D volume mesh",
        "square.msh": "is a 2-D mesh (its nodes lie in one coordinate plane): a 3-D volume mesh",
        "stray.msh": "has boundary triangles that are no face of a volume cell",
        "degenerate.vtu": "1 of its 1 tetra cells are degenerate (flat)",
        "tangled.vtu": "1 of its 1 hexahedron cells are inverted at some corners",
        "polygons.vtu": "has cells of type 'polygon', which are not read",
    }


def test_bad_mesh_files_name_parameter_file_and_reason(tmp_path, cube_vol, box_files):
    for name, reason in _bad_mesh_files(tmp_path, cube_vol, box_files).items():
        with pytest.raises(ParameterError) as err:
            inputs.load_mesh(tmp_path / name)
        message = str(err.value)
        assert message.startswith(f"mesh = '{tmp_path / name}': "), message
        assert reason in message and "\n" not in message, message


def test_bad_growth_files_name_file_and_reason(tmp_path, cube_vol):
    mesh = inputs.load_mesh(cube_vol[0])
    nv = mesh.nv
    good = np.full(nv, 1.1)
    negative, nan = good.copy(), good.copy()
    negative[5], nan[3] = -0.5, np.nan
    (tmp_path / "dir.csv").mkdir()
    (tmp_path / "theta.json").write_text("[]")
    (tmp_path / "short.csv").write_text("\n".join(map(str, good[:-2])))
    (tmp_path / "negative.csv").write_text("\n".join(map(str, negative)))
    (tmp_path / "nan.txt").write_text("\n".join(map(str, nan)))
    (tmp_path / "words.txt").write_text("1.0\nabc\n")
    (tmp_path / "columns.csv").write_text("\n".join(f"{v},{v}" for v in good))
    (tmp_path / "corrupt.npz").write_bytes(b"PK\x03\x04 not a zip")
    np.savez(tmp_path / "two.npz", a=good, b=good)
    x5 = ", ".join(f"{c:.6g}" for c in mesh.vertices[5].point)
    expected = {
        "missing.npz": "does not exist",
        "dir.csv": "is a directory",
        "theta.json": "unknown extension '.json'; allowed: .npz, .csv, .txt",
        "short.csv": f"has {nv - 2} values, expected {nv}",
        "negative.csv": f"theta = -0.5 is not > 0 at vertex 5 ({x5})",
        "nan.txt": "theta = nan is not finite at vertex 3",
        "words.txt": "not a table of numbers",
        "columns.csv": "2 columns",
        "corrupt.npz": "not a readable .npz file",
        "two.npz": "name the per-vertex values 'theta'",
    }
    for name, reason in expected.items():
        with pytest.raises(ParameterError) as err:
            inputs.load_growth(tmp_path / name, mesh)
        message = str(err.value)
        assert name in message and reason in message, message


def test_a_5000_character_path_or_value_is_refused_with_a_short_message():
    from ngincompat.scenes import CustomScene

    for settings in ({"mesh": "/tmp/" + "a" * 5000 + ".msh"},
                     {"theta_file": "/tmp/" + "b" * 5000 + ".npz"},
                     {"maxh": "1" * 5000 + "x"}):
        with pytest.raises(ParameterError) as info:
            CustomScene.from_settings(settings)
        key = next(iter(settings))
        assert str(info.value).startswith(f"{key} = ") and len(str(info.value)) < 250
