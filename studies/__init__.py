"""lfdrom.studies: case catalogue, study files, runner, results store and reports.

Entry points: :func:`run_study` (compute what a study's store lacks, return its results) and
:func:`load_results` (read a study's results from its store, computing nothing). They are imported on first
use, so that ``import studies`` (and ``lfdrom cases``) stays light.
"""

from .legacy import install as _install_legacy_paths

__all__ = ["run_study", "load_results"]

_install_legacy_paths()


def __getattr__(name):
    if name == "run_study":
        from .run.runner import run_study

        return run_study
    if name == "load_results":
        from .store.results import load_results

        return load_results
    raise AttributeError(f"module 'studies' has no attribute {name!r}")
