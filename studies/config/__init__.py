"""Study files (TOML) -> a validated, frozen :class:`StudyConfig` (the first stage of a study).

- :mod:`studies.config.study`: :func:`load_study` / :func:`parse_study`, the study file's core tables (cases,
  gusts, sweep, methods, simulation, cfd, report) and, through :mod:`studies.sections`, each registered section's
  table;
- :mod:`studies.config.reader`: typed values, allowed keys and "did you mean" errors (:class:`StudyConfigError`);
- :mod:`studies.config.entries`: case entries and ``[report]``;
- :mod:`studies.config.schema`: the frozen configuration objects and limits;
- :mod:`studies.config.cases` (with ``case_fields``, ``case_types``, ``grid_spec``): the paper's test cases and
  gusts and user cases;
- :mod:`studies.config.numbers`, :mod:`studies.config.hashing`: number parsing and canonical JSON.

The names of :mod:`studies.config.study` (what ``studies.config`` was before it became a package) are read here
on first use, so that ``import studies.config.cases`` stays light.
"""

import importlib
import pkgutil

__all__ = ['StudyConfigError', 'StudyConfig', 'CaseSweep', 'MethodOptions', 'SimulationOptions', 'CFDOptions',
           'ReportOptions', 'SweepPoint', 'load_study', 'loads_study', 'parse_study', 'as_config', 'parse_number',
           'normalise_float', 'canonical_json', 'config_hash', 'max_order', 'T_PAPER', 'T_RANGE', 'MAX_STEPS', 'MAX_M',
           'min_order', 'march_memory_bytes',
           'TOP_KEYS', 'GRID_KEYS', 'SWEEP_KEYS', 'CASE_KEYS', 'GUST_KEYS', 'METHOD_KEYS', 'SIMULATION_KEYS',
           'CFD_KEYS', 'REPORT_KEYS']


def __getattr__(name):
    # not for the package's own modules: ``from . import plots`` inside it must import the module, not this
    if name.startswith("_") or name in {m.name for m in pkgutil.iter_modules(__path__)}:
        raise AttributeError(f"module 'studies.config' has no attribute {name!r}")
    try:
        return getattr(importlib.import_module("studies.config.study"), name)
    except AttributeError:
        raise AttributeError(f"module 'studies.config' has no attribute {name!r}") from None
