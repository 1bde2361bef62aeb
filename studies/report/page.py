"""The report's Markdown page: its sections, the prose slots and the tables of the study.

:func:`page_markdown` writes the page from the results, the tables (:func:`studies.report.rows.report_tables`) and
the figures (:func:`studies.report.figures.report_figures`). The page has *prose slots* (:data:`SLOTS`),
``<!-- prose:NAME -->`` ... ``<!-- /prose:NAME -->``, whose text survives regeneration (:func:`read_prose` reads
them and checks given prose); :func:`check_page` refuses to overwrite a page that ``lfdrom report`` did not
write. In paper mode the slots quote the paper's claims (:data:`PAPER_CLAIMS`).
"""

from __future__ import annotations

import datetime as _dt
import difflib
import os
import re
import tomllib
from pathlib import Path
from typing import Mapping, Optional, Sequence

import numpy as np

from ..store.files import GENERATED_MARKER, generated_marker, is_generated_page
from .numbers import TemplateError, check_templates, fill
from .rows import T_key, frf_outputs, is_number, percent, summary_rows
from .tables import Column, format_table

__all__ = [
    "ReportError",
    "SLOTS",
    "PAPER_CLAIMS",
    "FIGURE_SECTIONS",
    "read_prose",
    "check_page",
    "findings",
    "page_markdown",
]


class ReportError(RuntimeError):
    """A report cannot be written (unreadable prose file, results of the wrong type, results unavailable)."""


SLOTS = ("summary", "frf", "hankel", "orders", "histories", "cases", "heatmaps", "methods", "cost")
"""Prose slots of the page, in order."""

PAPER_CLAIMS = {
    "frf": "N_r = 25 gives ROMs that agree well with the LFD for T1-T4, well behaved at small frequencies; for "
           "T5 and T6 (NACA2410) N_r = 25 does not fully capture the dynamics, and N_r = 55 (T5) and 35 (T6) "
           "capture them, especially at higher frequencies; an overly large N_r over-fits (Figs. 11-18). With "
           "N_omega = 33, N_r = 9 still gives a suitable ROM of T2 (Fig. 19).",
    "histories": "ROM and LTD agree in the transient and the steady state (Figs. 20-27). G3 tests the higher "
                 "frequencies, where ROM and LTD disagree somewhat; where the transients are large (NACA0018 and "
                 "NACA2410 at M 0.25) a larger ROM comes closer to the LTD. The T2 ROM with N_omega = 33, N_r = 9 "
                 "matches the G3 peak better but oscillates as Cl settles (Fig. 29). The ROMs are better at low "
                 "frequencies (long gusts, Figs. 30-37), and lag the LTD by one time step.",
    "cases": "NACA2410 at M 0.25 (T5) responds to G3 with a longer rise time and greater transients in Cm than at "
             "M 0.735 (T6) (Fig. 28).",
    "methods": "Further work in the paper: stabilise identified systems, and match the zero-frequency gain exactly "
               "so that the steady-state gains are equal.",
    "cost": "The ROM predicts the response to any input in a fraction of the time of the time-domain simulation.",
}
"""What the paper says, quoted next to the slot where our results are compared with it."""

FIGURE_SECTIONS = (("frf", "Frequency responses: ROM against LFD"), ("hankel", "Hankel singular values"),
                   ("orders", "Errors against N_r, T and N_omega"), ("histories", "Gust responses: ROM against LTD"),
                   ("cases", "LTD responses of the cases"), ("heatmaps", "Peak errors"))
"""The page's figure sections, in order: (section of the figures and of its prose slot, heading)."""

OPTIONAL_SECTIONS = ("cases",)
"""Figure sections left out of the page when they have neither figures nor prose (figures drawn)."""

# ---------------------------------------------------------------------------------------------
# Prose slots and the page check
# ---------------------------------------------------------------------------------------------

_SLOT_RE = re.compile(r"<!-- prose:(?P<name>[A-Za-z0-9_]+) -->\n(?P<body>.*?)<!-- /prose:(?P=name) -->", re.S)


