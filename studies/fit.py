"""``lfdrom fit DATA``: a stable, DC-exact ROM from anyone's frequency-response data.

The front door for frequency responses that did not come from lfdrom's CFD (a loads team's own CFD, a
wind-tunnel test). It reads the data (:func:`load_data`), checks them (:func:`sysid.diagnose`), chooses the
order (a number, or ``auto``: :func:`holdout_order`), fits with :func:`sysid.identify` and writes the ROM
(``rom.npz`` and ``rom.mat``, :mod:`studies.rom_export`), a Markdown summary (``summary.md``) and figures
(:mod:`studies.fit_plots`) to ``--out``.

File formats
------------
All frequencies are angular frequencies in convective units ``omega`` (``U_inf / c``; the reduced frequency is
``k = omega c / (2 U_inf) = omega / 2``), or discrete frequencies ``omega_d`` in ``[0, pi]`` with a sampling
period ``T`` (bilinear map ``omega = (2/T) tan(omega_d / 2)``). ``omega = inf`` is allowed: its value is the
continuous feedthrough (0 for an aerofoil's gust response) and is imposed, never fitted. Responses are per
unit input with time dependence ``exp(+i omega t)``.

``.npz``
    lfdrom's own format (:meth:`sysid.FrequencyResponse.save`), or a plain ``.npz`` with the ``.mat``
    variables below.
``.mat`` (MATLAB, v5 or v7; not v7.3/HDF5)
    ``H``: complex ``(p, m, K)`` (outputs, inputs, frequencies, as MATLAB's ``frd`` ``ResponseData``); a
    ``(p, K)`` or ``(1, K)``/``(K, 1)`` array is read as single-input. Or ``H_re`` and ``H_im``, real arrays of
    the same shape. Frequencies: exactly one of ``omega`` (``U/c``; ``Inf`` allowed), ``k`` (reduced
    frequency, ``omega = 2 k``) or ``omega_d`` (rad/sample, then ``T`` is required). Optional: ``T``
    (sampling period), ``inputs`` and ``outputs`` (cell arrays or char rows of names).
    In MATLAB: ``save('data.mat', 'H', 'omega', 'outputs', 'inputs')``.
CSV
    Lines starting with ``#`` are comments; a comment ``# key: value`` sets ``frequency`` (the unit of the
    frequency column: ``omega``, ``k`` or ``omega_d``), ``T`` or ``input`` (the input's name). The first other
    line is the header: the frequency column first, named ``omega``, ``k`` or ``omega_d`` (any other name
    needs ``# frequency: ...`` or ``--freq-unit``), then a ``NAME_re`` and a ``NAME_im`` column per output
    (``NAME/INPUT_re`` for several inputs). Values are plain numbers (``inf`` for ``omega = inf``)::

        # frequency: k
        # input: gust
        k,Cl_re,Cl_im,Cm_re,Cm_im
        0.0,6.28,0.0,-0.11,0.0
        ...

Options and rules
-----------------
- ``--T``: needed for data on continuous frequencies. Default: the file's ``T``, else ``T = 2 /
  sqrt(omega_lo omega_hi)`` (smallest positive, largest finite ``omega``; :func:`sysid.diagnostics.default_T`),
  which puts the geometric mean of the band at ``omega_d = pi / 2``.
- ``--order auto`` (hold-out selection, :func:`holdout_order`): the frequencies sorted by ``omega`` are split
  into even-indexed ones (fitted; the ``omega = 0`` and ``omega = inf`` samples always belong to them) and
  odd-indexed ones (held out). Every order ``1..--max-order`` is fitted to the first set with the same
  options as the final fit; its hold-out error is the largest over outputs of the RMS error on the held-out
  frequencies relative to the RMS of the data there. The order chosen is the *smallest* whose hold-out error
  is at most ``1.1 x`` the best plus ``1e-6`` (differences below that are solver round-off). The final model
  is then fitted to all the data.
- ``--dc-gain match|none`` (default ``match`` when the data have an ``omega = 0`` sample, else ``none``),
  ``--stable/--no-stable`` (default stable).

Exit status (``studies.commands.EXIT_*``): 0 written; 1 the identification failed; 2 bad input (file, options),
reported with the file and the line (CSV) or key (``.npz``/``.mat``) and what to do; 4 the output folder
cannot be written.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["FitInputError", "FitOutcome", "load_data", "holdout_order", "fit_data", "write_outputs",
           "add_parser", "cmd_fit", "FREQ_UNITS"]

from .fit_data import FREQ_UNITS, FitInputError, load_data
from .exit_codes import EXIT_FAILED, EXIT_NOT_WRITTEN, EXIT_OK
from .exit_codes import EXIT_UNAVAILABLE as EXIT_BAD_INPUT  # 2: bad input, found before anything is computed
from .files import atomic_write_text
from .numbers import parse_number

HOLDOUT_RTOL, HOLDOUT_ATOL = 0.1, 1e-6



# ---------------------------------------------------------------------------------------------
# Fitting
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class HoldoutSelection:
    """Result of :func:`holdout_order`: ``orders`` tried, their ``errors`` (NaN where the fit failed), the
    ``chosen`` order and the ``rule`` in words."""

    orders: np.ndarray
    errors: np.ndarray
    chosen: int
    rule: str


def _source(frf) -> str:
    """The data file's name for messages: ``metadata["file"]`` (lfdrom ``.npz``), else ``metadata["source"]``."""
    return str(frf.metadata.get("file") or frf.metadata.get("source") or "<data>")


