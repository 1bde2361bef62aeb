"""The study's frozen configuration objects and the limits its values must keep.

:class:`StudyConfig` holds a validated study (``studies.config`` parses the TOML file into it): its cases with
their sweep axes (:class:`CaseSweep`), gusts, identification variants (:class:`MethodOptions`), simulation,
CFD and report options. :meth:`StudyConfig.points` enumerates the sweep (:class:`SweepPoint`).
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

from .cases import FlowCase, UnknownCaseError
from .hashing import canonical_json, dataclass_dict

__all__ = [
    "StudyConfig",
    "CaseSweep",
    "MethodOptions",
    "SimulationOptions",
    "CFDOptions",
    "ReportOptions",
    "SweepPoint",
    "case_canonical",
    "T_PAPER",
    "T_RANGE",
    "MAX_M",
    "MAX_STEPS",
    "MIN_GUST_STEPS",
    "DISCRETISATIONS",
    "LTD_SCHEMES",
    "WEIGHTS",
    "ALGORITHMS",
    "GUST_METHODS",
    "OUTPUTS",
]

T_PAPER = 70.0 / (2.0 * math.pi)
"""The paper's sampling period of the bilinear map (convective time)."""

T_RANGE = (0.02, 200.0)
"""Accepted sampling periods of the bilinear map (convective time). The grid's centre frequency is
``omega = 2 / T`` (at ``omega_d = pi / 2``, half the samples below it); the aerofoil's gust response lives at
``omega ~ 0.01 .. 100`` (``k = omega / 2 ~ 0.005 .. 50``), so ``2 / T`` must lie in that band: a smaller ``T``
puts every sample far above the response (only the feedthrough is seen: ``T = 1e-13`` gave a meaningless
grid and a "0.5 %" fit, ``T = 1e-300`` NaN models), a larger one crowds every sample at ``omega ~ 0``."""

MAX_M = 4096
"""Largest ``M_base`` (``N_omega = M + 1`` frequencies computed by the LFD per case and ``T``): 16 times the
paper's 256."""

MIN_GUST_STEPS = 2
"""Fewest time steps of ``[simulation] dt`` in which a 1-cosine gust may pass the aerofoil (its length in chords
over ``dt``): a shorter one is missed or aliased by the sampling (below ``dt`` its samples can all be zero). Two
steps give three samples of the bump, enough for the coarse test studies; real studies use 50 or more."""

MAX_STEPS = 1_000_000
"""Most time steps ``t_end / dt`` a study may ask of the LTD march (one sparse back-substitution per step,
about 0.03 s on the paper grid: a million steps are some 8 hours per case)."""

DISCRETISATIONS = ("tustin", "zoh")
LTD_SCHEMES = ("bdf2", "radau5")
"""Time schemes of the LTD reference (``cfd.ltd``): BDF2 at ``dt``, or Radau IIA at its default step with the loads
on the ``dt`` grid."""
WEIGHTS = ("none", "inverse_magnitude")
ALGORITHMS = ("auto", "relocation", "subspace", "mckelvey1", "mckelvey2")
GUST_METHODS = ("svm", "fvm")
OUTPUTS = ("Cl", "Cm", "Cd")


