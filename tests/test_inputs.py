"""User inputs: mesh files (Netgen .vol, Gmsh .msh) and growth fields given as data."""

import gzip
import itertools

import ngsolve as ngs
import numpy as np
import pytest
from conftest import random_points, values_at

from geometries import cylinder
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
                    q.reverse()
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


def test_gmsh_box_regions_and_boundaries(tmp_path):
    path = tmp_path / "box.msh"
    ntets, nodes = write_box_msh(path, n=(2, 2, 2), size=(2.0, 1.0, 1.0))
    mesh = inputs.load_mesh(path)
    assert mesh.ne == ntets == 48 and mesh.nv == 27
    # vertices in the order of $Nodes: the order of per-vertex user data
    np.testing.assert_array_equal([v.point for v in mesh.vertices], nodes)
    assert set(mesh.GetMaterials()) == {"soft", "stiff"}
    assert set(mesh.GetBoundaries()) == {"fixed", "loaded", "sides"}
    assert ngs.Integrate(1, mesh) == pytest.approx(2.0, rel=1e-12)
    assert ngs.Integrate(1, mesh, definedon=mesh.Materials("stiff")) == pytest.approx(1.0)
    area = {b: ngs.Integrate(1, mesh, ngs.BND, definedon=mesh.Boundaries(b))
            for b in ("fixed", "loaded", "sides")}
    assert area == pytest.approx({"fixed": 1.0, "loaded": 1.0, "sides": 8.0})
    # boundary normals point outwards: the divergence theorem for X gives 3 |body|
    n = ngs.specialcf.normal(3)
    assert ngs.Integrate(n * ngs.CF((ngs.x, ngs.y, ngs.z)), mesh, ngs.BND) == pytest.approx(6)


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
    with pytest.raises(ParameterError, match=rf"growth\.npz: was written on a mesh with "
                                             rf"{cube_vol[1].nv} vertices, this one has "
                                             rf"{unit_cube_hex.nv}"):
        inputs.load_growth(tmp_path / "growth.npz", unit_cube_hex)
    moved = ngs.Mesh(cube_vol[1].ngmesh.Copy())
    moved.ngmesh.Scale(2.0)
    moved = ngs.Mesh(moved.ngmesh)
    with pytest.raises(ParameterError, match=r"growth\.npz: was written on a mesh with vertex"):
        inputs.load_growth(tmp_path / "growth.npz", moved)


def test_growth_with_other_dofs_is_refused(tmp_path, cube_vol):
    """The stored field values per element catch dofs that no longer mean the same field."""
    mesh = inputs.load_mesh(cube_vol[0])
    path = inputs.save_growth(tmp_path / "growth.npz", mesh, 1 + 0.1 * ngs.x * ngs.y, order=3)
    with np.load(path) as data:
        arrays = dict(data)
    arrays["dofs"][mesh.nv:] = arrays["dofs"][mesh.nv:][::-1]    # higher-order dofs shuffled
    np.savez(path, **arrays)
    with pytest.raises(ParameterError, match=r"growth\.npz: its dofs do not give back"):
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

def _bad_mesh_files(tmp_path, cube_vol):
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
    write_box_msh(tmp_path / "v4.msh", version="4.1 0 8")
    write_box_msh(tmp_path / "binary.msh", version="2.2 1 8")
    write_box_msh(tmp_path / "truncated.msh")
    box = (tmp_path / "truncated.msh").read_text()
    (tmp_path / "truncated.msh").write_text(box[:box.index("$Elements") + 200])
    (tmp_path / "unnamed.msh").write_text(box.replace('3 2 "stiff"\n', "").replace(
        "$PhysicalNames\n5", "$PhysicalNames\n4"))
    (tmp_path / "blank.msh").write_text(box.replace('"soft"', '"soft tissue"'))
    (tmp_path / "surface.msh").write_text(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n"
        "$EndNodes\n$Elements\n1\n1 2 2 0 1 1 2 3\n$EndElements\n")
    return {
        "missing.vol": "does not exist",
        "dir.vol": "is a directory",
        "mesh.stl": "unknown mesh file extension '.stl'; allowed: .vol, .vol.gz, .msh",
        "junk.vol": "not a Netgen mesh",
        "truncated.vol": "truncated",
        "noend.vol": "truncated",
        "broken.vol.gz": "damaged gzip data",
        "badpoint.vol": "an element uses point 999 but the file has",
        "flat.vol": "not a 3-D mesh",
        "novolume.vol": "no volume elements",
        "v4.msh": "Gmsh format 4.1; only ASCII format 2",
        "binary.msh": "binary Gmsh file",
        "truncated.msh": "truncated",
        "unnamed.msh": "physical group 2 (dimension 3) has no name",
        "blank.msh": 'physical name "soft tissue" contains blanks',
        "surface.msh": "2-D mesh",
    }


def test_bad_mesh_files_name_file_and_reason(tmp_path, cube_vol):
    for name, reason in _bad_mesh_files(tmp_path, cube_vol).items():
        with pytest.raises(ParameterError) as err:
            inputs.load_mesh(tmp_path / name)
        message = str(err.value)
        assert name in message and reason in message, message
        assert "\n" not in message


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
        "theta.json": "unknown growth file extension '.json'; allowed: .npz, .csv, .txt",
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
