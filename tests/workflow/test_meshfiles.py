"""ngincompat.workflow.meshfiles: meshio's formats converted to Netgen, checked on the way."""

import logging

import meshio
import ngsolve as ngs
import numpy as np
import pytest
from netgen import occ
from workflow.test_inputs import write_box_msh

from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.workflow import inputs, meshfiles

#: The corners of the unit corner tetrahedron and a point (1, 1, 1) beyond its slanted face.
CORNERS = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]], float)


def measures(mesh):
    """What a mesh is for a run: vertices, element count, volume per region, area per face
    descriptor (in their order), and the divergence theorem for X with ngsolve's normal."""
    def areas(k):
        mask = ngs.BitArray(len(mesh.GetBoundaries()))
        mask.Clear()
        mask.Set(k)
        return ngs.Integrate(1, mesh, ngs.BND, definedon=ngs.Region(mesh, ngs.BND, mask))

    return {
        "vertices": np.array([v.point for v in mesh.vertices]),
        "ne": mesh.ne,
        "regions": [ngs.Integrate(1, mesh, definedon=mesh.Materials(f"^{m}$"))
                    for m in dict.fromkeys(mesh.GetMaterials())],
        "faces": [areas(k) for k in range(len(mesh.GetBoundaries()))],
        "flux": ngs.Integrate(ngs.specialcf.normal(3) * ngs.CF((ngs.x, ngs.y, ngs.z)), mesh,
                              ngs.BND),
    }


# --- read through inputs.load_mesh ---------------------------------------------------------

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


def test_every_format_gives_the_mesh_of_the_vol_file(box_files, caplog):
    """The independent check of the conversion: the same vertices in the same order, and the
    same volume per region, area per face and boundary normals as Netgen's own .vol file."""
    reference = measures(inputs.load_mesh(box_files / "box.vol"))
    assert sum(reference["regions"]) == pytest.approx(2.0, rel=1e-12)
    assert reference["flux"] == pytest.approx(3 * 2.0 + 1.0, rel=1e-12)   # + the interface
    faces = tuple(f"face{k}" for k in range(1, 12))
    unnamed = (("region100001", "region100002"), tuple(f"boundary{k}" for k in range(1, 12)))
    expected_names = {
        "netgen2.msh": unnamed, "binary22.msh": unnamed, "box.vtu": unnamed,
        "box.vtk": unnamed, "box.mesh": unnamed,
        "ascii4.msh": (("soft", "stiff"), faces), "binary4.msh": (("soft", "stiff"), faces),
        "box.inp": (("soft", "stiff"), ("default",) * 3),
    }
    for name, (materials, boundaries) in expected_names.items():
        caplog.clear()
        with caplog.at_level(logging.WARNING):
            mesh = inputs.load_mesh(box_files / name)
        got = measures(mesh)
        np.testing.assert_array_equal(got["vertices"], reference["vertices"], err_msg=name)
        assert got["ne"] == reference["ne"], name
        assert got["regions"] == pytest.approx(reference["regions"], rel=1e-12), name
        assert got["flux"] == pytest.approx(reference["flux"], rel=1e-12), name
        assert (mesh.GetMaterials(), mesh.GetBoundaries()) == (materials, boundaries), name
        if name == "box.inp":           # Abaqus: element sets, the triangles carry no tags
            assert sum(got["faces"]) == pytest.approx(sum(reference["faces"]), rel=1e-12)
        else:
            assert got["faces"] == pytest.approx(reference["faces"], rel=1e-12), name
        assert ("without a name" in caplog.text) == (boundaries != faces), name


def test_hexahedra_and_prisms_in_either_orientation(tmp_path):
    """Cells of both orientations (file conventions differ) are turned to Netgen's: positive
    Jacobians, outward normals; outer faces without boundary cells are added as 'default'."""
    nodes = np.array([(x, y, z) for z in range(2) for y in range(2) for x in range(3)], float)
    index = {tuple(p): k for k, p in enumerate(nodes)}
    hexes = [[index[(i + dx, dy, dz)] for dz in (0, 1) for dx, dy in ((0, 0), (1, 0), (1, 1),
                                                                     (0, 1))]
             for i in range(2)]
    wedges = [[h[0], h[1], h[2], h[4], h[5], h[6]] for h in hexes] + \
             [[h[0], h[2], h[3], h[4], h[6], h[7]] for h in hexes]
    mirrored = {"hexahedron": [0, 3, 2, 1, 4, 7, 6, 5], "wedge": [0, 2, 1, 3, 5, 4]}
    jacobian = ngs.Det(ngs.specialcf.JacobianMatrix(3))
    rules = {et: ngs.IntegrationRule([p], [1.0]) for et, p in
             ((ngs.ET.HEX, (0.5, 0.5, 0.5)), (ngs.ET.PRISM, (1 / 3, 1 / 3, 0.5)))}
    for kind, cells in (("hexahedron", hexes), ("wedge", wedges)):
        cells = np.array(cells)
        cells[1::2] = cells[1::2][:, mirrored[kind]]        # every other cell mirrored
        meshio.write(tmp_path / f"{kind}.vtu", meshio.Mesh(nodes, [(kind, cells)]))
        mesh = inputs.load_mesh(tmp_path / f"{kind}.vtu")
        assert mesh.ne == len(cells) and set(mesh.GetBoundaries()) == {"default"}
        assert ngs.Integrate(1, mesh) == pytest.approx(2.0, rel=1e-12)
        assert min(jacobian(mesh.MapToAllElements(rules, ngs.VOL))) > 0
        n = ngs.specialcf.normal(3)
        assert ngs.Integrate(n * ngs.CF((ngs.x, ngs.y, ngs.z)), mesh, ngs.BND) == \
            pytest.approx(6.0, rel=1e-12)


