"""``lfdrom fit DATA``: a stable, DC-exact ROM from anyone's frequency-response data.

The front door for frequency responses that did not come from lfdrom's CFD (a loads team's own CFD, a
wind-tunnel test). It reads the data (:func:`load_data`), checks them (:func:`sysid.diagnose`), chooses the
order (a number, or ``auto``: :func:`holdout_order`), fits with :func:`sysid.identify` and writes the ROM
(``rom.npz`` and ``rom.mat``, :mod:`studies.store.rom_export`), a Markdown summary (``summary.md``) and figures
(:mod:`studies.cli.fit_plots`) to ``--out``.

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
    frequency column: ``omega``, ``k``, ``omega_d``, ``rad/s`` or ``Hz``), ``T`` or ``input`` (the input's name).
    The first other line is the header: the frequency column first, named ``omega``, ``k`` or ``omega_d`` (any
    other name needs ``# frequency: ...`` or ``--frequency-unit``), then a ``NAME_re`` and a ``NAME_im`` column per
    output
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
  odd-indexed ones (held out). Every order ``1..--max-order`` (at most what the first set supports,
  :func:`supported_order`; a larger ``--max-order`` is capped with a note) is fitted to the first set with the same
  options as the final fit; its hold-out error is the largest over outputs of the RMS error on the held-out
  frequencies relative to the RMS of the data there. The order chosen is the *smallest* whose hold-out error
  is at most ``1.1 x`` the best plus ``1e-6`` (differences below that are solver round-off). The final model
  is then fitted to all the data.
- ``--dc-gain match|none|VALUE[,VALUE...]`` (default ``match`` when the data have an ``omega = 0`` sample, else
  ``none``; values: a known real DC gain, imposed, outputs by rows), ``--stable/--no-stable`` (default stable).
- ``--frequency-unit``: the unit of the frequencies (``rad/s`` and ``Hz`` for data in physical units): the figures'
  axes and the summary say what the data are instead of assuming an aerofoil's reduced frequency.

Exit status (``studies.cli.commands.EXIT_*``): 0 written; 1 the identification failed; 2 bad input (file, options),
reported with the file and the line (CSV) or key (``.npz``/``.mat``) and what to do; 4 the output folder
cannot be written.
"""

from __future__ import annotations

import argparse
import math
import multiprocessing
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["FitInputError", "FitOutcome", "load_data", "holdout_order", "supported_order", "fit_data", "write_outputs",
           "add_parser", "cmd_fit", "FREQ_UNITS", "FIT_FILES", "fit_marker", "written_by_fit", "check_out_dir"]

from .fit_data import FREQ_UNITS, FitInputError, load_data
from .exit_codes import EXIT_FAILED, EXIT_NOT_WRITTEN, EXIT_OK
from .exit_codes import EXIT_UNAVAILABLE as EXIT_BAD_INPUT  # 2: bad input, found before anything is computed
from ..store.files import atomic_write_text, generated_marker, generated_prefix, is_generated_page
from ..config.numbers import parse_number
from sysid import errors as _sysid_errors
from sysid.grids import period_range

HOLDOUT_RTOL, HOLDOUT_ATOL = 0.1, 1e-6
SYSID_INPUT_ERRORS = (_sysid_errors.FrequencyDataError, _sysid_errors.FrequencyGridError, _sysid_errors.OrderError,
                      _sysid_errors.ConstraintError, _sysid_errors.OptionError)
"""The typed errors of :mod:`sysid.errors` that say the input (data, frequencies, options) is unusable:
``lfdrom fit`` reports them as bad input (exit 2), not as a failed identification (``SolverError`` and anything
untyped: exit 1)."""
T_ADVICE = ("give the sampling period with --T (in the time unit of the frequencies), or rescale the frequencies "
            "(e.g. to rad/s, Hz or U/c) so that they are neither vanishingly small nor huge")
"""What to do about data whose frequencies no sampling period suits (said with a sysid grid error)."""
DEFAULT_MAX_ORDER = 30
"""``--max-order`` when not given: the largest order ``--order auto`` tries (fewer when the data support fewer)."""



# ---------------------------------------------------------------------------------------------
# Fitting
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class HoldoutSelection:
    """Result of :func:`holdout_order`: ``orders`` tried, their ``errors`` (NaN where the fit failed), the
    ``chosen`` order, the ``rule`` in words and ``supported``, the largest order the fitted frequencies support
    (:func:`supported_order`; no order above it is tried, whatever ``max_order`` asked)."""

    orders: np.ndarray
    errors: np.ndarray
    chosen: int
    rule: str
    supported: int | None = None


