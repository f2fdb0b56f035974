"""Safe parsing of user expressions."""

import ast
import itertools
import math

import ngsolve as ngs
import numpy as np
import pytest
from conftest import random_points, values_at
from hypothesis import HealthCheck, given, note, settings
from hypothesis import strategies as st

from geometries import cube
from ngincompat.errors import ExpressionError, ParameterError
from ngincompat.mechanics import expressions
from ngincompat.mechanics.expressions import parse_expression
from ngincompat.mechanics.growth import check_positive

INF, NAN = math.inf, math.nan


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


# --- negative bases, NaN and inf --------------------------------------------------------------

def _grid(n=5):
    """Points of the unit cube on a grid that includes X = 0.5 exactly."""
    s = np.linspace(0.0, 1.0, n)
    return np.array(list(itertools.product(s, s, s)))


def _as_seen(mesh, pts):
    """The coordinates NGSolve evaluates at the points (they differ from pts in the last bit;
    a reference value must start from these)."""
    return values_at(ngs.CF((ngs.x, ngs.y, ngs.z)), mesh, pts)


def test_square_of_a_negative_base_is_a_positive_field(unit_cube_hex):
    """The issue: theta = 1 + (X2-0.5)**2*t was NaN where X2 < 0.5 (NGSolve's pow with the
    float exponent 2.0 is exp(2 log(X2 - 0.5)))."""
    time = ngs.Parameter(1.0)
    theta = parse_expression("1 + (X2-0.5)**2*t", time, name="theta")
    pts = _grid()
    values = values_at(theta, unit_cube_hex, pts)[:, 0]
    np.testing.assert_allclose(values, 1 + (_as_seen(unit_cube_hex, pts)[:, 1] - 0.5) ** 2,
                               rtol=1e-15)
    assert np.all(np.isfinite(values)) and np.all(values > 0)
    check_positive(theta, unit_cube_hex, time)


@pytest.mark.parametrize("text, t, expected", [
    ("(X1-0.5)**3", 1.0, lambda x: (x - 0.5) ** 3),
    ("(X1-0.5)**-2", 1.0, lambda x: (x - 0.5) ** -2.0),
    ("(0.5-X1)**(1+1)", 1.0, lambda x: (0.5 - x) ** 2),
    ("(X1-0.5)**100", 1.0, lambda x: (x - 0.5) ** 100),  # beyond the products: |a|**n
    ("(X1-0.5)**101", 1.0, lambda x: (x - 0.5) ** 101),
    ("(X1-0.5)**(-65)", 1.0, lambda x: (x - 0.5) ** -65.0),
    ("(X1-0.5)**(2*t)", 1.0, lambda x: (x - 0.5) ** 2),  # an integer exponent at run time
    ("(X1-0.5)**(2*t)", 1.5, lambda x: (x - 0.5) ** 3),
    ("(X1-0.5)**(2*t)", 0.25, lambda x: np.power(x - 0.5, 0.5)),  # NaN for a negative base
    ("(X1-0.5)**1.5", 1.0, lambda x: np.power(x - 0.5, 1.5)),
])
def test_powers_follow_numpy(unit_cube_hex, text, t, expected):
    pts = _grid()
    with np.errstate(all="ignore"):
        want = expected(_as_seen(unit_cube_hex, pts)[:, 0])
    got = values_at(parse_expression(text, ngs.Parameter(t)), unit_cube_hex, pts)[:, 0]
    np.testing.assert_array_equal(np.isnan(got), np.isnan(want))
    np.testing.assert_allclose(got, want, rtol=1e-13)


SPECIAL = [-INF, -1e300, -8.0, -2.0, -1.0, -0.5, -0.0, 0.0, 0.5, 1.0, 2.0, 3.0, 1e300, INF, NAN]
SPECIAL_EXPONENTS = SPECIAL + [-65.0, -3.0, -2.5, 1 / 3, 2.5, 65.0, 66.0, 1e20, 2.0 ** 52 + 1,
                               -(2.0 ** 52 + 1), 2.0 ** 51 + 0.5, 3e-250, -3e-250, 5e-324]


def _same(got, want):
    """Equal as numpy results: NaN where NaN, the same signed zero and infinity, else close."""
    if np.isnan(want) or np.isnan(got):
        return bool(np.isnan(want) and np.isnan(got))
    if want == 0 or np.isinf(want):
        return bool(got == want and np.signbit(got) == np.signbit(want))
    return abs(got - want) <= 1e-13 * abs(want)