def _toml_position(message: str) -> tuple:
    """(line, column or None, message without the position) of a ``tomllib.TOMLDecodeError`` message."""
    match = re.search(r"\s*\(at line (\d+), column (\d+)\)\s*$", message)
    if match:
        return int(match.group(1)), int(match.group(2)), message[:match.start()]
    match = re.search(r"\s*\(at end of document\)\s*$", message)
    if match:
        return None, None, message[:match.start()] + " (at the end of the file)"
    return None, None, message


def _key_line(text: str, key: str) -> Optional[int]:
    """Line (1-based) where the top-level TOML key ``key`` is defined (``key = ...`` or ``[key]``), if found."""
    escaped = re.escape(key)
    pattern = re.compile(rf"""^\s*(?:\[\s*)?(?:{escaped}|"{escaped}"|'{escaped}')\s*[=.\]]""")
    for number, line in enumerate(text.splitlines(), 1):
        if pattern.match(line):
            return number
    return None


def _slots_hint(name: str) -> str:
    close = difflib.get_close_matches(name, SLOTS, n=1)
    return (f" (did you mean {close[0]!r}?)" if close else "") + f"; the slots are {', '.join(SLOTS)}"


def read_prose(prose, page_path=None) -> dict:
    """Texts of the prose slots, checked: those written in an existing page, overridden by ``prose``.

    Cheap and independent of any result, so that a study's prose file can be checked before anything is
    computed.

    Parameters
    ----------
    prose : mapping, path-like or None
        ``{slot: text}``, or the path of a TOML file of such keys (``summary = \"\"\"...\"\"\"``). The slots are
        :data:`SLOTS`.
    page_path : path-like, optional
        An existing report page whose slot texts are kept (between ``<!-- prose:NAME -->`` and
        ``<!-- /prose:NAME -->``); ``prose`` overrides them slot by slot. Not read when absent.

    Returns
    -------
    dict
        Slot name -> text (stripped of surrounding newlines); slots without text are absent.

    Raises
    ------
    ReportError
        The prose file is missing, unreadable or not valid TOML (the message gives the file, line and column),
        names a slot that does not exist (the message gives the line, the slots and the closest one), or gives
        a slot something other than text; ``prose`` is neither a mapping nor a path.
    """
    slots = {}
    if page_path is not None:
        page_path = Path(page_path)
        try:
            text = page_path.read_text(encoding="utf-8") if page_path.is_file() else ""
        except (OSError, UnicodeDecodeError) as e:
            raise ReportError(f"{page_path}: cannot read the existing page for its prose slots: {e}") from None
        for match in _SLOT_RE.finditer(text):
            body = match.group("body").strip("\n")
            if body and not body.startswith("_(prose to be written"):  # old pages: a placeholder, not prose
                slots[match.group("name")] = body
    if prose is None:
        return slots
    source, text = "prose", None
    if isinstance(prose, (str, Path)):
        path = Path(prose)
        source = str(path)
        try:
            text = path.read_text(encoding="utf-8")
        except FileNotFoundError:
            raise ReportError(f"{path}: no such prose file (a TOML file of slot = \"text\" strings; slots: "
                              f"{', '.join(SLOTS)})") from None
        except UnicodeDecodeError as e:
            raise ReportError(f"{path}: the prose file is not UTF-8 text ({e}); save it as UTF-8") from None
        except OSError as e:
            raise ReportError(f"{path}: cannot read the prose file: {e.strerror or e}") from None
        try:
            prose = tomllib.loads(text)
        except tomllib.TOMLDecodeError as e:
            line, column, message = _toml_position(str(e))
            where = f", line {line}" + (f", column {column}" if column else "") if line else ""
            raise ReportError(f"{path}{where}: the prose file is not valid TOML: {message}; write each slot as "
                              f'NAME = """text""" (slots: {", ".join(SLOTS)})') from None
    if not isinstance(prose, Mapping):
        raise ReportError(f"prose must be a mapping of slot -> text or a TOML file, got {type(prose).__name__}")
    for name, body in prose.items():
        line = _key_line(text, str(name)) if text is not None else None
        at = f"{source}, line {line}" if line else source
        if name not in SLOTS:
            raise ReportError(f"{at}: unknown prose slot {name!r}{_slots_hint(str(name))}")
        if not isinstance(body, str):
            raise ReportError(f"{at}: prose slot {name!r} must be text (a string), got {type(body).__name__}")
        try:
            check_templates(body, f"{at}: prose slot {name!r}")
        except TemplateError as e:
            raise ReportError(str(e)) from None
        if body.strip():
            slots[name] = body.strip("\n")
    return slots