def supported_order(frf) -> int:
    """The largest order :func:`sysid.identify` accepts for these data (0 when none).

    :func:`sysid.max_order` for the data's grid: Algorithm 1 on McKelvey's equispaced grid
    (:attr:`sysid.FrequencyResponse.is_equispaced`), Algorithm 2 on any other, the way ``identify`` chooses. It
    is the most the subspace step supports whatever the target order, so an order above it is refused (an
    :class:`sysid.OrderError`) without fitting anything; more frequencies support more.

    Parameters
    ----------
    frf : sysid.FrequencyResponse
        Data with ``T`` (discrete frequencies).

    Returns
    -------
    int
    """
    import sysid

    if frf.nfreq < 2:
        return 0
    p, m = frf.shape[:2]
    return int(sysid.max_order(frf.nfreq - 1, "mckelvey1" if frf.is_equispaced else "mckelvey2", p, m))


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


def _holdout_error(part, val, den, n, dc_gain, stable, algorithm, effort="fast"):
    """Hold-out error of order ``n`` (the module docstring's measure), or ``"order"`` when the fitted half cannot
    support that order, or None when the fit failed otherwise."""
    import warnings

    import sysid

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            res = sysid.identify(part, int(n), dc_gain=dc_gain, stable=stable, algorithm=algorithm, effort=effort)
        Hm = res.evaluate(val.omega_d)
    except sysid.OrderError:
        return "order"
    except (ValueError, RuntimeError, np.linalg.LinAlgError):
        return None
    Hv = np.asarray(val.H)
    return float((np.sqrt(np.mean(np.abs(Hm - Hv) ** 2, axis=(1, 2))) / den).max())


def _holdout_errors(part, val, den, orders, dc_gain, stable, algorithm, workers, effort="fast"):
    """:func:`_holdout_error` of every order: in ``workers`` forked processes when there are several (the fits are
    independent and deterministic, so the answer does not depend on the split), highest order first (the
    costliest), else in this process."""
    args = [(part, val, den, int(n), dc_gain, stable, algorithm, effort) for n in orders]
    if workers > 1 and "fork" in multiprocessing.get_all_start_methods():
        with multiprocessing.get_context("fork").Pool(min(workers, len(args))) as pool:
            return pool.starmap(_holdout_error, args[::-1], chunksize=1)[::-1]
    return [_holdout_error(*a) for a in args]


def holdout_order(frf, *, max_order: int = DEFAULT_MAX_ORDER, dc_gain=None, stable: bool = True,
                  algorithm: str = "auto", workers: int | None = None, effort: str = "fast") -> HoldoutSelection:
    """Choose the order by hold-out (rule in the module docstring).

    Parameters
    ----------
    frf : sysid.FrequencyResponse
        Data with ``T``.
    max_order : int
        Largest order tried; at most :func:`supported_order` of the fitted half (``HoldoutSelection.supported``),
        above which every fit would be refused.
    dc_gain, stable, algorithm, effort
        As for :func:`sysid.identify` (``dc_gain`` is None or a (p, m) array; ``"match"`` is resolved by the
        caller so that the held-out half keeps the full data's DC value).
    workers : int, optional
        Processes that fit the orders side by side (forked, where the platform can fork; else one). Default:
        the machine's CPU count, at most 8. The chosen order does not depend on it.

    Returns
    -------
    HoldoutSelection
    """
    from sysid.data_checks import check_data_scale, check_nonzero_outputs

    # what would make every order fail, said as identify says it ("no order could be fitted" hid it)
    check_nonzero_outputs(frf.H, frf.outputs)
    check_data_scale(frf.H, frf.outputs)
    fit_idx, held = _split(frf)
    if held.size == 0:
        raise FitInputError(_source(frf), "--order", "too few frequencies to hold any out; give --order N")
    part, val = frf.take(fit_idx), frf.take(held)
    Hv = np.asarray(val.H)
    den = np.maximum(np.sqrt(np.mean(np.abs(Hv) ** 2, axis=(1, 2))), np.finfo(float).tiny)
    supported = supported_order(part)
    orders = np.arange(1, min(int(max_order), supported) + 1)   # above `supported` every fit is refused
    workers = min(os.cpu_count() or 1, 8) if workers is None else int(workers)
    results = _holdout_errors(part, val, den, orders, dc_gain, stable, algorithm, workers, effort)
    errs = np.full(orders.size, np.nan)
    for i, e in enumerate(results):
        if e == "order":
            if np.isfinite(errs[:i]).any():
                break  # above what the fitted half supports
            continue  # below what the data need (e.g. fewer states than inputs)
        if e is not None:
            errs[i] = e
    if not np.isfinite(errs).any():
        raise FitInputError(_source(frf), "--order", "no order could be fitted to the even-indexed frequencies; give "
                                                 "--order N")
    best = np.nanmin(errs)
    ok = np.flatnonzero(errs <= (1 + HOLDOUT_RTOL) * best + HOLDOUT_ATOL)
    chosen = int(orders[ok[0]])
    w = frf.omega if frf.omega is not None else frf.omega_d
    ends = [name for name, present in (("omega = 0", (w == 0).any()),
                                       ("omega = inf", np.isinf(w).any() or (frf.omega is None and (w >= np.pi).any())))
            if present]
    which = "even-indexed" + (f", plus {' and '.join(ends)}" if ends else "")
    rule = (f"hold-out: fitted orders 1..{int(orders[np.isfinite(errs)].max())} to {fit_idx.size} of the "
            f"{frf.nfreq} frequencies ({which}), measured on the other {held.size}; "
            f"chose the smallest order whose hold-out error is <= 1.1 x the best ({best:.3g}) + 1e-6")
    return HoldoutSelection(orders=orders, errors=errs, chosen=chosen, rule=rule, supported=supported)


