"""Boundary and initial conditions, each acting on a named node set.

Kinematic conditions (``PrescribedDisplacement``, ``PrescribedVelocity``, ``Fixed``)
are enforced by the solver after each update; force-like conditions (``BodyForce``,
``Traction``) add to the external force density the model evaluates;
``InitialVelocity`` is applied once at t = 0, a constant per set or a field
(:class:`FieldExpression` of the coordinates, or point values from a file).
"""

from __future__ import annotations

import ast
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from peridynamics.loading.time_functions import Constant, TimeFunction

COMPONENTS = {"x": 0, "y": 1, "z": 2}


def _components(values: Mapping[str, float], dim: int, what: str) -> list[tuple[int, float]]:
    out = []
    for name, val in values.items():
        if name not in COMPONENTS or COMPONENTS[name] >= dim:
            allowed = ", ".join(list(COMPONENTS)[:dim])
            raise ValueError(f"{what}: component {name!r} is not one of {allowed}")
        out.append((COMPONENTS[name], float(val)))
    return out


@dataclass(frozen=True)
class PrescribedDisplacement:
    """u_c(t) = value_c * f(t) on ``nodes`` for each given component (m)."""

    nodes: NDArray[np.intp]
    values: Mapping[str, float]
    function: TimeFunction = field(default_factory=Constant)

    def apply(self, u: NDArray, v: NDArray, t: float, dt: float) -> None:
        """Set u at time ``t`` and v to the secant rate over the last step."""
        f_now, f_old = self.function(t), self.function(t - dt)
        for c, val in _components(self.values, u.shape[1], "displacement"):
            u[self.nodes, c] = val * f_now
            v[self.nodes, c] = val * (f_now - f_old) / dt


@dataclass(frozen=True)
class Fixed:
    """u = v = 0 on ``nodes`` for the listed components (all when ``None``). For a model
    with rotations (micropolar), ``"rotation"`` fixes theta = omega = 0 too; ``None``
    (every component) clamps: displacements and rotation."""

    nodes: NDArray[np.intp]
    components: tuple[str, ...] | None = None

    @property
    def rotation(self) -> bool:
        """True when the condition fixes the rotation of a micropolar model."""
        return self.components is None or "rotation" in self.components

    def apply_rotation(self, theta: NDArray, omega: NDArray) -> None:
        """theta = omega = 0 on ``nodes`` when :attr:`rotation` (arrays (n, 1))."""
        if self.rotation:
            theta[self.nodes] = 0.0
            omega[self.nodes] = 0.0

    def indices(self, dim: int) -> list[int]:
        """The displacement components it fixes (0 = x, ...)."""
        names = (
            tuple(c for c in self.components if c != "rotation")
            if self.components
            else (tuple(COMPONENTS)[:dim])
        )
        return [c for c, _ in _components(dict.fromkeys(names, 0.0), dim, "fixed")]

    def apply(self, u: NDArray, v: NDArray, t: float, dt: float) -> None:
        for c in self.indices(u.shape[1]):
            u[self.nodes, c] = 0.0
            v[self.nodes, c] = 0.0


@dataclass(frozen=True)
class PrescribedVelocity:
    """v_c(t) = value_c * f(t) on ``nodes`` (m/s); u follows by integration."""

    nodes: NDArray[np.intp]
    values: Mapping[str, float]
    function: TimeFunction = field(default_factory=Constant)

    def apply(self, u: NDArray, v: NDArray, t: float, dt: float) -> None:
        """Replace the last step's drift by the prescribed mid-step velocity."""
        mid = self.function(t - 0.5 * dt)
        now = self.function(t)
        for c, val in _components(self.values, u.shape[1], "velocity"):
            u[self.nodes, c] += dt * (val * mid - v[self.nodes, c])
            v[self.nodes, c] = val * now

    def set_velocity(self, v: NDArray, t: float) -> None:
        """Set v at time ``t`` (after the second velocity-Verlet kick)."""
        for c, val in _components(self.values, v.shape[1], "velocity"):
            v[self.nodes, c] = val * self.function(t)


@dataclass(frozen=True)
class InitialVelocity:
    """v(0) = value on ``nodes`` (m/s); ``value`` is one vector (dim,) for every node or
    one per node (len(nodes), dim), e.g. from :class:`FieldExpression` or
    :func:`read_point_values`."""

    nodes: NDArray[np.intp]
    value: tuple[float, ...] | NDArray[np.float64]

    def apply_initial(self, v: NDArray) -> None:
        val = np.asarray(self.value, dtype=float)
        if val.shape not in ((v.shape[1],), (len(self.nodes), v.shape[1])):
            raise ValueError(
                f"initial velocity needs {v.shape[1]} components (one vector, or one per "
                f"node), got shape {val.shape}"
            )
        v[self.nodes] = val


