"""Evaluating expressions: numbers with units, vectors, frames, names.

A bare number keeps ``dim=None`` until it meets a slot, where it takes the
slot's SI unit (:mod:`cosmos.lang.evaluate.values`). The ``expect_*`` methods
are those slots: they check kind, size and dimension and raise a
:class:`ProgramError` that points at the offending expression.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Callable, Mapping
from math import isfinite

from cosmos.errors import ProgramError, Span
from cosmos.lang import ast, units
from cosmos.lang.check import limits
from cosmos.lang.evaluate.values import (
    Binding,
    FrameValue,
    Scalar,
    SuppressedError,
    Value,
    Vec,
    kind_of,
)
from cosmos.lang.units import Dim
from cosmos.rotations import FloatArray, readonly, rpy_to_matrix


class Evaluator:
    """Evaluates expressions against named values.

    Args:
        names: Names in scope, keyed by case-folded name.
        text_of: The source text of a span, for messages.
    """

    __slots__ = ("names", "text_of")

    def __init__(self, names: Mapping[str, Binding], text_of: Callable[[Span], str]):
        self.names = names
        self.text_of = text_of

    # ------------------------------------------------------------ evaluation

    def evaluate(self, expr: ast.Expr) -> Value:
        """The value of an expression; every number in it finite.

        Raises:
            ProgramError: An unknown name, a unit or kind mismatch, or a number
                too large to represent.
        """
        kind = type(expr)
        if kind is ast.Number:
            number, dim = self._number_value(expr)  # type: ignore[arg-type]
            return Scalar(number, dim)
        if kind is ast.Name:
            return self._lookup(expr)  # type: ignore[arg-type]
        if kind is ast.Vector:
            return self._vector(expr)  # type: ignore[arg-type]
        if kind is ast.Pose:
            return self._pose(expr)  # type: ignore[arg-type]
        if kind is ast.Binary:
            value = self._binary(expr)  # type: ignore[arg-type]
            if type(value) is FrameValue:  # a frame moved by an offset: _binary checked its origin
                return value
        else:
            value = self._evaluate(expr)
            if kind is not ast.Unary:
                return value
        if not _finite(value):
            raise ProgramError("this number is too large", expr.span)
        return value

    def number_value(self, expr: ast.Number) -> tuple[float, Dim | None]:
        """The number in SI and its dimension (None for a bare number); finite.

        Raises:
            ProgramError: An unknown unit, or a number too large to represent.
        """
        return self._number_value(expr)

    def _number_value(self, expr: ast.Number) -> tuple[float, Dim | None]:
        """The number in SI and its dimension (None for a bare number); finite."""
        if expr.unit is None:
            number, dim = expr.value, None
        else:
            try:
                unit = units.parse_unit(expr.unit)
            except units.UnknownUnit as error:
                raise ProgramError(str(error), expr.span) from None
            number, dim = expr.value * unit.factor, unit.dim
        if not math.isfinite(number):
            raise ProgramError("this number is too large", expr.span)
        return number, dim

    def _evaluate(self, expr: ast.Expr) -> Value:
        if isinstance(expr, ast.Number):
            return Scalar(*self._number_value(expr))
        if isinstance(expr, ast.Name):
            return self._lookup(expr)
        if isinstance(expr, ast.Vector):
            return self._vector(expr)
        if isinstance(expr, ast.Unary):
            operand = self.evaluate(expr.operand)
            if expr.op == "+":
                return operand
            return self._scale(operand, -1.0, expr.span)
        if isinstance(expr, ast.Binary):
            return self._binary(expr)
        return self._pose(expr)

    def _lookup(self, expr: ast.Name) -> Value:
        names, key = self.names, expr.name.casefold()
        binding = names[key] if key in names else None  # not .get: a mappingproxy's is a method call
        if binding is None:
            raise ProgramError(f"unknown name '{expr.name}'{suggest(expr.name, self.names)}", expr.span)
        if binding.value is None:
            raise SuppressedError(f"'{expr.name}' has an error in its definition", expr.span)
        return binding.value

    def _vector(self, expr: ast.Vector) -> Vec:
        values: list[float] = []
        dim: Dim | None = None
        first_with_dim: ast.Expr | None = None
        for item in expr.items:
            if type(item) is ast.Number:  # most components: no Scalar made
                number, unit = item.value, item.unit
                if unit is None and isfinite(number):  # a bare number: itself
                    values.append(number)
                    continue
                number, item_dim = self._number_value(item)
            else:
                value = self.evaluate(item)
                if not isinstance(value, Scalar):
                    raise ProgramError(
                        f"a vector's components must be numbers; this is {kind_of(value)}", item.span
                    )
                number, item_dim = value.value, value.dim
            if item_dim is not None:
                if dim is None:
                    dim, first_with_dim = item_dim, item
                elif item_dim != dim:
                    assert first_with_dim is not None
                    raise ProgramError(
                        f"the components of a vector must be of one kind: "
                        f"{self.text_of(first_with_dim.span)} is {units.describe(dim)}, "
                        f"{self.text_of(item.span)} is {units.describe(item_dim)}",
                        item.span,
                    )
            values.append(number)
        return Vec(tuple(values), dim)

    def _scale(self, value: Value, factor: float, span: Span) -> Value:
        if isinstance(value, Scalar):
            return Scalar(value.value * factor, value.dim)
        if isinstance(value, Vec):
            return Vec(tuple(v * factor for v in value.values), value.dim)
        raise ProgramError("a frame cannot be negated or scaled", span)

    def _binary(self, expr: ast.Binary) -> Value:
        left = self.evaluate(expr.left)
        right = self.evaluate(expr.right)
        if expr.op == "*":
            return self._multiply(left, right, expr)
        sign = 1.0 if expr.op == "+" else -1.0
        if isinstance(left, FrameValue):
            if isinstance(right, FrameValue) and sign < 0:
                return Vec(tuple(left.position - right.position), units.LENGTH)
            dx, dy, dz = self._vector_values(expr.right, right, 3, units.LENGTH, "an offset")
            x, y, z = left.position.tolist()
            # float(): an offset made by subtracting frames holds numpy floats (which warn on overflow)
            moved = (x + sign * float(dx), y + sign * float(dy), z + sign * float(dz))
            if not (isfinite(moved[0]) and isfinite(moved[1]) and isfinite(moved[2])):
                raise ProgramError("this number is too large", expr.span)
            return FrameValue(readonly(moved), left.rotation)
        if isinstance(right, FrameValue):
            raise ProgramError(
                f"write the frame first: {self.text_of(expr.right.span)} {expr.op} ...", expr.span
            )
        if type(left) is not type(right):
            raise ProgramError(
                f"cannot {'add' if sign > 0 else 'subtract'} {kind_of(right)} "
                f"{'to' if sign > 0 else 'from'} {kind_of(left)}",
                expr.span,
            )
        dim = self._common_dim(left.dim, right.dim, expr)
        if isinstance(left, Scalar):
            assert isinstance(right, Scalar)
            return Scalar(left.value + sign * right.value, dim)
        assert isinstance(left, Vec) and isinstance(right, Vec)
        if len(left.values) != len(right.values):
            raise ProgramError(
                f"cannot combine vectors of {len(left.values)} and {len(right.values)} components",
                expr.span,
            )
        return Vec(tuple(a + sign * b for a, b in zip(left.values, right.values, strict=True)), dim)

    def _common_dim(self, a: Dim | None, b: Dim | None, expr: ast.Binary) -> Dim | None:
        if a is None or b is None or a == b:
            return a if a is not None else b
        raise ProgramError(
            f"cannot {'add' if expr.op == '+' else 'subtract'} {units.describe(b)} "
            f"({self.text_of(expr.right.span)}) and {units.describe(a)} "
            f"({self.text_of(expr.left.span)})",
            expr.span,
        )

    def _multiply(self, left: Value, right: Value, expr: ast.Binary) -> Value:
        if isinstance(left, Vec) and isinstance(right, Scalar):
            left, right = right, left
        if not isinstance(left, Scalar) or isinstance(right, FrameValue):
            raise ProgramError("only numbers can multiply: a number * a number or a vector", expr.span)
        dim = None
        if left.dim is not None or right.dim is not None:
            dim = units.multiply(left.dim or units.DIMENSIONLESS, right.dim or units.DIMENSIONLESS)
        if isinstance(right, Scalar):
            return Scalar(left.value * right.value, dim)
        return Vec(tuple([left.value * v for v in right.values]), dim)

    def _pose(self, expr: ast.Pose) -> FrameValue:
        position = self.expect_position(expr.position, "a pose's position")
        angles = self.evaluate(expr.rpy)
        self.expect_vector(expr.rpy, angles, 3, units.ANGLE, "RPY")
        assert isinstance(angles, Vec)  # expect_vector refuses anything else
        # The floats themselves (a zero's sign aside, as the array had them: the
        # matrix is the same, its zeros made +0.0 by readonly).
        return FrameValue(position.position, rpy_to_matrix(*angles.values))

    # ----------------------------------------------------------------- slots

    def expect_scalar(self, expr: ast.Expr, dim: Dim, what: str) -> float:
        """The SI value of ``expr``, which must be a number of dimension ``dim``.

        Args:
            expr: The expression.
            dim: The slot's dimension; a bare number is read in its SI unit.
            what: The slot, for messages (``"FORCE"``).
        """
        if type(expr) is ast.Number:  # most slots: a number as written, no Scalar made
            number, number_dim = self._number_value(expr)
            if number_dim is None or number_dim == dim:
                return self._in_range(expr, dim, what, number)
        value = self.evaluate(expr)
        if not isinstance(value, Scalar):
            raise ProgramError(
                f"{what} needs {units.describe(dim)}, like {units.example(dim)}; "
                f"{self.text_of(expr.span)} is {kind_of(value)}",
                expr.span,
            )
        if value.dim is not None and value.dim != dim:
            raise ProgramError(
                f"{what} needs {units.describe(dim)}, like {units.example(dim)}; "
                f"{self.text_of(expr.span)} is {units.describe(value.dim)}",
                expr.span,
            )
        return self._in_range(expr, dim, what, value.value)

    def _in_range(self, expr: ast.Expr, dim: Dim, what: str, value: float) -> float:
        """``value``, if within the slot's physical range (:mod:`cosmos.lang.limits`)."""
        problem = limits.scalar_problem(what, dim, value, self.text_of(expr.span))
        if problem is not None:
            raise ProgramError(problem, expr.span)
        return value

    def expect_vector(self, expr: ast.Expr, value: Value, size: int, dim: Dim, what: str) -> FloatArray:
        """``value`` (of ``expr``) as a read-only (size,) SI array of dimension ``dim``."""
        return readonly(self._vector_values(expr, value, size, dim, what))

    def _vector_values(
        self, expr: ast.Expr, value: Value, size: int, dim: Dim, what: str
    ) -> tuple[float, ...]:
        """``expect_vector``'s checks; the vector's numbers as they are."""
        if not isinstance(value, Vec):
            raise ProgramError(
                f"{what} needs a vector of {size} {units.plural(dim)}, like "
                f"({', '.join([units.example(dim)] * size)}); "
                f"{self.text_of(expr.span)} is {kind_of(value)}",
                expr.span,
            )
        if len(value.values) != size:
            raise ProgramError(f"{what} needs {size} components, not {len(value.values)}", expr.span)
        if value.dim is not None and value.dim != dim:
            raise ProgramError(
                f"{what} needs {units.plural(dim)}; "
                f"{self.text_of(expr.span)} holds {units.plural(value.dim)}",
                expr.span,
            )
        problem = limits.vector_problem(what, dim, value.values, self.text_of(expr.span))
        if problem is not None:
            raise ProgramError(problem, expr.span)
        return value.values

    def expect_vector3(self, expr: ast.Expr, dim: Dim, what: str) -> FloatArray:
        """Evaluate ``expr`` as a vector of 3 components of dimension ``dim``."""
        return self.expect_vector(expr, self.evaluate(expr), 3, dim, what)

    def expect_position(self, expr: ast.Expr, what: str) -> FrameValue:
        """A position or frame: a 3-vector of lengths becomes a frame without orientation."""
        value = self.evaluate(expr)
        if isinstance(value, FrameValue):
            return value
        if isinstance(value, Scalar):
            raise ProgramError(
                f"{what} needs a position like (0.5, 0.1, 0.3) or a frame; "
                f"{self.text_of(expr.span)} is {kind_of(value)}",
                expr.span,
            )
        return FrameValue(self.expect_vector(expr, value, 3, units.LENGTH, what), None)


def _finite(value: Value) -> bool:
    if isinstance(value, Scalar):
        return math.isfinite(value.value)
    if isinstance(value, Vec):
        return all(map(math.isfinite, value.values))
    return all(map(math.isfinite, value.position.tolist()))


def suggest(name: str, known: Mapping[str, object]) -> str:
    """``"; did you mean 'hole'?"``, or the known names, for an unknown name."""
    close = difflib.get_close_matches(name.casefold(), list(known), n=1, cutoff=0.6)
    if close:
        return f"; did you mean '{close[0]}'?"
    if not known:
        return ""
    listed = sorted(known)
    more = ", ..." if len(listed) > 10 else ""
    return "; known names: " + ", ".join(listed[:10]) + more