def _split(frf) -> tuple[np.ndarray, np.ndarray]:
    """Indices ``(fit, held_out)``: even/odd positions by increasing omega; DC and inf always fitted."""
    w = frf.omega if frf.omega is not None else frf.omega_d
    order = np.argsort(w, kind="stable")
    fit = set(order[::2].tolist())
    for k in (0, order.size - 1):
        v = w[order[k]]
        if v == 0 or np.isinf(v) or (frf.omega is None and v >= np.pi):
            fit.add(int(order[k]))
    fit_idx = np.array(sorted(fit, key=lambda i: w[i]))
    held = np.array([i for i in order if i not in fit])
    return fit_idx, held


def holdout_order(frf, *, max_order: int = 30, dc_gain=None, stable: bool = True,
                  algorithm: str = "auto") -> HoldoutSelection:
    """Choose the order by hold-out (rule in the module docstring).

    Parameters
    ----------
    frf : sysid.FrequencyResponse
        Data with ``T``.
    max_order : int
        Largest order tried (fewer when the fitting half cannot support it).
    dc_gain, stable, algorithm
        As for :func:`sysid.identify` (``dc_gain`` is None or a (p, m) array; ``"match"`` is resolved by the
        caller so that the held-out half keeps the full data's DC value).

    Returns
    -------
    HoldoutSelection
    """
    import sysid

    fit_idx, held = _split(frf)
    if held.size == 0:
        raise FitInputError(_source(frf), "--order", "too few frequencies to hold any out; give --order N")
    part, val = frf.take(fit_idx), frf.take(held)
    Hv = np.asarray(val.H)
    den = np.maximum(np.sqrt(np.mean(np.abs(Hv) ** 2, axis=(1, 2))), np.finfo(float).tiny)
    orders = np.arange(1, max_order + 1)
    errs = np.full(orders.size, np.nan)
    for i, n in enumerate(orders):
        try:
            import warnings

            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                res = sysid.identify(part, int(n), dc_gain=dc_gain, stable=stable, algorithm=algorithm)
            Hm = res.evaluate(val.omega_d)
        except sysid.OrderError:
            if np.isfinite(errs[:i]).any():
                break  # above what the fitted half supports
            continue  # below what the data need (e.g. fewer states than inputs)
        except (ValueError, RuntimeError, np.linalg.LinAlgError):
            continue
        errs[i] = float((np.sqrt(np.mean(np.abs(Hm - Hv) ** 2, axis=(1, 2))) / den).max())
    if not np.isfinite(errs).any():
        raise FitInputError(_source(frf), "--order", "no order could be fitted to the even-indexed frequencies; give "
                                                 "--order N")
    best = np.nanmin(errs)
    ok = np.flatnonzero(errs <= (1 + HOLDOUT_RTOL) * best + HOLDOUT_ATOL)
    chosen = int(orders[ok[0]])
    rule = (f"hold-out: fitted orders 1..{int(orders[np.isfinite(errs)].max())} to {fit_idx.size} of the "
            f"{frf.nfreq} frequencies (even-indexed, plus omega = 0 and inf), measured on the other {held.size}; "
            f"chose the smallest order whose hold-out error is <= 1.1 x the best ({best:.3g}) + 1e-6")
    return HoldoutSelection(orders=orders, errors=errs, chosen=chosen, rule=rule)


