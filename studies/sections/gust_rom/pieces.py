"""The gust-ROM section's pieces: their kinds, keys, sources and payloads.

The gust-ROM pipeline's results are stored piece by piece in the study's :class:`studies.store.cache.ResultStore`.
Each piece has

- a kind (:data:`PIECES`, declared as :data:`PIECE_KINDS`): ``steady``, ``frf``, ``ltd``, ``rom``, ``sim``;
- a key: the canonical JSON of its sub-configuration (the ``*_piece`` functions below: each holds only what
  changes that piece, so that changing ``N_r`` keeps the FRF) and the hash of the sources it depends on
  (:data:`PIECE_KINDS`, :data:`ROM_DEPENDENCIES`);
- a payload ``(arrays, metadata)`` (the ``*_payload`` functions below).

Store layout (written by the tasks through the ``*_payload`` functions, read by :mod:`studies.store.results`)
----------------------------------------------------------------------------------------------------
====== ===================================== ===========================================================
piece  arrays                                metadata
====== ===================================== ===========================================================
steady ``q`` (ni-1, nj-1, 4)                 ``cl``, ``cd``, ``cm``, ``converged``, ``iterations``, ``seconds``
frf    ``H`` (p, 1, K), ``omega_d``,          ``T``, ``M``, ``outputs``, ``inputs``, ``method``, ``seconds``,
       ``omega`` (K,), K = M_base + 1         ``lfd`` (the solver's own metadata, e.g. the fast sweep's estimate)
ltd    ``t``, ``u``, ``cl``, ``cm``, ``cd``   ``seconds``, ``dt``, ``gust_method``
       (n + 1,)
rom    ``A`` (n, n), ``B`` (n, 1),            ``metrics``, ``identify_method``, ``enforced``, ``outputs``
       ``C`` (p, n), ``D`` (p, 1),
       ``hankel_sv`` (q,), ``frf_rom``
       (p, 1, M_base + 1)
sim    ``t``, ``cl``, ``cm`` (n + 1,)         ``metrics``
====== ===================================== ===========================================================

Every piece's metadata also holds ``status`` (``"ok"`` or ``"failed"``); a failed piece has no arrays and an
``error`` (``"ExceptionType: message"``). A failed steady flow or FRF marks the ROMs that need it failed (with
that reason); a failed LTD or ROM simulation is listed in :attr:`StudyResults.failed`.
"""

from __future__ import annotations

from typing import Any, Mapping, Optional

import numpy as np

from sysid import FrequencyResponse
from sysid.history_metrics import history_errors

from ...config.cases import FlowCase, GustCase
from ...config.schema import CFDOptions, SimulationOptions, SweepPoint, case_canonical
from ...store.entries import error_text, failure_payload, is_failed, open_store, store_dependencies
from ..protocol import PieceKind

__all__ = [
    "PIECES",
    "PIECE_KINDS",
    "ROM_DEPENDENCIES",
    "PAYLOAD_ARRAYS",
    "steady_piece",
    "frf_piece",
    "rom_piece",
    "ltd_piece",
    "sim_piece",
    "store_dependencies",
    "open_store",
    "failure_payload",
    "steady_payload",
    "frf_payload",
    "ltd_payload",
    "rom_payload",
    "sim_payload",
    "is_failed",
    "error_text",
    "sim_metrics",
    "SIM_OUTPUTS",
]

PIECES = ("steady", "frf", "ltd", "rom", "sim")
"""The kinds of piece, in the order a case computes them."""

SIM_OUTPUTS = ("Cl", "Cm")
"""Outputs whose gust histories are compared (when the study computes them)."""


# ---------------------------------------------------------------------------------------------
# Keys: each sub-configuration holds only what changes that piece
# ---------------------------------------------------------------------------------------------

def steady_piece(case: FlowCase) -> dict:
    """Steady flow: aerofoil, Mach, incidence, grid (not the case's name)."""
    return case_canonical(case)