T_BAND_FACTOR = 10.0
"""How far outside the data's band the centre frequency ``2/T`` of the bilinear map may lie (module docstring)."""


def check_T_against_data(source, omega, T: float, where: str = "--T") -> None:
    """Refuse a sampling period that maps the data's frequencies onto one end of the unit circle.

    The rule of ``lfdrom run`` (:data:`studies.schema.T_RANGE`: the map's centre frequency ``2/T``, which goes
    to ``omega_d = pi/2``, within the band of the response), with the data's own band and a factor
    :data:`T_BAND_FACTOR` of slack either side: ``omega_lo / 10 <= 2/T <= 10 omega_hi`` (smallest positive and
    largest finite ``omega``). Then the band reaches past ``omega_d = 2 atan(1/10) = 0.2`` rad from ``z = 1``
    and from ``z = -1``; beyond it every sample crowds into one end (``T = 1e-300``: all of them within 1e-297
    rad of ``z = 1``, and the fit, the diagnostics and their errors are round-off and NaN).

    Raises
    ------
    FitInputError
        Names ``where`` (``--T`` or the file's key), the band and the range of T that fits it.
    """
    w = np.asarray(omega, dtype=float)
    w = w[np.isfinite(w) & (w > 0)]
    if w.size == 0:
        return
    lo, hi = float(w.min()), float(w.max())
    T_min, T_max = period_range(w, T_BAND_FACTOR)   # sysid's one rule for a period against a band
    if T_min <= T <= T_max:
        return
    side = ("far above the data's band: every sample maps near omega_d = 0 (z = 1), the model would be fitted to "
            "the DC gain alone" if T < T_min else
            "far below the data's band: every sample maps near omega_d = pi (z = -1), the model would be fitted to "
            "the high-frequency limit alone")
    raise FitInputError(source, where, f"T = {T:.6g} puts the bilinear map's centre frequency 2/T = {2.0 / T:.3g} "
                                       f"{side} (omega from {lo:.4g} to {hi:.4g}); use {T_min:.4g} <= T <= "
                                       f"{T_max:.4g}, or leave --T out for 2/sqrt(omega_lo omega_hi) = "
                                       f"{2.0 / np.sqrt(lo * hi):.4g}")


