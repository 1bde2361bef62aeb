"""Errors and field checks of case definitions: real numbers, integers, names and NACA codes.

The checks raise :class:`CaseError` with the owner and field in the message; :class:`UnknownCaseError` is what a
catalogue lookup (:mod:`studies.config.cases`) raises for a name it does not hold.
"""

from __future__ import annotations

import math
import numbers
import re

__all__ = ["CaseError", "UnknownCaseError", "check_real", "check_integer", "check_name", "naca_code"]


class CaseError(ValueError):
    """A test or gust case definition is invalid (bad NACA code, Mach out of range, bad gust...).

    Attributes
    ----------
    field : str or None
        The field that is wrong (``"length"``, ``"name"``...) where the check knows it, for the study file's key.
    """

    def __init__(self, message, field=None):
        super().__init__(message)
        self.field = field


class UnknownCaseError(CaseError, KeyError):
    """A case name is not in the catalogue. Subclasses ``KeyError`` (and ``ValueError``).

    Attributes
    ----------
    name : str
        The name that was looked up.
    known : tuple of str
        The names in the catalogue.
    """

    def __init__(self, kind: str, name: object, known):
        self.name = name
        self.known = tuple(known)
        msg = (f"unknown {kind} {name!r}; known {kind}s: {', '.join(self.known)} "
               "(names are case-insensitive)")
        super().__init__(msg)
        self.message = msg

    def __str__(self) -> str:  # KeyError would otherwise quote the message
        return self.message


def check_real(owner: str, name: str, value) -> float:
    """A finite real number (not a bool), as a float.

    Parameters
    ----------
    owner : str
        What it belongs to (e.g. ``"case 'mine'"``, ``"grid"``), for the error message.
    name : str
        The field's name, for the error message.
    value : any

    Returns
    -------
    float

    Raises
    ------
    CaseError
        Not a finite real number.
    """
    if isinstance(value, bool):
        raise CaseError(f"{owner}: {name} must be a real number, got {value!r}", name)
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise CaseError(f"{owner}: {name} must be a real number, got {value!r}", name) from None
    if not math.isfinite(v):
        raise CaseError(f"{owner}: {name} must be finite, got {value!r}", name)
    return v


def check_integer(owner: str, name: str, value) -> int:
    """An integer (not a bool), as an int.

    Parameters
    ----------
    owner : str
        What it belongs to (e.g. ``"grid"``), for the error message.
    name : str
        The field's name, for the error message.
    value : any

    Returns
    -------
    int

    Raises
    ------
    CaseError
        Not an integer.
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise CaseError(f"{owner}: {name} must be an integer, got {value!r}")
    return int(value)


_NAME_RE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.+\-]*$")


def check_name(owner: str, name) -> str:
    """A case, gust or method name checked: letters, digits and ``_ . + -`` (it names files and table rows).

    Parameters
    ----------
    owner : str
        What is named (``"case"``, ``"gust"``, ``"method"``), for the error message.
    name : any

    Returns
    -------
    str
        ``name``.

    Raises
    ------
    CaseError
        Not such a string.
    """
    if not isinstance(name, str) or not _NAME_RE.match(name):
        raise CaseError(
            f"{owner} name {name!r} must be a non-empty string of letters, digits and _ . + - "
            "(it names files and table rows), e.g. 'naca0012-m05'", "name")
    return name


def naca_code(owner: str, code) -> str:
    """A NACA 4-digit code checked by ``cfd.naca``.

    Parameters
    ----------
    owner : str
        What it belongs to (e.g. ``"case 'mine'"``), for the error message.
    code : str or int
        ``"0012"``, ``"NACA 0012"`` or ``12``.

    Returns
    -------
    str
        The four digits, e.g. ``"0012"``.

    Raises
    ------
    CaseError
        Not a valid code.
    """
    from cfd.mesh.geometry import naca  # the submodule: works even where the cfd package namespace is bare

    try:
        naca(code)
    except ValueError as e:  # cfd.GeometryError
        raise CaseError(f"{owner}: {e}") from None
    if isinstance(code, int):
        return f"{code:04d}"
    return str(code).strip().upper().removeprefix("NACA").strip()