@dataclass(frozen=True)
class MethodOptions:
    """One identification variant (arguments of ``sysid.identify``).

    Attributes
    ----------
    name : str
    dc_gain : {"none", "match"}
    stable : bool
    margin : float
    weights : {"none", "inverse_magnitude"}
        ``"inverse_magnitude"``: weights ``1 / max(|H|, floor)^2`` of the B/D refit (relative errors).
    algorithm : {"auto", "mckelvey1", "mckelvey2"}
    """

    name: str = "default"
    dc_gain: str = "none"
    stable: bool = False
    margin: float = 1e-3
    weights: str = "none"
    algorithm: str = "auto"

    def identify_kwargs(self, H=None) -> dict:
        """Keyword arguments of ``sysid.identify``.

        Parameters
        ----------
        H : array_like, shape (p, m, K), optional
            The data; needed for ``weights = "inverse_magnitude"`` (see :meth:`weights_for`).
        """
        kw = dict(dc_gain="match" if self.dc_gain == "match" else None, stable=self.stable, margin=self.margin)
        if self.algorithm in ("mckelvey1", "mckelvey2"):
            kw.update(algorithm="subspace", method=self.algorithm)
        else:
            kw.update(algorithm=self.algorithm, method="auto")
        if self.weights != "none":
            if H is None:
                raise ValueError(f"method {self.name!r}: weights = {self.weights!r} needs the data H")
            kw["weights"] = self.weights_for(H)
        return kw

    def resolved_algorithm(self, p: int, m: int = 1) -> str:
        """``"relocation"`` or ``"subspace"``: what ``sysid.identify`` runs for this variant on data with ``p``
        outputs and ``m`` inputs (``"auto"``: relocation when the DC gain or stability is imposed and
        ``min(p, m) == 1``, as :func:`sysid.identify` decides)."""
        from sysid.identify import resolve_algorithm

        algorithm = "subspace" if self.algorithm in ("mckelvey1", "mckelvey2") else self.algorithm
        return resolve_algorithm(algorithm, p, m, stable=self.stable, dc_gain=self.dc_gain == "match")

    def weights_for(self, H, floor: float = 1e-3):
        """Refit weights for data ``H`` (shape (p, m, K)), or None for ``weights = "none"``.

        ``"inverse_magnitude"``: ``1 / max(|H|, floor * max_k |H|)^2`` per channel, so that the B/D refit
        minimises relative errors; ``floor`` keeps zeros of ``H`` (e.g. the ``omega = inf`` sample) finite.
        """
        if self.weights == "none":
            return None
        import numpy as np

        a = np.abs(np.asarray(H))
        peak = a.max(axis=-1, keepdims=True)
        peak = np.where(peak > 0.0, peak, 1.0)
        return 1.0 / np.maximum(a, floor * peak) ** 2

    def canonical(self) -> dict:
        """Everything but the name (the name does not change the result)."""
        return dict(dc_gain=self.dc_gain, stable=self.stable, margin=self.margin, weights=self.weights,
                    algorithm=self.algorithm)


@dataclass(frozen=True)
class SimulationOptions:
    """Gust-response settings (ROM against LTD).

    ``scheme``: the LTD's time scheme (:data:`LTD_SCHEMES`). ``"bdf2"`` (the default) marches at ``dt``, the
    scheme of the nonlinear solver (so a linear-against-nonlinear comparison differs by the nonlinearity alone);
    ``"radau5"`` (Radau IIA, ``cfd.ltd``; measured on T2: 2.3x cheaper, 2.7 - 24x closer to a fine reference on
    the 1-cosine gusts, docs/performance.md) writes the loads on the same ``dt`` grid.
    """

    discretisation: str = "tustin"
    dt: float = 0.02
    t_end: float = 40.0
    x0: float = -2.0
    scheme: str = "bdf2"


@dataclass(frozen=True)
class CFDOptions:
    """Settings of the LFD and LTD solves."""

    gust_method: str = "svm"
    outputs: tuple = ("Cl", "Cm")


@dataclass(frozen=True)
class ReportOptions:
    """Where the study's report goes (not part of any hash: it changes no result).

    Attributes
    ----------
    page : pathlib.Path or None
        The Markdown page; None: ``<output>/report.md``.
    prose : pathlib.Path or None
        TOML file of prose-slot texts.
    figures : bool
    title : str or None
    paper : bool or None
        None: the report decides (on for the paper's cases).
    """

    page: Optional[Path] = None
    prose: Optional[Path] = None
    figures: bool = True
    title: Optional[str] = None
    paper: Optional[bool] = None


@dataclass(frozen=True)
class CaseSweep:
    """A test case with its sweep axes (sorted, unique)."""

    case: FlowCase
    orders: tuple
    T: tuple
    M: tuple


@dataclass(frozen=True)
class SweepPoint:
    """One identification: a case, ``T``, ``M`` (``N_omega = M + 1``), an order and a method variant."""

    case: FlowCase
    T: float
    M: int
    order: int
    method: MethodOptions

    @property
    def n_omega(self) -> int:
        return self.M + 1