def _dc_values(source, values, shape) -> np.ndarray:
    """A known DC gain as a real ``(p, m)`` array: ``p m`` values, outputs by rows (``--dc-gain 6.28,-0.11``)."""
    p, m = shape
    try:
        a = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise FitInputError(source, "--dc-gain", f"{values!r} is not a list of real numbers") from None
    if a.size != p * m:
        raise FitInputError(source, "--dc-gain", f"{a.size} value(s) for {p} output(s) x {m} input(s); give {p * m} "
                                                 "(outputs by rows: H(0)[0, 0], H(0)[0, 1], ..., H(0)[1, 0], ...), or "
                                                 "match or none")
    if not np.isfinite(a).all():
        raise FitInputError(source, "--dc-gain", f"{values!r}: the DC gain must be finite")
    return a.reshape(p, m)


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
             max_order: int = DEFAULT_MAX_ORDER, algorithm: str = "auto", effort: str = "fast") -> FitOutcome:
    """Diagnose, choose the order and identify a ROM.

    Parameters
    ----------
    frf : sysid.FrequencyResponse
        From :func:`load_data`.
    order : int or "auto"
    dc_gain : {"auto", "match", "none"} or array_like (p, m)
        ``"auto"``: ``"match"`` when the data have an ``omega = 0`` sample. An array: the known real DC gain,
        imposed (data without an ``omega = 0`` sample, or a DC value known better than the data's).
    stable : bool
    T : float, optional
        Overrides the data's sampling period; default the data's, else :func:`sysid.diagnostics.default_T`.
    max_order : int
        For ``order="auto"``.
    algorithm : {"auto", "relocation", "subspace"}
        :func:`sysid.identify`'s (``"subspace"`` with ``--dc-gain none --no-stable`` is the paper's method).
    effort : {"fast", "thorough"}
        :func:`sysid.identify`'s (the relocation's candidates), for the hold-out fits and the final one.

    Returns
    -------
    FitOutcome

    Raises
    ------
    FitInputError
        Unusable options or data: a ``T`` that does not suit the frequencies, no default ``T`` for them (a
        :data:`SYSID_INPUT_ERRORS` of :func:`sysid.diagnostics.default_T`), ``match`` without an ``omega = 0``
        sample, an order the data do not support.
    sysid.FrequencyDataError, sysid.FrequencyGridError, sysid.ConstraintError, sysid.OptionError
        From the diagnostics or the fit (:data:`SYSID_INPUT_ERRORS`; ``lfdrom fit`` reports them as bad input).
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
        try:
            Td = default_T(frf.omega)
        except SYSID_INPUT_ERRORS as e:   # e.g. frequencies so small that omega_lo omega_hi underflows
            raise FitInputError(src, "--T", f"no default sampling period for these frequencies ({e}); {T_ADVICE}") \
                from None
        frf = frf.with_T(Td)
        w = frf.omega[np.isfinite(frf.omega) & (frf.omega > 0)]
        T_rule = (f"T = {Td:.6g} (default 2 / sqrt(omega_lo omega_hi), omega from {w.min():.4g} to {w.max():.4g}: "
                  "their geometric mean maps to omega_d = pi/2)")
    if frf.omega is not None:   # continuous data: T places them on the unit circle (data in omega_d: T does not)
        check_T_against_data(src, frf.omega, frf.T, "--T" if T is not None else "key 'T'")
    import warnings

    with warnings.catch_warnings(record=True) as caught_diag:   # reported with the fit, never with a source line
        warnings.simplefilter("always")
        diag = sysid.diagnose(frf)
    given_dc = None if isinstance(dc_gain, str) else _dc_values(src, dc_gain, frf.shape[:2])
    if not diag.has_dc:   # sysid's advice, in this command's terms, and none when the user chose
        from dataclasses import replace

        keep = tuple(w for w in diag.warnings if not w.startswith("no omega = 0 sample"))
        if dc_gain == "auto":
            keep += ("no omega = 0 sample: the DC gain is neither imposed nor checked; give it with --dc-gain "
                     "VALUE[,VALUE...] if you know it",)
        diag = replace(diag, warnings=keep)
    if given_dc is not None:
        dc_gain = "given"
    elif dc_gain == "auto":
        dc_gain = "match" if diag.has_dc else "none"
    if dc_gain == "match" and not diag.has_dc:
        raise FitInputError(src, "--dc-gain", "match needs an omega = 0 sample in the data; add it or use "
                                              "--dc-gain none")
    dc = given_dc
    if dc_gain == "match":
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # diagnose() reports a complex DC sample
            dc = np.array(frf.dc_gain)
    check_nonzero_outputs(frf.H, frf.outputs)  # before the hold-out fits, which would skip every order for it
    selection = None
    if order == "auto":
        selection = holdout_order(frf, max_order=max_order, dc_gain=dc, stable=stable, algorithm=algorithm,
                                  effort=effort)
        n = selection.chosen
    else:
        n = int(order)
    import warnings

    try:
        with warnings.catch_warnings(record=True) as caught:   # reported with the fit, not as Python warnings
            warnings.simplefilter("always")
            res = sysid.identify(frf, n, dc_gain=dc, stable=stable, algorithm=algorithm, effort=effort)
    except sysid.OrderError as e:
        raise FitInputError(src, "--order", str(e)) from None
    notes = tuple(dict.fromkeys(str(w.message) for w in list(caught_diag) + list(caught)
                                if issubclass(w.category, RuntimeWarning)))
    for w in list(caught_diag) + list(caught):   # anything else (a library's deprecation, ...) goes on as it came
        if not issubclass(w.category, RuntimeWarning):
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    options = {"order": order, "dc_gain": dc_gain, "stable": bool(stable), "max_order": max_order,
               "algorithm": res.algorithm, "effort": effort}
    if given_dc is not None:
        options["dc_values"] = given_dc
    return FitOutcome(data=frf, diagnostics=diag, result=res, selection=selection, T_rule=T_rule, options=options,
                      elapsed=time.perf_counter() - t0, warnings=notes)


# ---------------------------------------------------------------------------------------------
# Writing
# ---------------------------------------------------------------------------------------------

FIT_FILES = ("summary.md", "rom.npz", "rom.mat", "bode.png", "error.png", "hankel.png", "poles.png")
"""The files ``lfdrom fit`` writes to its ``--out`` folder; it replaces one only when it carries the fit's marker."""

