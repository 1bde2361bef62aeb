"""lfdrom.studies: study files, the runner, the results store, the reports and the ``lfdrom`` command line.

A study flows through four stages, one sub-package each, top to bottom::

    study.toml -> studies.config -> studies.run -> studies.store -> studies.report -> page, tables, figures
                  parse_study       run_study      ResultStore,      make_report
                  -> StudyConfig    (tasks on an   load_results
                                    executor)      -> StudyResults

None of the stages names a part of a study: each iterates over the registered *sections*
(:mod:`studies.sections.protocol`), each in its own folder, ``studies/sections/<name>/`` (its table, pieces,
plan, tasks, reader and report part): the paper's gust-ROM pipeline (:mod:`studies.sections.gust_rom`),
``[aeroelastic]`` and ``[nonlinear]``. :mod:`studies.cli` is the command line on top of them. The map of all
packages is docs/architecture.md.

Entry points: :func:`run_study` (compute what a study's store lacks, return its results) and
:func:`load_results` (read a study's results from its store, computing nothing). They are imported on first
use, so that ``import studies`` (and ``lfdrom cases``) stays light. The module paths of the flat package before
this layout (``studies.runner``, ``studies.pieces``, ...) still import, with a ``DeprecationWarning``
(:mod:`studies.legacy`).
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
