"""ngincompat.workflow.volfile: Netgen .vol files checked before Netgen reads them."""

import gzip
import logging

import pytest

from ngincompat.errors import ParameterError
from ngincompat.workflow import volfile


@pytest.fixture(scope="module")
def cube_text(tmp_path_factory, unit_cube_tet):
    """The text of ``cube(maxh=0.5, elements="tet")`` saved by Netgen (OCC geometry after
    ``endmesh``), and that mesh."""
    path = tmp_path_factory.mktemp("vol") / "cube.vol"
    unit_cube_tet.ngmesh.Save(str(path))
    return path.read_text(), unit_cube_tet


def _section(text, name):
    """(text before the section's rows, its rows, text after them)."""
    head, rest = text.split(f"\n{name}\n", 1)
    count, rest = rest.split("\n", 1)
    rows = rest.split("\n")
    return head + f"\n{name}\n", rows[:int(count)], "\n".join(rows[int(count):])


def _with_rows(text, name, rows, count=None):
    head, _, tail = _section(text, name)
    return head + f"{len(rows) if count is None else count}\n" + "\n".join(rows) + "\n" + tail


def _refused(path, reason, curve=False):
    with pytest.raises(ParameterError) as info:
        volfile.read(path, curve=curve)
    message = str(info.value)
    assert message.startswith(f"mesh = '{path}': ") and "\n" not in message, message
    assert reason in message, message


@pytest.mark.parametrize("name", ["cube.vol", "cube.VOL.GZ"])
def test_a_vol_file_reads_back_the_mesh_netgen_saved(tmp_path, cube_text, name):
    text, original = cube_text
    path = tmp_path / name
    if name.lower().endswith(".gz"):
        path.write_bytes(gzip.compress(text.encode()))
    else:
        path.write_text(text)
    mesh = volfile.read(path)
    assert (mesh.ne, mesh.nv) == (original.ne, original.nv)
    assert mesh.GetBoundaries() == original.GetBoundaries()


def test_a_mesh_to_curve_needs_the_geometry_after_endmesh(tmp_path, cube_text):
    text, original = cube_text
    plain = tmp_path / "plain.vol"
    plain.write_text(text[:text.index("endmesh")] + "endmesh\n")
    assert volfile.read(plain).ne == original.ne                 # read as it is: fine
    _refused(plain, "carries no geometry to curve the mesh to", curve=True)
    with_geometry = tmp_path / "geometry.vol"
    with_geometry.write_text(text)
    assert volfile.read(with_geometry, curve=True).ne == original.ne


def test_a_geometry_netgen_cannot_read_is_refused_after_a_separate_process_tried(tmp_path,
                                                                                 cube_text):
    text, _ = cube_text
    path = tmp_path / "badgeometry.vol"
    path.write_text(text[:text.index("endmesh")] + "endmesh\nOCCGeometry\ngarbage\n")
    _refused(path, "its geometry (after 'endmesh') could not be read", curve=True)
    # without curving, the geometry is not read at all
    assert volfile.read(path).ne > 0


@pytest.mark.parametrize("change, reason", [
    (lambda t: _with_rows(t, "points", ["x"], count="abc"), "section 'points' (line"),
    (lambda t: _with_rows(t, "points", ["0 0", *_section(t, "points")[1][1:]]),
     "section 'points' has rows that are not 3 coordinates"),
    (lambda t: _with_rows(t, "points", ["nan 0 0", *_section(t, "points")[1][1:]]),
     "section 'points' has coordinates that are not finite"),
    (lambda t: _with_rows(t, "points", ["x 0 0", *_section(t, "points")[1][1:]]),
     "section 'points' has a value that is not a number"),
    (lambda t: _with_rows(t, "volumeelements",
                          [" 1 4 1 2 x 3", *_section(t, "volumeelements")[1][1:]]),
     "row 1 of section 'volumeelements' is not an element: '1 4 1 2 x 3'"),
    (lambda t: _with_rows(t, "volumeelements",
                          [" 1 4 1 2 3 0", *_section(t, "volumeelements")[1][1:]]),
     "row 1 of section 'volumeelements' is not an element"),
    (lambda t: t.replace("\npoints\n", "\nnopoints\n", 1), "has no 'points' section"),
    (lambda t: "\n# a comment\n\n" + t.replace("mesh3d", "mesh2d", 1), "does not start with"),
])
def test_a_damaged_vol_file_is_refused_in_one_line_naming_what(tmp_path, cube_text, change,
                                                                reason):
    path = tmp_path / "damaged.vol"
    path.write_text(change(cube_text[0]))
    _refused(path, reason)


def test_comments_and_blank_lines_before_the_header_are_skipped(tmp_path, cube_text):
    path = tmp_path / "commented.vol"
    path.write_text("# written by hand\n\n" + cube_text[0])
    assert volfile.read(path).ne == cube_text[1].ne


def test_a_file_that_is_not_text_is_refused(tmp_path):
    path = tmp_path / "binary.vol"
    path.write_bytes(b"\xff\xfe\x00\x81mesh")
    _refused(path, "is not a text file: not a Netgen mesh")


def test_a_point_that_is_no_corner_is_refused(tmp_path, cube_text):
    """An extra point in the points section (as a second-order mesh's edge nodes are)."""
    text = cube_text[0]
    rows = _section(text, "points")[1]
    path = tmp_path / "extra.vol"
    path.write_text(_with_rows(text, "points", [*rows, "5 5 5"]))
    _refused(path, "has 1 nodes that are not element corners (second-order elements?)")


def test_a_mesh_without_boundary_elements_is_read_with_a_warning(tmp_path, cube_text,
                                                                   caplog):
    text = cube_text[0]
    path = tmp_path / "nosurface.vol"
    path.write_text(_with_rows(text, "surfaceelementsuv", []))
    with caplog.at_level(logging.WARNING):
        mesh = volfile.read(path)
    assert mesh.ne == cube_text[1].ne
    assert "has no boundary elements: the whole surface is traction-free" in caplog.text
