"""The study subcommands of ``lfdrom``: ``cases``, ``run``, ``report`` and ``rom`` (registered by studies.cli).

Each validates its inputs with :mod:`studies.config.cases` and :mod:`studies.config` before anything is computed,
checks that every folder it will write accepts files and that the prose file parses, then calls
``studies.run.runner.run_study`` and ``studies.report.make_report``. ``rom`` then writes the one ROM the runner
identified as ``.npz`` and ``.mat`` (:mod:`studies.store.rom_export`): by default the stable, DC-exact identification, and
a written ROM that is unstable or far off its data is warned about (:func:`rom_warnings`); ``run`` names a study's
unstable ROMs at its end (:func:`unstable_rom_note`).

Exit status (the last line printed says which):

- 0: everything asked for was computed and written;
- 1: the runner or the report failed (an unexpected error, reported with its type);
- 2: bad input (study file, options, prose file), found before any computation;
- 3: incomplete: some pieces failed or are missing; what was computed is stored, a rerun retries the rest;
- 4: nothing could be written: the store, the output folder, the page's folder or the ROM file;
- 130: interrupted (Ctrl-C); what was stored is kept, the same command resumes.
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

from ..config.cases import TEST_CASES, case_table
from ..config.study import StudyConfig, StudyConfigError, load_study, parse_study
from .exit_codes import EXIT_FAILED, EXIT_INCOMPLETE, EXIT_INTERRUPTED, EXIT_NOT_WRITTEN, EXIT_OK, EXIT_UNAVAILABLE
from ..config.grid_spec import GRID_PRESETS

__all__ = ["add_subcommands", "dispatch", "cmd_cases", "cmd_run", "cmd_report", "cmd_rom", "rom_study", "COMMANDS",
           "EXIT_OK", "EXIT_FAILED", "EXIT_UNAVAILABLE", "EXIT_INCOMPLETE", "EXIT_NOT_WRITTEN", "EXIT_INTERRUPTED",
           "run_status", "rom_summary_line", "rom_warnings", "unstable_rom_note", "ROM_ERROR_WARNING"]

COMMANDS = ("cases", "run", "report", "rom", "fit")


def _err(msg: str) -> None:
    print(f"lfdrom: error: {msg}", file=sys.stderr)


# ---------------------------------------------------------------------------------------------
# Parsers
# ---------------------------------------------------------------------------------------------

def add_subcommands(sub) -> None:
    """Register ``cases``, ``run``, ``report`` and ``rom`` on an ``argparse`` subparsers object."""
    p = sub.add_parser("cases", help="list the paper's test cases T1-T6 and gust cases G1-G6",
                       description="The paper's test cases (Table 1) and gust cases (Table 2); G6 is the unit "
                                   "step v_g / U = 1 (gust angle 45 deg, tan = 1).")
    p.add_argument("--format", choices=("text", "markdown", "json"), default="text",
                   help="table format (default text)")

    def study_args(p, verb):
        p.add_argument("study", type=Path, metavar="STUDY.toml", help="study file (see studies/demo.toml)")
        p.add_argument("--out", type=Path, default=None,
                       help="output folder (default: the study's 'output', relative to the study file)")
        p.add_argument("--store", type=Path, default=None, help="results store (default: the study's 'store')")
        p.add_argument("--quiet", action="store_true", help=f"no progress output while {verb}")

    p = sub.add_parser("run", help="run a study: CFD, identification sweep, gust responses (resumable), report",
                       description="Validate STUDY.toml, then compute every piece not already in the results "
                                   "store: steady flow, LFD frequency responses, ROMs for each sweep point, LTD "
                                   "and ROM gust responses, metrics; then write the report (as 'lfdrom report': "
                                   "the study's [report] page, or <output>/report.md).")
    study_args(p, "running")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="Dask scheduler address (tcp://host:port); default local processes")
    p.add_argument("--workers", default="auto", metavar="N|auto",
                   help="local worker processes (default auto: as many as the study has parallel tasks, at most "
                        "the CPU count)")
    p.add_argument("--no-report", action="store_true", help="compute only; write the report later with "
                                                            "'lfdrom report'")
    p.add_argument("--force", action="store_true", help="recompute even what the store holds")
    p.add_argument("--force-page", action="store_true",
                   help="overwrite the report page even when it was not written by lfdrom (no generator marker)")
    p.add_argument("--dry-run", action="store_true", help="validate and list the sweep points, compute nothing")
    p.add_argument("--progress", choices=("auto", "bar", "lines", "pieces"), default=None,
                   help="progress output while computing: a line per finished piece and, from inside the steady "
                        "flow, the frequency sweep and the LTD march, a bar on a terminal ('bar') or throttled "
                        "lines ('lines'); 'pieces': the piece lines only; default auto (the bar when stderr is a "
                        "terminal and CI is unset, else lines); --quiet: nothing")

    p = sub.add_parser("report", help="tables and figures of a study from its stored results",
                       description="Write the tables (CSV, Markdown, LaTeX) and figures of STUDY.toml from the "
                                   "results store only (run the study first).")
    study_args(p, "writing")
    p.add_argument("--page", default=None, metavar="FILE.md",
                   help="write the report page here (e.g. docs/paper-reproduction.md; its figures and tables go "
                        "to a folder of the same name) instead of <output>/report.md")
    p.add_argument("--prose", default=None, metavar="FILE.toml",
                   help="TOML file of prose-slot texts (slot = \"text\"); slots already in the page are kept")
    p.add_argument("--force-page", action="store_true",
                   help="overwrite the page even when it was not written by lfdrom (no generator marker)")
    p.add_argument("--redraw", action="store_true",
                   help="draw every figure even when figures/manifest.json says they are up to date")

    p = sub.add_parser("rom", help="identify and save one ROM (npz and MATLAB .mat)",
                       description="One ROM of a paper case (T1-T6) or of your own aerofoil (--naca, --mach): "
                                   "LFD response on McKelvey's grid, identification at --order, saved as .npz "
                                   "and .mat (A, B, C, D, T).")
    p.add_argument("case", metavar="CASE", help="paper case T1-T6, or a label for --naca/--mach")
    p.add_argument("--order", type=int, required=True, help="model order N_r")
    p.add_argument("--naca", default=None, help="NACA 4-digit code of a user case (e.g. 0012)")
    p.add_argument("--mach", default=None, help="Mach number of a user case")
    p.add_argument("--alpha", default=None, help="incidence of a user case, degrees (default 0)")
    p.add_argument("--T", default="70/(2*pi)", help="sampling period of the bilinear map (default 70/(2*pi))")
    p.add_argument("--M", type=int, default=256, help="grid intervals, N_omega = M + 1 (default 256)")
    p.add_argument("--dc-gain", action=argparse.BooleanOptionalAction, default=True,
                   help="match the DC gain exactly (default; --no-dc-gain: least squares at omega = 0 too)")
    p.add_argument("--stable", action=argparse.BooleanOptionalAction, default=True,
                   help="enforce stability, spectral radius < 1 - 1e-3 (default; --no-stable: not enforced)")
    p.add_argument("--paper", action="store_true",
                   help="the paper's unconstrained identification (McKelvey subspace + least squares, as "
                        "--no-dc-gain --no-stable): often unstable at high orders, which is warned about")
    p.add_argument("--grid", choices=tuple(GRID_PRESETS), default="paper",
                   help="C-grid: paper (181 x 60, minutes) or coarse (65 x 17, seconds; its accuracy against the "
                        "paper grid: docs/mesh.md); default paper")
    p.add_argument("--out", type=Path, default=Path("results/rom"),
                   help="output folder (default results/rom; files CASE_N<order>_M<M>.npz and .mat, "
                        "CASE_N<order>_M<M>_coarse.* on the coarse grid), or a file name ending in .npz or .mat "
                        "(both files are written)")
    p.add_argument("--store", type=Path, default=None,
                   help="results store (default OUT/store, or store/ next to an OUT file)")
    p.add_argument("--quiet", action="store_true")
    from .fit import add_parser as add_fit_parser  # lfdrom fit DATA: anyone's frequency responses

    add_fit_parser(sub)


# ---------------------------------------------------------------------------------------------
# Commands
# ---------------------------------------------------------------------------------------------

def _text_table(rows, columns) -> str:
    cells = [[str(c) for c in columns]] + [[_fmt(r[c]) for c in columns] for r in rows]
    widths = [max(len(row[i]) for row in cells) for i in range(len(columns))]
    lines = ["  ".join(v.ljust(w) for v, w in zip(row, widths)).rstrip() for row in cells]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def _md_table(rows, columns) -> str:
    lines = ["| " + " | ".join(columns) + " |", "|" + "|".join(" --- " for _ in columns) + "|"]
    lines += ["| " + " | ".join(_fmt(r[c]) for c in columns) + " |" for r in rows]
    return "\n".join(lines)


def _fmt(v) -> str:
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)


def cmd_cases(args) -> int:
    """Print T1-T6 and G1-G6."""
    flows, gusts = case_table()
    if args.format == "json":
        print(json.dumps({"test_cases": flows, "gust_cases": gusts}, indent=1))
        return EXIT_OK
    fcols = ("name", "aerofoil", "mach", "alpha_deg", "grid")
    gcols = ("name", "kind", "length", "angle_deg", "amplitude")
    table = _md_table if args.format == "markdown" else _text_table
    print("Test cases (paper Table 1)\n")
    print(table(flows, fcols))
    print("\nGust cases (paper Table 2; length in chords, amplitude = v_max / U = tan(angle))\n")
    print(table(gusts, gcols))
    print("\nG6 is the paper's step with v_gmax = 1: the unit step of the input v_g / U (responses per radian).")
    return EXIT_OK


def _load(path: Path):
    try:
        return load_study(path)
    except StudyConfigError as e:
        _err(str(e))
        return None


def _apply_paths(config: StudyConfig, args) -> StudyConfig:
    from dataclasses import replace

    changes = {}
    if getattr(args, "out", None) is not None:
        changes["output_dir"] = args.out.resolve()
        if args.store is None and config.store_dir == config.output_dir / "store":
            changes["store_dir"] = changes["output_dir"] / "store"
    if getattr(args, "store", None) is not None:
        changes["store_dir"] = args.store.resolve()
    return replace(config, **changes) if changes else config


def report_targets(config: StudyConfig, args) -> tuple:
    """``(page, folder)`` of the report of ``lfdrom run`` / ``lfdrom report`` (``studies.report.report_paths``
    with ``--out`` and ``--page``)."""
    from ..report.make import report_paths

    return report_paths(config, config.output_dir if getattr(args, "out", None) is not None else None,
                        getattr(args, "page", None))


def _preflight(config: StudyConfig, *, report=None, prose=None, force_page: bool = False, store: bool = True,
               output: bool = True, extra=()) -> int:
    """Check, before anything is computed, what would otherwise fail late.

    Every folder the command will write accepts files (the store and the output folder unless told not to,
    the report's page, tables and figures folders when ``report = (page, folder)`` is given, and ``extra``
    ``(folder, what, fix)``); the page ends in ``.md``, is not a folder and is ours to overwrite; the prose file
    parses. Returns EXIT_OK, or (after saying why) EXIT_UNAVAILABLE / EXIT_NOT_WRITTEN.
    """
    from ..store.files import NotWritableError, probe_writable
    from ..report.make import ReportError, check_page, read_prose

    folders = []
    if store:
        folders.append((config.store_dir, "results store", "give another one with --store"))
    if output:
        folders.append((config.output_dir, "output folder", "give another one with --out"))
    if report is not None:
        page, folder = report
        if page.suffix != ".md":
            _err(f"{page}: the report page must be a Markdown file ending in .md (its tables and figures go to the "
                 f"folder of the same name); give another --page")
            return EXIT_UNAVAILABLE
        folders += [(page.parent, "report page's folder", "give another page with --page"),
                    (folder / "tables", "report's tables folder", "give another --page or --out"),
                    (folder / "figures", "report's figures folder", "give another --page or --out")]
    folders.extend(extra)
    for where, what, fix in folders:
        if Path(where).resolve().parent == Path(where).resolve():   # --out / or --store / (the study file refuses it)
            _err(f"{where}: the {what} would be the filesystem root; {fix}")
            return EXIT_UNAVAILABLE
        try:
            probe_writable(where, what=what, fix=fix)
        except NotWritableError as e:
            _err(str(e))
            return EXIT_NOT_WRITTEN
    prose = prose if prose is not None else config.report.prose
    try:
        if report is not None:
            check_page(report[0], force_page=force_page)
            if prose is not None:
                read_prose(prose)
    except ReportError as e:
        _err(str(e))
        return EXIT_UNAVAILABLE
    return EXIT_OK


def _run(config: StudyConfig, args, **options):
    """``studies.run.runner.run_study`` with the command line's options; ``(results, status)``."""
    from ..run.runner import RunInterrupted, RunnerError, run_study
    from ..store.cache import StoreReadError

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("always", RuntimeWarning)
            warnings.showwarning = _show_warning
            return run_study(config, **options), EXIT_OK
    except RunInterrupted as e:
        _err(str(e))
        return None, EXIT_INTERRUPTED
    except (RunnerError, StudyConfigError) as e:
        _err(str(e))
        return None, EXIT_UNAVAILABLE
    except OSError as e:
        _err(f"the study runner could not write: {type(e).__name__}: {e}")
        return None, EXIT_NOT_WRITTEN
    except StoreReadError as e:  # an entry that cannot be read (a file in place of its folder): the run went on
        # with the other pieces (studies.tasks.needs_compute), but its results cannot be gathered
        _err(f"{e}; the run stored what it could compute: run again once the entry is readable")
        return None, EXIT_INCOMPLETE
    except Exception as e:  # noqa: BLE001 - the command line reports any failure with its type
        _err(f"the study runner failed: {type(e).__name__}: {e}")
        return None, EXIT_FAILED


