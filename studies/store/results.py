"""Results of a study read back from the results store: the contract between the runner and the reports.

:func:`load_results` reads what :func:`studies.run.runner.run_study` stored (it never computes) and returns a
:class:`StudyResults`: frozen records of plain NumPy arrays, no CFD objects. ``studies.report`` builds every
table and figure from it.

Records
-------
- :class:`FRFRecord` (case, T): the LFD gust response on ``sysid.mckelvey_grid(M_base, T)``.
- :class:`LTDRecord` (case, gust): the LTD reference history.
- :class:`RomRecord` (case, T, M, order, method): one identification, ``status`` ``"ok"`` or ``"failed"``.
- :class:`SimRecord` (case, T, M, order, method, gust): the ROM's gust history against the LTD one.

Metrics (computed by the tasks with :func:`sysid.metrics.rom_metrics` and
:func:`studies.sections.gust_rom.pieces.sim_metrics`, stored with the pieces)
------------------------------------------------------------------------------------------------------------
``RomRecord.metrics`` (``X`` is each output of the study, ``Cl`` and ``Cm`` by default):

- ``frf_max_err_X``, ``frf_rms_err_X``: relative FRF errors of the ROM against the LFD response on the full
  base grid (``M_base + 1`` points, also where a subsampled ROM was not fitted), per
  :mod:`sysid.metrics` (peak- and energy-normalised per output);
- ``frf_max_err_fit``, ``frf_rms_err_fit``: the overall errors on the ``M + 1`` points identified from;
- ``dc_err_X``: ``|G_rom(z = 1) - H(omega = 0)|`` (absolute, per radian);
- ``spectral_radius`` (discrete ROM at ``T``), ``stable`` (``spectral_radius < 1``), ``seconds``.

``SimRecord.metrics``: for each output ``X`` in ``Cl``, ``Cm`` (those the study computes), errors of the load
envelope (the largest positive and the largest negative load of a history, as loads engineers read them):

- ``peak_err_X = max(|max y_rom - max y_ltd|, |min y_rom - min y_ltd|) / max |y_ltd|``: the larger error of
  the two extremes, relative to the LTD's largest magnitude (so a history whose positive and negative extremes
  have nearly equal magnitudes is not judged by which of the two happens to be larger);
- ``t_peak_err_X = |t_peak_rom - t_peak_ltd|`` (convective time): ``t_peak_ltd`` is the time of the LTD's
  largest magnitude (:func:`sysid.history_metrics.peak`), ``t_peak_rom`` the time of the ROM's extreme of the same sign;
- ``rms_err_X = rms(y_rom - y_ltd) / rms(y_ltd)``;
- ``seconds_rom`` (re-discretisation and simulation) and ``seconds_ltd`` (the LTD march of that gust; when
  several gusts were marched together, their shared time divided by their number).

The store layout (arrays and metadata of each piece) is documented in :mod:`studies.sections.gust_rom.pieces`. Every
piece's metadata also holds ``status`` (``"ok"`` or ``"failed"``); a failed piece has no arrays and an ``error``
(``"ExceptionType: message"``). A failed steady flow or FRF marks the ROMs that need it failed (with that reason); a
failed LTD or ROM simulation is listed in :attr:`StudyResults.failed`.
"""

from __future__ import annotations

import importlib
import warnings
from dataclasses import dataclass, field
from typing import Any, Optional

import numpy as np

from sysid import FrequencyResponse
from sysid.history_metrics import envelope_errors, peak
from sysid.metrics import rom_metrics

from ..config.study import as_config
from .entries import error_text, failure_payload, is_failed, open_store, store_dependencies
from ..config.schema import StudyConfig
from ..sections.protocol import active_sections

__all__ = [
    "FRFRecord",
    "LTDRecord",
    "RomRecord",
    "SimRecord",
    "StudyResults",
    "load_results",
    "open_store",
    "store_dependencies",
    "failure_payload",
    "rom_metrics",
    "peak",
    "envelope_errors",
    "is_failed",
    "error_text",
]
# open_store, store_dependencies, failure_payload, is_failed and error_text are studies.store.entries', the metrics
# sysid.metrics' and sysid.history_metrics'; they are re-exported here, where they used to be. The gust-ROM pieces'
# payloads and keys (steady_payload, ..., sim_metrics, SIM_OUTPUTS) are studies.sections.gust_rom.pieces'; read here
# they still work, with a DeprecationWarning (__getattr__ below).

