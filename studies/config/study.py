"""Study files (TOML) -> a validated, frozen :class:`StudyConfig`.

A study file names the test cases and gusts, the sweep axes of the identification (model order
``N_r``, sampling period ``T`` of the bilinear map, number of frequencies ``N_omega = M + 1`` by
subsampling a base grid of ``M_base`` intervals), the identification variants and the simulation
settings. Everything is checked here, before any computation: unknown keys, bad values and sweep
points that the identification cannot support (an order too large for ``N_omega``) raise one typed
error, :class:`StudyConfigError`, that names the file and the dotted key.

Schema (every key optional unless marked; see ``studies/demo.toml`` and ``studies/paper.toml``)::

    name = "demo"                  # default: the file's stem
    description = "..."            # free text (not part of the hash)
    output = "../results/demo"     # relative to the study file's folder (not empty, nor /);
                                   # default results/<name> there
    store = "../results/store"     # results store (studies.store.cache), relative like output (not the study
                                   # file's folder, nor /; studies may share one); default <output>/store
    cases = ["T2", {name = "T5", orders = [25, 55]},
             {name = "mine", naca = "0012", mach = 0.5, alpha_deg = 1.0, grid = {nj = 48}}]   # required
    gusts = ["G3", "G6", {name = "g2c", kind = "one_minus_cosine", length = 2.0, angle_deg = 1.0}]

    [grid]          # overrides of the paper grid (181 x 60, 100 on the wall, R = 25) for every case
    ni = 181; nj = 60; n_surface = 100; farfield = 25.0

    [sweep]
    orders = [9, 15, 25]           # N_r, positive integers (required here or in every case)
    T = ["70/(2*pi)"]              # numbers or arithmetic strings (numbers, pi, e, + - * / **, parentheses)
    M_base = 256                   # intervals of the computed FRF grid (a power of two, >= 4)
    M = [256, 32]                  # subsampled grids: powers of two dividing M_base, >= 2; default [M_base]

    [methods.plain]                # identification variants, by name; [method] is short for [methods.default]
    dc_gain = "none"               # "none" | "match" (or false | true)
    stable = false                 # enforce spectral radius < 1 - margin
    margin = 1e-3
    weights = "none"               # "none" | "inverse_magnitude"
    algorithm = "auto"             # "auto" | "relocation" | "subspace" | "mckelvey1" | "mckelvey2":
                                   # auto = sysid.identify's default (pole relocation with the DC gain or
                                   # stability, else the paper's McKelvey subspace); mckelvey1/2 = subspace
                                   # with that algorithm

    [simulation]                   # gust responses: ROM against LTD
    discretisation = "tustin"      # re-discretisation of the continuous ROM at dt: "tustin" | "zoh"
    dt = 0.02                      # LTD time step (convective time)
    t_end = 40.0                   # final time
    x0 = -2.0                      # gust front at s = 0 (chords, <= cfd.gust.X0_MAX)

    [cfd]
    gust_method = "svm"            # "svm" | "fvm"
    outputs = ["Cl", "Cm"]         # subset of Cl, Cm, Cd

    [report]                       # what `lfdrom run` (at its end) and `lfdrom report` write
    page = "../docs/study.md"      # the Markdown page (relative to the study file; ends in .md); its tables and
                                   # figures go to the folder of the same name (docs/study/); default
                                   # <output>/report.md with <output>/tables, <output>/figures
    prose = "study-prose.toml"     # texts of the page's prose slots (slot = "text"); slots in the page are kept
    figures = true                 # false: tables and page only
    title = "..."                  # the page's title (default from the study's name)
    paper = true                   # paper mode: captions name the paper's figures, slots quote its claims
                                   # (default: on when a case is one of T1-T6)

Each registered section with a table (:mod:`studies.sections.protocol`: ``[aeroelastic]``, ``[nonlinear]``, ...)
parses its own table after the core ones, with the study's cases, gusts and settings at hand for its up-front
checks; its options are ``StudyConfig.sections`` (``config.aeroelastic``).

A case entry may override ``orders``, ``T`` and ``M`` (replacing the ``[sweep]`` axis for that case) and
``grid`` (on top of ``[grid]``). Axes are sorted and de-duplicated. List positions in keys are 0-based
(``cases[1].mach``).

Floats are normalised to 12 significant digits when read (so ``"70/(2*pi)"`` and ``"70/2/pi"`` are the same
study, and the values computed with are exactly the values hashed). :meth:`StudyConfig.canonical_json` is the
hashable form (sorted keys; paths and description left out); the ``*_piece`` functions give the
sub-configurations that key each cached piece (steady flow, FRF, ROM, LTD and ROM histories), so that
changing ``N_r`` keeps the FRF.
"""