def _progress(args):
    """``run_study``'s ``progress``: False with ``--quiet``, else the ``--progress`` mode (default True: auto)."""
    if args.quiet:
        return False
    return True if getattr(args, "progress", None) in (None, "auto") else args.progress


def _show_warning(message, category, filename, lineno, file=None, line=None):
    print(f"lfdrom: warning: {message}", file=sys.stderr)


def run_status(results) -> tuple:
    """Exit status and closing line of a finished run.

    Returns
    -------
    (int, str)
        EXIT_OK when every piece of the study is stored and none failed; EXIT_NOT_WRITTEN when results of
        this run could not be written to the store; EXIT_INCOMPLETE when pieces failed or are missing
        (identifications that failed included).
    """
    summary = results.run
    if summary is not None and summary.write_failures:
        what = "; ".join(f"{t['kind']} {t['case']}: {t['error']}" for t in summary.task_failures if t.get("write"))
        return EXIT_NOT_WRITTEN, (f"nothing written for {summary.write_failures} task(s) ({what[:300]}): check the "
                                  f"store {results.config.store_dir} (space, permissions)")
    bad_roms = [r.label() for r in results.roms if not r.ok]
    problems = len(results.failed) + len(bad_roms) + len(results.missing)
    if problems:
        parts = []
        if results.failed or bad_roms:
            parts.append(f"{len(results.failed) + len(bad_roms)} piece(s) failed")
        if results.missing:
            parts.append(f"{len(results.missing)} missing")
        examples = (results.failed + bad_roms + results.missing)[:3]
        return EXIT_INCOMPLETE, (f"incomplete: {', '.join(parts)} (e.g. {'; '.join(map(str, examples))[:400]}); "
                                 "what was computed is stored, and running again retries the rest")
    return EXIT_OK, "done: every piece computed and stored"