_GUST_ROM_NAMES = ("SIM_OUTPUTS", "frf_payload", "frf_piece", "ltd_payload", "ltd_piece", "rom_payload", "rom_piece",
                   "sim_metrics", "sim_payload", "sim_piece", "steady_payload", "steady_piece")


def __getattr__(name):
    if name in _GUST_ROM_NAMES:
        warnings.warn(f"studies.store.results.{name} moved to studies.sections.gust_rom.pieces.{name}: import it "
                      "from there (the old name is kept for one release)", DeprecationWarning, stacklevel=2)
        return getattr(importlib.import_module("studies.sections.gust_rom.pieces"), name)
    raise AttributeError(f"module 'studies.store.results' has no attribute {name!r}")

# ---------------------------------------------------------------------------------------------
# Records
# ---------------------------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class FRFRecord:
    """The LFD gust frequency response of one case at one ``T`` (``M + 1`` points, ``M = M_base``).

    Attributes
    ----------
    case : str
    T : float
        Sampling period of the bilinear map (convective time).
    M : int
        Grid intervals of the computed response (the study's ``M_base``).
    frf : sysid.FrequencyResponse
        ``H`` of shape (p, 1, M + 1), outputs of the study (``"Cl"``, ``"Cm"``), input ``"gust"``, per radian
        of gust angle; ``omega`` continuous (U/c units, last one ``inf``), ``omega_d`` and ``T``.
    seconds : float
        Compute time of the sweep (wall clock, s).
    method : str
        ``"direct"`` or ``"fast"`` (the LFD path that produced it; ``"auto"`` when the solver did not say).
    lfd : dict
        The LFD solver's own metadata as stored (``cfd.lfd_response``): for the fast sweep ``tol``,
        ``tol_met``, ``error_estimate`` (p, K) absolute per radian, ``residual_norm``, ``shifts``,
        ``basis_size``; empty for records made without a solver.
    """

    case: str
    T: float
    M: int
    frf: FrequencyResponse
    seconds: float
    method: str
    lfd: dict = field(default_factory=dict)

    @property
    def tol_met(self):
        """The fast sweep's verdict on its tolerance (None for the direct path: exact to round-off)."""
        return self.lfd.get("tol_met")

    @property
    def max_relative_error_estimate(self):
        """Largest estimated error of the sweep relative to ``|H|`` over the finite frequencies (NaN when the
        solver gave no estimate: the direct path)."""
        est = self.lfd.get("error_estimate")
        if est is None:
            return float("nan")
        est = np.asarray(est, dtype=float)
        H = np.abs(np.asarray(self.frf.H)[:, 0])
        fin = np.isfinite(self.frf.omega)
        scale = np.maximum(H[:, fin], 1e-3 * H[:, fin].max(axis=1, keepdims=True))
        return float(np.max(est[:, fin] / scale)) if np.any(fin) else float("nan")


@dataclass(frozen=True, eq=False)
class LTDRecord:
    """The LTD reference response of one case to one gust.

    Attributes
    ----------
    case, gust : str
        E.g. ``"T2"``, ``"G3"``.
    t : ndarray, shape (n + 1,)
        Convective time, ``0, dt, ..., t_end``.
    u : ndarray, shape (n + 1,)
        Gust input ``v_g(x_ref, t) / U`` at the gust's real amplitude.
    cl, cm : ndarray, shape (n + 1,)
        Load perturbations about the steady loads.
    seconds : float
        Compute time (s).
    """

    case: str
    gust: str
    t: np.ndarray
    u: np.ndarray
    cl: np.ndarray
    cm: np.ndarray
    seconds: float


