"""A brain from voxels: a user's NIfTI label image or the MNI152 template -> hexahedra with the
materials gray and white; the lumped mass of hexahedra; the atrophy scene on such meshes."""

import sys

import ngsolve as ngs
import numpy as np
import pytest
from conftest import VOXEL
from conftest import voxel_labels as labels
from conftest import write_nifti as write

from geometries import cube
from geometries.voxel_brain import (
    MNI152_VOLUME,
    _coarsen,
    _largest_part,
    from_nifti,
    mni152,
    mni152_elements,
    voxel_mesh,
)
from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.fem.transport import FisherKPP, diffusion_tensor
from ngincompat.scenes import AtrophyScene

nibabel = pytest.importorskip("nibabel")


def volumes(mesh):
    return {k: ngs.Integrate(1, mesh, definedon=mesh.Materials(k)) for k in ("gray", "white")}


def test_label_image_becomes_hexahedra_with_the_voxel_volumes(tmp_path):
    mesh = from_nifti(write(tmp_path / "brain.nii.gz", labels()), maxh=VOXEL / 10)
    cm3 = (VOXEL / 10) ** 3
    assert set(mesh.GetMaterials()) == {"gray", "white"}
    assert {el.type for el in mesh.Elements(ngs.VOL)} == {ngs.HEX}
    assert mesh.ne == 6 * 5 * 4                                      # the island is dropped
    vol = volumes(mesh)
    assert vol["white"] == pytest.approx(4 * cm3, rel=1e-12)
    assert vol["gray"] == pytest.approx((120 - 4) * cm3, rel=1e-12)
    # the outer surface and the interface are named and their areas are voxel faces
    surface = ngs.Integrate(1, mesh, ngs.BND, definedon=mesh.Boundaries("surface"))
    interface = ngs.Integrate(1, mesh, ngs.BND, definedon=mesh.Boundaries("interface"))
    face = (VOXEL / 10) ** 2
    assert surface == pytest.approx(2 * (30 + 24 + 20) * face, rel=1e-12)
    assert interface == pytest.approx(2 * (4 + 2 + 2) * face, rel=1e-12)


def test_the_mesh_keeps_the_images_world_coordinates(tmp_path):
    """The affine's origin is kept: the block of voxels 1-6, 1-5, 1-4 (centres; each voxel
    spans its index +- 1/2) lies at origin + VOXEL x [0.5, 6.5] x [0.5, 5.5] x [0.5, 4.5] mm,
    on the project's axes (X1 = y, X2 = -x, X3 = z) in cm."""
    origin = np.array([-40.0, 20.0, 10.0])
    affine = np.diag([VOXEL, VOXEL, VOXEL, 1.0])
    affine[:3, 3] = origin
    mesh = from_nifti(write(tmp_path / "brain.nii.gz", labels(), affine), maxh=VOXEL / 10)
    pts = np.array([v.point for v in mesh.vertices])
    low = (origin + VOXEL * 0.5) / 10
    high = (origin + VOXEL * np.array([6.5, 5.5, 4.5])) / 10
    np.testing.assert_allclose(pts.min(axis=0), [low[1], -high[0], low[2]], atol=1e-12)
    np.testing.assert_allclose(pts.max(axis=0), [high[1], -low[0], high[2]], atol=1e-12)


@pytest.mark.parametrize("mirror", [1.0, -1.0])
def test_voxels_split_into_conforming_tetrahedra_of_the_same_volumes(tmp_path, mirror):
    """Six tetrahedra per voxel, all oriented as Netgen's (negative volume), each face shared
    by at most two of them, the surface and the interface made of their faces."""
    affine = np.diag([mirror * VOXEL, VOXEL, VOXEL, 1.0])
    path = write(tmp_path / "brain.nii.gz", labels(), affine)
    hexes, tets = (from_nifti(path, maxh=VOXEL / 10, elements=e) for e in ("hex", "tet"))
    assert {el.type for el in tets.Elements(ngs.VOL)} == {ngs.TET} and tets.ne == 6 * hexes.ne
    for key, value in volumes(hexes).items():
        assert volumes(tets)[key] == pytest.approx(value, rel=1e-12)
    for name in ("surface", "interface"):
        areas = [ngs.Integrate(1, m, ngs.BND, definedon=m.Boundaries(name)) for m in (hexes, tets)]
        assert areas[1] == pytest.approx(areas[0], rel=1e-12)
    ngmesh = tets.ngmesh
    points = np.array([[p[0], p[1], p[2]] for p in ngmesh.Points()])
    faces, signs = {}, []
    for el in ngmesh.Elements3D():
        v = [p.nr - 1 for p in el.vertices]
        signs.append(np.sign(np.linalg.det(points[v[1:]] - points[v[0]])))
        for f in ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)):
            key = tuple(sorted(v[i] for i in f))
            faces[key] = faces.get(key, 0) + 1
    assert set(signs) == {-1.0}
    assert max(faces.values()) == 2
    surface = {tuple(sorted(p.nr - 1 for p in el.vertices)) for el in ngmesh.Elements2D()}
    outer = {f for f, n in faces.items() if n == 1}
    assert outer <= surface and all(faces.get(f) in (1, 2) for f in surface)


