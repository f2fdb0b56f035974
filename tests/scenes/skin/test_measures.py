"""ngincompat.scenes.skin.measures: growth and incompatibility at the apex, and the compression
under the former contact zone."""

import ngsolve as ngs
import pytest

from geometries import cube, skin_patch
from ngincompat.fem import contact
from ngincompat.scenes.skin.measures import apex, compression


def test_apex_reads_both_fields_at_the_centre_of_the_bottom_face():
    mesh = cube(side=1.0, maxh=0.5)
    values = apex(mesh, 2 + ngs.x + 3 * ngs.y, 5 + ngs.z)
    assert values["theta_apex"] == pytest.approx(2.0, abs=1e-5)
    assert values["burgers_apex"] == pytest.approx(5.0, abs=1e-5)


class Pressed:
    """A contact term as :func:`compression` reads it: the expander's grid and a contact
    pressure, here positive where X1 > 1/4 only."""

    def __init__(self, expander, pressure):
        self.expander, self.pressure = expander, pressure

    def contact_pressure(self):
        return self.pressure


@pytest.fixture(scope="module")
def patch():
    size = 4.0
    mesh = skin_patch(footprint="square", footprint_size=size, maxh=2.0, curve_order=1)
    return mesh, contact.Expander("square", size, 1000.0), size


def test_compression_is_read_only_where_the_expander_pressed(patch):
    """sigma = -1 - X1 on a square footprint [-2, 2]^2 pressed where X1 > 1/4: the smallest
    value is at the pressed grid points' largest X1 and the mean that of those points."""
    mesh, expander, size = patch
    pts = expander.points(0.5)
    pressed = pts[pts[:, 0] > 0.25]
    values = compression(mesh, Pressed(expander, ngs.IfPos(ngs.x - 0.25, 1.0, 0.0)), -1 - ngs.x,
                         spacing=0.5)
    assert values["min_principal_stress_contact_zone"] == pytest.approx(
        -1 - pressed[:, 0].max(), abs=1e-9)
    assert values["min_principal_stress_contact_zone_mean"] == pytest.approx(
        -1 - pressed[:, 0].mean(), abs=1e-9)
    assert 0 < len(pressed) < len(pts) and pressed[:, 0].max() <= size / 2


def test_no_contact_no_compression(patch):
    mesh, expander, _ = patch
    assert compression(mesh, Pressed(expander, ngs.CF(0.0)), -1 - ngs.x, spacing=0.5) == {}
