"""Interval bounds of growth expressions (:mod:`ngincompat.mechanics.bounds`) and the proof of
theta > 0 between sampled points that they give.

The enclosure is checked against numpy's own evaluation of the same text (the reference of
tests/mechanics/test_expressions.py) at points drawn inside random boxes: every value numpy computes
lies in the enclosure, and where numpy gives NaN the enclosure proves nothing.
"""

import warnings

import ngsolve as ngs
import numpy as np
import pytest
from hypothesis import HealthCheck, given, note, settings
from hypothesis import strategies as st
from mechanics.test_expressions import EXPRESSION_TEXTS, _reference_env, reference

from geometries import cube
from ngincompat.cli import main
from ngincompat.errors import ParameterError
from ngincompat.mechanics.bounds import Interval, _reciprocal, enclosure, positive_on
from ngincompat.mechanics.expressions import parse_expression
from ngincompat.mechanics.growth import check_positive
from ngincompat.sampling import element_points
from ngincompat.scenes import SCENES

UNIT = (np.zeros((1, 4)), np.ones((1, 4)))
GAP = "1 - 2*exp(-((X1 - 0.37)/0.01)**2)"       # < 0 on 0.3617 < X1 < 0.3783 only

BOX = st.tuples(*[st.floats(0.0, 1.0)] * 8)