def check_page(page, *, force_page: bool = False) -> None:
    """Refuse to overwrite a file that is not a report page: check ``page`` before anything is written.

    Parameters
    ----------
    page : path-like
        Where the report page is to be written.
    force_page : bool
        Overwrite an existing file even when ``lfdrom report`` did not write it.

    Raises
    ------
    ReportError
        ``page`` is a folder, or an existing file without the generator marker
        (:func:`studies.store.files.is_generated_page`) and ``force_page`` is false; the message says how out.
    """
    path = Path(page)
    if path.is_dir():
        raise ReportError(f"{path}: is a folder; give the page as a file (e.g. {path / 'report.md'})")
    if force_page or not path.exists() or is_generated_page(path):
        return
    raise ReportError(f"{path}: exists and was not written by lfdrom report (its first line is not the "
                      f"'{GENERATED_MARKER} ...' comment), so it is left as it is; write the report elsewhere "
                      f"(--page OTHER.md or --out DIR; [report] page in the study file) or replace this file with "
                      f"--force-page (make_report(..., force_page=True))")


def _slot(name: str, slots: dict, paper: bool) -> str:
    """A prose slot: the paper's claim (paper mode), then the slot's text between its markers.

    A slot without text is empty: its markers are HTML comments, invisible on the rendered page, where text can
    be written by hand (it is kept when the page is regenerated).
    """
    lines = []
    if paper and name in PAPER_CLAIMS:
        lines.append(f"> **The paper:** {PAPER_CLAIMS[name]}\n")
    body = slots.get(name, "")
    lines.append(f"<!-- prose:{name} -->\n" + (f"{body}\n" if body else "") + f"<!-- /prose:{name} -->\n")
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------------
# Findings
# ---------------------------------------------------------------------------------------------

def _percent_or_na(value) -> str:
    return percent(value) if is_number(value) or value == float("inf") else "n/a"


def findings(results, rows: Optional[Sequence[Mapping]] = None) -> str:
    """What a study found, from its own numbers: the page's summary when no prose is given for it.

    Per case, the best ROM (stable ones first, then the smallest FRF max error over the outputs), its FRF
    errors per output and its worst gust peak errors; and how many ROMs are stable.

    Parameters
    ----------
    results : StudyResults
    rows : sequence of mapping, optional
        :func:`studies.report.rows.summary_rows` of ``results`` (computed when not given).

    Returns
    -------
    str
        Markdown (a paragraph and a list), or "" when no ROM was identified.
    """
    rows = list(summary_rows(results) if rows is None else rows)
    if not rows:
        return ""
    outputs = frf_outputs(results)
    n_stable = sum(1 for row in rows if row.get("stable") is True or row.get("stable") == np.True_)
    lines = [f"**Findings** (from the tables below; text in the `summary` prose slot takes the place of this "
             f"paragraph): {n_stable} of {len(rows)} identified ROMs are stable."]
    cases = []
    for row in rows:
        if row["case"] not in cases:
            cases.append(row["case"])

    def largest_frf_error(row):
        values = [float(row.get(f"frf_max_err_{output}")) for output in outputs
                  if is_number(row.get(f"frf_max_err_{output}"))]
        return max(values) if values else float("inf")

    for case in cases:
        case_rows = [row for row in rows if row["case"] == case]
        stable = [row for row in case_rows if bool(row.get("stable"))]
        best = min(stable or case_rows, key=largest_frf_error)
        multi_T = len({T_key(row["T"]) for row in case_rows}) > 1
        what = (f"N_r = {best['order']}, N_omega = {best['N_omega']}" + (f", T = {best['T']:.4g}" if multi_T else "")
                + f", method {best['method']}")
        frf = ", ".join(f"{output} {_percent_or_na(best.get(f'frf_max_err_{output}'))}" for output in outputs)
        peaks = [f"{output} {_percent_or_na(best[f'worst_peak_err_{output}'])} ({best[f'worst_gust_{output}']})"
                 for output in ("Cl", "Cm") if is_number(best.get(f"worst_peak_err_{output}"))
                 or best.get(f"worst_peak_err_{output}") == float("inf")]
        qualifier = "" if stable else " (no stable ROM: the smallest FRF error)"
        lines.append(f"- {case}{qualifier}: best ROM {what}: FRF max error {frf}"
                     + (f"; worst gust peak error {', '.join(peaks)}" if peaks else "; no gust history yet")
                     + (f"; {len(stable)} of {len(case_rows)} ROMs stable." if len(cases) > 1 else "."))
    return lines[0] + "\n\n" + "\n".join(lines[1:]) + "\n"