def frf_piece(case: FlowCase, T: float, M_base: int, cfd: CFDOptions) -> dict:
    """LFD frequency response on ``sysid.mckelvey_grid(M_base, T)``; subsampled grids reuse it."""
    return dict(steady=steady_piece(case), T=T, M=M_base, gust_method=cfd.gust_method, outputs=list(cfd.outputs))


def rom_piece(point: SweepPoint, M_base: int, cfd: CFDOptions) -> dict:
    """Identified ROM of one sweep point."""
    return dict(frf=frf_piece(point.case, point.T, M_base, cfd), M=point.M, order=point.order,
                method=point.method.canonical())


def _scheme_key(sim: SimulationOptions) -> dict:
    """The LTD scheme's entry of a key: none for the default BDF2 (keys of BDF2 pieces keep their form)."""
    return {} if sim.scheme == "bdf2" else {"scheme": sim.scheme}


def ltd_piece(case: FlowCase, gust: GustCase, sim: SimulationOptions, cfd: CFDOptions) -> dict:
    """LTD reference history of a case and gust.

    Not keyed by ``cfd.outputs``: a history holds Cl, Cm and Cd whatever outputs the FRFs are fitted to, so a
    study that changes its outputs reuses its LTDs.
    """
    return dict(steady=steady_piece(case), gust=dict(kind=gust.kind, length=gust.length, angle_deg=gust.angle_deg),
                dt=sim.dt, t_end=sim.t_end, x0=sim.x0, gust_method=cfd.gust_method, **_scheme_key(sim))


def sim_piece(point: SweepPoint, gust: GustCase, M_base: int, sim: SimulationOptions, cfd: CFDOptions) -> dict:
    """ROM gust history of one sweep point and gust."""
    return dict(rom=rom_piece(point, M_base, cfd),
                gust=dict(kind=gust.kind, length=gust.length, angle_deg=gust.angle_deg),
                discretisation=sim.discretisation, dt=sim.dt, t_end=sim.t_end, x0=sim.x0,
                **_scheme_key(sim))    # its errors are against that LTD


#: Arrays each piece's payload holds (the ``*_payload`` functions below); an entry of another layout is corrupt.
PAYLOAD_ARRAYS = {"steady": ("q",), "frf": ("H", "omega_d", "omega"), "ltd": ("t", "u", "cl", "cm", "cd"),
                  "rom": ("A", "B", "C", "D", "hankel_sv", "frf_rom"), "sim": ("t", "cl", "cm")}

ROM_DEPENDENCIES = ("cfd", "sysid", "studies.config.study", "studies.config.reader", "studies.config.entries",
                    "studies.config.numbers", "studies.config.schema", "studies.sections.gust_rom.pieces",
                    "studies.sections.gust_rom.tasks")
"""Sources of the ROM and ROM-simulation pieces: ``cfd`` and ``sysid``, the study file's parser
(:mod:`studies.config.study` with its value reader and case entries) and number parser (the values computed
with), the configuration objects (method options, weights), this module (keys, payloads, the simulation metrics)
and the tasks that compute them."""

PIECE_KINDS = (PieceKind("steady", ("cfd",), PAYLOAD_ARRAYS["steady"]),
               PieceKind("frf", ("cfd",), PAYLOAD_ARRAYS["frf"]),
               PieceKind("ltd", ("cfd",), PAYLOAD_ARRAYS["ltd"]),
               PieceKind("rom", ROM_DEPENDENCIES, PAYLOAD_ARRAYS["rom"]),
               PieceKind("sim", ROM_DEPENDENCIES, PAYLOAD_ARRAYS["sim"]))
"""The section's store kinds: the CFD pieces (expensive) depend on ``cfd`` only (the tasks' wrappers around it
are thin), the identification pieces (cheap) on :data:`ROM_DEPENDENCIES`. ``store_dependencies``,
``open_store``, ``error_text``, ``failure_payload`` and ``is_failed`` are :mod:`studies.store.entries`' (for every
section), re-exported here as before."""


