"""Safe parsing of user expressions such as ``theta = "1 + 0.25*X1*t"``.

An expression is parsed with :mod:`ast` and translated node by node into an NGSolve
CoefficientFunction. Only numbers, the names below, the arithmetic operators
``+ - * / **`` and the whitelisted functions are accepted; anything else (attribute access,
calls of other names, comprehensions, strings, ...) is an :class:`ExpressionError`. Nothing is
ever passed to :func:`eval`.

Names: ``X1, X2, X3`` (reference coordinates, also ``x, y, z``), ``t`` (growth time in [0, 1]),
``R`` (distance from the origin), ``Rxy`` (distance from the X3 axis), ``pi``, ``e``.
Functions: ``sqrt exp log sin cos tan atan tanh sinh cosh abs min max``.
"""

import ast
import math
import operator

import ngsolve as ngs

from .errors import ExpressionError

FUNCTIONS = {
    "sqrt": ngs.sqrt,
    "exp": ngs.exp,
    "log": ngs.log,
    "sin": ngs.sin,
    "cos": ngs.cos,
    "tan": ngs.tan,
    "atan": ngs.atan,
    "tanh": lambda a: 1 - 2 / (ngs.exp(2 * a) + 1),
    "sinh": ngs.sinh,
    "cosh": ngs.cosh,
    "abs": lambda a: ngs.IfPos(a, a, -a),
    "min": lambda a, b: ngs.IfPos(a - b, b, a),
    "max": lambda a, b: ngs.IfPos(a - b, a, b),
}
_ARITY = {"min": 2, "max": 2}

_BINARY = {
    ast.Add: operator.add,
    ast.Sub: operator.sub,
    ast.Mult: operator.mul,
    ast.Div: operator.truediv,
    ast.Pow: operator.pow,
}


def _names(time):
    x, y, z = ngs.x, ngs.y, ngs.z
    return {
        "X1": x, "X2": y, "X3": z, "x": x, "y": y, "z": z,
        "t": time,
        "R": ngs.sqrt(x * x + y * y + z * z),
        "Rxy": ngs.sqrt(x * x + y * y),
        "pi": math.pi,
        "e": math.e,
    }


def parse_expression(text, time=None, name="expression"):
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
        A scalar CoefficientFunction (constants are wrapped too).

    Raises
    ------
    ExpressionError
        For a syntax error or anything outside the whitelist.
    """
    if not isinstance(text, str) or not text.strip():
        raise ExpressionError(f"{name} must be a non-empty expression in X1, X2, X3 and t")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as err:
        raise ExpressionError(f"{name} = {text!r} is not a valid expression: {err.msg}") from None
    names = _names(1.0 if time is None else time)

    def build(node):
        if isinstance(node, ast.Expression):
            return build(node.body)
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) \
                and not isinstance(node.value, bool):
            return float(node.value)
        if isinstance(node, ast.Name):
            if node.id in names:
                return names[node.id]
            raise ExpressionError(
                f"{name} = {text!r} uses the unknown name {node.id!r}; "
                f"allowed names: {', '.join(sorted(names))}")
        if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            return _BINARY[type(node.op)](build(node.left), build(node.right))
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            operand = build(node.operand)
            return -operand if isinstance(node.op, ast.USub) else operand
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) \
                and node.func.id in FUNCTIONS and not node.keywords:
            arity = _ARITY.get(node.func.id, 1)
            if len(node.args) != arity:
                raise ExpressionError(
                    f"{name} = {text!r}: {node.func.id}() takes {arity} argument(s)")
            args = [_as_cf(build(a)) for a in node.args]
            return FUNCTIONS[node.func.id](*args)
        if isinstance(node, ast.Call):
            called = node.func.id if isinstance(node.func, ast.Name) else ast.unparse(node.func)
            what = f"a call of {called}()"
        else:
            what = f"'{ast.unparse(node)}'"
        raise ExpressionError(
            f"{name} = {text!r} contains {what}, which is not allowed; "
            f"use numbers, X1, X2, X3, t, R, + - * / ** and {', '.join(sorted(FUNCTIONS))}")

    return _as_cf(build(tree))


def _as_cf(value):
    return value if isinstance(value, ngs.CoefficientFunction) else ngs.CF(value)