def test_second_order_cells_are_read_with_their_corners(tmp_path, caplog):
    ngmesh = occ.OCCGeometry(occ.Cylinder(occ.Pnt(0, 0, 0), occ.Z, r=1, h=1)).GenerateMesh(
        maxh=0.6)
    straight = ngs.Mesh(ngmesh.Copy())
    ngmesh.SecondOrder()
    ngmesh.Export(str(tmp_path / "cylinder.msh"), "Gmsh2 Format")
    assert {c.type for c in meshio.read(tmp_path / "cylinder.msh").cells} == {"tetra10",
                                                                             "triangle6"}
    with caplog.at_level(logging.WARNING):
        mesh = inputs.load_mesh(tmp_path / "cylinder.msh")
    assert "second-order cells (tetra10, triangle6) are read with their corners only" in \
        caplog.text
    assert (mesh.nv, mesh.ne) == (straight.nv, straight.ne)
    np.testing.assert_allclose([v.point for v in mesh.vertices],
                               [v.point for v in straight.vertices], atol=5e-7)
    volume = ngs.Integrate(1, mesh)
    assert volume == pytest.approx(ngs.Integrate(1, straight), rel=1e-5)
    assert ngs.Integrate(1, ngs.Mesh(ngmesh)) - volume > 0.05    # the curved cells' volume


