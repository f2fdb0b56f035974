"""Guaranteed bounds of a growth expression over boxes of (X1, X2, X3, t): interval arithmetic.

Sampling theta at points cannot show that it is positive between them: a narrow negative
Gaussian, ``1 - 2*exp(-((X1 - 0.37)/0.01)**2)``, passes every check at the integration points of
a coarse mesh while theta < 0 on a slab of the body. Interval arithmetic can: each operation of
the expression (:mod:`ngincompat.mechanics.expressions`) is evaluated on intervals, so that for
every box [X1 lo, X1 hi] x ... x [t lo, t hi] the result is an interval holding every value the
expression takes in the box (an enclosure; wider than the true range where a variable occurs
several times, tighter as the box shrinks). :func:`positive_on` bisects the boxes on which the
enclosure does not prove 0 < theta < inf, and checks each box's centre, until every box is
proven or a point with theta <= 0 (or not finite) is found.

Rounding: the end points are moved outward by a few units in the last place after each
operation (an end point at exactly zero stays), so the enclosure holds in floating point too.
Signed zeros: 1/+0 = inf but 1/-0 = -inf, so an end point at zero says which zeros the interval
may hold: a lower end is -0 wherever -0 may occur, an upper end at zero is always +0 (the
order -0 < +0).
A value that may be NaN (the square root or logarithm of an interval reaching below zero,
0 times infinity, the sine of infinity) is enclosed by [-inf, inf]: it cannot be proven
positive there, and every result computed from it is marked the same.
"""

import ast
import math
from collections.abc import Callable
from typing import Self

import numpy as np

from ngincompat.mechanics.expressions import syntax_tree

#: How many times a box may be bisected before :func:`positive_on` gives up on it: 24
#: halvings shrink a box's extent in each of the four variables by 2**6.
MAX_ROUNDS = 24
#: How many boxes :func:`positive_on` may hold at once: about 10**5 boxes are a few megabytes.
MAX_BOXES = 100_000

#: Outward rounding after each operation, in units in the last place.
_ULPS = 4


def _outward(v: np.ndarray, direction: int) -> np.ndarray:
    """``v`` moved by :data:`_ULPS` units in the last place towards ``direction`` (+-1);
    zeros and infinities stay."""
    finite = np.isfinite(v) & (v != 0)
    step = _ULPS * np.spacing(np.abs(np.where(finite, v, 1.0)))
    return np.where(finite, v + direction * step, v)


class Interval:
    """Arrays of lower and upper end points, one pair per box, and whether the expression may
    be NaN somewhere in the box (``nan``: a NaN end point sets it, and it passes on to every
    result computed from the interval)."""

    __slots__ = ("lo", "hi", "nan")

    def __init__(self, lo: np.ndarray, hi: np.ndarray, nan: bool | np.ndarray = False) -> None:
        with np.errstate(invalid="ignore"):
            lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
            self.nan = np.isnan(lo) | np.isnan(hi) | nan
            # zero and infinity stay: zero is exact (x - x, 0 * y, a box's side at 0)
            self.lo = np.where(self.nan, -np.inf, _outward(lo, -1))
            # -0 + 0 = +0: an upper end at zero allows +0
            self.hi = np.where(self.nan, np.inf, _outward(hi, 1)) + 0.0

    @classmethod
    def point(cls, value: float, n: int) -> Self:
        return cls(np.full(n, value), np.full(n, value))

    def contains_zero(self) -> np.ndarray:
        return (self.lo <= 0) & (self.hi >= 0)


def _negative_zero(low: np.ndarray, *ends: np.ndarray) -> np.ndarray:
    """``low`` with its zero made -0 where one of ``ends`` is -0: numpy's min and max may
    return either of two zeros, and a lower end must allow -0 wherever it may occur."""
    minus = np.any([(e == 0) & np.signbit(e) for e in ends], axis=0)
    return np.where((low == 0) & minus, -0.0, low)


def _add(a: Interval, b: Interval) -> Interval:
    # inf + -inf is NaN
    nan = ((a.hi == np.inf) & (b.lo == -np.inf)) | ((a.lo == -np.inf) & (b.hi == np.inf))
    with np.errstate(invalid="ignore"):
        return Interval(a.lo + b.lo, a.hi + b.hi, nan)


def _sub(a: Interval, b: Interval) -> Interval:
    return _add(a, _neg(b))