def unstable_rom_note(results) -> str:
    """One line naming the study's unstable ROMs (spectral radius >= 1), or ``""`` when there are none: a study may
    ask for the paper's unconstrained identification on purpose, but its unstable models are never passed over
    in silence (the report's tables list every spectral radius)."""
    bad = [r for r in results.roms if r.ok and not r.metrics.get("spectral_radius", float("nan")) < 1.0]
    if not bad:
        return ""
    names = "; ".join(f"{r.label()} ({r.metrics.get('spectral_radius', float('nan')):.4g})" for r in bad[:3])
    return (f"{len(bad)} of {len(results.roms)} ROM(s) are unstable (spectral radius >= 1), e.g. {names}: their gust "
            "responses grow without bound; a method with dc_gain = \"match\" and stable = true avoids this")


def _plan(config: StudyConfig) -> str:
    lines = [f"study {config.name!r} ({config.source}): {len(config.cases)} case(s), {len(config.gusts)} gust(s), "
             f"{len(config.methods)} method variant(s), {len(config.points())} identifications",
             f"  output {config.output_dir}", f"  store  {config.store_dir}", f"  hash   {config.hash()[:16]}"]
    for case_sweep in config.cases:
        c = case_sweep.case
        lines.append(f"  {c.name}: {c.aerofoil} M{c.mach:g} alpha {c.alpha_deg:g} deg, grid {c.grid.ni} x {c.grid.nj};"
                     f" N_r {list(case_sweep.orders)}, T {[round(t, 6) for t in case_sweep.T]}, M {list(case_sweep.M)}")
    lines.append(f"  gusts: {', '.join(g.name for g in config.gusts) or '-'}; methods: "
                 f"{', '.join(m.name for m in config.methods)}")
    from ..sections.protocol import section

    for name, options in config.sections:  # [aeroelastic], [nonlinear], ...: studies.sections.protocol
        text = section(name).describe(options)
        if text:
            lines.append(text)
    return "\n".join(lines)