@dataclass(frozen=True, eq=False)
class RomRecord:
    """One sweep point: case, ``T``, ``M`` (``N_omega = M + 1``), order and method variant.

    Attributes
    ----------
    case : str
    T : float
    M : int
    order : int
        ``N_r``.
    method : str
        The study's method-variant name (e.g. ``"dc_stable"``).
    status : {"ok", "failed"}
    error : str or None
        ``"ExceptionType: message"`` when failed.
    A, B, C, D : ndarray or None
        Discrete ROM at sampling period ``T``: shapes (n, n), (n, 1), (p, n), (p, 1); None when failed.
    hankel_sv : ndarray, shape (q,), or None
        Hankel singular values of the subspace step.
    frf_rom : ndarray, complex, shape (p, 1, M_base + 1), or None
        The ROM at the :class:`FRFRecord`'s ``omega_d`` points.
    metrics : dict
        See the module docstring; empty when failed.
    """

    case: str
    T: float
    M: int
    order: int
    method: str
    status: str
    error: Optional[str] = None
    A: Optional[np.ndarray] = None
    B: Optional[np.ndarray] = None
    C: Optional[np.ndarray] = None
    D: Optional[np.ndarray] = None
    hankel_sv: Optional[np.ndarray] = None
    frf_rom: Optional[np.ndarray] = None
    metrics: dict = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        """``status == "ok"``."""
        return self.status == "ok"

    def model(self, outputs=("Cl", "Cm"), inputs=("gust",)):
        """The discrete ROM as a ``control.StateSpace`` (``dt = T``).

        Raises
        ------
        ValueError
            The point failed (no model).
        """
        if not self.ok:
            raise ValueError(f"sweep point {self.label()} failed ({self.error}); it has no model")
        import control

        p = self.C.shape[0]
        outs = list(outputs)[:p] if len(outputs) >= p else [f"y[{i}]" for i in range(p)]
        return control.ss(self.A, self.B, self.C, self.D, self.T, inputs=list(inputs), outputs=outs)

    def label(self) -> str:
        """Short text naming the point, e.g. ``"T2 T=11.1408 M=256 N_r=9 plain"``."""
        return f"{self.case} T={self.T:.6g} M={self.M} N_r={self.order} {self.method}"


@dataclass(frozen=True, eq=False)
class SimRecord:
    """A ROM's response to one gust, against the LTD one.

    Attributes
    ----------
    case : str
    T : float
    M : int
    order : int
    method : str
    gust : str
    t : ndarray, shape (n + 1,)
        The LTD time grid (convective time).
    cl, cm : ndarray, shape (n + 1,)
        ROM loads (perturbations) at the gust's real amplitude.
    metrics : dict
        See the module docstring.
    """

    case: str
    T: float
    M: int
    order: int
    method: str
    gust: str
    t: np.ndarray
    cl: np.ndarray
    cm: np.ndarray
    metrics: dict = field(default_factory=dict)


_ROM_COLUMNS = ("case", "T", "M", "N_omega", "order", "method", "status", "error")
_SIM_COLUMNS = ("case", "T", "M", "N_omega", "order", "method", "gust")