def _mul(a: Interval, b: Interval) -> Interval:
    with np.errstate(invalid="ignore", over="ignore"):
        products = np.stack([a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi])
    # 0 * inf is NaN, also where the zero lies inside an interval whose ends are not zero
    nan = ((a.contains_zero() & (np.isinf(b.lo) | np.isinf(b.hi)))
           | (b.contains_zero() & (np.isinf(a.lo) | np.isinf(a.hi))))
    return Interval(_negative_zero(np.min(products, axis=0), *products),
                    np.max(products, axis=0), nan)


def _reciprocal(a: Interval) -> Interval:
    """1 / a as numpy computes it: 1/+0 = inf and 1/-0 = -inf, so an interval holding +0 (its
    lower end <= 0 <= its upper end) reaches inf and one holding -0 (a lower end below zero or
    at -0) reaches -inf; the reciprocal of a subnormal side overflows to infinity, as numpy's
    value does."""
    with np.errstate(divide="ignore", over="ignore"):
        lo, hi = 1.0 / a.hi, 1.0 / a.lo
    holds_zero = (a.lo <= 0) & (a.hi >= 0)
    minus_zero = (holds_zero & (a.lo < 0)) | ((a.lo == 0) & np.signbit(a.lo))
    return Interval(np.where(minus_zero, -np.inf, lo), np.where(holds_zero, np.inf, hi))


def _div(a: Interval, b: Interval) -> Interval:
    return _mul(a, _reciprocal(b))


def _neg(a: Interval) -> Interval:
    return Interval(-a.hi, -a.lo)


def _monotone(f: Callable[[np.ndarray], np.ndarray], a: Interval) -> Interval:
    """f(a) for an f increasing over a that keeps the sign of zero (exp, sqrt, atan, tanh,
    sinh; tan between two poles, cosh of |a|)."""
    with np.errstate(all="ignore"):
        return Interval(f(a.lo), f(a.hi))


def _even_power(a: Interval, n: float) -> Interval:
    """a**n for an even integer n >= 0: smallest at the point of the box nearest to 0."""
    with np.errstate(over="ignore", under="ignore"):
        lo, hi = np.abs(a.lo) ** n, np.abs(a.hi) ** n
    low = np.where(a.contains_zero(), 0.0, np.minimum(lo, hi))
    return Interval(low, np.maximum(lo, hi))


def _sqrt(a: Interval) -> Interval:
    # NaN below zero: the box holds a point where theta is NaN unless all of it is >= 0
    # sqrt(-0) = -0: a lower end at -0 stays
    root = _monotone(np.sqrt, Interval(np.where(a.lo < 0, 0.0, a.lo), np.maximum(a.hi, 0)))
    return Interval(np.where(a.lo < 0, np.nan, root.lo), root.hi)


def _log(a: Interval) -> Interval:
    with np.errstate(divide="ignore", invalid="ignore"):
        lo, hi = np.log(a.lo), np.log(a.hi)
    return Interval(np.where(a.lo < 0, np.nan, lo), hi)


def _power(a: Interval, b: Interval, exponent: float | None) -> Interval:
    """a**b as numpy computes it (see :func:`ngincompat.mechanics.expressions.power`)."""
    if exponent is not None and float(exponent).is_integer():
        # every float from 2**53 on is an even integer
        even = abs(exponent) >= 2 ** 53 or exponent % 2 == 0
        if exponent == 0:
            return Interval.point(1.0, a.lo.size)
        if even:
            magnitude = _even_power(a, abs(exponent))
        else:
            with np.errstate(over="ignore"):
                magnitude = Interval(np.copysign(np.abs(a.lo) ** abs(exponent), a.lo),
                                     np.copysign(np.abs(a.hi) ** abs(exponent), a.hi))
        return magnitude if exponent > 0 else _reciprocal(magnitude)
    if exponent is not None:
        # a non-integer constant: NaN for a < 0, monotone in a >= 0
        with np.errstate(all="ignore"):
            lo, hi = np.maximum(a.lo, 0) ** exponent, np.maximum(a.hi, 0) ** exponent
        result = Interval(np.minimum(lo, hi), np.maximum(lo, hi))
        return Interval(np.where(a.lo < 0, np.nan, result.lo), result.hi)
    # a variable exponent: exp(b log a) where a > 0, unknown elsewhere
    value = _monotone(np.exp, _mul(b, _log(a)))
    positive = a.lo > 0
    return Interval(np.where(positive, value.lo, np.nan), np.where(positive, value.hi, np.nan))