def _check_special(function, reference, first, second, unit_cube_hex):
    """function(a, b) for special values, as constants and as Parameters (a CoefficientFunction
    that NGSolve cannot fold), evaluated vectorised and at a single point (NGSolve's two
    evaluation paths differ, e.g. its pow), against reference on float64 arrays."""
    points = unit_cube_hex(np.array([0.3, 0.6]), np.array([0.3, 0.6]), np.array([0.3, 0.6]))
    point = unit_cube_hex(0.3, 0.3, 0.3)
    bad = []
    for a, b in itertools.product(first, second):
        with np.errstate(all="ignore"):
            want = float(reference(np.array([a]), np.array([b]))[0])
        for kinds in ((True, True), (True, False), (False, True), (False, False)):
            args = [ngs.Parameter(v) if k else v for v, k in zip((a, b), kinds, strict=True)]
            cf = function(*args)
            got = [cf] if isinstance(cf, float) else [np.asarray(cf(points))[0, 0], cf(point)]
            bad += [(a, b, kinds, g, want) for g in got if not _same(g, want)]
    assert not bad, bad[:10]


def test_power_matches_numpy_on_special_values(unit_cube_hex):
    _check_special(expressions.power, np.power, SPECIAL, SPECIAL_EXPONENTS, unit_cube_hex)


@pytest.mark.parametrize("name, reference", [("minimum", np.minimum), ("maximum", np.maximum)])
def test_min_max_match_numpy_on_special_values(unit_cube_hex, name, reference):
    """NaN in either argument gives NaN (IfPos alone sends NaN to one branch)."""
    _check_special(getattr(expressions, name), reference, SPECIAL, SPECIAL, unit_cube_hex)


@pytest.mark.parametrize("name, reference", [("absolute", np.abs), ("tanh", np.tanh)])
def test_abs_tanh_match_numpy_on_special_values(unit_cube_hex, name, reference):
    values = SPECIAL + [1e-10, -1e-300, 19.0, 20.0, -21.0, 0.3, 700.0, -800.0]
    _check_special(lambda a, b: getattr(expressions, name)(a), lambda a, b: reference(a),
                   values, [0.0], unit_cube_hex)


@pytest.mark.parametrize("text, expected", [
    ("max(sqrt(X1 - 2), 1)", lambda x: np.full_like(x, NAN)),
    ("min(1, log(X1 - 2))", lambda x: np.full_like(x, NAN)),
    ("0*log(X1 - 2)", lambda x: np.full_like(x, NAN)),  # NGSolve folds 0*f into 0
    ("0*exp(1000*X1)", lambda x: np.where(np.exp(1000 * x) == INF, NAN, 0.0)),
    ("1/(X1 - X1)", lambda x: np.full_like(x, INF)),
    ("1/(0*(X1 - 2))", lambda x: np.full_like(x, -INF)),
    ("1/abs(X1 - X1)", lambda x: np.full_like(x, INF)),
    ("1/0 + X1", lambda x: np.full_like(x, INF)),
    ("(-8)**(1/3) + X1", lambda x: np.full_like(x, NAN)),
    ("10.0**400 - X1", lambda x: np.full_like(x, INF)),
    # constants are folded as numpy does for arrays (for a scalar 0.5 numpy's power is sqrt)
    ("log(0)**0.5 + X1", lambda x: np.full_like(x, INF)),
    ("1/(-0.0)**0.5 + X1", lambda x: np.full_like(x, INF)),
    ("tanh(1e-10*X1)", lambda x: np.tanh(1e-10 * x)),  # was 1 - 2/(exp(2a)+1): cancellation
    ("tanh(400*X1)", lambda x: np.tanh(400 * x)),
])
def test_nan_and_inf_follow_numpy(unit_cube_hex, text, expected):
    pts = random_points(20)
    with np.errstate(all="ignore"):
        want = expected(_as_seen(unit_cube_hex, pts)[:, 0])
    got = values_at(parse_expression(text), unit_cube_hex, pts)[:, 0]
    np.testing.assert_array_equal(np.isnan(got), np.isnan(want))
    np.testing.assert_allclose(got, want, rtol=1e-14)


@pytest.mark.parametrize("text", ["min(X1, X2)", "max(X1 - 0.5, 0)", "abs(X1 - 0.5)",
                                  "tanh(3*X1 - 1)", "(X1 - 0.5)**3", "(X1 + 0.5)**t",
                                  "(X1 - 0.5)**(2*t)", "2**X1", "X1**100"])