def cmd_run(args) -> int:
    """Validate the study, check every output location, run ``studies.run.runner.run_study``, write the report."""
    config = _load(args.study)
    if config is None:
        return EXIT_UNAVAILABLE
    config = _apply_paths(config, args)
    workers = _workers(args.workers)
    if workers is None:
        return EXIT_UNAVAILABLE
    from ..run.executors import RunnerError, check_scheduler

    try:
        check_scheduler(args.scheduler)
    except RunnerError as e:
        _err(str(e))
        return EXIT_UNAVAILABLE
    if args.dry_run or not args.quiet:
        print(_plan(config))
    status = _preflight(config, report=None if args.no_report else report_targets(config, args),
                        force_page=args.force_page)
    if status != EXIT_OK or args.dry_run:
        return status
    results, status = _run(config, args, output_dir=config.output_dir, store_dir=config.store_dir,
                           scheduler=args.scheduler, workers=workers, progress=_progress(args), force=args.force)
    if status != EXIT_OK:
        return status
    status, line = run_status(results)
    note = unstable_rom_note(results)
    if note:
        _show_warning(note, RuntimeWarning, "", 0)
    if not args.no_report:
        report_status = _report(config, args)
        if isinstance(report_status, int):  # a Path when the report was written
            _err(f"lfdrom run: the results are stored ({line}); write the report with 'lfdrom report "
                 f"{args.study}' once the problem above is fixed")
            return report_status if status == EXIT_OK else status
    (print if status == EXIT_OK else _err)(f"lfdrom run: {line}")
    return status