from __future__ import annotations

import importlib
import math
import tomllib
import warnings
from dataclasses import replace
from pathlib import Path
from typing import Any, Mapping

from sysid.order_limits import max_order, min_order, order_supported

from .cases import GUST_CASES, CaseError, GridSpec, GustCase, UnknownCaseError, check_name, gust_case
from .reader import (
    CASE_KEYS,
    CFD_KEYS,
    GRID_KEYS,
    GUST_KEYS,
    METHOD_KEYS,
    REPORT_KEYS,
    SIMULATION_KEYS,
    SWEEP_KEYS,
    TOP_KEYS,
    ConfigReader,
    StudyConfigError,
    grid_config_error,
)
from .entries import parse_case_entry, parse_report_table
from .hashing import canonical_json, config_hash
from .numbers import normalise_float, parse_number
from ..sections.protocol import StudyTables, sections
from .schema import (
    ALGORITHMS,
    DISCRETISATIONS,
    LTD_SCHEMES,
    GUST_METHODS,
    MAX_M,
    MAX_STEPS,
    MIN_GUST_STEPS,
    OUTPUTS,
    T_PAPER,
    T_RANGE,
    WEIGHTS,
    CaseSweep,
    CFDOptions,
    MethodOptions,
    ReportOptions,
    SimulationOptions,
    StudyConfig,
    SweepPoint,
)