def test_expressions_stay_differentiable(unit_cube_hex, text):
    """Exact incompatibility needs theta.Diff(X): the builders use nothing NGSolve cannot
    differentiate (floor, for one, is not)."""
    time = ngs.Parameter(1.5)
    cf = parse_expression(text, time)
    pts = random_points(10)
    h = 1e-6
    plus, minus = pts + [h, 0, 0], pts - [h, 0, 0]
    fd = (values_at(cf, unit_cube_hex, plus) - values_at(cf, unit_cube_hex, minus)) / (2 * h)
    derivative = values_at(cf.Diff(ngs.x), unit_cube_hex, pts)
    np.testing.assert_allclose(derivative, fd, rtol=1e-6, atol=1e-8)


# --- check_positive ---------------------------------------------------------------------------

@pytest.mark.parametrize("text, shown", [("1/(X1 - X1)", "inf"), ("sqrt(X1 - 2)", "nan"),
                                         ("log(X1 - X1)", "-inf")])
def test_non_finite_theta_is_called_not_finite(unit_cube_hex, text, shown):
    time = ngs.Parameter(0.0)
    theta = parse_expression(text, time, name="theta")
    with pytest.raises(ParameterError) as err:
        check_positive(theta, unit_cube_hex, time)
    message = str(err.value)
    assert message.startswith(f"theta is not finite (theta = {shown}) at X = (")
    assert ", t = 0:" in message
    assert "must be finite and positive (0 < theta < inf)" in message


def test_non_positive_theta_names_the_value_and_the_range(unit_cube_hex):
    with pytest.raises(ParameterError, match=r"^theta = -1 at X = \(.+\): the growth indicator "
                                             r"must be finite and positive \(0 < theta < inf\)"):
        check_positive(parse_expression("-1 + 0*X1"), unit_cube_hex)


# --- property: the parser against an independent numpy evaluation ----------------------------
#
# An expression drawn from the grammar is parsed into a CoefficientFunction and evaluated at
# many points in one call; the same text is parsed by ast and evaluated by numpy on float64
# arrays (the reference semantics). NaN must appear exactly where numpy has NaN, inf where numpy
# has inf (same sign), and finite values must agree.
#
# "Agree" needs a tolerance that is about semantics, not round-off: NGSolve and numpy use
# different exp/log/sin/... (a last-bit difference), NGSolve's pow is exp(b log a), and integer
# powers are products. The numpy evaluator therefore carries, next to each value, an interval
# [lo, hi] that contains the value any implementation with these per-operation errors would
# compute: it starts exact (the coordinates are those NGSolve evaluates), stays exact through
# correctly rounded operations of exact operands (+ - * / sqrt are IEEE in both), and otherwise
# grows by U_LIBM relative (plus TINY absolute, for results below the normal range) per
# operation and by the operation's sensitivity (its values at the interval's corners). So the
# absolute floor scales with the magnitudes of the intermediate values: cancellation in
# sin(X1)**2 + cos(X1)**2 - 1 gives an interval of width ~1e-16, not a relative error of 1.
# A value is compared where |got - value| <= RTOL |value| + (interval width). Where the interval
# reaches a point at which the result changes kind (sqrt/log of an interval containing 0,
# division by one, a pole of tan, overflow, a negative base with an exponent that may or may not
# be an integer, a zero whose sign is unsure), the point is not compared: the implementations
# may legitimately differ. Numbers are drawn in [0, 10] with three decimals and the expressions
# are small, so that such points are rare; the test checks that nearly all points are compared.

U_EXACT = 2.0 ** -50    # a few ulps: corners of an interval are themselves rounded
U_LIBM = 1e-13          # library functions and pow, per operation (relative)
TINY = 1e-300           # absolute allowance where a result may fall below the normal range
RTOL = 1e-9

NAMES = ("X1", "X2", "X3", "x", "y", "z", "t", "R", "Rxy", "pi", "e")
UNARY = ("sqrt", "exp", "log", "sin", "cos", "tan", "atan", "tanh", "sinh", "cosh", "abs")
NUMPY_UNARY = {"sqrt": np.sqrt, "exp": np.exp, "log": np.log, "sin": np.sin, "cos": np.cos,
               "tan": np.tan, "atan": np.arctan, "tanh": np.tanh, "sinh": np.sinh,
               "cosh": np.cosh, "abs": np.abs}