@pytest.mark.parametrize("content", ["", "garbage\n"], ids=["empty", "garbage"])
def test_an_unreadable_msh_file_is_bad_input_not_meshios_exit(content, tmp_path, capsys):
    """meshio prints its error and calls sys.exit(1) when no reader takes a file, which
    ``except Exception`` let through: exit 1 with meshio's words instead of exit 2."""
    path = tmp_path / "box.msh"
    path.write_text(content)
    assert main(["run", "custom", "--set", f"mesh={path}", "--out", str(tmp_path / "out"),
                 "-q"]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("ngincompat: error: mesh = "), lines
    assert "box.msh" in lines[0] and "gmsh" in lines[0] and captured.out == ""


# --- read directly -------------------------------------------------------------------------

def _flux(mesh):
    """The divergence theorem for X: 3 |body| where the boundary normals point outward."""
    return ngs.Integrate(ngs.specialcf.normal(3) * ngs.CF((ngs.x, ngs.y, ngs.z)), mesh, ngs.BND)


@pytest.mark.parametrize("corners", [[0, 1, 2, 3], [0, 2, 1, 3]], ids=["positive", "negative"])
def test_a_tetrahedron_of_either_orientation_is_read_with_its_volume(tmp_path, corners,
                                                                      caplog):
    """The unit corner tetrahedron (volume 1/6) without boundary cells and one node that is
    no corner: the node left out, the four outer faces added as 'default', each said."""
    path = tmp_path / "tet.vtu"
    meshio.write(path, meshio.Mesh(CORNERS, [("tetra", np.array([corners]))]))
    with caplog.at_level(logging.WARNING):
        mesh = meshfiles.read(path, ".vtu")
    assert (mesh.ne, mesh.nv) == (1, 4)
    assert ngs.Integrate(1, mesh) == pytest.approx(1 / 6, rel=1e-12)
    assert _flux(mesh) == pytest.approx(0.5, rel=1e-12)
    assert mesh.GetMaterials() == ("default",) and mesh.GetBoundaries() == ("default",)
    assert "1 of its 5 nodes are no corner of a volume cell and are left out" in caplog.text
    assert "4 outer triangles have no boundary cell in the file" in caplog.text


def test_regions_and_an_interface_keep_their_physical_names(tmp_path):
    """Two tetrahedra of two physical groups sharing the face (1,0,0), (0,1,0), (0,0,1), a
    triangle of a third group on it: an interface from the lower region to the higher."""
    path = tmp_path / "two.msh"
    tags = {"gmsh:physical": [np.array([1, 2]), np.array([7])],
            "gmsh:geometrical": [np.array([1, 2]), np.array([7])]}
    names = {"inner": np.array([1, 3]), "outer": np.array([2, 3]), "iface": np.array([7, 2])}
    meshio.write(path, meshio.Mesh(CORNERS, [("tetra", np.array([[0, 1, 2, 3], [1, 2, 3, 4]])),
                                             ("triangle", np.array([[1, 2, 3]]))],
                                   cell_data=tags, field_data=names),
                 file_format="gmsh22", binary=False)
    mesh = meshfiles.read(path, ".msh")
    assert mesh.GetMaterials() == ("inner", "outer")
    assert ngs.Integrate(1, mesh, definedon=mesh.Materials("inner")) == pytest.approx(1 / 6)
    assert ngs.Integrate(1, mesh, definedon=mesh.Materials("outer")) == pytest.approx(1 / 3)
    assert ngs.Integrate(1, mesh, ngs.BND, definedon=mesh.Boundaries("iface")) == \
        pytest.approx(3 ** 0.5 / 2, rel=1e-12)
    sides = {fd.bcname: (fd.domin, fd.domout) for fd in mesh.ngmesh.FaceDescriptors()}
    assert sides["iface"] == (1, 2)
    # outward on the outer faces (3 |body| = 1.5), out of "inner" on the interface (0.5)
    assert _flux(mesh) == pytest.approx(2.0, rel=1e-12)


@pytest.mark.parametrize("name, mesh, reason", [
    ("repeated.vtu", meshio.Mesh(CORNERS, [("tetra", np.array([[0, 1, 2, 3]] * 3))]),
     "has triangles shared by more than two volume cells: overlapping or repeated cells"),
    ("infinite.vtu", meshio.Mesh(np.vstack([CORNERS[:4], [np.inf, 0, 0]]),
                                 [("tetra", np.array([[0, 1, 2, 3]]))]),
     "has node coordinates that are not finite"),
    ("sets.inp", meshio.Mesh(CORNERS, [("tetra", np.array([[0, 1, 2, 3], [1, 2, 3, 4]]))],
                             cell_sets={"a": [np.array([0, 1])], "b": [np.array([1])]}),
     "its cell sets 'a' and 'b' share cells: the regions of a mesh must not overlap"),
    ("edges.vtu", meshio.Mesh(CORNERS, [("line", np.array([[0, 1], [1, 2]]))]),
     "has no cells: a 3-D volume mesh"),
    ("surface.vtu", meshio.Mesh(CORNERS, [("triangle", np.array([[0, 1, 3], [1, 2, 3]]))]),
     "is a surface mesh (triangles and quadrilaterals only)"),
])
def test_a_mesh_that_is_no_volume_of_cells_is_refused_naming_why(tmp_path, name, mesh, reason):
    path = tmp_path / name
    meshio.write(path, mesh)
    with pytest.raises(ParameterError) as info:
        meshfiles.read(path, "." + name.split(".")[1])
    message = str(info.value)
    assert message.startswith(f"mesh = '{path}': ") and reason in message, message


# --- the one-line errors -------------------------------------------------------------------

def test_a_file_error_names_the_parameter_the_file_and_the_reason():
    error = meshfiles.file_error("/data/box.msh", "does not exist", "theta_file")
    assert isinstance(error, ParameterError)
    assert str(error) == "theta_file = '/data/box.msh': does not exist"
    assert str(meshfiles.file_error("a.vol", "r")) == "mesh = 'a.vol': r"


def test_a_long_path_is_quoted_by_its_start_and_its_end():
    path = "/" + "a" * 1000 + "/mesh.msh"
    message = str(meshfiles.file_error(path, "does not exist"))
    quoted = message.split("'")[1]
    assert len(quoted) == meshfiles.PATH_QUOTE + 3
    assert quoted.startswith("/aaa") and quoted.endswith("/mesh.msh") and "..." in quoted


def test_the_suffix_is_the_longest_allowed_ending_in_any_case():
    allowed = (".vol", ".vol.gz", ".msh")
    assert meshfiles.suffix_of("dir.x/Brain.VOL.GZ", allowed) == ".vol.gz"
    assert meshfiles.suffix_of("brain.vol", allowed) == ".vol"
    assert meshfiles.suffix_of("brain.gz", allowed) is None
    assert meshfiles.suffix_of("brain.msh.txt", allowed) is None


def test_a_message_is_one_line_of_at_most_200_characters():
    assert meshfiles.one_line(ValueError("a\n  b\tc ")) == "a b c"
    assert meshfiles.one_line(KeyboardInterrupt()) == "KeyboardInterrupt"
    long = meshfiles.one_line(ValueError("x" * 500))
    assert len(long) == 200 and long.endswith("...")
    assert meshfiles.point(np.array([1.0, 2.5e-7, 1 / 3])) == "(1, 2.5e-07, 0.333333)"
