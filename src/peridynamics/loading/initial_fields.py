"""Initial-value fields: a value at t = 0 as an arithmetic expression of the reference
coordinates (:class:`FieldExpression`, a small language parsed with :mod:`ast`, so a deck
cannot run arbitrary Python), or point values read from a ``.npy`` / ``.csv`` file
(:func:`read_point_values`, :func:`point_rows`); used by
:class:`peridynamics.loading.conditions.InitialVelocity`.
"""

from __future__ import annotations

import ast
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "FIELD_FUNCTIONS",
    "FIELD_NAMES",
    "MAX_EXPRESSION_LENGTH",
    "FieldExpression",
    "point_rows",
    "read_point_values",
]

#: the names an initial-value expression may use: the reference coordinates (m), the
#: time (always 0: these are values at t = 0) and two constants
FIELD_NAMES = ("x", "y", "z", "t", "pi", "e")
#: the functions an initial-value expression may call, with their number of arguments
FIELD_FUNCTIONS: dict[str, tuple[Callable[..., Any], int]] = {
    "sin": (np.sin, 1),
    "cos": (np.cos, 1),
    "tan": (np.tan, 1),
    "exp": (np.exp, 1),
    "log": (np.log, 1),
    "sqrt": (np.sqrt, 1),
    "abs": (np.abs, 1),
    "tanh": (np.tanh, 1),
    "arctan2": (np.arctan2, 2),
    "minimum": (np.minimum, 2),
    "maximum": (np.maximum, 2),
    "where": (np.where, 3),
}
MAX_EXPRESSION_LENGTH = 1000
_BINARY: dict[type, Callable[[Any, Any], Any]] = {
    ast.Add: np.add,
    ast.Sub: np.subtract,
    ast.Mult: np.multiply,
    ast.Div: np.divide,
    ast.Pow: np.power,
}
_COMPARE: dict[type, Callable[[Any, Any], Any]] = {
    ast.Lt: np.less,
    ast.LtE: np.less_equal,
    ast.Gt: np.greater,
    ast.GtE: np.greater_equal,
}
_SYMBOLS = {ast.Lt: "<", ast.LtE: "<=", ast.Gt: ">", ast.GtE: ">=", ast.Eq: "==", ast.NotEq: "!="}


def _short(text: str, n: int = 60) -> str:
    return repr(text if len(text) <= n else text[: n - 3] + "...")