@dataclass(frozen=True)
class BodyForce:
    """b(t) = value * f(t) on ``nodes`` (N/m^3); ``value`` is one vector (dim,) for every
    node or one per node (len(nodes), dim)."""

    nodes: NDArray[np.intp]
    value: tuple[float, ...] | NDArray[np.float64]
    function: TimeFunction = field(default_factory=Constant)

    def checked_value(self, dim: int) -> NDArray[np.float64]:
        """``value`` as an array of shape (dim,) or (len(nodes), dim); ValueError else."""
        val = np.asarray(self.value, dtype=float)
        if val.shape not in ((dim,), (len(self.nodes), dim)):
            raise ValueError(
                f"body force needs {dim} components (one vector, or one per node), "
                f"got shape {val.shape}"
            )
        return val

    def add_to(self, b: NDArray, t: float) -> None:
        b[self.nodes] += self.checked_value(b.shape[1]) * self.function(t)


def traction_as_body_force(
    nodes: NDArray[np.intp],
    traction: NDArray[np.float64],
    x: NDArray[np.float64],
    spacing: float,
    normal: NDArray[np.float64] | None = None,
    layer_thickness: float | None = None,
    function: TimeFunction | None = None,
    jittered: bool = False,
    volume: NDArray[np.float64] | None = None,
    cross_section: float = 1.0,
) -> BodyForce:
    """A surface traction t (Pa) spread as a body force t / l over a boundary layer.

    ``l`` is ``layer_thickness`` if given; else the extent of the node set along the
    surface ``normal`` plus one spacing (one grid row -> dx, k rows -> k dx); without a
    normal, the smallest extent of the set along a coordinate axis plus one spacing (the
    thin direction of an axis-aligned layer, whatever the direction of the traction).
    The total force is then traction x loaded area for grid layers. On a ``jittered``
    grid (the layer's rows are not flat) ``l`` is the layer's volume (``volume`` of its
    points) over its face area: the extents of the set across the normal plus one
    spacing each (2-D: times ``cross_section``, the thickness), so the total force is
    traction x that area.
    """
    traction = np.asarray(traction, dtype=float)
    if layer_thickness is None:
        pts = x[nodes]
        dim = x.shape[1]
        if normal is None:
            axis = int(np.argmin(np.ptp(pts, axis=0)))
            n = np.eye(dim)[axis]
        else:
            n = np.asarray(normal, dtype=float)
            norm = float(np.linalg.norm(n))
            if norm == 0:
                raise ValueError("traction: the normal must be a non-zero vector")
            n = n / norm
        if jittered and volume is not None and dim > 1:
            # tangent directions: the rest of an orthonormal basis with n first
            q = np.linalg.qr(np.column_stack([n, np.eye(dim)]))[0][:, 1:dim]
            rows = np.round(np.ptp(pts @ q, axis=0) / spacing)  # rows across the face - 1
            area = float(np.prod((rows + 1.0) * spacing))
            area *= cross_section if dim == 2 else 1.0
            layer_thickness = float(np.sum(volume[nodes])) / area
        else:
            layer_thickness = float(np.ptp(pts @ n)) + spacing
    if not layer_thickness > 0:
        raise ValueError("traction layer_thickness must be > 0 m")
    return BodyForce(
        nodes=nodes, value=tuple(traction / layer_thickness), function=function or Constant()
    )


def cavity_pressure_as_body_force(
    nodes: NDArray[np.intp],
    pressure: float,
    x: NDArray[np.float64],
    volume: NDArray[np.float64],
    center: NDArray[np.float64],
    spacing: float,
    thickness: float = 1.0,
    layer_thickness: float | None = None,
    function: TimeFunction | None = None,
) -> BodyForce:
    """A pressure p (Pa) on the wall of a cavity around ``center`` (a circular hole in
    2-D, a spherical one in 3-D), as a radial body force p / l pushing each node of the
    layer away from the centre.

    Without ``layer_thickness`` the body force is scaled so that the total radial force
    is p times the wall area: l = sum(V_layer) / A_wall with the wall radius R taken as
    the distance of the closest layer node (A_wall = 2 pi R ``thickness`` in 2-D,
    4 pi R^2 in 3-D). In 1-D the two-sided push uses l = extent of the set + spacing.
    """
    rel = x[nodes] - np.asarray(center, dtype=float)
    r = np.linalg.norm(rel, axis=1)
    if np.any(r == 0):
        raise ValueError("cavity pressure: a loaded node sits on the centre; move the centre")
    if layer_thickness is None:
        dim = x.shape[1]
        radius = float(r.min())
        if dim == 1:
            layer_thickness = float(np.ptp(r)) + spacing
        else:
            wall = 2 * np.pi * radius * thickness if dim == 2 else 4 * np.pi * radius**2
            layer_thickness = float(np.sum(volume[nodes])) / wall
    if not layer_thickness > 0:
        raise ValueError("pressure layer_thickness must be > 0 m")
    value = (pressure / layer_thickness) * rel / r[:, None]
    return BodyForce(nodes=nodes, value=value, function=function or Constant())


Kinematic = PrescribedDisplacement | PrescribedVelocity | Fixed


# ------------------------------------------------------------ initial-value fields
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