def test_a_4d_float_label_image_with_one_volume_is_read(tmp_path):
    lab = labels().astype(np.float32)[..., None] + 1e-4        # (x, y, z, 1), not exact
    mesh = from_nifti(write(tmp_path / "brain4d.nii", lab), maxh=VOXEL / 10)
    assert mesh.ne == 120
    assert volumes(mesh)["white"] == pytest.approx(4 * (VOXEL / 10) ** 3, rel=1e-12)
    with pytest.raises(ParameterError, match="3-D NIfTI"):
        from_nifti(write(tmp_path / "two.nii", np.stack([labels()] * 2, axis=-1)))


def test_a_netgen_mesh_file_with_gray_and_white_is_read(tmp_path):
    path = tmp_path / "brain.vol.gz"
    from_nifti(write(tmp_path / "brain.nii", labels()), maxh=VOXEL / 10).ngmesh.Save(str(path))
    case = AtrophyScene(geometry=str(path), seed="1.5,-1.75,1.25", outputs="none").build()
    cm3 = (VOXEL / 10) ** 3
    assert case.volume0["white"] == pytest.approx(4 * cm3, rel=1e-12)
    assert case.volume0["total"] == pytest.approx(120 * cm3, rel=1e-12)


def test_a_mirrored_image_keeps_hexahedra_positive(tmp_path):
    """A negative x step (radiological orientation) is a reflection: volumes stay positive."""
    affine = np.diag([-VOXEL, VOXEL, VOXEL, 1.0])
    mesh = from_nifti(write(tmp_path / "mirrored.nii", labels(), affine), maxh=VOXEL / 10)
    detj = ngs.Det(ngs.specialcf.JacobianMatrix(3))
    assert ngs.Integrate(ngs.IfPos(-detj, 1, 0), mesh) == 0          # no inverted hexahedron
    assert ngs.Integrate(ngs.IfPos(detj, 1, 0), mesh) == pytest.approx(120 * (VOXEL / 10) ** 3,
                                                                        rel=1e-12)


def test_coarsening_averages_blocks_and_keeps_the_largest_part():
    gray = np.zeros((8, 8, 8))
    white = np.zeros((8, 8, 8))
    gray[:4, :4, :4] = 1.0                  # one full 4-block of gray
    white[4:8, :4, :4] = 0.6                # a 4-block of 60 % white, face neighbour
    white[4:8, 4:8, 4:8] = 0.4              # below 1/2: outside
    mesh = voxel_mesh(gray, white, np.diag([2.0, 2.0, 2.0, 1.0]), block=4)
    assert mesh.ne == 2
    vol = volumes(mesh)
    assert vol["gray"] == pytest.approx(0.8 ** 3) and vol["white"] == pytest.approx(0.8 ** 3)


@pytest.mark.parametrize("content, match", [
    (None, "no such file"),
    (b"not an image", "not a readable NIfTI"),
    ("zeros", "no brain voxels"),
    ("white only", "no gray voxels"),
])
def test_bad_label_images_name_the_file_and_the_fault(tmp_path, content, match):
    path = tmp_path / "bad.nii"
    if isinstance(content, bytes):
        path.write_bytes(content)
    elif content == "zeros":
        write(path, np.zeros((4, 4, 4), dtype=np.int16))
    elif content == "white only":
        write(path, np.full((4, 4, 4), 2, dtype=np.int16))
    with pytest.raises(ParameterError, match=match) as err:
        AtrophyScene(geometry=str(path), maxh=0.5, outputs="none").build()
    assert str(path) in str(err.value)