__all__ = [
    "StudyConfigError",
    "StudyConfig",
    "CaseSweep",
    "MethodOptions",
    "SimulationOptions",
    "CFDOptions",
    "ReportOptions",
    "SweepPoint",
    "load_study",
    "loads_study",
    "parse_study",
    "as_config",
    "parse_number",
    "normalise_float",
    "canonical_json",
    "config_hash",
    "max_order",
    "T_PAPER",
    "T_RANGE",
    "MAX_STEPS",
    "MAX_M",
    "min_order",
    "march_memory_bytes",
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
# The names above that this module does not define are re-exported from their homes: studies.config.reader
# (StudyConfigError and the keys each table allows), studies.config.schema (the configuration objects and limits),
# studies.config.numbers, studies.config.hashing and sysid.order_limits (max_order, min_order).
# studies.config.reader reads the values and studies.config.entries the case entries and [report]. The piece keys
# (steady_piece, frf_piece, ...) are the gust-ROM section's (studies.sections.gust_rom.pieces); read here they
# still work, with a DeprecationWarning (__getattr__ below).

_PIECE_KEYS = ("steady_piece", "frf_piece", "rom_piece", "ltd_piece", "sim_piece")


def __getattr__(name):
    if name in _PIECE_KEYS:
        warnings.warn(f"studies.config.{name} moved to studies.sections.gust_rom.pieces.{name}: import it from "
                      "there (the old name is kept for one release)", DeprecationWarning, stacklevel=2)
        return getattr(importlib.import_module("studies.sections.gust_rom.pieces"), name)
    raise AttributeError(f"module 'studies.config.study' has no attribute {name!r}")


def march_memory_bytes(steps: int, gusts: int) -> tuple:
    """Memory the LTD march and the ROM simulations of one case hold for ``steps`` time steps.

    The march keeps the time grid and three load histories per gust (``cfd.ltd_responses``); each stored
    history has five arrays (time, input, Cl, Cm, Cd), and a ROM simulation (FFT convolution of the Markov
    parameters, ``sysid.simulate.rom_simulation``) about four complex arrays of twice the length. Returns
    ``(bytes, formula)``: an estimate that is right to a factor of two, enough to refuse what cannot fit.
    """
    n = steps + 1
    return 8 * n * (1 + 3 * gusts + 5 * gusts + 16), "8 (steps + 1) (8 gusts + 17) bytes"


def _size_text(gib: float) -> str:
    return f"{gib * 1024:.3g} MiB" if gib < 1 else (f"{gib:.3g} GiB" if gib < 1024 else f"{gib / 1024:.3g} TiB")


def _is_pow2(n: int) -> bool:
    return n >= 1 and n & (n - 1) == 0


# ---------------------------------------------------------------------------------------------
# Parsing
# ---------------------------------------------------------------------------------------------

def load_study(path) -> StudyConfig:
    """Read and validate a study file.

    Parameters
    ----------
    path : path-like
        A TOML study file. Relative ``output`` and ``store`` are taken from its folder.

    Returns
    -------
    StudyConfig

    Raises
    ------
    StudyConfigError
        Missing or unreadable file, a folder (the message names the ``.toml`` file when the folder holds one),
        TOML syntax, unknown keys, bad values, impossible sweep points.
    """
    path = Path(path)
    if path.is_dir():
        raise StudyConfigError(str(path), None, _folder_problem(path))
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise StudyConfigError(str(path), None, "no such study file; give the path of a .toml study "
                               "(examples: studies/demo.toml, studies/paper.toml)") from None
    except (OSError, UnicodeDecodeError) as e:
        raise StudyConfigError(str(path), None, f"cannot read the study file: {e}") from None
    return loads_study(text, source=str(path), base_dir=path.resolve().parent, default_name=path.stem)


def _folder_problem(folder: Path) -> str:
    """What to say of a folder given as the study file: give the ``.toml`` file, naming the folder's own."""
    try:
        found = sorted(p.name for p in folder.glob("*.toml") if p.is_file())
    except OSError:   # an unreadable folder: say what to give all the same
        found = []
    text = "is a folder, not a study file; give the path of the .toml study file"
    if len(found) == 1:
        return f"{text}: {folder / found[0]}"
    if found:
        shown = ", ".join(found[:5]) + (f" and {len(found) - 5} more" if len(found) > 5 else "")
        return f"{text} (this folder holds {len(found)}: {shown})"
    return f"{text} (this folder holds none; examples: studies/demo.toml, studies/paper.toml)"


def _check_output(P: ConfigReader, text: str, output_dir: Path, study_folder: Path | None, name: str) -> None:
    """Refuse an ``output`` that is empty or the filesystem root.

    The run writes its report, tables, figures, run log and (by default) the results store into ``output``. An
    empty ``output`` is a slip (it resolved to the study file's folder without saying so: write ``"."`` for that)
    and ``"/"`` puts all of it into the root. ``study_folder`` is None for a study without a file (its relative
    paths are taken from the working folder, e.g. ``lfdrom rom``'s).

    Raises
    ------
    StudyConfigError
        At key ``output``, saying what to give instead.
    """
    fix = f"give a folder for the study's results, e.g. \"results/{name}\"" + (
        " (relative to the study file; \".\" for the study file's own folder), or leave output out"
        if study_folder is not None else "")
    _check_folder(P, "output", text, output_dir, fix, "its report, figures and store")


def _check_store(P: ConfigReader, text: str, store_dir: Path, study_folder: Path | None) -> None:
    """Refuse a ``store`` that is empty or the filesystem root.

    The results store (:mod:`studies.store.cache`) fills its folder with cache entries; ``store = ""`` resolved to
    the study file's folder without saying so and ``"/"`` put them into the root. A store shared by several
    studies (e.g. ``"../results/store"``) is fine: that is what it is for.

    Raises
    ------
    StudyConfigError
        At key ``store``, saying what to give instead.
    """
    fix = "give a folder for the results store, e.g. \"results/store\"" + (
        " (relative to the study file; studies may share one), or leave store out (default: <output>/store)"
        if study_folder is not None else "")
    _check_folder(P, "store", text, store_dir, fix, "its cache of flows, frequency responses and ROMs")


def _check_folder(P: ConfigReader, key: str, text: str, folder: Path, fix: str, root_use: str) -> None:
    """The checks of :func:`_check_output` and :func:`_check_store`: ``key`` = ``text`` (resolved: ``folder``)
    is not empty and not the filesystem root; ``root_use`` says what the run would write there."""
    if not text.strip():
        raise P.err(key, f"is empty: {fix}")
    if folder.parent == folder:
        raise P.err(key, f"{text!r} is the filesystem root {folder}, where the run would write {root_use}; {fix}")


def as_config(study) -> StudyConfig:
    """A study as a :class:`StudyConfig`: returned as is, or read from its file (:func:`load_study`).

    Parameters
    ----------
    study : StudyConfig or path-like

    Returns
    -------
    StudyConfig

    Raises
    ------
    StudyConfigError
        The study file is invalid.
    TypeError
        Neither a StudyConfig nor a path.
    """
    if isinstance(study, StudyConfig):
        return study
    if isinstance(study, (str, Path)):
        return load_study(study)
    raise TypeError(f"expected a StudyConfig or the path of a study file, got {type(study).__name__}")


def loads_study(text: str, source: str = "<string>", base_dir=None, default_name: str = "study") -> StudyConfig:
    """Validate a study given as TOML text (see :func:`load_study`)."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise StudyConfigError(source, None, f"not valid TOML: {e}") from None
    return parse_study(data, source=source, base_dir=base_dir, default_name=default_name)


def parse_study(data: Mapping[str, Any], source: str = "<dict>", base_dir=None,
                default_name: str = "study") -> StudyConfig:
    """Validate a study given as a dictionary (the parsed TOML); see :func:`load_study`."""
    P = ConfigReader(source)
    data = P.table(dict(data), None)
    registered = sections()
    P.check_keys(data, TOP_KEYS + tuple(s.table for s in registered if s.table is not None), "")
    base = Path(base_dir) if base_dir is not None else Path.cwd()

    name = P.string(data.get("name", default_name), "name")
    if not name or any(c in name for c in "/\\\0"):
        raise P.err("name", f"{name!r} must be a non-empty name without path separators")
    description = P.string(data.get("description", ""), "description")

    # global grid overrides
    grid_over = P.table(data.get("grid", {}), "grid")
    P.check_keys(grid_over, GRID_KEYS, "grid")
    try:
        base_grid = GridSpec(**grid_over)
    except CaseError as e:
        raise grid_config_error(P, "grid", e) from None

    # sweep
    sweep = P.table(data.get("sweep", {}), "sweep")
    P.check_keys(sweep, SWEEP_KEYS, "sweep")
    M_base = P.integer(sweep.get("M_base", 256), "sweep.M_base", minimum=4)
    if not _is_pow2(M_base):
        raise P.err("sweep.M_base", f"must be a power of two (e.g. 256 = 2^8 as in the paper), got {M_base}")
    if M_base > MAX_M:
        raise P.err("sweep.M_base", (
            f"M_base = {M_base} asks the LFD for {M_base + 1} frequencies per case and T (at most {MAX_M + 1}): "
            f"the paper's 257 take about 3 minutes by the fast sweep on the paper grid, and the identification "
            f"needs no more (the T sweep and N_omega = 33 .. 257 show where accuracy goes); use M_base <= {MAX_M}"))

    def parse_order(v, key):
        return P.integer(v, key, minimum=1)

    def parse_T(v, key):
        T = P.number(v, key, positive=True)
        if not T_RANGE[0] <= T <= T_RANGE[1]:
            raise P.err(key, (
                f"T = {T:g} puts the identification grid's centre frequency 2/T = {2.0 / T:.3g} U/c (k = {1.0 / T:.3g}) "
                f"{'far above' if T < T_RANGE[0] else 'far below'} the aerofoil's gust response (k ~ 0.005 - 50): the "
                f"model would be fitted to {'the feedthrough alone' if T < T_RANGE[0] else 'the DC gain alone'}; use "
                f"{T_RANGE[0]:g} <= T <= {T_RANGE[1]:g} (the paper's: 70/(2*pi) = 11.14; 2 - 4 resolves k ~ 1 - 10 better)"))
        return T

    def parse_M(v, key):
        M = P.integer(v, key, minimum=2)
        if not _is_pow2(M):
            raise P.err(key, f"must be a power of two (N_omega = M + 1 by subsampling M_base = {M_base}), got {M}")
        if M > M_base or M_base % M:
            raise P.err(key, f"M = {M} does not divide M_base = {M_base}; use one of "
                        f"{', '.join(str(M_base >> i) for i in range(M_base.bit_length() - 1))}")
        return M

    g_orders = P.axis(sweep["orders"], "sweep.orders", parse_order) if "orders" in sweep else None
    g_T = P.axis(sweep.get("T", [T_PAPER]), "sweep.T", parse_T)
    g_M = P.axis(sweep.get("M", [M_base]), "sweep.M", parse_M)

    # cfd and simulation
    cfd_t = P.table(data.get("cfd", {}), "cfd")
    P.check_keys(cfd_t, CFD_KEYS, "cfd")
    gust_method = P.choice(cfd_t.get("gust_method", "svm"), "cfd.gust_method", GUST_METHODS)
    outs = cfd_t.get("outputs", ["Cl", "Cm"])
    if not isinstance(outs, list) or not outs:
        raise P.err("cfd.outputs", f"must be a non-empty list of {', '.join(OUTPUTS)}, got {outs!r}")
    outs = tuple(P.choice(o, f"cfd.outputs[{i}]", OUTPUTS) for i, o in enumerate(outs))
    if len(set(outs)) != len(outs):
        raise P.err("cfd.outputs", f"lists an output twice: {list(outs)}")
    cfd = CFDOptions(gust_method=gust_method, outputs=outs)

    sim_t = P.table(data.get("simulation", {}), "simulation")
    P.check_keys(sim_t, SIMULATION_KEYS, "simulation")
    d = SimulationOptions()
    disc = P.choice(sim_t.get("discretisation", d.discretisation), "simulation.discretisation", DISCRETISATIONS)
    dt = P.number(sim_t.get("dt", d.dt), "simulation.dt", positive=True)
    t_end = P.number(sim_t.get("t_end", d.t_end), "simulation.t_end", positive=True)
    x0 = P.number(sim_t.get("x0", d.x0), "simulation.x0")
    scheme = P.choice(sim_t.get("scheme", d.scheme), "simulation.scheme", LTD_SCHEMES)
    from cfd.gust import X0_MAX

    if x0 > X0_MAX:
        raise P.err("simulation.x0", f"x0 = {x0} puts the gust front inside the aerofoil's region of influence; "
                    f"use x0 <= {X0_MAX} chords (-2 recommended)")
    if t_end < dt:
        raise P.err("simulation.t_end", f"t_end = {t_end} is shorter than one time step dt = {dt}")
    if t_end <= -x0:
        raise P.err("simulation.t_end", f"t_end = {t_end} ends before the gust reaches the aerofoil at s = {-x0} "
                    f"(x0 = {x0}); use a longer t_end")
    steps = math.ceil(t_end / dt - 1e-9)
    if steps > MAX_STEPS and data.get("gusts"):  # no gusts: no march
        gib = march_memory_bytes(steps, max(1, len(data.get("gusts", []) or [])))[0] / 2**30
        raise P.err("simulation.dt" if dt < d.dt / 10 else "simulation.t_end", (
            f"t_end / dt = {t_end:g} / {dt:g} = {steps:.3g} time steps (at most {MAX_STEPS:,}): the LTD march would "
            f"need {_size_text(gib)} for its histories alone and about {steps * 0.03 / 3600:.3g} h per case on the "
            f"paper grid with BDF2; use dt ~ 0.02 (BDF2 phase error ~ 1 % at k = 5; the output grid of "
            f"scheme = 'radau5') and t_end ~ 20 - 60"))
    sim = SimulationOptions(discretisation=disc, dt=dt, t_end=t_end, x0=x0, scheme=scheme)

    # methods
    if "method" in data and "methods" in data:
        raise P.err("method", "give either [method] (one variant) or [methods.NAME] tables, not both")
    if "methods" in data:
        mt = P.table(data["methods"], "methods")
        if not mt:
            raise P.err("methods", "define at least one variant, e.g. [methods.plain]")
        raw_methods = list(mt.items())
    else:
        raw_methods = [("default", data.get("method", {}))]
    methods = []
    for mname, mtab in raw_methods:
        prefix = "method" if "method" in data else f"methods.{mname}"
        mtab = P.table(mtab, prefix)
        P.check_keys(mtab, METHOD_KEYS, prefix)
        try:
            check_name("method", mname)
        except CaseError as e:
            raise P.err(prefix, str(e)) from None
        dc = mtab.get("dc_gain", "none")
        if isinstance(dc, bool):
            dc = "match" if dc else "none"
        dc = P.choice(dc, f"{prefix}.dc_gain", ("none", "match"))
        margin = P.number(mtab.get("margin", 1e-3), f"{prefix}.margin", nonneg=True)
        if margin >= 1.0:
            raise P.err(f"{prefix}.margin", f"must be in [0, 1) (discrete spectral radius < 1 - margin), got {margin}")
        methods.append(MethodOptions(
            name=mname, dc_gain=dc, stable=P.boolean(mtab.get("stable", False), f"{prefix}.stable"), margin=margin,
            weights=P.choice(mtab.get("weights", "none"), f"{prefix}.weights", WEIGHTS),
            algorithm=P.choice(mtab.get("algorithm", "auto"), f"{prefix}.algorithm", ALGORITHMS)))

    # cases
    if "cases" not in data:
        raise P.err("cases", "missing: list the test cases, e.g. cases = [\"T2\"] (paper names T1-T6) or "
                    "inline tables {name = \"mine\", naca = \"0012\", mach = 0.5}")
    raw_cases = data["cases"]
    if not isinstance(raw_cases, list) or not raw_cases:
        raise P.err("cases", f"must be a non-empty list, got {raw_cases!r}")
    sweeps = []
    for i, entry in enumerate(raw_cases):
        key = f"cases[{i}]"
        sweeps.append(parse_case_entry(P, entry, key, base_grid, g_orders, g_T, g_M, parse_order, parse_T, parse_M))
    names = [case_sweep.case.name.casefold() for case_sweep in sweeps]
    for i, n in enumerate(names):
        if names.index(n) != i:
            raise P.err(f"cases[{i}].name", f"case {sweeps[i].case.name!r} appears twice; give each case once")

    # gusts
    raw_gusts = data.get("gusts", [])
    if not isinstance(raw_gusts, list):
        raise P.err("gusts", f"must be a list (e.g. [\"G3\", \"G6\"]), got {raw_gusts!r}")
    if "gusts" in data and not raw_gusts:
        raise P.err("gusts", "is empty: name the gusts (e.g. [\"G3\", \"G6\"]), or leave the key out for a study "
                             "without gust responses")
    gusts = []
    for i, entry in enumerate(raw_gusts):
        key = f"gusts[{i}]"
        if isinstance(entry, str):
            try:
                gusts.append(gust_case(entry))
            except UnknownCaseError as e:
                raise P.err(key, str(e)) from None
            continue
        entry = P.table(entry, key)
        P.check_keys(entry, GUST_KEYS, key)
        if set(entry) == {"name"}:
            try:
                gusts.append(gust_case(entry["name"]))
            except UnknownCaseError as e:
                raise P.err(f"{key}.name", str(e)) from None
            continue
        for req in ("name", "kind", "angle_deg"):
            if req not in entry:
                raise P.err(f"{key}.{req}", "missing: a user gust needs name, kind, angle_deg (and length for "
                            "one_minus_cosine)")
        if isinstance(entry["name"], str) and entry["name"].casefold() in {g.casefold() for g in GUST_CASES}:
            raise P.err(f"{key}.name", f"{entry['name']!r} is a paper gust case with fixed parameters; give your "
                        "gust another name, or use just \"" + entry["name"] + "\"")
        try:
            length = entry.get("length")
            gusts.append(GustCase(entry["name"], entry["kind"],
                                  None if length is None else P.number(length, f"{key}.length"),
                                  P.number(entry["angle_deg"], f"{key}.angle_deg")))
        except CaseError as e:
            raise P.err(f"{key}.{e.field}" if e.field else key, str(e)) from None
    for i, g in enumerate(gusts):
        if g.length is not None and g.length < MIN_GUST_STEPS * dt:
            raise P.err(f"gusts[{i}].length" if isinstance(raw_gusts[i], Mapping) else f"gusts[{i}]", (
                f"gust {g.name!r} of length {g.length:g} chords passes the aerofoil in {g.length / dt:.3g} time steps "
                f"of dt = {dt:g} (at least {MIN_GUST_STEPS}): the march would not resolve it; lengthen the gust or "
                "use a smaller [simulation] dt"))
    gnames = [g.name.casefold() for g in gusts]
    for i, n in enumerate(gnames):
        if gnames.index(n) != i:
            raise P.err(f"gusts[{i}]", f"gust {gusts[i].name!r} appears twice; give each gust once")

    # impossible sweep points, before any computation
    p = len(cfd.outputs)
    for i, case_sweep in enumerate(sweeps):
        okey = f"cases[{i}].orders" if case_sweep.orders is not g_orders else "sweep.orders"
        for variant in methods:
            low = min_order(p, 1, variant.dc_gain, variant.resolved_algorithm(p, 1))
            if min(case_sweep.orders) < low:
                raise P.err(okey, (
                    f"order {min(case_sweep.orders)} cannot meet method {variant.name!r}'s constraints for case "
                    f"{case_sweep.case.name}: "
                    f"the exact DC gain and the omega = inf value of {p} outputs fix {2 * p} coefficients of B and "
                    f"D, which an order below {low} does not have; use orders >= {low}, dc_gain = \"none\" or "
                    f"algorithm = \"relocation\""))
        for M in case_sweep.M:
            for variant in methods:
                for n in case_sweep.orders:
                    if not order_supported(n, M, variant.algorithm, p):
                        lim = max_order(M, variant.algorithm, p)
                        raise P.err(okey, (
                            f"order {n} is impossible for case {case_sweep.case.name} with M = {M} (N_omega = "
                            f"{M + 1}) and algorithm {variant.algorithm!r} (method {variant.name!r}): the subspace "
                            "step supports at most "
                            f"{lim} states there; lower the order or use a larger M"))

    out = data.get("output")
    output_dir = ((base / P.string(out, "output")) if out is not None else base / "results" / name).resolve()
    if out is not None:
        _check_output(P, out, output_dir, base.resolve() if base_dir is not None else None, name)
    store = data.get("store")
    store_dir = (base / P.string(store, "store")).resolve() if store is not None else output_dir / "store"
    if store is not None:
        _check_store(P, store, store_dir, base.resolve() if base_dir is not None else None)
    report = parse_report_table(P, data.get("report", {}), base)
    # the sections' tables ([aeroelastic], [nonlinear], ...): studies.sections.protocol
    study = StudyTables(cases=tuple(sweeps), gusts=tuple(gusts), simulation=sim, cfd=cfd, methods=tuple(methods),
                        M_base=M_base)
    options = ()
    for s in registered:
        if s.table is not None and s.table in data:
            options += ((s.name, s.parse(data[s.table], P.err, replace(study, sections=options))),)
    return StudyConfig(name=name, description=description, source=source, output_dir=output_dir,
                       store_dir=store_dir, cases=tuple(sweeps), gusts=tuple(gusts), M_base=M_base,
                       methods=tuple(methods), simulation=sim, cfd=cfd, report=report, sections=options)
