"""The vocabulary of a study file and the typed reading of its values.

The keys each table allows, the names people reach for instead (for "did you mean"), :class:`StudyConfigError`
(names the file and the dotted key) and :class:`ConfigReader`, which reads one value at a time and raises that
error. :mod:`studies.config` parses a whole study file with them.
"""

from __future__ import annotations

import difflib
import re
from typing import Mapping, Optional

from .case_fields import CaseError
from .numbers import normalise_float, parse_number

__all__ = [
    "StudyConfigError",
    "ConfigReader",
    "did_you_mean",
    "table_array",
    "grid_config_error",
    "TOP_KEYS",
    "GRID_KEYS",
    "SWEEP_KEYS",
    "CASE_KEYS",
    "GUST_KEYS",
    "METHOD_KEYS",
    "SIMULATION_KEYS",
    "CFD_KEYS",
    "REPORT_KEYS",
]

# the keys each table of a study file allows (the schema is in the docstring of studies.config.study); the
# registered sections add their own top-level tables (studies.sections.protocol.Section.table)
TOP_KEYS = ("name", "description", "output", "store", "cases", "gusts", "grid", "sweep", "method", "methods",
            "simulation", "cfd", "report")
GRID_KEYS = ("ni", "nj", "n_surface", "farfield")
SWEEP_KEYS = ("orders", "T", "M_base", "M")
CASE_KEYS = ("name", "naca", "mach", "alpha_deg", "grid", "orders", "T", "M")
GUST_KEYS = ("name", "kind", "length", "angle_deg")
METHOD_KEYS = ("dc_gain", "stable", "margin", "weights", "algorithm")
SIMULATION_KEYS = ("discretisation", "dt", "t_end", "x0", "scheme")
CFD_KEYS = ("gust_method", "outputs")
REPORT_KEYS = ("page", "prose", "figures", "title", "paper")

# names people reach for, mapped to ours (used for "did you mean" only)
_ALIASES = {
    "n_r": "orders", "nr": "orders", "order": "orders", "rom_order": "orders", "n_omega": "M",
    "m": "M", "t": "T", "period": "T", "mbase": "M_base", "m_base": "M_base", "discretization": "discretisation",
    "method": "algorithm", "dc": "dc_gain", "stability": "stable", "weight": "weights", "alpha": "alpha_deg",
    "angle": "angle_deg", "gust": "gusts", "case": "cases", "out": "output", "output_dir": "output",
    "cache": "store", "tend": "t_end", "t_final": "t_end", "mach_number": "mach", "aerofoil": "naca",
    "airfoil": "naca",
}


class StudyConfigError(ValueError):
    """A study file is invalid. Names the file and the dotted key.

    Attributes
    ----------
    file : str
        The study file (or ``"<string>"``).
    key : str or None
        Dotted key, e.g. ``"sweep.orders"`` or ``"cases[1].mach"``; None for file-level problems.
    problem : str
        What was wrong and what to do.
    """

    def __init__(self, file: str, key: Optional[str], problem: str):
        self.file = str(file)
        self.key = key
        self.problem = problem
        where = f"{self.file}: {key}: " if key else f"{self.file}: "
        super().__init__(where + problem)


class ConfigReader:
    """Reads the values of one study file, raising :class:`StudyConfigError` with the file and the dotted key.

    Parameters
    ----------
    source : str
        The study file's name, for the errors.

    Each reader method takes the value and its dotted key (e.g. ``"sweep.orders"``) and returns the value checked
    (and normalised: numbers to 12 significant digits, axes sorted and de-duplicated).
    """

    def __init__(self, source: str):
        self.source = source

    def err(self, key, problem):
        """A :class:`StudyConfigError` naming this reader's file and ``key`` (to raise)."""
        return StudyConfigError(self.source, key, problem)

    def table(self, value, key) -> dict:
        """``value`` checked to be a table (dict)."""
        if not isinstance(value, dict):
            raise self.err(key, f"must be a table, got {type(value).__name__} {value!r}")
        return value

    def check_keys(self, table: Mapping, allowed, prefix: str):
        """Refuse a key of ``table`` that is not in ``allowed``, with a "did you mean" and the allowed keys."""
        for k in table:
            if k not in allowed:
                key = f"{prefix}.{k}" if prefix else k
                raise self.err(key, f"unknown key{did_you_mean(k, allowed)}; allowed here: {', '.join(allowed)}")

    def number(self, value, key, *, positive=False, nonneg=False) -> float:
        """A number or arithmetic string (:func:`studies.config.numbers.parse_number`), normalised to 12 digits."""
        try:
            v = parse_number(value)
        except ValueError as e:
            raise self.err(key, str(e)) from None
        if positive and v <= 0.0:
            raise self.err(key, f"must be positive, got {v!r}")
        if nonneg and v < 0.0:
            raise self.err(key, f"must be >= 0, got {v!r}")
        return normalise_float(v)

    def integer(self, value, key, *, minimum=None) -> int:
        """An integer (not a bool), at least ``minimum`` when given."""
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.err(key, f"must be an integer, got {value!r}")
        if minimum is not None and value < minimum:
            raise self.err(key, f"must be >= {minimum}, got {value}")
        return int(value)

    def choice(self, value, key, options) -> str:
        """One of the strings ``options``."""
        if not isinstance(value, str) or value not in options:
            raise self.err(key, f"must be one of {', '.join(repr(o) for o in options)}, got {value!r}"
                           f"{did_you_mean(value, options) if isinstance(value, str) else ''}")
        return value

    def boolean(self, value, key) -> bool:
        """``true`` or ``false``."""
        if not isinstance(value, bool):
            raise self.err(key, f"must be true or false, got {value!r}")
        return value

    def string(self, value, key) -> str:
        """A string."""
        if not isinstance(value, str):
            raise self.err(key, f"must be a string, got {value!r}")
        return value

    def axis(self, value, key, parse_one) -> tuple:
        """A sweep axis: one value or a non-empty list, each read by ``parse_one(value, key)``; sorted. A value
        given twice (after reading: ``"70/(2*pi)"`` and ``11.140846016432674`` are one T) is refused: a study
        file that lists it twice most likely meant another value."""
        if not isinstance(value, list):
            value = [value]
        if not value:
            raise self.err(key, "must not be empty")
        vals = [parse_one(v, f"{key}[{i}]") for i, v in enumerate(value)]
        for i, v in enumerate(vals):
            if vals.index(v) != i:
                raise self.err(f"{key}[{i}]", f"{value[i]!r} is {key}[{vals.index(v)}] again ({v!r}); give each value "
                                              "once")
        return tuple(sorted(vals))