@dataclass(frozen=True)
class FitOutcome:
    """What :func:`fit_data` did: the data (with ``T``), their diagnostics, the identification result, the
    order selection (None for a given order), the options and the time taken."""

    data: Any
    diagnostics: Any
    result: Any
    selection: HoldoutSelection | None
    T_rule: str
    options: dict
    elapsed: float
    warnings: tuple = ()   # what sysid.identify warned about the final fit (messages), printed and in summary.md


def fit_data(frf, *, order: int | str = "auto", dc_gain: str = "auto", stable: bool = True, T: float | None = None,
             max_order: int = 30, algorithm: str = "auto") -> FitOutcome:
    """Diagnose, choose the order and identify a ROM.

    Parameters
    ----------
    frf : sysid.FrequencyResponse
        From :func:`load_data`.
    order : int or "auto"
    dc_gain : {"auto", "match", "none"}
        ``"auto"``: ``"match"`` when the data have an ``omega = 0`` sample.
    stable : bool
    T : float, optional
        Overrides the data's sampling period; default the data's, else :func:`sysid.diagnostics.default_T`.
    max_order : int
        For ``order="auto"``.
    algorithm : {"auto", "relocation", "subspace"}
        :func:`sysid.identify`'s (``"subspace"`` with ``--dc-gain none --no-stable`` is the paper's method).

    Returns
    -------
    FitOutcome
    """
    import sysid
    from sysid.data_checks import check_nonzero_outputs
    from sysid.diagnostics import default_T

    t0 = time.perf_counter()
    src = _source(frf)
    if T is not None:
        if frf.omega is None:  # discrete frequencies without a T: this T places them
            frf = sysid.FrequencyResponse(frf.H, frf.omega_d, T, inputs=frf.inputs, outputs=frf.outputs,
                                          metadata=frf.metadata)
        frf, T_rule = frf.with_T(T), f"T = {T:.6g} (given)"
    elif frf.T is not None:
        T_rule = f"T = {frf.T:.6g} (from the data file)"
    elif frf.omega is None:
        raise FitInputError(src, "--T", "the data are on discrete frequencies omega_d without a sampling period; "
                                        "give it with --T (fit_data(..., T=...))")
    else:
        Td = default_T(frf.omega)
        frf = frf.with_T(Td)
        w = frf.omega[np.isfinite(frf.omega) & (frf.omega > 0)]
        T_rule = (f"T = {Td:.6g} (default 2 / sqrt(omega_lo omega_hi), omega from {w.min():.4g} to {w.max():.4g}: "
                  "their geometric mean maps to omega_d = pi/2)")
    diag = sysid.diagnose(frf)
    if dc_gain == "auto":
        dc_gain = "match" if diag.has_dc else "none"
    if dc_gain == "match" and not diag.has_dc:
        raise FitInputError(src, "--dc-gain", "match needs an omega = 0 sample in the data; add it or use "
                                              "--dc-gain none")
    dc = None
    if dc_gain == "match":
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # diagnose() reports a complex DC sample
            dc = np.array(frf.dc_gain)
    check_nonzero_outputs(frf.H, frf.outputs)  # before the hold-out fits, which would skip every order for it
    selection = None
    if order == "auto":
        selection = holdout_order(frf, max_order=max_order, dc_gain=dc, stable=stable, algorithm=algorithm)
        n = selection.chosen
    else:
        n = int(order)
    import warnings

    try:
        with warnings.catch_warnings(record=True) as caught:   # reported with the fit, not as Python warnings
            warnings.simplefilter("always")
            res = sysid.identify(frf, n, dc_gain=dc, stable=stable, algorithm=algorithm)
    except sysid.OrderError as e:
        raise FitInputError(src, "--order", str(e)) from None
    notes = tuple(dict.fromkeys(str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)))
    for w in caught:   # anything else (a library's deprecation, ...) goes on as it came
        if not issubclass(w.category, RuntimeWarning):
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    options = {"order": order, "dc_gain": dc_gain, "stable": bool(stable), "max_order": max_order,
               "algorithm": res.algorithm}
    return FitOutcome(data=frf, diagnostics=diag, result=res, selection=selection, T_rule=T_rule, options=options,
                      elapsed=time.perf_counter() - t0, warnings=notes)


# ---------------------------------------------------------------------------------------------
# Writing
# ---------------------------------------------------------------------------------------------