NUMPY_BINARY = {ast.Add: np.add, ast.Sub: np.subtract, ast.Mult: np.multiply,
                ast.Div: np.divide, ast.Pow: np.power}


class Value:
    """numpy's value ``v`` and an interval [lo, hi] around it; ``unsure`` marks points whose
    kind of result (NaN, +-inf, finite, sign of a zero) rounding may change."""

    def __init__(self, v, lo=None, hi=None, unsure=None):
        self.v = v
        self.lo = v if lo is None else lo
        self.hi = v if hi is None else hi
        self.unsure = np.zeros(v.shape, bool) if unsure is None else unsure

    @property
    def exact(self):
        return (self.lo == self.hi) | ~np.isfinite(self.v)


def _kind(x):
    """0 for a number, 1 for inf, 2 for -inf, 3 for NaN."""
    return np.isnan(x) * 3 + (x == INF) + (x == -INF) * 2


def _special(x):
    """Inputs whose results every libm gives exactly (C99 special values)."""
    return (x == 0) | ~np.isfinite(x)


def _result(v, corners, unsure, rel, absolute=0.0):
    """A Value from numpy's value v and the operation at the corners of its operands."""
    corners = np.array(corners)
    unsure = unsure | np.any(_kind(corners) != _kind(v), axis=0)
    unsure |= np.any((corners == 0) & (v == 0) & (np.signbit(corners) != np.signbit(v)), axis=0)
    with np.errstate(all="ignore"):
        lo = np.minimum(np.min(corners, axis=0), v)
        hi = np.maximum(np.max(corners, axis=0), v)
        lo = lo - rel * np.abs(lo) - absolute
        hi = hi + rel * np.abs(hi) + absolute
    finite = np.isfinite(v)
    unsure = unsure | (finite & ~(np.isfinite(lo) & np.isfinite(hi)))  # may overflow
    return Value(v, np.where(finite, lo, v), np.where(finite, hi, v), unsure)


def _contains_integer(lo, hi):
    return (np.floor(lo) != np.floor(hi)) | (lo == np.floor(lo))


def _power(a, b):
    with np.errstate(all="ignore"):
        v = np.power(a.v, b.v)
        corners = [np.power(x, y) for x in (a.lo, a.hi) for y in (b.lo, b.hi)]
        unsure = a.unsure | b.unsure
        integer = b.exact & np.isfinite(b.v) & (b.v == np.round(b.v))
        even = integer & (np.mod(b.v, 2) == 0)
        # a^b is monotone in each operand for a > 0 (the corners bound it), and in a for an
        # exact integer b on each side of 0
        crosses = (a.lo < 0) & (a.hi > 0)
        corners.append(np.where(crosses & even & (b.v > 0), 0.0, v))
        unsure |= crosses & ~(integer & (b.v >= 0))
        # a negative base: NaN or not depends on b being an integer
        unsure |= (a.lo < 0) & ~b.exact & _contains_integer(b.lo, b.hi)
        logs = np.abs(b.v * np.log(np.abs(a.v)))
        rel = np.where(a.exact & b.exact & (_special(a.v) | _special(b.v) | (np.abs(a.v) == 1)),
                       0.0, U_LIBM * (1 + np.where(np.isfinite(logs), logs, 0)))
        absolute = np.where(rel > 0, TINY, 0.0)
    return _result(v, corners, unsure, rel, absolute)


def _binary(op, a, b):
    func = NUMPY_BINARY[op]
    if op is ast.Pow:
        return _power(a, b)
    with np.errstate(all="ignore"):
        v = func(a.v, b.v)
        corners = [func(x, y) for x in (a.lo, a.hi) for y in (b.lo, b.hi)]
    unsure = a.unsure | b.unsure
    if op is ast.Div:
        unsure = unsure | (~b.exact & (b.lo <= 0) & (b.hi >= 0))
    exact = a.exact & b.exact
    absolute = 0.0
    if op in (ast.Mult, ast.Div):  # these may fall below the normal range
        absolute = np.where(exact, 0.0, TINY)
    return _result(v, corners, unsure, np.where(exact, 0.0, U_EXACT), absolute)