def _workers(value):
    """``--workers``: a positive integer or ``"auto"``; None (after saying why) when neither."""
    if str(value).strip().casefold() == "auto":
        return "auto"
    try:
        n = int(value)
    except (TypeError, ValueError):
        _err(f"--workers {value}: give a positive integer or auto")
        return None
    if n < 1:
        _err(f"--workers {value}: give at least 1")
        return None
    return n


def _report(config: StudyConfig, args):
    """``make_report`` with the page of ``--page``, else of ``--out``/report.md, else the study's [report].
    Returns the page written (a Path), or the exit status (an int) after saying what went wrong."""
    from ..store.files import NotWritableError
    from ..report.make import ReportError, make_report

    options = dict(store_dir=config.store_dir, progress=not args.quiet, page=getattr(args, "page", None),
                   prose=getattr(args, "prose", None), redraw=bool(getattr(args, "redraw", False)),
                   force_page=bool(getattr(args, "force_page", False)))
    if getattr(args, "out", None) is not None:
        options["output_dir"] = config.output_dir
    from ..store.cache import StoreReadError

    try:
        return make_report(config, **options)
    except StoreReadError as e:
        _err(str(e))
        return EXIT_UNAVAILABLE
    except (NotWritableError, OSError) as e:
        _err(f"the report could not be written: {e}")
        return EXIT_NOT_WRITTEN
    except (ReportError, StudyConfigError) as e:
        _err(str(e))
        return EXIT_UNAVAILABLE
    except Exception as e:  # noqa: BLE001 - the command line reports any failure with its type
        _err(f"the report failed: {type(e).__name__}: {e}")
        return EXIT_FAILED