def test_bad_mesh_files_name_the_file(tmp_path):
    missing = tmp_path / "missing.vol"
    with pytest.raises(ParameterError, match=f"{missing}: no such file"):
        AtrophyScene(geometry=str(missing), outputs="none").build()
    garbage = tmp_path / "garbage.vol"
    garbage.write_text("this is not a mesh\n")
    with pytest.raises(ParameterError, match=str(garbage)):
        AtrophyScene(geometry=str(garbage), outputs="none").build()
    cube_only = tmp_path / "cube.vol"
    cube(maxh=0.5).ngmesh.Save(str(cube_only))
    with pytest.raises(ParameterError, match="lacks the materials"):
        AtrophyScene(geometry=str(cube_only), outputs="none").build()
    with pytest.raises(ParameterError, match="geometry"):
        AtrophyScene(geometry="brain.stl")


def test_lumped_hex_mass_is_the_volume_and_exact_for_trilinear(unit_cube_hex):
    """The vertex rule of hexahedra: weights sum to the volume and integrate trilinear
    functions exactly (on a sheared, non-affine mesh too)."""
    from ngincompat.fem.transport import _VERTEX_RULES

    rule = _VERTEX_RULES[ngs.HEX]
    assert sum(rule.weights) == pytest.approx(1.0)
    x, y, z = ngs.x, ngs.y, ngs.z
    f = 1 + 2 * x - y + 3 * z + x * y - 2 * y * z + 4 * x * z + 5 * x * y * z
    mesh = unit_cube_hex
    exact = ngs.Integrate(f, mesh, order=6)
    lumped = ngs.Integrate(f * ngs.dx(intrules={ngs.HEX: rule}), mesh)
    assert lumped == pytest.approx(exact, rel=1e-13)
    # the lumped mass of the transport: its diagonal sums to the volume
    kpp = FisherKPP(mesh, diffusion_tensor(1.0), alpha=1.0, c0=0.1)
    assert float(np.sum(kpp.mass)) == pytest.approx(1.0, rel=1e-13)
    assert np.all(kpp.mass > 0)


def test_atrophy_runs_on_hexahedra_from_a_label_image(tmp_path):
    """Transport, atrophy and the mixed equilibrium (order 2) on a voxel brain: 0 <= c <= 1,
    gray loses more volume than white, |b| is non-zero, the body is self-equilibrated."""
    lab = np.zeros((10, 9, 8), dtype=np.int16)
    lab[1:7, 1:7, 1:6] = 1
    lab[3:5, 3:5, 3:4] = 2
    path = write(tmp_path / "brain.nii.gz", lab)
    scene = AtrophyScene(geometry=path, maxh=0.5, seed="1.75,-1.75,0.5", seed_radius=0.5, t_end=4.0,
                         dt=1.0, snapshots=1, g_order=2, outputs="none")
    m = scene.run().metrics
    assert 0 <= m["c_min"] and m["c_max"] <= 1
    assert m["gray_volume_loss"] > m["white_volume_loss"] > 0
    assert m["burgers_max"] > 1e-4
    assert m["equilibrium_residual_rel"] < 1e-6