_FIGURES = tuple(name for name in FIT_FILES if name.endswith(".png"))


def fit_marker(data_path) -> str:
    """The generator marker of the files of one fit (:func:`studies.files.generated_marker` of ``lfdrom fit``):
    the first line of ``summary.md``, the ``generator`` entry of the ROM files' metadata and the ``generator``
    text chunk of the figures."""
    return generated_marker(Path(data_path).name, program="fit",
                            note="lfdrom fit replaces the files of this folder that carry this marker (this summary, "
                                 "rom.npz, rom.mat and the figures) when it fits into the folder again, and no other")


def written_by_fit(path) -> bool:
    """Whether the file at ``path`` carries ``lfdrom fit``'s generator marker (so that replacing it loses nothing
    the fit cannot write again).

    ``.md``: the first line (:func:`studies.files.is_generated_page`); ``.npz`` and ``.mat``: the ``generator``
    entry of the JSON ``metadata`` (:mod:`studies.rom_export`); ``.png``: the ``generator`` text chunk. A file
    that cannot be read as its suffix says (someone else's) is not ours; a missing one is not either.
    """
    import json

    path = Path(path)
    prefix = generated_prefix("fit")
    if not path.is_file():
        return False
    suffix = path.suffix.lower()
    try:
        if suffix == ".md":
            return is_generated_page(path, program="fit")
        if suffix == ".npz":
            with np.load(path, allow_pickle=False) as z:
                meta = json.loads(str(z["metadata"]))
        elif suffix == ".mat":
            import scipy.io

            meta = json.loads(str(np.squeeze(scipy.io.loadmat(path, variable_names=["metadata"])["metadata"])))
        elif suffix == ".png":
            from PIL import Image

            with Image.open(path) as im:
                meta = {"generator": getattr(im, "text", {}).get("generator", "")}
        else:
            return False
    except Exception:  # noqa: BLE001 - unreadable as ours: someone else's file
        return False
    return isinstance(meta, dict) and str(meta.get("generator", "")).startswith(prefix)


def check_out_dir(out_dir, data_path) -> None:
    """Refuse an output folder where ``lfdrom fit`` would destroy a file that is not its own.

    Raises
    ------
    FitInputError
        ``out_dir`` holds the data file itself, or a file of a name in :data:`FIT_FILES` without the fit's
        generator marker (:func:`written_by_fit`: the user's own ``summary.md``, ``rom.mat``, a figure...); the
        message names them and says what to do. Nothing is written or created.
    """
    out_dir, data = Path(out_dir), Path(data_path)
    if not out_dir.is_dir():
        return  # a new folder (or a file in its place: reported when the folder is created)
    here = out_dir.resolve()
    if here in (data.absolute().parent.resolve(), data.resolve().parent):
        raise FitInputError(out_dir, "--out", f"holds the input {data.name}: lfdrom fit writes its files into a folder "
                                              f"of their own; give another --out (default fit-{data.stem})")
    foreign = [name for name in FIT_FILES if (out_dir / name).exists() or (out_dir / name).is_symlink()]
    foreign = [name for name in foreign if (out_dir / name).is_symlink() or not written_by_fit(out_dir / name)]
    if foreign:
        raise FitInputError(out_dir, "--out", f"holds {', '.join(foreign)}, not written by lfdrom fit (no generator "
                                              f"marker '{generated_prefix('fit')} ...'), which the fit would replace; "
                                              "they are left as they are: give another --out (a new folder) or move "
                                              "them away")