def did_you_mean(word: str, options) -> str:
    """``" (did you mean 'x'?)"`` for the option ``x`` that ``word`` most likely meant, else ``""``.

    Tries the names people reach for (``n_r`` -> ``orders``), then the case, then a close spelling.
    """
    options = list(options)
    alias = _ALIASES.get(word.lower())
    if alias in options:
        return f" (did you mean {alias!r}?)"
    low = {o.lower(): o for o in options}
    if word.lower() in low:
        return f" (did you mean {low[word.lower()]!r}?)"
    close = difflib.get_close_matches(word, options, n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


def table_array(error, value, key: str, *, most: Optional[int] = None) -> list:
    """``value`` checked to be a TOML array of tables (``[[key]]``): a non-empty list of tables (dicts).

    A single table is refused, not taken for a list of one: ``sections = {name = "w"}`` or ``[aeroelastic.sections]``
    (single brackets) read as one table, and an incomplete one was then reported as a missing key of
    ``sections[0]``, which the study file does not have.

    Parameters
    ----------
    error : callable
        ``error(dotted_key, problem) -> Exception`` (:meth:`ConfigReader.err` or a section's error factory).
    value
        The parsed TOML value.
    key : str
        Its dotted key, e.g. ``"aeroelastic.sections"``; the entries are ``key[i]``.
    most : int, optional
        The most entries allowed.

    Raises
    ------
    StudyConfigError
        At ``key`` (not an array, a single table, empty, too long) or ``key[i]`` (an entry that is not a table),
        saying to write each entry under its own ``[[key]]``.
    """
    name = key.rsplit(".", 1)[-1]
    how = f"start each entry with its own [[{key}]] line (double brackets) followed by its keys"
    if isinstance(value, dict):
        raise error(key, f"must be an array of tables, got a single table {value!r} ({name} = {{...}} or "
                         f"[{key}] in single brackets): {how}")
    if not isinstance(value, list):
        raise error(key, f"must be an array of tables ([[{key}]]), got {type(value).__name__} {value!r}: {how}")
    if not value:
        raise error(key, f"is empty: give at least one [[{key}]] table")
    if most is not None and len(value) > most:
        raise error(key, f"has {len(value)} tables, at most {most} are allowed: give at most {most} [[{key}]]")
    for i, entry in enumerate(value):
        if not isinstance(entry, dict):
            raise error(f"{key}[{i}]", f"must be a table, got {type(entry).__name__} {entry!r}: {how}")
    return value


def grid_config_error(P: ConfigReader, prefix: str, e: CaseError) -> StudyConfigError:
    """A :class:`studies.config.cases.GridSpec` error as a :class:`StudyConfigError` at the grid key it names.

    Parameters
    ----------
    P : ConfigReader
    prefix : str
        The dotted key of the grid table (``"grid"`` or ``"cases[1].grid"``).
    e : CaseError
        The error of ``GridSpec``; ``"grid: nj = ..."`` becomes key ``prefix.nj``.
    """
    msg = str(e).removeprefix("grid: ")
    m = re.match(r"(ni|nj|n_surface|farfield)\b", msg)
    return P.err(f"{prefix}.{m.group(1)}" if m else prefix, msg)
