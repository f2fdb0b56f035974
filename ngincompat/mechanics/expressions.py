"""Safe parsing of user expressions such as ``theta = "1 + 0.25*X1*t"``.

An expression is parsed with :mod:`ast` and translated node by node into an NGSolve
CoefficientFunction. Only numbers, the names below, the arithmetic operators
``+ - * / **`` and the whitelisted functions are accepted; anything else (attribute access,
calls of other names, comprehensions, strings, ...) is an :class:`ExpressionError`. Nothing is
ever passed to :func:`eval`.

Names: ``X1, X2, X3`` (reference coordinates, also ``x, y, z``), ``t`` (growth time in [0, 1]),
``R`` (distance from the origin), ``Rxy`` (distance from the X3 axis), ``pi``, ``e``.
Functions: ``sqrt exp log sin cos tan atan tanh sinh cosh abs min max``.

Semantics
---------
Every operation means what it means for numpy float64 arrays: ``**`` is :func:`numpy.power`
(so ``(X2 - 0.5)**2`` is fine for X2 < 0.5 while ``(X2 - 0.5)**0.5`` is NaN there), ``min`` and
``max`` are :func:`numpy.minimum` and :func:`numpy.maximum` (a NaN argument gives NaN), ``abs``,
``tanh`` and the others are their numpy namesakes, and NaN and inf propagate as in numpy (``1/0``
is inf, ``0 * inf`` is NaN). NGSolve differs from numpy in a few places; the builders below work
around each of them:

* its ``pow`` is ``exp(b log a)``, NaN for a negative base even for an integer exponent, and
  wrong for a few special values (``0**0``, ``(-inf)**0.5``);
* it simplifies ``0 * f`` to the zero function (numpy: ``0 * nan`` is NaN), and its zero
  constant forgets the sign of -0;
* ``IfPos`` sends NaN to its else branch, so ``min``/``max``/``abs`` written with ``IfPos``
  alone lose or invent NaN; NGSolve has no ``tanh``.

Sub-expressions of constants are folded with numpy itself. The result is compiled
(:meth:`ngsolve.CoefficientFunction.Compile`), so a sub-expression that a builder uses several
times is evaluated once; it stays differentiable (``CF.Diff``) in X1, X2, X3.
"""

import ast
import math
import re
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import ngsolve as ngs
import numpy as np

from ngincompat.errors import ExpressionError, shown

if TYPE_CHECKING:
    from typing_extensions import TypeIs

#: Integer exponents up to this size are expanded into products (repeated squaring, exact up to
#: a few roundings); larger ones use ``|a|**n`` with the sign of ``a**n``.
MAX_PRODUCT_EXPONENT = 64

#: Limits checked before an expression is translated, so that no input can exhaust the
#: parser, the recursion or the memory (10,000 unary minuses raised MemoryError, a sum of
#: 3,000 terms RecursionError, a 1e6-character expression ran for minutes): its length in
#: characters, the depth of its syntax tree and the number of nodes of that tree. A growth
#: law written by hand stays far below them (the longest in the examples has 40 nodes).
MAX_LENGTH = 2000
MAX_DEPTH = 100
MAX_NODES = 1000
#: The numbers an expression may write: decimal, with an optional fraction and exponent
#: (Python's parser would also take 0x10, 1_0 and full-width digits).
DECIMAL = re.compile(r"(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")

_BIG = sys.float_info.max
#: ``(v + _ROUND) - _ROUND`` is v rounded to the nearest integer for 0 <= v < 2**52.
_ROUND = 2.0 ** 52
#: From here on tanh(a) rounds to +-1 in double precision (1 - tanh(20) < 1e-17).
_TANH_SATURATION = 20.0


def _is_const(value: object) -> "TypeIs[float]":
    return isinstance(value, float)