def _unary(name, a):
    func = NUMPY_UNARY[name]
    with np.errstate(all="ignore"):
        v = func(a.v)
        corners = [func(a.lo), func(a.hi)]
    unsure = a.unsure.copy()
    crosses = (a.lo < 0) & (a.hi > 0)
    if name in ("sin", "cos"):  # Lipschitz 1: v +- the width of the argument
        with np.errstate(all="ignore"):
            width = np.maximum(a.hi - a.v, a.v - a.lo)
        corners = [np.where(np.isfinite(v), v - width, v), np.where(np.isfinite(v), v + width, v)]
    elif name == "tan":  # monotone between poles
        with np.errstate(all="ignore"):
            unsure |= np.floor(a.lo / np.pi + 0.5) != np.floor(a.hi / np.pi + 0.5)
    elif name == "cosh":
        corners.append(np.where(crosses, 1.0, v))
    elif name == "abs":
        corners.append(np.where(crosses, 0.0, v))
    # sqrt, exp, log, atan, tanh, sinh are monotone: the corners bound them
    if name in ("sqrt", "abs"):  # exact operations
        rel, absolute = np.where(a.exact, 0.0, U_EXACT), 0.0
    else:
        rel = np.where(a.exact & _special(a.v), 0.0, U_LIBM)
        absolute = np.where(rel > 0, TINY, 0.0)
    return _result(v, corners, unsure, rel, absolute)


def _minmax(name, a, b):
    func = np.minimum if name == "min" else np.maximum
    v = func(a.v, b.v)
    corners = [func(x, y) for x in (a.lo, a.hi) for y in (b.lo, b.hi)]
    exact = a.exact & b.exact
    return _result(v, corners, a.unsure | b.unsure, np.where(exact, 0.0, U_EXACT))


def reference(text, env):
    """Evaluate ``text`` with numpy on float64 arrays; ``env`` maps names to Values."""
    def walk(node):
        if isinstance(node, ast.Expression):
            return walk(node.body)
        if isinstance(node, ast.Constant):
            return Value(np.full(n, float(node.value)))
        if isinstance(node, ast.Name):
            return env[node.id]
        if isinstance(node, ast.UnaryOp):
            a = walk(node.operand)
            if isinstance(node.op, ast.UAdd):
                return a
            return Value(-a.v, -a.hi, -a.lo, a.unsure)
        if isinstance(node, ast.BinOp):
            return _binary(type(node.op), walk(node.left), walk(node.right))
        args = [walk(a) for a in node.args]
        if node.func.id in ("min", "max"):
            return _minmax(node.func.id, *args)
        return _unary(node.func.id, *args)

    n = len(env["X1"].v)
    return walk(ast.parse(text, mode="eval"))


def _reference_env(x, y, z, t):
    exact = {"X1": Value(x), "X2": Value(y), "X3": Value(z), "t": Value(np.full(len(x), t)),
             "pi": Value(np.full(len(x), np.pi)), "e": Value(np.full(len(x), np.e))}
    exact.update(x=exact["X1"], y=exact["X2"], z=exact["X3"])
    exact["R"] = reference("sqrt(X1*X1 + X2*X2 + X3*X3)", exact)  # as the parser builds R
    exact["Rxy"] = reference("sqrt(X1*X1 + X2*X2)", exact)
    return exact


def _number(k):
    return repr(k / 1000)


NUMBERS = st.one_of(st.integers(0, 10), st.integers(0, 10_000).map(_number),
                    st.sampled_from(["0.5", "1e-3", "1e-8", "100", "2.5", "0"]))
# Leaves with the values where numpy's and NGSolve's semantics part: signed zeros, NaN, +-inf,
# tiny and overflowing values (random arithmetic reaches them too, but rarely)
SPECIAL_LEAVES = ["(X1 - X1)", "(-(X2 - X2))", "sqrt(X1 - 2)", "log(X3 - X3)", "(1/(X1 - X1))",
                  "(-1/(X2 - X2))", "(1e-8*X1)", "exp(800*X2)", "(-exp(800*X3))"]
LEAVES = st.one_of(NUMBERS.map(str), st.sampled_from(NAMES), st.sampled_from(SPECIAL_LEAVES))
# exponents: small integers (products), large ones (|a|**n with a sign), non-integers, -0
EXPONENT_TEXTS = st.one_of(st.integers(-4, 8).map(lambda k: f"({k})"),
                      st.sampled_from(["0.5", "1.5", "(-0.5)", "2.5", "65", "66", "(-65)",
                                       "(-0.0)", "(1/3)"]))