def cmd_report(args) -> int:
    """Validate the study and write its report from the store (``studies.report.make_report``)."""
    config = _load(args.study)
    if config is None:
        return EXIT_UNAVAILABLE
    config = _apply_paths(config, args)
    # the report reads the store (it may be read-only) and writes only the page, tables and figures
    status = _preflight(config, report=report_targets(config, args), prose=args.prose, force_page=args.force_page,
                        store=False, output=False)
    if status != EXIT_OK:
        return status
    page = _report(config, args)
    if isinstance(page, int):
        return page
    from ..store.results import load_results

    status, line = run_status(load_results(config))
    if status == EXIT_OK:
        return EXIT_OK
    _err(f"lfdrom report: {page} written from an incomplete store ({line}); 'lfdrom run {args.study}' computes the "
         "rest")
    return status


def rom_study(args) -> StudyConfig:
    """The one-point study of ``lfdrom rom`` (validated like a study file; raises StudyConfigError)."""
    if args.case.casefold() in {n.casefold() for n in TEST_CASES}:
        given = [f"--{n}" for n in ("naca", "mach", "alpha") if getattr(args, n, None) is not None]
        if given:
            raise StudyConfigError("<command line>", given[0], f"{args.case} is a paper case with a fixed aerofoil, "
                                   "Mach number and incidence; give another CASE label to define your own")
        case = args.case
    else:
        if args.naca is None or args.mach is None:
            raise StudyConfigError("<command line>", "CASE", (
                f"{args.case!r} is not a paper case ({', '.join(TEST_CASES)}); for your own aerofoil give "
                "--naca and --mach (e.g. lfdrom rom mine --naca 0012 --mach 0.5 --order 20)"))
        case = {"name": args.case, "naca": args.naca, "mach": args.mach,
                "alpha_deg": 0.0 if args.alpha is None else args.alpha}
    paper = bool(getattr(args, "paper", False))
    method = {"dc_gain": "match" if args.dc_gain and not paper else "none", "stable": bool(args.stable) and not paper}
    data = {"name": "rom", "cases": [case], "sweep": {"orders": [args.order], "T": [args.T],
                                                                    "M_base": args.M, "M": [args.M]},
            "method": method}
    if getattr(args, "grid", "paper") != "paper":   # the paper grid is every case's default: its hash stays
        data["grid"] = GRID_PRESETS[args.grid].kwargs()
    out = args.out.resolve()
    if out.suffix in (".npz", ".mat"):
        out = out.parent
    data["output"] = str(out)
    data["store"] = str(args.store.resolve() if args.store is not None else out / "store")
    return parse_study(data, source="<command line>")


_ROM_KEYS = {"cases[0].name": "CASE", "cases[0].naca": "--naca", "cases[0].mach": "--mach",
             "cases[0].alpha_deg": "--alpha", "sweep.orders": "--order", "sweep.orders[0]": "--order",
             "sweep.T[0]": "--T", "sweep.M_base": "--M", "sweep.M[0]": "--M", "output": "--out", "store": "--store"}


def cmd_rom(args) -> int:
    """Validate one ROM's inputs and hand over to the runner."""
    for name in ("mach", "alpha"):
        v = getattr(args, name)
        if v is not None:
            try:
                setattr(args, name, float(v))
            except ValueError:
                _err(f"<command line>: --{name}: {v!r} is not a number")
                return EXIT_UNAVAILABLE
    try:
        config = rom_study(args)
    except StudyConfigError as e:
        key = _ROM_KEYS.get(e.key, e.key)
        _err(f"<command line>: {key}: {e.problem}" if key else str(e))
        return EXIT_UNAVAILABLE
    if not args.quiet:
        print(_plan(config))
    npz, mat = _rom_files(args)
    for f in (npz, mat):
        if f.is_dir():
            _err(f"{f}: is a folder; the ROM is written as {npz.name} and {mat.name}: give another --out")
            return EXIT_NOT_WRITTEN
    status = _preflight(config, extra=[(npz.parent, "ROM output folder", "give another --out")])
    if status != EXIT_OK:
        return status
    results, status = _run(config, args, output_dir=config.output_dir, store_dir=config.store_dir,
                           progress=not args.quiet)
    if status != EXIT_OK:
        return status
    return _export_rom(results, args)


def _rom_files(args):
    """``(npz, mat)`` paths of ``lfdrom rom``: ``--out`` a folder, or a file name ending in .npz or .mat."""
    out = args.out
    if out.suffix.lower() in (".npz", ".mat"):
        stem = out.with_suffix("")
    else:
        grid = getattr(args, "grid", "paper")
        stem = out / (f"{args.case}_N{args.order}_M{args.M}" + ("" if grid == "paper" else f"_{grid}"))
    return stem.with_suffix(".npz"), stem.with_suffix(".mat")