def _periodic(a: Interval, f: Callable[[np.ndarray], np.ndarray], peak: float,
              trough: float) -> Interval:
    """sin or cos on an interval: the end points, and +-1 where the interval holds a peak
    (``peak + 2 pi k``) or a trough."""
    with np.errstate(invalid="ignore"):
        ends = np.stack([f(a.lo), f(a.hi)])
        lo, hi = _negative_zero(np.min(ends, axis=0), *ends), np.max(ends, axis=0)

        def holds(x0: float) -> np.ndarray:
            k = np.ceil((a.lo - x0) / (2 * np.pi))
            return x0 + 2 * np.pi * k <= a.hi

        infinite = ~np.isfinite(a.lo) | ~np.isfinite(a.hi)     # sin(inf) is NaN
        wide = infinite | (a.hi - a.lo >= 2 * np.pi)
        hi = np.where(wide | holds(peak), 1.0, hi)
        lo = np.where(wide | holds(trough), -1.0, lo)
    return Interval(lo, hi, infinite)


def _tan(a: Interval) -> Interval:
    with np.errstate(invalid="ignore"):
        k = np.ceil((a.lo - np.pi / 2) / np.pi)
        pole = (np.pi / 2 + np.pi * k <= a.hi) | ~np.isfinite(a.lo) | ~np.isfinite(a.hi)
    value = _monotone(np.tan, a)
    return Interval(np.where(pole, -np.inf, value.lo), np.where(pole, np.inf, value.hi),
                    ~np.isfinite(a.lo) | ~np.isfinite(a.hi))


def _cosh(a: Interval) -> Interval:
    value = _monotone(np.cosh, Interval(np.abs(a.lo), np.abs(a.hi)))
    high = np.maximum(value.lo, value.hi)
    low = np.where(a.contains_zero(), 1.0, np.minimum(value.lo, value.hi))
    return Interval(low, high)


def _abs(a: Interval) -> Interval:
    return _even_power(a, 1)


FUNCTIONS: dict[str, Callable[..., Interval]] = {
    "sqrt": _sqrt,
    "exp": lambda a: _monotone(np.exp, a),
    "log": _log,
    "sin": lambda a: _periodic(a, np.sin, np.pi / 2, -np.pi / 2),
    "cos": lambda a: _periodic(a, np.cos, 0.0, np.pi),
    "tan": _tan,
    "atan": lambda a: _monotone(np.arctan, a),
    "tanh": lambda a: _monotone(np.tanh, a),
    "sinh": lambda a: _monotone(np.sinh, a),
    "cosh": _cosh,
    "abs": _abs,
    "min": lambda a, b: Interval(_negative_zero(np.minimum(a.lo, b.lo), a.lo, b.lo),
                                 np.minimum(a.hi, b.hi)),
    "max": lambda a, b: Interval(_negative_zero(np.maximum(a.lo, b.lo), a.lo, b.lo),
                                 np.maximum(a.hi, b.hi)),
}

_BINARY = {ast.Add: _add, ast.Sub: _sub, ast.Mult: _mul, ast.Div: _div}