def _continuous_poles(res, limit: int = 12) -> str:
    """The ROM's poles mapped to the s-plane, sorted by |s|, as text (at most ``limit``)."""
    z = np.linalg.eigvals(np.asarray(res.model.A))
    with np.errstate(divide="ignore", invalid="ignore"):
        s = (2.0 / res.T) * (z - 1.0) / (z + 1.0)
    s = s[np.argsort(np.abs(s))]
    s = s[s.imag >= -1e-12 * np.maximum(1.0, np.abs(s))]  # one of each conjugate pair
    txt = ", ".join(f"{v.real:.4g}" if abs(v.imag) <= 1e-9 * max(1.0, abs(v)) else f"{v.real:.4g} +- {abs(v.imag):.4g}i"
                    for v in s[:limit])
    return txt + (f", ... ({s.size - limit} more)" if s.size > limit else "")


def _model_dc(res) -> np.ndarray:
    return res.evaluate(np.array([0.0]))[:, :, 0].real


def summary_markdown(out: FitOutcome, data_path, command: str | None = None) -> str:
    """The Markdown summary of a fit: data, diagnostics, order and why, errors, DC, stability, files."""
    res, frf, diag = out.result, out.data, out.diagnostics
    p, m, K = frf.shape
    w = frf.omega
    fin = w[np.isfinite(w)]
    lines = [f"# ROM fitted to {Path(data_path).name}", ""]
    if command:
        lines += ["```", command, "```", ""]
    lines += [
        "## Data", "",
        f"- {p} output(s) {list(frf.outputs)}, {m} input(s) {list(frf.inputs)}, {K} frequencies, omega from "
        f"{fin.min():.4g} to {fin.max():.4g} (U/c; k = omega/2 from {fin.min() / 2:.4g} to {fin.max() / 2:.4g})"
        + ("; plus omega = inf" if np.isinf(w).any() else ""),
        f"- {out.T_rule}", "",
        "## Data diagnostics (`sysid.diagnose`)", "", diag.markdown(), "",
        "## Order", "",
    ]
    if out.selection is None:
        lines.append(f"- order {res.order}, given (--order {res.order})")
    else:
        sel = out.selection
        lines.append(f"- order **{sel.chosen}** by {sel.rule}")
        fin_e = np.isfinite(sel.errors)
        lines += ["", "| order | hold-out RMS error |", "| --- | --- |"]
        lines += [f"| {n} | {e:.3e} |" for n, e in zip(sel.orders[fin_e], sel.errors[fin_e])]
    lines += ["", "## Fit (`sysid.identify`)", ""]
    enf = ", ".join(k for k, v in res.enforced.items() if v) or "none"
    lines += [f"- options: dc_gain={out.options['dc_gain']}, stable={out.options['stable']}; algorithm "
              f"{out.options.get('algorithm', res.algorithm)}; enforced: {enf}",
              f"- spectral radius {res.spectral_radius:.6f} ({'stable' if res.spectral_radius < 1 else 'UNSTABLE'})",
              f"- continuous poles (s in U/c, by the inverse bilinear map s = (2/T)(z - 1)/(z + 1)): "
              f"{_continuous_poles(res)}",
              "", "| output | max error / peak | RMS error / RMS | DC error |", "| --- | --- | --- | --- |"]
    dcm = _model_dc(res)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        dcd = frf.dc_gain
    for i, o in enumerate(frf.outputs):
        if dcd is not None:
            scale = max(float(np.abs(dcd[i]).max()), np.finfo(float).tiny)
            dce = f"{float(np.abs(dcm[i] - dcd[i]).max()) / scale:.2e}"
        else:
            dce = "no omega = 0 sample"
        lines.append(f"| {o} | {res.errors.max_rel_per_output[i]:.3e} | {res.errors.rms_rel_per_output[i]:.3e} "
                     f"| {dce} |")
    lines += ["", "Errors are over all data frequencies: max |model - data| over the output's peak |data|, RMS "
              "error over the RMS of the data (`sysid.metrics`); DC error relative to |H(0)|.", ""]
    if out.warnings:
        lines += ["**Warnings of the fit** (`sysid.identify`):", ""] + [f"- {note}" for note in out.warnings] + [""]
    lines += ["## Files", "",
              "- `rom.npz`, `rom.mat`: discrete model `A, B, C, D, T` (sampling period T, bilinear map; in MATLAB "
              "`r = load('rom.mat'); sys = ss(r.A, r.B, r.C, r.D, r.T)`; `d2c(sys, 'tustin')` gives the continuous "
              "model)",
              "- `bode.png`: data and ROM; `error.png`: |model - data| / peak against frequency; `hankel.png`: "
              "Hankel singular values; `poles.png`: poles in the z-plane", ""]
    return "\n".join(lines)