@dataclass(frozen=True)
class StudyConfig:
    """A validated study (see the module docstring for the file format).

    Attributes
    ----------
    name : str
    description : str
    source : str
        The study file, or ``"<string>"``.
    output_dir, store_dir : pathlib.Path
    cases : tuple of CaseSweep
    gusts : tuple of GustCase
    M_base : int
    methods : tuple of MethodOptions
    simulation : SimulationOptions
    cfd : CFDOptions
    report : ReportOptions
    sections : tuple of (str, object)
        The options of the study's sections that have a table (``[aeroelastic]``, ``[nonlinear]``, ...), as
        ``(section name, options)`` pairs in the order of the registered sections
        (:mod:`studies.sections.protocol`); a section the study does not have is absent. ``config.<name>`` reads
        a registered section's options (None when absent): ``config.aeroelastic``.
    """

    name: str
    description: str
    source: str
    output_dir: Path
    store_dir: Path
    cases: tuple
    gusts: tuple
    M_base: int
    methods: tuple
    simulation: SimulationOptions = field(default_factory=SimulationOptions)
    cfd: CFDOptions = field(default_factory=CFDOptions)
    report: ReportOptions = field(default_factory=ReportOptions)
    sections: tuple = ()

    def __getattr__(self, name: str):
        # config.<section name>: that section's options, None when the study does not have it
        if name.startswith("_") or name == "sections":
            raise AttributeError(name)
        from ..sections.protocol import section_names

        if name in section_names():
            return self.section(name)
        raise AttributeError(f"'StudyConfig' object has no attribute {name!r}")

    def section(self, name: str):
        """The options of the section ``name`` (e.g. ``"aeroelastic"``), or None when the study does not have it."""
        for key, options in self.sections:
            if key == name:
                return options
        return None

    def with_section(self, name: str, options) -> "StudyConfig":
        """A copy with the options of section ``name`` replaced (None: removed); sections keep their order."""
        from dataclasses import replace

        kept = [(key, value) for key, value in self.sections if key != name]
        if options is not None:
            position = [key for key, _ in self.sections].index(name) if name in dict(self.sections) else len(kept)
            kept.insert(position, (name, options))
        return replace(self, sections=tuple(kept))

    def case(self, name: str) -> CaseSweep:
        """The case sweep named ``name`` (case-insensitive)."""
        for case_sweep in self.cases:
            if case_sweep.case.name.casefold() == name.casefold():
                return case_sweep
        raise UnknownCaseError("case of this study", name, [case_sweep.case.name for case_sweep in self.cases])

    def points(self) -> tuple:
        """Every identification of the study, in file order (case, T, M, order, method)."""
        pts = []
        for case_sweep in self.cases:
            for T in case_sweep.T:
                for M in case_sweep.M:
                    for n in case_sweep.orders:
                        for variant in self.methods:
                            pts.append(SweepPoint(case_sweep.case, T, M, n, variant))
        return tuple(pts)

    def canonical(self) -> dict:
        """The hashable content: everything that changes results (no paths, no description)."""
        out = dict(
            name=self.name,
            cases=[dict(case=case_canonical(case_sweep.case), name=case_sweep.case.name,
                        orders=list(case_sweep.orders), T=list(case_sweep.T), M=list(case_sweep.M))
                   for case_sweep in self.cases],
            gusts=[g.to_dict() for g in self.gusts],
            M_base=self.M_base,
            methods={m.name: m.canonical() for m in self.methods},
            simulation=dataclass_dict(self.simulation),
            cfd=dict(gust_method=self.cfd.gust_method, outputs=list(self.cfd.outputs)),
        )
        for name, options in self.sections:  # absent otherwise: the hashes of studies without them are unchanged
            out[name] = options.canonical()
        return out

    def canonical_json(self) -> str:
        """:func:`canonical_json` of :meth:`canonical`."""
        return canonical_json(self.canonical())

    def hash(self) -> str:
        """sha256 (hex) of :meth:`canonical_json`."""
        return hashlib.sha256(self.canonical_json().encode()).hexdigest()


def case_canonical(case: FlowCase) -> dict:
    """The hashable content of a flow case: aerofoil, Mach, incidence and grid (not its name)."""
    return dict(naca=case.naca, mach=case.mach, alpha_deg=case.alpha_deg, grid=case.grid.kwargs())