# ---------------------------------------------------------------------------------------------
# Pieces of the page
# ---------------------------------------------------------------------------------------------

def _relative(path: Path, start: Path) -> str:
    return Path(os.path.relpath(path, start)).as_posix()


def _git_commit() -> str:
    from ..store.provenance import git_commit

    try:
        info = git_commit()
    except Exception:  # noqa: BLE001 - provenance is best effort
        return "unknown"
    if not isinstance(info, Mapping):
        return "unknown"
    commit = str(info.get("commit") or "unknown")[:12]
    return commit + (" (dirty tree)" if info.get("dirty") else "")


def _study_table(config) -> str:
    rows = []
    for study_case in config.cases:
        case = study_case.case
        rows.append(dict(case=case.name, aerofoil=f"NACA{case.naca}", mach=case.mach, alpha=case.alpha_deg,
                         grid=f"{case.grid.ni} x {case.grid.nj}", orders=", ".join(map(str, study_case.orders)),
                         T=", ".join(f"{T:.4g}" for T in study_case.T),
                         N_omega=", ".join(str(M + 1) for M in study_case.M)))
    return format_table(rows, [Column("case"), Column("aerofoil"), Column("mach", "Mach", ".4g"),
                               Column("alpha", "alpha [deg]", ".3g"), Column("grid"), Column("orders", "N_r"),
                               Column("T", "T [c/U]"), Column("N_omega")], "markdown")


def _gust_table(config) -> str:
    rows = [dict(gust=gust.name, kind=gust.kind.replace("_", "-"), length=gust.length, angle=gust.angle_deg)
            for gust in config.gusts]
    if not rows:
        return "_(no gusts)_\n"
    return format_table(rows, [Column("gust"), Column("kind"), Column("length", "length [c]", ".4g"),
                               Column("angle", "angle [deg]", ".4g")], "markdown")


def _method_table(config) -> str:
    rows = [dict(method=method.name, dc_gain=method.dc_gain, stable=method.stable,
                 margin=method.margin if method.stable else None, weights=method.weights,
                 algorithm=method.algorithm) for method in config.methods]
    return format_table(rows, [Column("method"), Column("dc_gain", "DC gain"), Column("stable", "stability enforced"),
                               Column("margin", "margin", ".0e"), Column("weights"), Column("algorithm")], "markdown")


_DOCS = Path(__file__).resolve().parents[2] / "docs"


def _paper_elsewhere(page_dir: Path) -> str:
    """Where the paper's figures that are not part of a study are reproduced (grids, steady flow, SVM/FVM)."""
    def link(name, anchor=""):
        return f"[{name}]({_relative(_DOCS / name, page_dir)}{anchor})"

    return ("The paper's figures outside a study are reproduced elsewhere: the C-grid (Figs. 1-2) in "
            f"{link('mesh.md')}, the steady pressure distributions of T1-T6 (Figs. 3-8) in {link('validation.md')} "
            f"(section 6), and the SVM against FVM LFD responses of T2 and T4 (Figs. 9-10) in "
            f"{link('gust_validation.md')} (section 6). The figures below are the analogues of Figs. 11-37.\n")