def write_outputs(out: FitOutcome, data_path, out_dir, *, command: str | None = None,
                  figures: bool = True) -> dict[str, Path]:
    """Write ``rom.npz``, ``rom.mat``, ``summary.md`` and the figures to ``out_dir``; returns their paths."""
    from .rom_export import export_rom_mat, export_rom_npz

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    res = out.result
    meta = dict(source=str(Path(data_path).name), order=int(res.order), T=float(res.T),
                dc_gain=out.options["dc_gain"], stable=out.options["stable"],
                max_error_per_output=dict(zip(out.data.outputs, map(float, res.errors.max_rel_per_output))),
                spectral_radius=float(res.spectral_radius), time="convective, s = t U / c",
                frequency="omega in U/c, k = omega / 2; discrete model with the bilinear map, dt = T")
    paths = {"npz": export_rom_npz(out_dir / "rom.npz", res.model, meta),
             "mat": export_rom_mat(out_dir / "rom.mat", res.model, meta)}
    md = out_dir / "summary.md"
    atomic_write_text(md, summary_markdown(out, data_path, command))
    paths["summary"] = md
    if figures:
        from .fit_plots import write_figures

        paths.update(write_figures(out, out_dir))
    return paths


def print_summary(out: FitOutcome, file=None) -> None:
    """Short plain-text summary on ``file`` (default stdout)."""
    res = out.result
    file = file or sys.stdout
    print(out.diagnostics.summary(), file=file)
    why = out.selection.rule if out.selection else "given"
    print(f"{out.T_rule}", file=file)
    print(f"order {res.order} ({why})", file=file)
    per = ", ".join(f"{o} {e:.2e}" for o, e in zip(out.data.outputs, res.errors.max_rel_per_output))
    dc = f"DC error {res.dc_error:.1e}" if res.dc_error is not None else "no omega = 0 sample (DC not checked)"
    print(f"max error / peak: {per}; {dc}; spectral radius {res.spectral_radius:.6f}", file=file)
    for note in out.warnings + tuple(result_warnings(out)):
        print(f"warning: {note}", file=file)


FIT_ERROR_WARNING = 0.05
"""Max error / peak (any output) above which ``lfdrom fit`` warns that the ROM is far off its data (the same limit
as ``studies.commands.ROM_ERROR_WARNING`` of ``lfdrom rom``; a test checks they agree)."""


def result_warnings(out: FitOutcome) -> list:
    """What ``lfdrom fit`` warns about the ROM it wrote: unstable (spectral radius >= 1, e.g. with ``--no-stable``)
    or more than :data:`FIT_ERROR_WARNING` of the peak off its data in some output. Empty for a sound ROM."""
    res = out.result
    notes = []
    if not res.spectral_radius < 1.0:
        notes.append(f"the ROM is unstable (spectral radius {res.spectral_radius:.6g} >= 1): its time responses grow "
                     "without bound; fit with --stable (the default)")
    far = [(o, float(e)) for o, e in zip(out.data.outputs, res.errors.max_rel_per_output)]
    far = [(o, e) for o, e in far if not e <= FIT_ERROR_WARNING]
    if far:
        what = ", ".join(f"{o} {100 * e:.3g} %" for o, e in far)
        notes.append(f"the ROM is far off its data (max error / peak: {what}; more than {100 * FIT_ERROR_WARNING:g} %): "
                     "try another --order, and see what the data diagnostics above flag")
    return notes


# ---------------------------------------------------------------------------------------------
# Command line
# ---------------------------------------------------------------------------------------------

