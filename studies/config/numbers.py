"""Numbers of a study file: plain arithmetic strings (``"70/(2*pi)"``) and the 12-digit normal form.

Floats are normalised to 12 significant digits when read, so that ``"70/(2*pi)"`` and ``"70/2/pi"`` are the
same study and the values computed with are exactly the values hashed.
"""

from __future__ import annotations

import ast
import math
import numbers
import operator

__all__ = ["normalise_float", "parse_number"]


def normalise_float(x: float) -> float:
    """``x`` rounded to 12 significant digits (``-0.0`` -> ``0.0``): the form stored and hashed."""
    v = float(f"{float(x):.12g}")
    return 0.0 if v == 0.0 else v


_BINOPS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
           ast.Pow: operator.pow}
_UNOPS = {ast.UAdd: operator.pos, ast.USub: operator.neg}
_NAMES = {"pi": math.pi, "e": math.e, "tau": 2.0 * math.pi}


def parse_number(value) -> float:
    """A real number from a TOML value: a number, or a string of plain arithmetic.

    Strings may contain numbers, the names ``pi``, ``e`` and ``tau``, the operators ``+ - * / **`` and
    parentheses, e.g. ``"70/(2*pi)"``. Nothing else is evaluated (no calls, attributes or other names).

    Raises
    ------
    ValueError
        Anything else, a division by zero, an overflow or a non-finite result.
    """
    if isinstance(value, bool):
        raise ValueError(f"expected a number, got {value!r}")
    if isinstance(value, numbers.Real):
        v = float(value)
    elif isinstance(value, str):
        text = value.strip()
        if not text or len(text) > 100:
            raise ValueError(f"expected a number or a short arithmetic expression, got {value!r}")
        try:
            tree = ast.parse(text, mode="eval")
        except SyntaxError:
            raise ValueError(f"{value!r} is not an arithmetic expression (e.g. \"70/(2*pi)\")") from None

        def ev(node) -> float:
            if isinstance(node, ast.Expression):
                return ev(node.body)
            if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) \
                    and not isinstance(node.value, bool):
                return float(node.value)
            if isinstance(node, ast.Name) and node.id in _NAMES:
                return _NAMES[node.id]
            if isinstance(node, ast.BinOp) and type(node.op) in _BINOPS:
                return _BINOPS[type(node.op)](ev(node.left), ev(node.right))
            if isinstance(node, ast.UnaryOp) and type(node.op) in _UNOPS:
                return _UNOPS[type(node.op)](ev(node.operand))
            raise ValueError(f"{value!r}: only numbers, pi, e, tau, + - * / ** and parentheses are allowed")

        try:
            v = ev(tree)
        except ZeroDivisionError:
            raise ValueError(f"{value!r} divides by zero") from None
        except OverflowError:
            raise ValueError(f"{value!r} overflows") from None
        if isinstance(v, complex):
            raise ValueError(f"{value!r} is not a real number")
    else:
        raise ValueError(f"expected a number or an arithmetic string, got {type(value).__name__} {value!r}")
    if not math.isfinite(v):
        raise ValueError(f"{value!r} is not finite")
    return v