def _band(frf) -> str:
    """The data's band in their own unit (:func:`studies.fit_data.frequency_axis`), and in omega."""
    from .fit_data import frequency_axis

    label, scale, unit = frequency_axis(frf)
    w = frf.omega
    fin = w[np.isfinite(w)]
    lo, hi = fin.min(), fin.max()
    if unit == "k":
        text = f"omega from {lo:.4g} to {hi:.4g} (U/c; k = omega/2 from {lo / 2:.4g} to {hi / 2:.4g})"
    elif unit in ("", "1/T"):
        text = f"omega from {lo:.4g} to {hi:.4g}"
    else:
        name = "f" if unit.endswith("Hz") else "omega"
        text = f"{name} from {lo * scale:.4g} to {hi * scale:.4g} {unit} (omega from {lo:.4g} to {hi:.4g})"
    return text + ("; plus omega = inf" if np.isinf(w).any() else "")


def _time_unit(frf) -> str:
    """The time unit of T and of the continuous poles: that of the data's frequencies."""
    from .fit_data import frequency_axis

    unit = frequency_axis(frf)[2]
    return {"k": "c/U (convective)", "": "the data's time unit", "1/T": "the data's time unit"}.get(unit, "s")


def _continuous_poles(res, limit: int = 12) -> str:
    """The ROM's poles mapped to the s-plane, sorted by |s|, as text (at most ``limit``)."""
    z = np.linalg.eigvals(np.asarray(res.matrices.A))
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
    lines = [fit_marker(data_path), f"# ROM fitted to {Path(data_path).name}", ""]
    if command:
        lines += ["```", command, "```", ""]
    lines += [
        "## Data", "",
        f"- {p} output(s) {list(frf.outputs)}, {m} input(s) {list(frf.inputs)}, {K} frequencies, {_band(frf)}",
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
              f"{out.options.get('algorithm', res.algorithm)}"
              + (f" (effort {out.options['effort']})" if res.algorithm == "relocation" and "effort" in out.options
                 else "") + f"; enforced: {enf}",
              f"- spectral radius {res.spectral_radius:.6f} ({'stable' if res.spectral_radius < 1 else 'UNSTABLE'})",
              f"- continuous poles (s in rad per {_time_unit(frf).split(' (')[0]}, by the inverse bilinear map s = "
              f"(2/T)(z - 1)/(z + 1)): "
              f"{_continuous_poles(res)}",
              "", "| output | max error / peak | RMS error / RMS | DC error | between the samples (estimate) / peak "
              "| left open by the samples / peak |", "| --- | --- | --- | --- | --- | --- |"]
    dcm = _model_dc(res)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        dcd = frf.dc_gain
    given = out.options.get("dc_values")
    for i, o in enumerate(frf.outputs):
        if given is not None:
            scale = max(float(np.abs(given[i]).max()), np.finfo(float).tiny)
            dce = f"{float(np.abs(dcm[i] - given[i]).max()) / scale:.2e} (to the given DC gain)"
        elif dcd is not None:
            scale = max(float(np.abs(dcd[i]).max()), np.finfo(float).tiny)
            dce = f"{float(np.abs(dcm[i] - dcd[i]).max()) / scale:.2e}"
        else:
            dce = "no omega = 0 sample"
        lines.append(f"| {o} | {res.errors.max_rel_per_output[i]:.3e} | {res.errors.rms_rel_per_output[i]:.3e} "
                     f"| {dce} | {res.between_error_per_output[i]:.2e} | {res.between_uncertainty_per_output[i]:.2e} |")
    lines += ["", "Errors are over all data frequencies: max |model - data| over the output's peak |data|, RMS "
              "error over the RMS of the data (`sysid.metrics`); DC error relative to |H(0)|. Between the samples "
              "(`sysid.between`, no truth used): the model's largest departure from local readings of the samples, "
              "beyond their spread, at every interval's midpoint and the model's resonances; left open: how far "
              "those readings disagree - where it is larger than the estimate, the estimate is a lower bound.", ""]
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
    """Write ``rom.npz``, ``rom.mat``, ``summary.md`` and the figures to ``out_dir``; returns their paths.

    Each file carries the fit's generator marker (:func:`fit_marker`); a file of the same name without it, or a
    folder that holds the data file, is refused before anything is written (:func:`check_out_dir`). Without
    ``figures`` the figures of an earlier fit in the folder (ours, by their marker) are removed: they would show
    another model than the summary's.

    Raises
    ------
    FitInputError
        From :func:`check_out_dir`.
    OSError
        A file cannot be written (each is written atomically: an existing one is replaced whole or kept).
    """
    from ..store.rom_export import export_rom_mat, export_rom_npz

    out_dir = Path(out_dir)
    check_out_dir(out_dir, data_path)
    out_dir.mkdir(parents=True, exist_ok=True)
    res = out.result
    from .fit_data import frequency_axis

    unit = frequency_axis(out.data)[2]
    time = _time_unit(out.data)
    meta = dict(generator=fit_marker(data_path), source=str(Path(data_path).name), order=int(res.order),
                T=float(res.T), dc_gain=out.options["dc_gain"], stable=out.options["stable"],
                max_error_per_output=dict(zip(out.data.outputs, map(float, res.errors.max_rel_per_output))),
                spectral_radius=float(res.spectral_radius), time=f"T in {time}",
                frequency=("omega in U/c, k = omega / 2" if unit == "k" else f"omega in rad per {time.split(' (')[0]}")
                + "; discrete model with the bilinear map, dt = T")
    if out.options.get("dc_values") is not None:
        meta["dc_gain_given"] = out.options["dc_values"]
    paths = {"npz": export_rom_npz(out_dir / "rom.npz", res.matrices, meta),
             "mat": export_rom_mat(out_dir / "rom.mat", res.matrices, meta)}
    md = out_dir / "summary.md"
    atomic_write_text(md, summary_markdown(out, data_path, command))
    paths["summary"] = md
    if figures:
        from .fit_plots import write_figures

        paths.update(write_figures(out, out_dir, text={"generator": fit_marker(data_path)}))
    else:
        for name in _FIGURES:
            if written_by_fit(out_dir / name):
                (out_dir / name).unlink()
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
    if out.options.get("dc_values") is not None:
        dc = "DC gain given (--dc-gain), imposed"
    else:
        dc = f"DC error {res.dc_error:.1e}" if res.dc_error is not None else "no omega = 0 sample (DC not checked)"
    print(f"max error / peak: {per}; {dc}; spectral radius {res.spectral_radius:.6f}", file=file)
    between = ", ".join(f"{o} {e:.2e} (left open {u:.2e})" for o, e, u in
                        zip(out.data.outputs, res.between_error_per_output, res.between_uncertainty_per_output))
    print(f"between the samples (estimate / peak, sysid.between): {between}", file=file)
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
    p.add_argument("--max-order", type=int, default=None,
                   help=f"largest order tried by --order auto (default {DEFAULT_MAX_ORDER}); never more than the "
                        "fitted half of the frequencies supports (a note says so when MAX_ORDER asks for more)")
    p.add_argument("--dc-gain", default=None, metavar="match|none|VALUE[,VALUE...]",
                   help="match the omega = 0 sample exactly, none, or impose a known real DC gain (one value per "
                        "output and input, outputs by rows); default: match when the data have an omega = 0 sample")
    p.add_argument("--stable", action=argparse.BooleanOptionalAction, default=True,
                   help="enforce a stable model (default --stable)")
    p.add_argument("--algorithm", choices=("auto", "relocation", "subspace"), default="auto",
                   help="sysid.identify's algorithm: relocation (pole relocation, the default for one input or "
                        "output with --stable or a DC gain), subspace (McKelvey + convex refits; with --dc-gain none "
                        "--no-stable the paper's method); default auto")
    p.add_argument("--effort", choices=("fast", "thorough"), default="fast",
                   help="the relocation's candidates (sysid.identify's effort): fast (default) or thorough (about "
                        "2.5 times as long, for errors about equal on the aerofoil data)")
    p.add_argument("--T", default=None, metavar="T",
                   help="sampling period of the bilinear map (in the time unit of the frequencies: c/U for omega or "
                        "k, seconds for rad/s or Hz; e.g. 70/(2*pi)); default the file's, else "
                        "2/sqrt(omega_lo omega_hi)")
    p.add_argument("--frequency-unit", "--freq-unit", dest="freq_unit", choices=FREQ_UNITS, default=None,
                   help="unit of the frequencies: CSV, of the frequency column (omega, k = omega/2, omega_d in "
                        "rad/sample, rad/s, Hz); .npz/.mat, how their omega is shown (rad/s, Hz, k or omega); the "
                        "figures' axes and summary.md say it (default: the column's or key's name)")
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