def _bullets(items: Sequence[str], limit: int = 40) -> str:
    lines = [f"- {item}" for item in items[:limit]]
    if len(items) > limit:
        lines.append(f"- ... and {len(items) - limit} more (see the tables)")
    return "\n".join(lines) + "\n"


def _figures_markdown(figures, page_dir: Path, section: str) -> str:
    if figures is None:
        return "_(figures not drawn in this run: `figures=False`)_\n"
    lines = []
    for figure in figures:
        if figure.section == section:
            lines.append(f"![{figure.path.stem}]({_relative(figure.path, page_dir)})\n\n*{figure.caption}*\n")
    return "\n".join(lines) if lines else "_(no data for these figures yet)_\n"


def _table_markdown(tables: dict, name: str, empty: str) -> str:
    rows, columns = tables[name]
    return format_table(rows, columns, "markdown") if rows else empty


# ---------------------------------------------------------------------------------------------
# The page, section by section (each a list of blocks; the page joins them with newlines)
# ---------------------------------------------------------------------------------------------

def _status_section(results, summary: list, slots: dict, paper: bool, page_dir: Path) -> list:
    config = results.config
    failed_points = [rom for rom in results.roms if rom.status != "ok"]
    other_failures = list(getattr(results, "failed", []))
    n_ok = sum(1 for rom in results.roms if rom.status == "ok")
    blocks = ["## Status\n",
              f"{n_ok} of {len(config.points())} identifications done, {len(failed_points)} failed; "
              f"{len(results.sims)} ROM gust histories against {len(results.ltd)} LTD references; "
              f"{len(results.missing)} piece(s) missing, {len(other_failures)} other failure(s).\n"]
    if results.missing:
        blocks.append("**Missing** (not in the store yet; run `lfdrom run` to compute them):\n")
        blocks.append(_bullets(list(results.missing)))
    if failed_points or other_failures:
        blocks.append("**Failed** (recorded with their error; the other points went on):\n")
        blocks.append(_bullets([f"{rom.case} T={rom.T:.4g} N_omega={rom.M + 1} N_r={rom.order} {rom.method}: "
                                f"{rom.error}" for rom in failed_points] + other_failures))
    if not slots.get("summary"):
        blocks.append(findings(results, summary))
    blocks.append(_slot("summary", slots, paper))
    if paper:
        blocks.append(_paper_elsewhere(page_dir))
    return blocks


def _study_section(config) -> list:
    simulation = config.simulation
    return ["## Study\n", _study_table(config),
            "\nGusts (angle = peak effective gust angle; responses are at this amplitude):\n", _gust_table(config),
            "\nIdentification variants:\n", _method_table(config),
            f"\nGust responses: LTD ({_LTD_SCHEME_TEXT[simulation.scheme]}) and ROM ({simulation.discretisation} "
            f"re-discretisation) at dt = {simulation.dt:g} c/U up to s = {simulation.t_end:g}, gust front at x0 = "
            f"{simulation.x0:g} c at s = 0; gust method {config.cfd.gust_method}.\n"]


_LTD_SCHEME_TEXT = {"bdf2": "BDF2", "radau5": "Radau IIA, loads on the dt grid"}


def _headline_section(config, tables: dict) -> list:
    rows, columns = tables["summary"]
    if not any(len(study_case.T) > 1 for study_case in config.cases):
        columns = [column for column in columns if column.key != "T"]  # one T per case: in the study table above
    return ["## Headline accuracy\n",
            "One row per identified ROM: FRF error against the LFD over the whole base grid (peak-normalised, "
            "`sysid.metrics`), DC error (absolute, per radian of gust angle), spectral radius of the discrete ROM "
            "at T, and the largest relative peak error over the gusts with the gust where it occurs.\n",
            (format_table(rows, columns, "markdown") if rows else "_(no ROM identified yet)_\n") + "\n"]


def _figure_sections(figures, slots: dict, paper: bool, page_dir: Path) -> list:
    blocks = []
    for section, heading in FIGURE_SECTIONS:
        if section in OPTIONAL_SECTIONS and figures is not None and not slots.get(section) \
                and not any(figure.section == section for figure in figures):
            continue  # never drops written text
        blocks += [f"## {heading}\n", _figures_markdown(figures, page_dir, section), _slot(section, slots, paper)]
    return blocks