class FieldExpression:
    """A value at t = 0 as an arithmetic expression of the reference coordinates.

    The text is parsed with :mod:`ast` and only this small language is accepted, so a
    deck cannot run arbitrary Python: numbers; the names ``x``, ``y``, ``z`` (m),
    ``t`` (0 s), ``pi``, ``e``; ``+ - * / **`` and unary ``-``/``+``; comparisons
    ``< <= > >=`` (true = 1, for ``where``); calls of the functions in
    :data:`FIELD_FUNCTIONS` (``sin cos tan exp log sqrt abs tanh`` of one argument,
    ``arctan2 minimum maximum`` of two, ``where(condition, a, b)``). Anything else
    (attributes, subscripts, keywords, strings, lambdas, ...) is a ``ValueError`` that
    says what is allowed. Evaluation is NumPy on whole arrays.
    """

    def __init__(self, text: str) -> None:
        self.text = str(text)
        if len(self.text) > MAX_EXPRESSION_LENGTH:
            raise ValueError(f"expression longer than {MAX_EXPRESSION_LENGTH} characters")
        try:
            self._tree = ast.parse(self.text.strip(), mode="eval")
        except SyntaxError as exc:
            where = f" at column {exc.offset}" if exc.offset else ""
            raise ValueError(f"not a valid expression{where}: {_short(self.text)}") from None
        except (RecursionError, MemoryError, ValueError):
            raise ValueError(f"too deeply nested: {_short(self.text)}") from None
        self.names: set[str] = set()
        self._check(self._tree.body)

    def _check(self, node: ast.AST) -> None:
        if isinstance(node, ast.Constant):
            if isinstance(node.value, bool) or not isinstance(node.value, int | float):
                raise ValueError(f"only numbers are allowed as constants, got {node.value!r}")
        elif isinstance(node, ast.Name):
            if node.id in FIELD_FUNCTIONS:
                raise ValueError(f"{node.id!r} is a function: call it, e.g. {node.id}(x)")
            if node.id not in FIELD_NAMES:
                raise ValueError(
                    f"unknown name {node.id!r}; allowed: {', '.join(FIELD_NAMES)} and the "
                    f"functions {', '.join(FIELD_FUNCTIONS)}"
                )
            self.names.add(node.id)
        elif isinstance(node, ast.BinOp):
            if type(node.op) not in _BINARY:
                raise ValueError("only the operators + - * / ** are allowed")
            self._check(node.left)
            self._check(node.right)
        elif isinstance(node, ast.UnaryOp):
            if not isinstance(node.op, ast.USub | ast.UAdd):
                raise ValueError("only unary - and + are allowed")
            self._check(node.operand)
        elif isinstance(node, ast.Compare):
            if len(node.ops) != 1:
                raise ValueError(
                    "chained comparisons (a < x < b) are not allowed; "
                    "nest where(): where(x > a, where(x < b, 1, 0), 0)"
                )
            if type(node.ops[0]) not in _COMPARE:
                got = _SYMBOLS.get(type(node.ops[0]), type(node.ops[0]).__name__)
                raise ValueError(f"only the comparisons < <= > >= are allowed, got {got}")
            self._check(node.left)
            self._check(node.comparators[0])
        elif isinstance(node, ast.Call):
            func = node.func.id if isinstance(node.func, ast.Name) else None
            if func not in FIELD_FUNCTIONS:
                raise ValueError(
                    f"unknown function {ast.unparse(node.func)!r}; allowed: "
                    f"{', '.join(FIELD_FUNCTIONS)}"
                )
            if node.keywords or any(isinstance(a, ast.Starred) for a in node.args):
                raise ValueError(f"{func}() takes positional arguments only")
            n_args = FIELD_FUNCTIONS[func][1]
            if len(node.args) != n_args:
                raise ValueError(f"{func}() takes {n_args} argument(s), got {len(node.args)}")
            for a in node.args:
                self._check(a)
        else:
            raise ValueError(
                f"{type(node).__name__.lower()} is not allowed in an expression "
                f"({ast.unparse(node)!r}); use numbers, x y z t pi e, + - * / **, "
                "comparisons and the functions " + ", ".join(FIELD_FUNCTIONS)
            )

    def __call__(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """The values at the points ``x`` (n, dim), shape (n,); may be non-finite (the
        caller checks)."""
        x = np.asarray(x, dtype=float)
        env: dict[str, Any] = {"t": 0.0, "pi": np.pi, "e": np.e}
        for k, name in enumerate("xyz"):
            if name in self.names:
                if k >= x.shape[1]:
                    raise ValueError(f"{name!r} does not exist in {x.shape[1]}-D")
                env[name] = x[:, k]
        with np.errstate(all="ignore"):
            out = self._eval(self._tree.body, env)
        return np.broadcast_to(np.asarray(out, dtype=float), (x.shape[0],)).copy()

    def _eval(self, node: ast.AST, env: dict[str, Any]) -> Any:
        if isinstance(node, ast.Constant):
            assert isinstance(node.value, int | float)  # checked when parsed
            return float(node.value)
        if isinstance(node, ast.Name):
            return env[node.id]
        if isinstance(node, ast.BinOp):
            op = _BINARY[type(node.op)]
            return op(np.float64(self._eval(node.left, env)), self._eval(node.right, env))
        if isinstance(node, ast.UnaryOp):
            val = self._eval(node.operand, env)
            return np.negative(val) if isinstance(node.op, ast.USub) else val
        if isinstance(node, ast.Compare):
            cmp = _COMPARE[type(node.ops[0])]
            return cmp(self._eval(node.left, env), self._eval(node.comparators[0], env)) * 1.0
        assert isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
        func = FIELD_FUNCTIONS[node.func.id][0]
        return func(*(self._eval(a, env) for a in node.args))


def read_point_values(path: str | Path, dim: int) -> NDArray[np.float64]:
    """Rows of point values from a ``.npy`` file (an array (n, dim); (n,) in 1-D) or a
    ``.csv`` file (n lines of ``dim`` comma-separated numbers; lines starting with ``#``
    are comments). Raises ValueError naming what is wrong."""
    path = Path(path)
    try:
        if path.suffix.lower() == ".npy":
            arr = np.load(path, allow_pickle=False)
        elif path.suffix.lower() == ".csv":
            arr = np.loadtxt(path, delimiter=",", ndmin=2, comments="#", dtype=float)
        else:
            raise ValueError(f"{path.name}: use a .npy or a .csv file")
    except OSError as exc:
        raise ValueError(f"cannot read {str(path)!r}: {exc.strerror or exc}") from None
    except ValueError as exc:
        raise ValueError(f"cannot read {str(path)!r}: {exc}") from None
    arr = np.asarray(arr)
    if arr.dtype.kind not in "iuf":
        raise ValueError(f"{path.name}: numbers expected, got an array of {arr.dtype}")
    if arr.ndim == 1 and dim == 1:
        arr = arr[:, None]
    if arr.ndim != 2 or arr.shape[1] != dim:
        raise ValueError(
            f"{path.name}: needs one row of {dim} value(s) per point, got an array of "
            f"shape {arr.shape}"
        )
    return arr.astype(float)


def point_rows(
    values: NDArray[np.float64], nodes: NDArray[np.intp], n_points: int, what: str
) -> NDArray[np.float64]:
    """The rows of ``values`` for ``nodes``: ``values`` has one row per point of the
    set (in the order of the set, i.e. increasing point index) or one row per point of
    the body (then the set's rows are taken). Checks the length and that every value of
    the file is finite."""
    bad = ~np.isfinite(values)
    if np.any(bad):
        where = np.flatnonzero(bad.any(axis=1))
        raise ValueError(
            f"{what} has {len(where)} row(s) with non-finite values (first: row {where[0]})"
        )
    if len(values) == len(nodes):
        rows = values
    elif len(values) == n_points:
        rows = values[nodes]
    else:
        raise ValueError(
            f"{what} has {len(values)} rows; it needs one per point of the node set "
            f"({len(nodes)}) or one per point of the body ({n_points})"
        )
    return np.ascontiguousarray(rows, dtype=float)