def _parse_dc_gain(text, file):
    """``--dc-gain``: ``"auto"`` (not given), ``"match"``, ``"none"`` or a list of numbers (comma-separated)."""
    if text is None:
        return "auto"
    word = str(text).strip().lower()
    if word in ("match", "none"):
        return word
    try:
        return [float(v) for v in str(text).split(",")]
    except ValueError:
        raise FitInputError(file, "--dc-gain", f"{text!r} is neither match, none nor a list of numbers (e.g. "
                                               "--dc-gain 6.28,-0.11 for two outputs)") from None


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


def max_order_note(asked: int | None, out: FitOutcome) -> str | None:
    """What ``lfdrom fit`` says when ``--max-order`` asked for more orders than the data support, else None.

    ``--max-order`` bounds a search: orders above what the fitted half of the frequencies supports
    (:func:`supported_order`) would each be refused, so they are not tried and the search ends there, with the
    same choice it would have made. The note says so when the user gave the bound (the default is silent: it
    is documented as capped), with what the data support and how to get more.

    Parameters
    ----------
    asked : int or None
        ``--max-order`` as given; None when left out.
    out : FitOutcome

    Returns
    -------
    str or None
    """
    sel = out.selection
    if asked is None or sel is None or sel.supported is None or asked <= sel.supported:
        return None
    n_fit = _split(out.data)[0].size
    return (f"--max-order {asked} is more than the data support: the hold-out fits use {n_fit} of the "
            f"{out.data.nfreq} frequencies, which support orders up to {sel.supported} (sysid.max_order), so orders "
            f"1..{sel.supported} were tried; more frequencies support higher orders")