def _extend(children):
    return st.one_of(
        st.tuples(st.sampled_from("+-*/"), children, children).map(
            lambda p: f"({p[1]} {p[0]} {p[2]})"),
        st.tuples(children, st.one_of(EXPONENT_TEXTS, children)).map(
            lambda p: f"({p[0]})**({p[1]})"),
        st.tuples(st.sampled_from(UNARY), children).map(lambda p: f"{p[0]}({p[1]})"),
        st.tuples(st.sampled_from(["min", "max"]), children, children).map(
            lambda p: f"{p[0]}({p[1]}, {p[2]})"),
        children.map(lambda c: f"(-{c})"),
    )


EXPRESSION_TEXTS = st.recursive(LEAVES, _extend, max_leaves=10)
COORDINATE = st.floats(0.0, 1.0)
POINTS = st.lists(st.tuples(COORDINATE, COORDINATE, COORDINATE), min_size=1, max_size=6)
TIMES = st.one_of(st.none(), st.tuples(st.floats(0.0, 1.0), st.booleans()))


@pytest.fixture(scope="module")
def property_mesh():
    mesh = cube(maxh=0.5)
    rng = np.random.default_rng(1)
    grid = _grid(3)  # corners, edge and face midpoints: X = 0.5 exactly
    fixed = np.vstack([grid, rng.uniform(0, 1, size=(20, 3))])
    return mesh, fixed


def compare_with_numpy(text, mesh, pts, time=None):
    """Evaluate ``text`` by the parser and by :func:`reference` at the points ``pts``; raise
    AssertionError where they differ. ``time``: None (t = 1), a float or a Parameter.

    Returns
    -------
    (int, int)
        The number of points and of points compared (not unsure).
    """
    mapped = mesh(pts[:, 0], pts[:, 1], pts[:, 2])
    x, y, z = (np.asarray(c(mapped)).ravel() for c in (ngs.x, ngs.y, ngs.z))
    t = 1.0 if time is None else time.Get() if isinstance(time, ngs.Parameter) else time
    got = np.asarray(parse_expression(text, time)(mapped)).ravel()
    want = reference(text, _reference_env(x, y, z, t))
    v, compared = want.v, ~want.unsure
    with np.errstate(all="ignore"):
        close = ((got >= want.lo - RTOL * np.abs(want.lo))
                 & (got <= want.hi + RTOL * np.abs(want.hi)))
    ok = np.where(np.isnan(v), np.isnan(got), np.where(np.isfinite(v), close, got == v))
    # a zero that is certain (not from an interval around 0) has a certain sign
    ok &= ~((want.lo == 0) & (want.hi == 0)) | (np.signbit(got) == np.signbit(v))
    bad = compared & ~ok
    if bad.any():
        i = np.flatnonzero(bad)[:5]
        raise AssertionError(
            f"{text!r} at t = {t} ({type(time).__name__}): NGSolve {got[i]} numpy {v[i]} "
            f"(interval {want.lo[i]} to {want.hi[i]}) at X = {pts[i].tolist()}")
    return len(got), int(compared.sum())


OPERANDS = ["X1", "t", "0", "0.5", "(-3)", "(X1 - 0.5)"] + SPECIAL_LEAVES


def test_each_operation_on_special_operands_matches_numpy(property_mesh):
    """Every function and operator of the grammar on every pair of operands that are ordinary,
    zero (both signs), NaN, +-inf, tiny or overflowing: the property test below reaches such
    combinations only by chance."""
    mesh, pts = property_mesh
    texts = [f"{f}({a})" for f in UNARY for a in OPERANDS]
    texts += [f"{f}({a}, {b})" for f in ("min", "max") for a in OPERANDS for b in OPERANDS]
    texts += [f"({a}) {op} ({b})" for op in ("+", "-", "*", "/", "**")
              for a in OPERANDS for b in OPERANDS]
    time = ngs.Parameter(0.5)
    for text in texts:
        compare_with_numpy(text, mesh, pts, time)


def test_parsed_expressions_match_numpy(property_mesh):
    """Random expressions of the grammar at random points (see the comment above)."""
    mesh, fixed = property_mesh
    counts = np.zeros(2, int)

    @settings(max_examples=1000, deadline=None, suppress_health_check=[HealthCheck.too_slow])
    @given(text=EXPRESSION_TEXTS, drawn=POINTS, time=TIMES)
    def check(text, drawn, time):
        if time is not None:
            t, as_parameter = time
            time = ngs.Parameter(t) if as_parameter else t
        note(f"theta = {text!r}, time = {time!r}")
        counts[:] += compare_with_numpy(text, mesh, np.vstack([fixed, np.array(drawn)]), time)

    check()
    # the intervals are not so wide that little is compared
    assert counts[1] >= 0.95 * counts[0], counts
