"""Safe parsing of user expressions."""

import ngsolve as ngs
import numpy as np
import pytest
from conftest import random_points, values_at

from ngincompat.errors import ExpressionError
from ngincompat.expressions import parse_expression


def test_expression_values_match_numpy(unit_cube_hex):
    time = ngs.Parameter(0.5)
    text = "1 + 0.25*X1*t - sqrt(X2**2 + 1)/4 + exp(-X3) * sin(pi*X1) + tanh(X2 - 0.5) " \
           "+ max(X1, X2) - abs(X3 - 0.5) + R/10"
    cf = parse_expression(text, time)
    pts = random_points(12)
    x, y, z = pts.T
    expected = (1 + 0.25 * x * 0.5 - np.sqrt(y ** 2 + 1) / 4 + np.exp(-z) * np.sin(np.pi * x)
                + np.tanh(y - 0.5) + np.maximum(x, y) - np.abs(z - 0.5)
                + np.sqrt(x ** 2 + y ** 2 + z ** 2) / 10)
    np.testing.assert_allclose(values_at(cf, unit_cube_hex, pts)[:, 0], expected, rtol=1e-12)
    time.Set(1.0)
    assert values_at(cf, unit_cube_hex, pts)[0, 0] == pytest.approx(expected[0] + 0.125 * x[0])


def test_constant_expression_is_a_coefficient_function(unit_cube_hex):
    cf = parse_expression("2.5")
    assert values_at(cf, unit_cube_hex, random_points(1))[0, 0] == 2.5


@pytest.mark.parametrize("text, message", [
    ("__import__('os').system('true')", "call of __import__"),
    ("X1.real", "not allowed"),
    ("open('f')", "call of open"),
    ("Y + 1", "unknown name 'Y'"),
    ("1 +", "not a valid expression"),
    ("", "non-empty"),
    ("[X1 for X1 in X2]", "not allowed"),
    ("sqrt(X1, X2)", "takes 1 argument"),
    ("'abc'", "not allowed"),
    ("X1 < 2", "not allowed"),
])
def test_bad_expressions_are_clear_errors(text, message):
    with pytest.raises(ExpressionError, match=message) as err:
        parse_expression(text, name="theta")
    assert "theta" in str(err.value)