def _tables_section(tables: dict, slots: dict, paper: bool, page_dir: Path, tab_dir: Path) -> list:
    blocks = ["## Identification variants: DC matching and stability\n",
              _table_markdown(tables, "methods", "_(no ROM yet)_\n"), _slot("methods", slots, paper),
              "## Cost\n",
              "Wall-clock seconds as stored with each piece (LTD time per gust; ROM time: re-discretisation and "
              "simulation of one gust history).\n",
              _table_markdown(tables, "cost", "_(nothing computed yet)_\n"), _slot("cost", slots, paper),
              "## Tables\n"]
    links = []
    for name in ("summary", "roms", "sims", "methods", "cost"):
        if tables[name][0]:
            files = sorted(tab_dir.glob(f"{name}.*"))
            links.append(f"- {name}: " + ", ".join(f"[{path.suffix[1:]}]({_relative(path, page_dir)})"
                                                   for path in files))
    blocks.append("\n".join(links) + "\n" if links else "_(no tables yet)_\n")
    blocks.append("Columns: T in convective time c/U; N_omega = M + 1 frequencies identified from; N_r the model "
                  "order; FRF errors relative (max: peak-normalised per output over the full LFD grid; RMS: "
                  "energy-normalised); DC errors absolute per radian of gust angle; peak error |peak_ROM - peak_LTD| "
                  "/ |peak_LTD| with the peak the signed extreme; peak time error in c/U; RMS error rms(ROM - LTD) / "
                  "rms(LTD); times in seconds.\n")
    return blocks


def page_markdown(results, tables: dict, figures: Optional[list], slots: dict, *, page_dir: Path, tab_dir: Path,
                  title: Optional[str], paper: bool) -> str:
    """The report page of ``results`` as Markdown.

    Parameters
    ----------
    results : StudyResults
    tables : dict
        :func:`studies.report.rows.report_tables` of ``results`` (the ``tables/`` files already written).
    figures : list or None
        The :class:`studies.report.figures.Figure` list; None when the figures were not drawn.
    slots : dict
        Texts of the prose slots (:func:`read_prose`); slots not in :data:`SLOTS` go at the page's end.
    page_dir, tab_dir : Path
        The page's folder (links are relative to it) and the tables' folder.
    title : str, optional
        Default: "Study report: NAME", or the paper's reproduction title in paper mode.
    paper : bool
        Paper mode: the paper's claims next to the slots and where its other figures are reproduced.
    """
    config = results.config
    try:   # numbers quoted from the tables: filled from this store (studies.report.numbers)
        slots = {name: fill(body, tables, f"prose slot {name!r}") for name, body in slots.items()}
    except TemplateError as e:
        raise ReportError(str(e)) from None
    if title is None:
        title = (f"Reproduction of Bagheri, Jones & Gaitonde (2016): study {config.name}" if paper
                 else f"Study report: {config.name}")
    blocks = [generated_marker(config.source), f"# {title}\n",
              f"Generated by `studies.report` from the results store of `{config.source}` only (nothing is computed "
              f"here) on {_dt.datetime.now(_dt.timezone.utc):%Y-%m-%d %H:%M} UTC, code at git {_git_commit()}; study "
              f"hash `{config.hash()[:16]}`. Regenerate with `lfdrom report {config.source}`; the text of the prose "
              f"slots (between their HTML comment markers) is kept.\n"]
    if getattr(config, "description", ""):
        blocks.append(f"{config.description}\n")
    blocks += _status_section(results, tables["summary"][0], slots, paper, page_dir)
    blocks += _study_section(config)
    blocks += _headline_section(config, tables)
    blocks += _figure_sections(figures, slots, paper, page_dir)
    blocks += _tables_section(tables, slots, paper, page_dir, tab_dir)
    for name in slots:
        if name not in SLOTS:  # a slot added by hand to the page: kept, at its end
            blocks.append(_slot(name, slots, False))
    return "\n".join(blocks)
