"""What a study section provides, and the registry of sections.

A study is its core tables (name, cases, gusts, ``[grid]``, ``[sweep]``, ``[methods]``, ``[simulation]``, ``[cfd]``,
``[report]``: :mod:`studies.config`) and its *sections*. A section is one part of the work, from its table in the
study file to its part of the report page: the paper's gust-ROM pipeline (:mod:`studies.sections.gust_rom`, steady
flow, FRF, LTD, ROM and ROM-simulation pieces, always on), ``[aeroelastic]`` (:mod:`studies.sections.aeroelastic`)
and ``[nonlinear]`` (:mod:`studies.sections.nonlinear`). The four stages of a study iterate over the registered
sections and name none of them:

====================================== =============================================================================
stage                                  what it asks of each section
====================================== =============================================================================
:func:`studies.config.parse_study`     :attr:`Section.table` and :meth:`Section.parse` (its table -> options object)
:func:`studies.run.runner.run_study`   :attr:`Section.pieces` (store kinds), :meth:`Section.width`,
                                       :meth:`Section.plan` (the :class:`Task` s that compute what the store lacks)
:func:`studies.store.load_results`     :meth:`Section.read` (what the store holds, what is missing, what failed)
:func:`studies.report.make_report`     :meth:`Section.template_tables`, :meth:`Section.report` (its part of the
                                       page, with its tables and figures)
====================================== =============================================================================

A new section is a subclass of :class:`Section` registered with :func:`register`: the built-in ones by the package
:mod:`studies.sections` (:data:`studies.sections.BUILTIN`), others by an entry point of the group
:data:`ENTRY_POINT_GROUP` (``[project.entry-points."lfdrom.sections"] name = "package.module:SECTION"``) or by a
direct :func:`register` call (tests). Sections are loaded once, on first use (:func:`sections`).

Pieces and keys
---------------
A section's results are stored piece by piece in the study's :class:`studies.store.cache.ResultStore`: each
:class:`PieceKind` names a store folder, the packages and modules whose sources enter its keys, and the arrays an
entry must hold. Its keys are the canonical JSON of a sub-configuration that the section builds (only what changes
the piece) and the code version of those sources.

Tasks and their order
---------------------
:meth:`Section.plan` returns :class:`Task` s: a top-level function (picklable, for process pools and Dask) with its
arguments, which stores pieces and returns one report per piece (:func:`studies.run.compute.piece_report`). A task
waits for the tasks it names: ``after`` (ended, whatever the outcome) and ``needs_ok`` (ended with their first
piece ok, else this task is skipped, and so are the tasks that wait for it). Names are :attr:`Task.ids`, shared by
convention between sections (``"steady:T2"``: the steady flow of case T2, :func:`step_id`); a name that no planned
task carries is satisfied (its pieces are stored). Tasks that become ready together start in the order of
(the position of their case in the study, :attr:`Task.priority`, the plan's order).
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Optional

__all__ = [
    "ENTRY_POINT_GROUP",
    "PieceKind",
    "Task",
    "Plan",
    "StudyTables",
    "SectionRead",
    "ReportContext",
    "Section",
    "SectionError",
    "register",
    "unregister",
    "sections",
    "section",
    "section_names",
    "active_sections",
    "piece_kinds",
    "step_id",
]

ENTRY_POINT_GROUP = "lfdrom.sections"
"""Entry-point group of sections installed by other distributions."""


class SectionError(ValueError):
    """A section that cannot be registered: a name or table taken by another section, a piece kind declared
    twice, an object that is not a :class:`Section`."""


@dataclass(frozen=True)
class PieceKind:
    """A kind of stored piece.

    Attributes
    ----------
    name : str
        The store's folder and the kind's name (``"frf"``): a short lower-case name.
    dependencies : tuple of str
        Packages and modules (dotted names) whose Python sources enter every key of this kind
        (:func:`studies.store.provenance.code_version`): editing them recomputes the pieces.
    arrays : tuple of str
        Arrays an entry that is not a failure must hold (an entry without them is treated as corrupted).
    """

    name: str
    dependencies: tuple
    arrays: tuple = ()


@dataclass(frozen=True)
class Task:
    """One unit of work of a run (see the module docstring).

    Attributes
    ----------
    kind : str
        What messages call the task (``"frf"``); a task that fails outside its pieces is reported as
        ``"<kind> task of <case> failed: ..."``.
    case : str
        The case (or other subject) the task is about, for messages and ordering.
    fn : callable
        A top-level function ``fn(*args) -> list of dict`` (one report per piece stored).
    args : tuple
    progress_key : str or None
        The key of the task's progress line (:func:`studies.run.progress.task_key`).
    ids : tuple of str
        Names other tasks wait for (several tasks may share one: waiting for it waits for all of them).
    after : tuple of str
        Names of tasks that must have ended first, whatever their outcome.
    needs_ok : tuple of str
        Names of tasks whose first piece must be ok; otherwise this task is skipped.
    priority : int
        Among tasks that become ready together, for the same case, lower starts first (the built-in sections:
        steady 0, motion FRF 10, flutter 20, LTD 30, FRF 40, ROMs 50, nonlinear marches 60).
    failure_note : str or None
        Said when the task's first piece is not ok (e.g. what is skipped because of it).
    """

    kind: str
    case: str
    fn: Callable
    args: tuple
    progress_key: Optional[str] = None
    ids: tuple = ()
    after: tuple = ()
    needs_ok: tuple = ()
    priority: int = 100
    failure_note: Optional[str] = None


@dataclass(frozen=True)
class Plan:
    """What a section's part of a run computes.

    Attributes
    ----------
    tasks : tuple of Task
    cfd_pieces : int
        CFD pieces to compute (counted in the run's first line and its progress total).
    rom_pieces : int
        Other pieces to compute, an upper bound (pieces of failed CFD are skipped).
    """

    tasks: tuple = ()
    cfd_pieces: int = 0
    rom_pieces: int = 0


@dataclass(frozen=True)
class StudyTables:
    """The study's core settings that a section's parser may check against (its cases, gusts, simulation).

    Attributes
    ----------
    cases : tuple of studies.config.schema.CaseSweep
    gusts : tuple of studies.config.cases.GustCase
    simulation : studies.config.schema.SimulationOptions
    cfd : studies.config.schema.CFDOptions
    methods : tuple of studies.config.schema.MethodOptions
        The identification variants (``[methods]``), for a section that picks one of the study's ROMs.
    M_base : int or None
        The computed frequency grid's intervals (``[sweep] M_base``).
    sections : tuple of (str, object)
        The options of the sections parsed before this one (in the order of :func:`sections`), as ``(name,
        options)`` pairs: a section that uses another's pieces checks up front that the study asks for them.
    """

    cases: tuple
    gusts: tuple
    simulation: Any
    cfd: Any
    methods: tuple = ()
    M_base: Optional[int] = None
    sections: tuple = ()

    def section(self, name: str) -> Any:
        """The options of an earlier-parsed section ``name``, or None when the study does not have it."""
        return dict(self.sections).get(name)


@dataclass(frozen=True)
class SectionRead:
    """What the store holds of a section (:meth:`Section.read`).

    Attributes
    ----------
    fields : dict
        Keyword fields of :class:`studies.store.results.StudyResults` this section fills (the gust-ROM section:
        ``frf``, ``ltd``, ``roms``, ``sims``, ``steady``).
    records : object, optional
        Anything else the section read; ``StudyResults.sections[name]``.
    missing : list of str
        Pieces not stored yet, ``"<kind> <case> ..."`` (entries of a case in ``unavailable`` are dropped by
        ``load_results``: they cannot be computed).
    failed : list of str
        Pieces that failed, with their error.
    unavailable : frozenset of str
        Cases whose pieces cannot be computed (e.g. their steady flow failed).
    """

    fields: dict = field(default_factory=dict)
    records: Any = None
    missing: list = field(default_factory=list)
    failed: list = field(default_factory=list)
    unavailable: frozenset = frozenset()


@dataclass(frozen=True)
class ReportContext:
    """Where and how a section writes its part of the report (:meth:`Section.report`).

    Attributes
    ----------
    results : studies.store.results.StudyResults
    out_dir : pathlib.Path
        Folder of ``tables/`` and ``figures/``.
    page_dir : pathlib.Path
        Folder of the page (links are relative to it).
    page_path : pathlib.Path
    figures : bool
        Draw figures (False: tables and text only).
    dpi : int
    say : callable
        ``say(text)``: progress messages.
    slots : dict
        Texts of the page's prose slots.
    title : str or None
    paper : bool or None
        Paper mode (None: the section decides).
    formats : tuple of str
        Table formats.
    redraw : bool
        Draw figures even when their cache says they are up to date.
    template_tables : dict
        ``name -> (rows, columns)``: the tables every active section offers to the prose's templates
        (:meth:`Section.template_tables`, :mod:`studies.report.numbers`).
    """

    results: Any
    out_dir: Any
    page_dir: Any
    page_path: Any
    figures: bool = True
    dpi: int = 120
    say: Callable = print
    slots: Mapping = field(default_factory=dict)
    title: Optional[str] = None
    paper: Optional[bool] = None
    formats: tuple = ("csv", "markdown", "latex")
    redraw: bool = False
    template_tables: Mapping = field(default_factory=dict)


class Section:
    """A study section (see the module docstring); subclass it and :func:`register` an instance.

    Attributes
    ----------
    name : str
        The section's name: the key of its options in ``StudyConfig.sections`` (``config.<name>`` reads them),
        of its records in ``StudyResults.sections``, and in messages.
    table : str or None
        Its table in the study file (``"aeroelastic"`` for ``[aeroelastic]``); None for a section that is always
        on and reads the core tables (the gust-ROM pipeline).
    pieces : tuple of PieceKind
        The store kinds it computes.
    """

    name: str = ""
    table: Optional[str] = None
    pieces: tuple = ()

    # ---- the study file ----------------------------------------------------------------------------------
    def parse(self, table: Any, error: Callable[[str, str], Exception], study: StudyTables) -> Any:
        """Validate the section's table; returns its frozen options object (with a ``canonical()`` method: the
        hashable content, part of the study's hash).

        Parameters
        ----------
        table : object
            The TOML value of :attr:`table` (a dict when well formed).
        error : callable
            ``error(dotted_key, problem) -> StudyConfigError``; raise what it returns, with the key in full
            (``"aeroelastic.sections[0].mu"``) and, for unknown keys, a "did you mean" hint
            (:func:`studies.config.reader.did_you_mean`).
        study : StudyTables
            The study's cases, gusts and settings, for up-front checks (a case the section names must exist).
        """
        raise NotImplementedError(f"section {self.name!r} has a table but no parser")

    def describe(self, options: Any) -> str:
        """One or more indented lines for ``lfdrom show`` (default: none)."""
        return ""

    def active(self, config) -> bool:
        """Whether the study has this section: its table was given (always for a section without a table)."""
        return self.table is None or config.section(self.name) is not None

    # ---- the run -----------------------------------------------------------------------------------------
    def width(self, config) -> int:
        """Tasks of the section that can run at once at its widest stage (sizes ``workers="auto"``)."""
        return 0

    def plan(self, config, store, force: bool) -> Plan:
        """The tasks that compute what ``store`` lacks (everything when ``force``)."""
        return Plan()

    def summary(self, config, results) -> Optional[str]:
        """A few words for the run's last line (``"8/8 ROMs ok, 8 ROM simulations"``), or None."""
        return None

    # ---- reading and reporting ---------------------------------------------------------------------------
    def read(self, config, store) -> SectionRead:
        """What the store holds of the section; computes nothing."""
        return SectionRead()

    def has_results(self, results) -> bool:
        """Whether ``results`` hold anything of this section (a report of nothing is refused over a page)."""
        return False

    def template_tables(self, results) -> dict:
        """Tables the page's prose may quote (``name -> (rows, columns)``, :mod:`studies.report.numbers`);
        default none."""
        return {}

    def report(self, context: ReportContext) -> str:
        """The section's part of the Markdown page (writing its tables and figures under ``context.out_dir``)."""
        return ""


_REGISTRY: dict = {}
_LOADED = False


def _check(new: Section) -> None:
    if not isinstance(new, Section):
        raise SectionError(f"a section must be a studies.sections.protocol.Section, got {type(new).__name__}")
    if not new.name or not new.name.isidentifier() or new.name.startswith("_"):
        raise SectionError(f"section name {new.name!r} must be a Python identifier not starting with '_'")
    for other in _REGISTRY.values():
        if other.name == new.name:
            continue
        if new.table is not None and other.table == new.table:
            raise SectionError(f"section {new.name!r}: table [{new.table}] is section {other.name!r}'s")
        taken = {k.name for k in other.pieces} & {k.name for k in new.pieces}
        if taken:
            raise SectionError(f"section {new.name!r}: piece kind(s) {sorted(taken)} are section {other.name!r}'s")


def register(new: Section) -> Section:
    """Register a section (replacing one of the same name); returns it.

    Raises
    ------
    SectionError
        Not a :class:`Section`, a bad name, or a table or piece kind that another section has.
    """
    _check(new)
    _REGISTRY[new.name] = new
    return new


def unregister(name: str) -> None:
    """Remove a registered section (no error when there is none)."""
    _REGISTRY.pop(name, None)


def _load() -> None:
    """Import the built-in sections (they register themselves) and the entry points' ones, once."""
    global _LOADED
    if _LOADED:
        return
    _LOADED = True
    builtin = importlib.import_module("studies.sections")
    for module in builtin.BUILTIN:
        importlib.import_module(module)
    from importlib.metadata import entry_points

    for ep in entry_points(group=ENTRY_POINT_GROUP):
        obj = ep.load()
        register(obj() if isinstance(obj, type) else obj)


def sections() -> tuple:
    """The registered sections: the built-in ones first, in the order of :data:`studies.sections.BUILTIN` (whatever
    order their modules were imported in), then the others in registration order."""
    _load()
    builtin = list(importlib.import_module("studies.sections").BUILTIN)

    def rank(s):
        module = type(s).__module__
        return builtin.index(module) if module in builtin else len(builtin)

    return tuple(sorted(_REGISTRY.values(), key=rank))       # stable: the others keep their registration order


def section(name: str) -> Section:
    """The registered section called ``name``.

    Raises
    ------
    KeyError
        No such section.
    """
    _load()
    return _REGISTRY[name]


def section_names() -> tuple:
    """Names of the registered sections."""
    return tuple(s.name for s in sections())


def active_sections(config) -> tuple:
    """The registered sections that ``config`` has (:meth:`Section.active`), in registration order."""
    return tuple(s for s in sections() if s.active(config))


def piece_kinds() -> dict:
    """Every registered section's piece kinds: name -> :class:`PieceKind`, in registration order."""
    return {kind.name: kind for s in sections() for kind in s.pieces}


def step_id(step: str, case: str) -> str:
    """The conventional task name of a step of a case, ``"steady:T2"`` (see :attr:`Task.ids`)."""
    return f"{step}:{case}"