@dataclass(frozen=True, eq=False)
class StudyResults:
    """What the store holds for a study (complete or not).

    Attributes
    ----------
    config : StudyConfig
    frf : dict of (case, T) -> FRFRecord
    ltd : dict of (case, gust) -> LTDRecord
    roms : list of RomRecord
        In the order of ``config.points()``; points not yet computed are left out (see ``missing``).
    sims : list of SimRecord
        ROM gust histories whose ROM and LTD reference both exist.
    missing : list of str
        Pieces not in the store yet, e.g. ``"frf T2 T=11.1408"``; empty when the study is complete (the
        FRFs and LTD histories of a case whose steady flow failed are not listed: they cannot be computed).
    failed : list of str
        Pieces that failed, with their error: CFD pieces (steady, FRF, LTD) and ROM simulations. Failed
        identifications are also :class:`RomRecord` with ``status = "failed"``.
    steady : dict of case -> dict
        Steady loads and solver data per case: ``cl``, ``cd``, ``cm``, ``iterations``, ``seconds``.
    run : studies.run.runner.RunSummary or None
        What the run that returned these results computed (None when read from the store alone).
    sections : dict of str -> object
        What other study sections read from the store (:attr:`studies.sections.protocol.SectionRead.records`),
        by section name.
    """

    config: StudyConfig
    frf: dict
    ltd: dict
    roms: list
    sims: list
    missing: list
    failed: list = field(default_factory=list)
    steady: dict = field(default_factory=dict)
    run: Any = None
    sections: dict = field(default_factory=dict)

    @property
    def complete(self) -> bool:
        """Nothing missing (failures count as done)."""
        return not self.missing

    def table(self, kind: str = "rom") -> list:
        """Flat rows, one dict per record: the record's identifying fields followed by its metrics.

        Parameters
        ----------
        kind : {"rom", "sim", "frf", "ltd"}
            ``"rom"``: case, T, M, N_omega, order, method, status, error and the ROM metrics (missing ones
            as NaN for failed points, so that every row has the same keys). ``"sim"``: case, T, M, N_omega,
            order, method, gust and the simulation metrics. ``"frf"``: case, T, M, method, seconds.
            ``"ltd"``: case, gust, seconds, n_steps.

        Returns
        -------
        list of dict

        Raises
        ------
        ValueError
            Unknown ``kind``.
        """
        if kind == "rom":
            keys = _union_keys(r.metrics for r in self.roms)
            rows = []
            for r in self.roms:
                row = dict(case=r.case, T=r.T, M=r.M, N_omega=r.M + 1, order=r.order, method=r.method,
                           status=r.status, error=r.error)
                row.update({k: r.metrics.get(k, float("nan")) for k in keys})
                rows.append(row)
            return rows
        if kind == "sim":
            keys = _union_keys(s.metrics for s in self.sims)
            return [dict(case=s.case, T=s.T, M=s.M, N_omega=s.M + 1, order=s.order, method=s.method, gust=s.gust,
                         **{k: s.metrics.get(k, float("nan")) for k in keys}) for s in self.sims]
        if kind == "frf":
            return [dict(case=f.case, T=f.T, M=f.M, method=f.method, seconds=f.seconds) for f in self.frf.values()]
        if kind == "ltd":
            return [dict(case=r.case, gust=r.gust, seconds=r.seconds, n_steps=len(r.t) - 1) for r in self.ltd.values()]
        raise ValueError(f"table kind must be 'rom', 'sim', 'frf' or 'ltd', got {kind!r}")

    def rom(self, case: str, T: float, M: int, order: int, method: str) -> RomRecord:
        """The :class:`RomRecord` of one sweep point (``T`` compared to 1e-9 relative).

        Raises
        ------
        KeyError
            No such record (not computed yet, or not a point of the study).
        """
        for r in self.roms:
            if (r.case == case and np.isclose(r.T, T, rtol=1e-9, atol=0.0) and r.M == M and r.order == order
                    and r.method == method):
                return r
        raise KeyError(f"no ROM record for {case} T={T:.6g} M={M} N_r={order} {method}")


def _union_keys(dicts) -> list:
    keys: list = []
    for d in dicts:
        for k in d:
            if k not in keys:
                keys.append(k)
    return keys


def load_results(study_or_path, *, store_dir=None) -> StudyResults:
    """Read a study's results from its store; computes nothing.

    Parameters
    ----------
    study_or_path : StudyConfig or path-like
        A validated study, or the path of its TOML file (validated here).
    store_dir : path-like, optional
        Overrides the study's store folder.

    Returns
    -------
    StudyResults
        With what the store holds; ``missing`` lists the rest.

    Raises
    ------
    studies.config.StudyConfigError
        The study file is invalid.
    TypeError
        Neither a StudyConfig nor a path.
    """
    config = as_config(study_or_path)
    store = open_store(config, store_dir)
    sections: dict = {}
    fields: dict = {}
    missing: list = []
    failed: list = []
    unavailable: set = set()
    for section in active_sections(config):  # studies.sections.protocol: each section reads its own pieces
        part = section.read(config, store)
        fields.update(part.fields)
        if part.records is not None:
            sections[section.name] = part.records
        missing += part.missing
        failed += part.failed
        unavailable |= set(part.unavailable)
    # a piece of a case whose steady flow failed cannot be computed: not missing
    missing = [m for m in missing if len(m.split()) < 2 or m.split()[1] not in unavailable]
    return StudyResults(config=config, missing=missing, failed=failed, sections=sections, **fields)