def test_without_nilearn_mni152_names_the_extra(monkeypatch, capsys, tmp_path):
    monkeypatch.setitem(sys.modules, "nilearn", None)          # import nilearn fails
    code = main(["run", "atrophy", "--out", str(tmp_path / "run"), "--set", "geometry=mni152",
                 "-q"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and err == ['ngincompat: error: geometry = mni152 needs nilearn: '
                                 'pip install -e ".[brain]"']


nilearn = pytest.importorskip("nilearn")


def test_mni152_is_cached_with_materials_and_brain_volumes(tmp_path, monkeypatch):
    """The template at 2 cm voxels (fast): gray and white, a brain-sized volume, and the
    second call reads the cached file."""
    monkeypatch.setenv("NGINCOMPAT_CACHE", str(tmp_path))
    mesh = mni152(2.0)
    assert set(mesh.GetMaterials()) == {"gray", "white"}
    vol = volumes(mesh)
    assert 800 < vol["gray"] + vol["white"] < 2500                # cm^3
    assert vol["white"] > 0 and vol["gray"] > 0
    files = list(tmp_path.iterdir())
    assert [f.name for f in files] == ["mni152_20mm_hex_v2.vol.gz"]
    again = mni152(2.0)
    assert again.ne == mesh.ne and volumes(again) == pytest.approx(vol)
    tets = mni152(2.0, elements="tet")           # its own cache file, the same brain
    assert tets.ne == 6 * mesh.ne and volumes(tets) == pytest.approx(vol, rel=1e-12)
    assert len(list(tmp_path.iterdir())) == 2
    with pytest.raises(ParameterError, match=r"maxh = 0.05 .*in \[0.1, 2\] cm"):
        mni152(0.05)


@pytest.mark.parametrize("maxh", [2.0, 1.0])
def test_the_default_seed_on_mni152_is_the_entorhinal_cortex_in_its_gray_matter(
        tmp_path, monkeypatch, maxh):
    """The template keeps its MNI coordinates, so the entorhinal seed (MNI -25, -10, -30
    mm), the default on this brain, lies in a gray element; the template's extent along
    MNI y is its own, -10.5 to 7.5 cm at 1 cm voxels, not centred."""
    monkeypatch.setenv("NGINCOMPAT_CACHE", str(tmp_path))
    scene = AtrophyScene(geometry="mni152", maxh=maxh)
    assert scene.seed == "entorhinal"
    mesh = mni152(maxh)
    point = mesh(*scene.seed_centre())
    assert point.nr >= 0
    assert mesh.GetMaterials()[mesh[ngs.ElementId(ngs.VOL, point.nr)].index] == "gray"
    if maxh == 1.0:
        pts = np.array([v.point for v in mesh.vertices])
        assert (pts[:, 0].min(), pts[:, 0].max()) == pytest.approx((-10.5, 7.5))


def test_an_odd_voxel_edge_is_made_of_the_1mm_maps(tmp_path, monkeypatch):
    """19 mm is no multiple of the 2 mm maps: blocks of 19 of the 1 mm voxels, with the
    brain's volume and about the estimated count of hexahedra."""
    monkeypatch.setenv("NGINCOMPAT_CACHE", str(tmp_path))
    mesh = mni152(1.9)
    assert [f.name for f in tmp_path.iterdir()] == ["mni152_19mm_hex_v2.vol.gz"]
    assert mesh.ne == pytest.approx(mni152_elements(1.9), rel=0.05)
    assert sum(volumes(mesh).values()) == pytest.approx(mesh.ne * 1.9 ** 3, rel=1e-9)
    assert mni152_elements(1.9) * 1.9 ** 3 == MNI152_VOLUME


@pytest.mark.parametrize("edge", [1, 3, 10])
def test_the_brains_voxel_volume_is_the_estimates_to_2_percent(edge):
    """The count of brain voxels (gray + white >= 1/2, the largest part) at 1 mm, 3 mm and
    1 cm from the 1 mm maps is MNI152_VOLUME / edge^3 to 2 %: the estimate that refuses a
    brain too large for the machine before the maps are meshed."""
    from nilearn import datasets

    gray = np.asarray(datasets.load_mni152_gm_template(resolution=1).get_fdata())
    white = np.asarray(datasets.load_mni152_wm_template(resolution=1).get_fdata())
    g, w = _coarsen(gray, edge), _coarsen(white, edge)
    count = int(_largest_part(g + w >= 0.5).sum())
    assert count == pytest.approx(mni152_elements(edge / 10), rel=0.02)


def test_the_1mm_brain_is_refused_on_a_workstation_by_its_size_and_allowed_when_raised():
    """maxh 0.1, the template's own voxels: about 1.75e6 hexahedra, refused before
    anything is loaded unless max_elements and max_dofs are raised (a cluster's run)."""
    with pytest.raises(ParameterError, match=r"^maxh = 0.1 .*about 1.7e\+06 elements.*"
                                             r"max_elements = 1000000"):
        AtrophyScene(geometry="mni152", maxh=0.1)
    AtrophyScene(geometry="mni152", maxh=0.1, max_elements=2_000_000, max_dofs=100_000_000)
    with pytest.raises(ParameterError, match=r"^maxh = 0.05 .*in \[0.1, 2\] cm"):
        AtrophyScene(geometry="mni152", maxh=0.05)