def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``fit`` on an ``argparse`` subparsers object."""
    p = subparsers.add_parser(
        "fit", help="fit a stable, DC-exact ROM to your own frequency-response data (.npz, .mat, .csv)",
        description="Read frequency-response data (.npz, MATLAB .mat or CSV; formats in docs/fit.md), check them "
                    "for consistency with a causal, stable, real system, choose the order and write the ROM "
                    "(rom.npz, rom.mat), summary.md and figures to --out.")
    p.add_argument("data", type=Path, metavar="DATA", help="data file: .npz, .mat or .csv")
    p.add_argument("--order", default="auto", metavar="N|auto",
                   help="model order, or auto (default): hold-out selection on alternate frequencies")
    p.add_argument("--max-order", type=int, default=30, help="largest order tried by --order auto (default 30)")
    p.add_argument("--dc-gain", choices=("match", "none"), default=None,
                   help="match the omega = 0 sample exactly (default: match when the data have it)")
    p.add_argument("--stable", action=argparse.BooleanOptionalAction, default=True,
                   help="enforce a stable model (default --stable)")
    p.add_argument("--algorithm", choices=("auto", "relocation", "subspace"), default="auto",
                   help="sysid.identify's algorithm: relocation (pole relocation, the default for one input or "
                        "output with --stable or a DC gain), subspace (McKelvey + convex refits; with --dc-gain none "
                        "--no-stable the paper's method); default auto")
    p.add_argument("--T", default=None, metavar="T",
                   help="sampling period of the bilinear map (convective units; e.g. 70/(2*pi)); default the file's, "
                        "else 2/sqrt(omega_lo omega_hi)")
    p.add_argument("--freq-unit", choices=FREQ_UNITS, default=None,
                   help="CSV: unit of the frequency column (omega in U/c, k = omega/2, omega_d in rad/sample)")
    p.add_argument("--input", default=None, metavar="NAME", help="CSV: the input's name (default '# input:' or u[0])")
    p.add_argument("--out", type=Path, default=None, help="output folder (default fit-<DATA stem>)")
    p.add_argument("--no-figures", action="store_true", help="write the ROM and the summary only")
    p.add_argument("--quiet", action="store_true", help="print only the files written")
    return p


def _parse_T(text: str | None, file) -> float | None:
    if text is None:
        return None
    try:
        v = parse_number(str(text))  # the study files' arithmetic: numbers, pi, e, tau, + - * / ** and parentheses
    except ValueError as e:
        raise FitInputError(file, "--T", f"{e} (e.g. 11.14 or 70/(2*pi))") from None
    if not (math.isfinite(v) and v > 0):
        raise FitInputError(file, "--T", f"must be positive and finite, got {text}")
    return v


def _parse_order(text, file) -> int | str:
    if str(text).lower() == "auto":
        return "auto"
    try:
        n = int(text)
    except ValueError:
        raise FitInputError(file, "--order", f"{text!r} is neither a positive integer nor 'auto'") from None
    if n < 1:
        raise FitInputError(file, "--order", f"must be >= 1, got {n}")
    return n


def cmd_fit(args) -> int:
    """Run ``lfdrom fit``; returns the exit status (0 ok, 1 identification failed, 2 bad input, 4 not written)."""
    import sysid

    def err(msg):
        print(f"lfdrom: error: {msg}", file=sys.stderr)

    try:
        T = _parse_T(args.T, args.data)
        order = _parse_order(args.order, args.data)
        if args.max_order < 1:
            raise FitInputError(args.data, "--max-order", f"must be >= 1, got {args.max_order}")
        frf = load_data(args.data, T=T, freq_unit=args.freq_unit, input_name=args.input)
    except FitInputError as e:
        err(str(e))
        return EXIT_BAD_INPUT
    out_dir = args.out if args.out is not None else Path(f"fit-{args.data.stem}")
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
        if not out_dir.is_dir():
            raise NotADirectoryError(f"{out_dir} is not a folder")
    except OSError as e:
        err(f"cannot write to {out_dir} ({e}); choose another --out")
        return EXIT_NOT_WRITTEN
    try:
        out = fit_data(frf, order=order, dc_gain=args.dc_gain or "auto", stable=args.stable, T=T,
                       max_order=args.max_order, algorithm=args.algorithm)
    except FitInputError as e:
        err(str(e))
        return EXIT_BAD_INPUT
    except (sysid.ConstraintError, sysid.FrequencyGridError, sysid.FrequencyDataError) as e:
        err(f"{args.data}: {e}")
        return EXIT_BAD_INPUT
    except Exception as e:  # noqa: BLE001 - the command line reports any failure with its type
        err(f"the identification of {args.data} failed: {type(e).__name__}: {e}")
        return EXIT_FAILED
    command = "lfdrom fit " + " ".join(sys.argv[2:]) if len(sys.argv) > 2 and sys.argv[1] == "fit" else None
    try:
        paths = write_outputs(out, args.data, out_dir, command=command, figures=not args.no_figures)
    except OSError as e:
        err(f"cannot write to {out_dir}: {e}")
        return EXIT_NOT_WRITTEN
    if not args.quiet:
        print_summary(out)
    print("wrote " + ", ".join(str(p) for p in paths.values()))
    if args.quiet:   # an unstable or poor ROM is never passed over in silence
        for note in result_warnings(out):
            print(f"lfdrom: warning: {note}", file=sys.stderr)
    return EXIT_OK