def _export_rom(results, args) -> int:
    """Write the one ROM of ``lfdrom rom`` as .npz and .mat (discrete, sampling period T)."""
    from ..store.rom_export import export_rom_mat, export_rom_npz

    (rec,) = results.roms or [None]
    if rec is None:
        _err(f"no ROM was produced: {'; '.join(results.missing + results.failed) or 'nothing stored'}")
        return EXIT_INCOMPLETE
    if not rec.ok:
        _err(f"the identification failed: {rec.error}")
        return EXIT_INCOMPLETE
    point = results.config.points()[0]
    model = rec.model(outputs=results.config.cfd.outputs)
    meta = dict(case=rec.case, naca=point.case.naca, mach=point.case.mach, alpha_deg=point.case.alpha_deg,
                grid=point.case.grid.kwargs(), order=rec.order, T=rec.T, M=rec.M, N_omega=rec.M + 1,
                method=point.method.canonical(), gust_method=results.config.cfd.gust_method,
                input="gust angle v_g(x=0)/U, rad", outputs=list(results.config.cfd.outputs),
                time="convective, s = t U / c", metrics=rec.metrics)
    npz, mat = _rom_files(args)
    try:
        export_rom_npz(npz, model, meta)
        export_rom_mat(mat, model, meta)
    except OSError as e:
        _err(f"the ROM could not be written: {e} (it is in the store {results.config.store_dir}; rerun with "
             "another --out to export it without recomputing)")
        return EXIT_NOT_WRITTEN
    notes = rom_warnings(rec, results.config.cfd.outputs)
    if not args.quiet or notes:
        print(rom_summary_line(rec, results.config.cfd.outputs))
    print(f"wrote {npz} and {mat}")
    for note in notes:
        _show_warning(note, RuntimeWarning, "", 0)
    return EXIT_OK


ROM_ERROR_WARNING = 0.05
"""FRF max error (peak-normalised, any output) above which ``lfdrom rom`` warns that the ROM is far off its data:
the stable, DC-exact fits of the paper study stay within 0.02 - 4.4 % (docs/paper-reproduction.md)."""


def rom_warnings(rec, outputs) -> list:
    """What ``lfdrom rom`` warns about a written ROM: unstable (spectral radius >= 1, or not finite) or further than
    :data:`ROM_ERROR_WARNING` from its frequency response in some output. Empty for a sound ROM."""
    m = rec.metrics
    notes = []
    radius = m.get("spectral_radius", float("nan"))
    if not radius < 1.0:
        notes.append(f"the ROM is unstable (spectral radius {radius:.6g} >= 1): its gust responses grow without bound; "
                     "the default identification (without --paper, --no-stable) enforces stability")
    far = [(o, m.get(f"frf_max_err_{o}", float("nan"))) for o in outputs]
    far = [(o, e) for o, e in far if not e <= ROM_ERROR_WARNING]
    if far:
        what = ", ".join(f"{o} {100 * e:.3g} %" for o, e in far)
        notes.append(f"the ROM is far off its frequency response (max error / peak: {what}; more than "
                     f"{100 * ROM_ERROR_WARNING:g} %): try another --order, the default stable, DC-exact "
                     "identification, or check the data with 'lfdrom fit' (its diagnostics)")
    return notes


def rom_summary_line(rec, outputs) -> str:
    """One line on a ROM: the FRF max error (peak-normalised) of every output, DC error, spectral radius."""
    m = rec.metrics
    errs = ", ".join(f"{o} {100 * m.get(f'frf_max_err_{o}', float('nan')):.3g} %" for o in outputs)
    dc = max((m.get(f"dc_err_{o}", float("nan")) for o in outputs), default=float("nan"))
    return (f"ROM {rec.label()}: FRF max error {errs}; DC error {dc:.2g}; spectral radius "
            f"{m.get('spectral_radius', float('nan')):.6f}")


def dispatch(args) -> int:
    """Run the subcommand of parsed ``args``; returns the exit status."""
    if args.command == "fit":
        from .fit import cmd_fit

        return cmd_fit(args)
    return {"cases": cmd_cases, "run": cmd_run, "report": cmd_report, "rom": cmd_rom}[args.command](args)