def enclosure(text: str, lo: np.ndarray, hi: np.ndarray,
              name: str = "theta") -> tuple[np.ndarray, np.ndarray]:
    """Bounds of the expression ``text`` on boxes.

    Parameters
    ----------
    text : str
        An expression of :mod:`ngincompat.mechanics.expressions` in X1, X2, X3, t.
    lo, hi : numpy.ndarray
        (n, 4): the corners of n boxes in (X1, X2, X3, t).
    name : str
        The parameter name in error messages.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        Lower and upper bounds (n,) of the expression on each box; -inf and inf where it may
        be NaN or unbounded there.
    """
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    n = lo.shape[0]
    X = [Interval(lo[:, k], hi[:, k]) for k in range(4)]
    squares = [_even_power(c, 2) for c in X[:3]]
    names = {"X1": X[0], "X2": X[1], "X3": X[2], "x": X[0], "y": X[1], "z": X[2], "t": X[3],
             "R": _sqrt(_add(_add(squares[0], squares[1]), squares[2])),
             "Rxy": _sqrt(_add(squares[0], squares[1])),
             "pi": Interval.point(math.pi, n), "e": Interval.point(math.e, n)}

    def constant(node: ast.expr) -> float | None:
        """The value of a constant exponent (``2``, ``-0.5``), else None."""
        if isinstance(node, ast.Constant):
            return float(node.value)  # type: ignore[arg-type]  # a number: syntax_tree
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            value = constant(node.operand)
            return None if value is None else (-value if isinstance(node.op, ast.USub)
                                               else value)
        return None

    def bound(node: ast.AST) -> Interval:
        if isinstance(node, ast.Expression):
            return bound(node.body)
        if isinstance(node, ast.Constant):
            value = (float(node.value)  # type: ignore[arg-type]  # a number: syntax_tree
                     if abs(node.value) < 2 ** 1024 else math.inf)  # type: ignore[arg-type]
            return Interval.point(value, n)
        if isinstance(node, ast.Name):
            return names[node.id]
        if isinstance(node, ast.UnaryOp):
            operands = [bound(node.operand)]
            result = _neg(operands[0]) if isinstance(node.op, ast.USub) else operands[0]
        elif isinstance(node, ast.BinOp):
            operands = [bound(node.left), bound(node.right)]
            if isinstance(node.op, ast.Pow):
                result = _power(*operands, constant(node.right))  # type: ignore[call-arg, arg-type]
            else:
                result = _BINARY[type(node.op)](*operands)
        else:
            # the one kind left by syntax_tree: a call of a function of FUNCTIONS
            operands = [bound(a) for a in node.args]  # type: ignore[attr-defined]
            result = FUNCTIONS[node.func.id](*operands)  # type: ignore[attr-defined]
        # a NaN operand makes the result NaN (numpy's nan ** 0 = 1 is taken as NaN too: the
        # enclosure stays one, only wider)
        return Interval(result.lo, result.hi, np.any([o.nan for o in operands], axis=0)
                        | result.nan)

    result = bound(syntax_tree(text, name))
    return result.lo, result.hi


def positive_on(text: str, lo: np.ndarray, hi: np.ndarray, name: str = "theta",
                evaluate: Callable[[np.ndarray], np.ndarray] | None = None
                ) -> tuple[np.ndarray, float, bool] | None:
    """Prove ``text`` > 0 on every box, or find a point where it is not positive and finite.

    (That theta is finite is for the sampling of
    :func:`ngincompat.mechanics.growth.check_positive` to find: an enclosure cannot tell
    ``1 + X1**1e308`` near X1 = 1 from infinity.) Boxes whose enclosure does not prove it
    positive are halved across their widest side (measured against the box they came from)
    and their centres evaluated, for at most
    :data:`MAX_ROUNDS` rounds and :data:`MAX_BOXES` boxes.

    Parameters
    ----------
    text : str
        The expression.
    lo, hi : numpy.ndarray
        (n, 4) corners of boxes in (X1, X2, X3, t) that cover the body over the growth time.
    name : str
        The parameter name in error messages.
    evaluate : callable, optional
        points (m, 4) -> values (m,); defaults to the enclosure of the points themselves.

    Returns
    -------
    None or (numpy.ndarray, float, bool)
        None when proven; else a point (X1, X2, X3, t), a number and whether it is a value:
        the first point found with value <= 0 or not finite and that value (True) or, when
        the boxes could not be resolved, the centre of the box with the smallest lower bound
        and that bound (False).
    """
    lo, hi = np.array(lo, dtype=float), np.array(hi, dtype=float)
    scale = np.where(hi > lo, hi - lo, 1.0)
    if evaluate is None:
        def evaluate(points: np.ndarray) -> np.ndarray:
            return enclosure(text, points, points, name)[0]
    for _ in range(MAX_ROUNDS + 1):
        open_ = ~(enclosure(text, lo, hi, name)[0] > 0)
        if not open_.any():
            return None
        lo, hi, scale = lo[open_], hi[open_], scale[open_]
        centres = (lo + hi) / 2
        values = np.asarray(evaluate(centres), dtype=float)
        bad = ~np.isfinite(values) | (values <= 0)
        if bad.any():
            i = int(np.argmax(bad))
            return centres[i], float(values[i]), True
        if 2 * len(lo) > MAX_BOXES:
            break
        axis = np.argmax((hi - lo) / scale, axis=1)
        rows = np.arange(len(lo))
        middle = centres[rows, axis]
        left_hi, right_lo = hi.copy(), lo.copy()
        left_hi[rows, axis] = middle
        right_lo[rows, axis] = middle
        lo, hi = np.concatenate([lo, right_lo]), np.concatenate([left_hi, hi])
        scale = np.concatenate([scale, scale])
    low, _ = enclosure(text, lo, hi, name)
    i = int(np.argmin(low))
    return (lo[i] + hi[i]) / 2, float(low[i]), False