# ---------------------------------------------------------------------------------------------
# Payloads: (arrays, metadata) of each piece
# ---------------------------------------------------------------------------------------------

def steady_payload(sol, seconds: float) -> tuple:
    """``(arrays, metadata)`` of a ``cfd.SteadySolution``."""
    return ({"q": np.asarray(sol.q)},
            dict(status="ok", cl=float(sol.cl), cd=float(sol.cd), cm=float(sol.cm), converged=bool(sol.converged),
                 iterations=int(sol.iterations), seconds=float(seconds)))


def frf_payload(frf: FrequencyResponse, M: int, method: str, seconds: float) -> tuple:
    """``(arrays, metadata)`` of an LFD response on McKelvey's grid of ``M`` intervals."""
    return ({"H": np.asarray(frf.H), "omega_d": np.asarray(frf.omega_d), "omega": np.asarray(frf.omega)},
            dict(status="ok", T=float(frf.T), M=int(M), outputs=list(frf.outputs), inputs=list(frf.inputs),
                 method=str(method), seconds=float(seconds), lfd=dict(frf.metadata)))


def ltd_payload(hist, seconds: float, gust_method: str) -> tuple:
    """``(arrays, metadata)`` of a ``cfd.LTDHistory`` (or any object with ``t, u, cl, cm, cd, dt``)."""
    return ({"t": np.asarray(hist.t), "u": np.asarray(hist.u), "cl": np.asarray(hist.cl), "cm": np.asarray(hist.cm),
             "cd": np.asarray(hist.cd)},
            dict(status="ok", seconds=float(seconds), dt=float(hist.dt), gust_method=str(gust_method)))


def rom_payload(A, B, C, D, hankel_sv, frf_rom, metrics: Mapping, *, identify_method: str = "",
                enforced: Optional[Mapping] = None, outputs=()) -> tuple:
    """``(arrays, metadata)`` of an identified ROM (see the module docstring for shapes)."""
    return ({"A": np.asarray(A, dtype=float), "B": np.asarray(B, dtype=float), "C": np.asarray(C, dtype=float),
             "D": np.asarray(D, dtype=float), "hankel_sv": np.asarray(hankel_sv, dtype=float),
             "frf_rom": np.asarray(frf_rom, dtype=complex)},
            dict(status="ok", metrics=dict(metrics), identify_method=str(identify_method),
                 enforced=dict(enforced or {}), outputs=list(outputs)))


def sim_payload(t, cl, cm, metrics: Mapping) -> tuple:
    """``(arrays, metadata)`` of a ROM gust history."""
    return ({"t": np.asarray(t, dtype=float), "cl": np.asarray(cl, dtype=float), "cm": np.asarray(cm, dtype=float)},
            dict(status="ok", metrics=dict(metrics)))


def sim_metrics(t, rom: Mapping[str, Any], ltd: Mapping[str, Any], seconds_rom: float, seconds_ltd: float) -> dict:
    """The metrics stored with a ROM gust history: its errors against the LTD one, and the times of both.

    Parameters
    ----------
    t : array_like, shape (n + 1,)
        The common time grid (convective time).
    rom, ltd : mapping of output name -> array_like, shape (n + 1,)
        Histories, e.g. ``{"Cl": cl, "Cm": cm}``; the outputs compared are those of :data:`SIM_OUTPUTS` in both.
    seconds_rom, seconds_ltd : float
        Wall times (s) of the ROM simulation and of the LTD march.

    Returns
    -------
    dict of str -> float
        :func:`sysid.history_metrics.history_errors` (``peak_err_X``, ``t_peak_err_X``, ``rms_err_X``), then
        ``seconds_rom`` and ``seconds_ltd``.
    """
    out = history_errors(t, rom, ltd, outputs=[o for o in SIM_OUTPUTS if o in rom and o in ltd])
    out["seconds_rom"] = float(seconds_rom)
    out["seconds_ltd"] = float(seconds_ltd)
    return out