@settings(max_examples=600, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(text=EXPRESSION_TEXTS, box=BOX, fractions=st.lists(st.tuples(*[st.floats(0, 1)] * 4),
                                                          min_size=1, max_size=5))
def test_every_value_numpy_computes_in_a_box_lies_in_its_enclosure(text, box, fractions):
    corners = np.array(box).reshape(2, 4)
    lo, hi = corners.min(axis=0), corners.max(axis=0)
    points = lo + np.array(fractions) * (hi - lo)
    low, high = enclosure(text, lo[None], hi[None])
    for point in points:
        env = _reference_env(*(np.array([c]) for c in point[:3]), point[3])
        value = reference(text, env).v[0]
        note(f"{text!r} at {point}: numpy {value}, enclosure [{low[0]}, {high[0]}]")
        if np.isnan(value):
            assert low[0] == -np.inf
        else:
            assert low[0] <= value <= high[0]


@pytest.mark.parametrize("text, low, high", [("1 + 0.25*X1*t", 1.0, 1.25),
                                              ("(X1 - 0.5)**2", 0.0, 0.25),
                                              ("sin(6*X1)", -1.0, 1.0),
                                              ("cosh(X1 - 0.5)", 1.0, np.cosh(0.5)),
                                              ("exp(-X2) * X3", 0.0, 1.0)])
def test_enclosure_of_a_function_whose_range_is_known(text, low, high):
    lo, hi = enclosure(text, *UNIT)
    assert lo[0] == pytest.approx(low, abs=1e-12) and lo[0] <= low
    assert hi[0] == pytest.approx(high, abs=1e-12) and hi[0] >= high


@pytest.mark.parametrize("text", ["1 + 0.25*X1*t", "1 + X1 - X1", "1.0001 - X1",
                                  "0.2 + sin(20*X1)**2", "1/(X1 - 0.5)**2", "max(X1, 0.1)**t",
                                  "1 + X1**1e308", "1.8 - R"])
def test_positive_expressions_are_proven(text):
    assert positive_on(text, *UNIT) is None


@pytest.mark.parametrize("text, where, index", [(GAP, (0.3617, 0.3783), 0),
                                                 ("1 + 2*sin(8*pi*t)", (7 / 48, 11 / 48), 3),
                                                 ("tan(3*X1) + 20", (np.pi / 6, 0.54), 0),
                                                 ("1 - X1", (0.99, 1.0), 0)])
def test_a_point_where_theta_is_not_positive_is_found(text, where, index):
    point, value, sampled = positive_on(text, *UNIT)
    assert value <= 1e-12 and sampled == (text != "1 - X1")
    assert where[0] - 0.01 <= point[index] <= where[1] + 0.01


def unsampled_dip(mesh):
    """theta with a narrow negative dip in X1 halfway between the X1 coordinates that
    check_positive samples on ``mesh`` (the widest gap), and where the dip is."""
    xs = np.unique(np.round(np.asarray(ngs.x(element_points(mesh, 4))).ravel(), 12))
    k = int(np.argmax(np.diff(xs)))
    centre, width = float(xs[k] + xs[k + 1]) / 2, float(xs[k + 1] - xs[k]) / 20
    return f"1 - 2*exp(-((X1 - {centre!r})/{width!r})**2)", centre


def test_the_gap_between_sampled_points_is_closed(unit_cube_hex):
    time = ngs.Parameter(0.0)
    text, centre = unsampled_dip(unit_cube_hex)
    theta = parse_expression(text, time, name="theta")
    check_positive(theta, unit_cube_hex, time)          # no sampled point is in the dip
    with pytest.raises(ParameterError, match="between the points where it was sampled") as err:
        check_positive(theta, unit_cube_hex, time, expression=text)
    x1 = float(str(err.value).split("X = (")[1].split(",")[0])
    assert abs(x1 - centre) < 0.01
    assert time.Get() == 0.0
    check_positive(parse_expression("1 + X1 - X1", time), cube(maxh=0.5), time,
                   expression="1 + X1 - X1")


def test_a_growth_whose_volume_change_overflows_is_refused(unit_cube_hex):
    """theta = 1 + 1e154 X1^2 is finite, but its cube (Jg of isotropic growth) is not: the
    run would compute Fg^-1 Curl Fg with an infinite Jg and report G = 8e-50."""
    time = ngs.Parameter(1.0)
    theta = parse_expression("1 + 1e154*X1*X1", time)
    with pytest.raises(ParameterError, match="overflows its cube"):
        check_positive(theta, unit_cube_hex, time)
    check_positive(parse_expression("1 + 1e100*X1*X1", time), unit_cube_hex, time)


def test_custom_scene_refuses_a_narrow_negative_dip(tmp_path, capsys):
    out = tmp_path / "dip"
    text, _ = unsampled_dip(SCENES["custom"](maxh=0.5, order=2).build().mesh)
    code = main(["run", "custom", "--out", str(out), "--maxh", "0.5", "--order", "2",
                 "--set", f"theta={text}", "-q"])
    err = capsys.readouterr().err
    assert code == 2, err
    assert "between the points where it was sampled" in err
    assert "Traceback" not in err


def test_the_reciprocal_of_a_subnormal_side_overflows_quietly_as_numpys():
    """1 / 1e-320 overflows: the enclosure's side is inf, like numpy's value, and no
    RuntimeWarning is raised (a random box of the enclosure test once drew such a side)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        inverse = _reciprocal(Interval(np.array([1e-320]), np.array([2e-320])))
    assert np.isinf(inverse.lo).all() and np.isinf(inverse.hi).all()


@pytest.mark.parametrize("text, x1", [
    ("-(1 / min(0, (X1 - X1)))", 0.5),      # drawn by the random test: min(0, +0) is +0
    ("-(1 / min(0, (X1 - X1)))", 0.0),
    ("1 / (X1 - X1)", 0.0),
    ("1 / (-X1)", 0.0),                      # -0
    ("1 / (X1 * (-1))", 0.0),
    ("1 / sqrt(-X1)", 0.0),                  # sqrt(-0) = -0
    ("1 / (-X1)**3", 0.0),
    ("1 / max(-X1, X1 - X1)", 0.0),
    ("1 / sin(-X1)", 0.0),
    ("-(1 / (X1 - 0.5)**2)", 0.5),
])
def test_the_sign_of_a_zero_decides_the_reciprocals_infinity_as_in_numpy(text, x1):
    """1/+0 = inf and 1/-0 = -inf: the enclosure of a point box holds numpy's value whichever
    zero the expression reaches there."""
    point = np.array([x1, 0.0, 0.0, 0.0])
    env = _reference_env(*(np.array([c]) for c in point[:3]), point[3])
    value = reference(text, env).v[0]
    low, high = enclosure(text, point[None], point[None])
    assert np.isinf(value) and low[0] <= value <= high[0], (value, low, high)


@pytest.mark.parametrize("text, box_hi", [
    ("2**((X1 - X1) * log(X3 - X3))", 1.0),  # 0 * -inf inside the box, not at its corners
    ("1 / (X1 - X1) - 1 / (X1 - X1)", 0.0),  # inf - inf
])
def test_a_value_numpy_computes_as_nan_leaves_the_enclosure_unbounded_quietly(text, box_hi):
    """Drawn by the random test: the enclosure proves nothing where numpy's value is NaN, and
    computing it raises no RuntimeWarning."""
    lo, hi = np.zeros(4), np.array([box_hi, 0.0, 0.0, 0.0])
    env = _reference_env(*(np.array([c]) for c in lo[:3]), lo[3])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert np.isnan(reference(text, env).v[0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        low, high = enclosure(text, lo[None], hi[None])
    assert low[0] == -np.inf and high[0] == np.inf