def cmd_fit(args) -> int:
    """Run ``lfdrom fit``; returns the exit status (0 ok, 1 identification failed, 2 bad input, 4 not written)."""
    import sysid

    def err(msg):
        print(f"lfdrom: error: {msg}", file=sys.stderr)

    try:
        T = _parse_T(args.T, args.data)
        order = _parse_order(args.order, args.data)
        dc_gain = _parse_dc_gain(args.dc_gain, args.data)
        max_order = DEFAULT_MAX_ORDER if args.max_order is None else args.max_order
        if max_order < 1:
            raise FitInputError(args.data, "--max-order", f"must be >= 1, got {max_order}")
        frf = load_data(args.data, T=T, freq_unit=args.freq_unit, input_name=args.input)
    except FitInputError as e:
        err(str(e))
        return EXIT_BAD_INPUT
    out_dir = args.out if args.out is not None else Path(f"fit-{args.data.stem}")
    try:
        check_out_dir(out_dir, args.data)   # before the fit: refused in a second, not after it
    except FitInputError as e:
        err(str(e))
        return EXIT_BAD_INPUT
    from ..store.files import probe_writable

    try:   # creates nothing: a fit refused below leaves no empty folder behind
        if out_dir.exists() and not out_dir.is_dir():
            raise NotADirectoryError(f"{out_dir} is not a folder")
        probe_writable(out_dir, what="fit's files", fix="choose another --out")
    except OSError as e:
        err(f"cannot write to {out_dir} ({e}); choose another --out")
        return EXIT_NOT_WRITTEN
    try:
        out = fit_data(frf, order=order, dc_gain=dc_gain, stable=args.stable, T=T,
                       max_order=max_order, algorithm=args.algorithm, effort=args.effort)
    except FitInputError as e:
        err(str(e))
        return EXIT_BAD_INPUT
    except SYSID_INPUT_ERRORS as e:   # sysid's typed input errors: the data or the options, not the method
        err(f"{args.data}: {e}" + (f"; {T_ADVICE}" if isinstance(e, sysid.FrequencyGridError) else ""))
        return EXIT_BAD_INPUT
    except Exception as e:  # noqa: BLE001 - the command line reports any failure with its type
        err(f"the identification of {args.data} failed: {type(e).__name__}: {e}")
        return EXIT_FAILED
    note = max_order_note(args.max_order, out)
    if note:
        print(f"lfdrom: note: {note}", file=sys.stderr)
    command = "lfdrom fit " + " ".join(sys.argv[2:]) if len(sys.argv) > 2 and sys.argv[1] == "fit" else None
    try:
        paths = write_outputs(out, args.data, out_dir, command=command, figures=not args.no_figures)
    except FitInputError as e:   # a foreign file appeared during the fit
        err(str(e))
        return EXIT_BAD_INPUT
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