def _fold(func: Callable[..., Any], *args: float) -> float:
    """Evaluate ``func`` on float constants as numpy does for float64 arrays (no warnings).

    Arrays, not scalars: for a scalar exponent numpy's ``power`` takes shortcuts (0.5 is
    ``sqrt``, so ``(-inf)**0.5`` would be NaN and ``(-0)**0.5`` -0 instead of inf and 0).
    """
    with np.errstate(all="ignore"):
        return float(func(*(np.array([a], dtype=float) for a in args))[0])


def _cf(value: float | ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    """A CoefficientFunction for ``value``; a constant becomes one NGSolve keeps as it is.

    ``ngs.CF(0.0)`` is NGSolve's zero function, which products and sums simplify away
    (``0 * f`` would be 0 where numpy gives NaN) and which has no sign; a Parameter holding the
    zero is an ordinary operand.
    """
    if not _is_const(value):
        return value
    return ngs.CF(value) if value != 0 else ngs.Parameter(value)


def _if_pos(condition: ngs.CoefficientFunction, then: float | ngs.CoefficientFunction,
            otherwise: float | ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    return ngs.IfPos(condition, _cf(then), _cf(otherwise))


def _nan_or_zero(a: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    """+0 where ``a`` is a number (inf included), NaN where it is NaN."""
    angle = ngs.atan(a)
    return angle - angle


def absolute(a: float | ngs.CoefficientFunction) -> float | ngs.CoefficientFunction:
    """``numpy.abs``: ``abs(-0) = 0``, ``abs(nan) = nan``."""
    if _is_const(a):
        return _fold(np.abs, a)
    return ngs.IfPos(a, a, 0.0 - a)


def minimum(a: float | ngs.CoefficientFunction,
            b: float | ngs.CoefficientFunction) -> float | ngs.CoefficientFunction:
    """``numpy.minimum``: ``a if (a < b or isnan(a)) else b``, so a NaN argument gives NaN."""
    if _is_const(a) and _is_const(b):
        return _fold(np.minimum, a, b)
    a, b = _cf(a), _cf(b)
    return ngs.IfPos(b - a, a, b - _nan_or_zero(a))


def maximum(a: float | ngs.CoefficientFunction,
            b: float | ngs.CoefficientFunction) -> float | ngs.CoefficientFunction:
    """``numpy.maximum``: ``a if (a > b or isnan(a)) else b``, so a NaN argument gives NaN."""
    if _is_const(a) and _is_const(b):
        return _fold(np.maximum, a, b)
    a, b = _cf(a), _cf(b)
    return ngs.IfPos(a - b, a, b - _nan_or_zero(a))


def tanh(a: float | ngs.CoefficientFunction) -> float | ngs.CoefficientFunction:
    """``numpy.tanh``, accurate for small |a| and exactly +-1 for large |a|."""
    if _is_const(a):
        return _fold(np.tanh, a)
    return _if_pos(a - _TANH_SATURATION, 1.0,
                   _if_pos(-a - _TANH_SATURATION, -1.0, ngs.sinh(a) / ngs.cosh(a)))


def power(a: float | ngs.CoefficientFunction,
          b: float | ngs.CoefficientFunction) -> float | ngs.CoefficientFunction:
    """``a ** b`` with the semantics of ``numpy.power`` for float64.

    In particular a negative base with an integer exponent is exact (``(-0.5)**2 = 0.25``; an
    integer-valued constant exponent with ``|n| <= MAX_PRODUCT_EXPONENT`` is expanded into
    products), a negative finite base with a non-integer exponent is NaN, ``a**0 = 1`` and
    ``1**b = 1`` for every a and b (NaN included), and inf, -inf, -0 and NaN follow the C99
    rules of ``pow``.

    Parameters
    ----------
    a, b : float or ngsolve.CoefficientFunction
        Base and exponent.

    Returns
    -------
    float or ngsolve.CoefficientFunction
        A float when both are constants.
    """
    if _is_const(a) and _is_const(b):
        return _fold(np.power, a, b)
    if _is_const(b):
        return _power_constant_exponent(a, b)
    if _is_const(a) and a == 1:
        return 1.0
    if _is_const(a) and 0 < a < math.inf:
        # exp(b log a) is right for every b here: 0, +-inf and NaN included
        return ngs.CF(a) ** b
    return _power_general(_cf(a), b)


def _power_constant_exponent(a: ngs.CoefficientFunction,
                             n: float) -> float | ngs.CoefficientFunction:
    if n == 0:
        return 1.0
    if math.isnan(n):  # numpy: 1**nan = 1, anything else NaN
        return _if_pos(a - 1, math.nan, _if_pos(1 - a, math.nan, a))
    if math.isinf(n):  # numpy: |a| < 1, == 1, > 1 give 0, 1, inf for n = inf (reversed for -inf)
        m = absolute(a)
        above, below = (math.inf, 0.0) if n > 0 else (0.0, math.inf)
        return _if_pos(m - 1, above, _if_pos(1 - m, below, m))
    if n.is_integer():
        k = int(n)
        if abs(k) <= MAX_PRODUCT_EXPONENT:
            return a ** k  # NGSolve's integer power: repeated squaring, 1 / a**|k| for k < 0
        m = absolute(a)
        if k % 2 == 0:
            return m ** float(k)
        # odd: the sign of a (-0 and -inf included) carries over
        return a * m ** float(k - 1) if k > 0 else 1.0 / (a * m ** float(-k - 1))
    # exp(n log a) is NaN for a < 0 as in numpy, but also for a = -inf (numpy: +inf or +0)
    return _if_pos(-a - _BIG, math.inf if n > 0 else 0.0, a ** n)


def _power_general(a: ngs.CoefficientFunction,
                   b: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    """``numpy.power`` for a non-constant exponent: the integer test of b is done pointwise."""
    m = absolute(a)
    # |a|**b for b != 0 and b not NaN; clamping b = +-inf to +-_BIG makes 1**inf = 1
    clamped = _if_pos(b - _BIG, _BIG, _if_pos(-b - _BIG, -_BIG, b))
    magnitude = m ** clamped
    # with round(v) = (v + 2**52) - 2**52 (exact for 0 <= v < 2**52): f = |b| - round(|b|) is 0
    # for integers, 0 < |f| <= 1/2 for non-integers, 0 or |f| >= 1 beyond 2**52 (all integers);
    # for integer b, h = |b|/2 is exact and q = |h - round(h)| is 1/2 exactly when b is odd;
    # b = +-inf gives NaN in both, which counts as even (as for numpy)
    size = absolute(b)
    fraction = absolute(size - ((size + _ROUND) - _ROUND))
    half = size * 0.5
    q = absolute(half - ((half + _ROUND) - _ROUND))
    integer_parity = _if_pos(q - 0.5, 1.0, _if_pos(0.5 - q, 1.0, _if_pos(q, -1.0, 1.0)))
    parity = _if_pos(fraction, _if_pos(1 - fraction, math.nan, integer_parity), integer_parity)
    odd_sign = _if_pos(-parity, -1.0, 1.0)  # -1 for odd b, else +1 (non-integer b too)
    # a with the sign bit: a finite negative base takes the parity (NaN for non-integer b),
    # -0 and -inf only the sign of odd powers; 1/a tells -0 from +0
    sign = _if_pos(a, 1.0, _if_pos(1.0 / a, 1.0,
                                   _if_pos(-a - _BIG, odd_sign, _if_pos(-a, parity, odd_sign))))
    # b = 0 gives 1 whatever a is; b = NaN gives NaN except for a = 1
    nan_exponent = _if_pos(a - 1, math.nan, _if_pos(1 - a, math.nan, a))
    return _if_pos(absolute(b), sign * magnitude, _if_pos(b - b + 1, 1.0, nan_exponent))


def _elementwise(numpy_function: Callable[..., Any],
                 cf_function: Callable[..., ngs.CoefficientFunction]
                 ) -> Callable[..., float | ngs.CoefficientFunction]:
    def apply(*args: float | ngs.CoefficientFunction) -> float | ngs.CoefficientFunction:
        if all(_is_const(a) for a in args):
            return _fold(numpy_function, *args)
        return cf_function(*(_cf(a) for a in args))
    return apply


FUNCTIONS: dict[str, Callable[..., float | ngs.CoefficientFunction]] = {
    "sqrt": _elementwise(np.sqrt, ngs.sqrt),
    "exp": _elementwise(np.exp, ngs.exp),
    "log": _elementwise(np.log, ngs.log),
    "sin": _elementwise(np.sin, ngs.sin),
    "cos": _elementwise(np.cos, ngs.cos),
    "tan": _elementwise(np.tan, ngs.tan),
    "atan": _elementwise(np.arctan, ngs.atan),
    "tanh": tanh,
    "sinh": _elementwise(np.sinh, ngs.sinh),
    "cosh": _elementwise(np.cosh, ngs.cosh),
    "abs": absolute,
    "min": minimum,
    "max": maximum,
}
_ARITY = {"min": 2, "max": 2}

_NUMPY_BINARY = {
    ast.Add: np.add,
    ast.Sub: np.subtract,
    ast.Mult: np.multiply,
    ast.Div: np.divide,
}


def _binary(op: type[ast.operator], a: float | ngs.CoefficientFunction,
            b: float | ngs.CoefficientFunction) -> float | ngs.CoefficientFunction:
    if op is ast.Pow:
        return power(a, b)
    if _is_const(a) and _is_const(b):
        return _fold(_NUMPY_BINARY[op], a, b)
    a, b = _cf(a), _cf(b)  # no Python float operand: NGSolve would turn f * 0 into 0
    if op is ast.Add:
        return a + b
    if op is ast.Sub:
        return a - b
    if op is ast.Mult:
        return a * b
    return a / b


def _names(time: float | ngs.CoefficientFunction) -> dict[str, float | ngs.CoefficientFunction]:
    x, y, z = ngs.x, ngs.y, ngs.z
    return {
        "X1": x, "X2": y, "X3": z, "x": x, "y": y, "z": z,
        "t": time,
        "R": ngs.sqrt(x * x + y * y + z * z),
        "Rxy": ngs.sqrt(x * x + y * y),
        "pi": math.pi,
        "e": math.e,
    }


def _number(value: float) -> float:
    try:
        return float(value)
    except OverflowError:  # an integer literal beyond the float range
        return math.inf




def _check_size(tree: ast.AST, text: str, name: str) -> None:
    """Refuse a syntax tree deeper than :data:`MAX_DEPTH` or larger than :data:`MAX_NODES`,
    walking it without recursion (the translation below recurses once per level)."""
    stack, nodes = [(tree, 1)], 0
    while stack:
        node, depth = stack.pop()
        nodes += 1
        if depth > MAX_DEPTH:
            raise ExpressionError(f"{name} = {shown(text)} is nested more than {MAX_DEPTH} "
                                  f"levels deep (a sum of n terms nests n levels): "
                                  f"allowed at most {MAX_DEPTH}")
        if nodes > MAX_NODES:
            raise ExpressionError(f"{name} = {shown(text)} has more than {MAX_NODES} terms "
                                  f"and operations: allowed at most {MAX_NODES}")
        stack.extend((child, depth + 1) for child in ast.iter_child_nodes(node))


def _parse(text: str, name: str) -> ast.Expression:
    """The syntax tree of ``text`` within the limits of size, not yet checked against the
    whitelist."""
    if not isinstance(text, str) or not text.strip():
        raise ExpressionError(f"{name} must be a non-empty expression in X1, X2, X3 and t")
    if len(text) > MAX_LENGTH:
        raise ExpressionError(f"{name} = {shown(text)} has {len(text)} characters: allowed "
                              f"at most {MAX_LENGTH}")
    foreign = next((c for c in text if not c.isascii()), None)
    if foreign is not None:
        raise ExpressionError(f"{name} = {shown(text)} has the character {foreign!r}: "
                              "allowed ASCII letters, digits and operators only")
    source = text.strip()
    try:
        tree = ast.parse(source, mode="eval")
    except (SyntaxError, MemoryError, RecursionError) as err:
        reason = err.msg if isinstance(err, SyntaxError) else "nested too deeply"
        raise ExpressionError(f"{name} = {shown(text)} is not a valid expression: "
                              f"{reason}") from None
    _check_size(tree, text, name)
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
            literal = ast.get_source_segment(source, node)
            if literal is not None and not DECIMAL.fullmatch(literal):
                raise ExpressionError(f"{name} = {shown(text)} writes the number "
                                      f"{literal!r}: allowed decimal numbers (2, 0.5, 1e-3)")
    return tree


def syntax_tree(text: str, name: str = "expression") -> ast.Expression:
    """The syntax tree of a valid expression (:func:`parse_expression` accepts it), for
    other evaluations of the same expression (:mod:`ngincompat.mechanics.bounds`).

    Raises
    ------
    ExpressionError
        As :func:`parse_expression`.
    """
    parse_expression(text, name=name)
    return _parse(text, name)


def parse_expression(text: str, time: ngs.Parameter | float | None = None,
                     name: str = "expression") -> ngs.CoefficientFunction:
    """Translate ``text`` into a CoefficientFunction of (X, t).

    Parameters
    ----------
    text : str
        The expression, e.g. ``"1 + 0.25*X1*t"``.
    time : ngsolve.Parameter or float, optional
        What ``t`` stands for; a Parameter lets a solver step the load. Defaults to 1.
    name : str
        The parameter name used in error messages.

    Returns
    -------
    ngsolve.CoefficientFunction
        A scalar CoefficientFunction (constants are wrapped too), compiled. Its values are
        those numpy computes for the same expression in float64 (see the module docstring).

    Raises
    ------
    ExpressionError
        For a syntax error or anything outside the whitelist.
    """
    tree = _parse(text, name)
    if time is None:
        time = 1.0
    elif not isinstance(time, ngs.CoefficientFunction):
        time = float(time)
    names = _names(time)

    def build(node: ast.AST) -> float | ngs.CoefficientFunction:
        if isinstance(node, ast.Expression):
            return build(node.body)
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) \
                and not isinstance(node.value, bool):
            return _number(node.value)
        if isinstance(node, ast.Name):
            if node.id in names:
                return names[node.id]
            raise ExpressionError(
                f"{name} = {shown(text)} uses the unknown name {node.id!r}; "
                f"allowed names: {', '.join(sorted(names))}")
        if isinstance(node, ast.BinOp) and type(node.op) in (*_NUMPY_BINARY, ast.Pow):
            return _binary(type(node.op), build(node.left), build(node.right))
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            operand = build(node.operand)
            return -operand if isinstance(node.op, ast.USub) else operand
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) \
                and node.func.id in FUNCTIONS and not node.keywords:
            arity = _ARITY.get(node.func.id, 1)
            if len(node.args) != arity:
                raise ExpressionError(
                    f"{name} = {shown(text)}: {node.func.id}() takes {arity} argument(s)")
            return FUNCTIONS[node.func.id](*(build(a) for a in node.args))
        if isinstance(node, ast.Call):
            called = node.func.id if isinstance(node.func, ast.Name) else ast.unparse(node.func)
            what = f"a call of {called}()"
        else:
            what = f"'{ast.unparse(node)}'"
        raise ExpressionError(
            f"{name} = {shown(text)} contains {what}, which is not allowed; "
            f"use numbers, X1, X2, X3, t, R, + - * / ** and {', '.join(sorted(FUNCTIONS))}")

    value = build(tree)
    return _cf(value) if _is_const(value) else value.Compile()
