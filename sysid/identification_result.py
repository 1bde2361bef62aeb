"""What :func:`sysid.identify` returns: the model with its errors on the data, the constraints it meets, what
stabilisation cost (:class:`StabilisationReport`) and the data's consistency diagnostics."""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

from .arrays import freeze_array_fields, read_only
from .frd import FrequencyResponse
from .errors import FrequencyGridError
from .grids import real_frequencies
from .metrics import FitErrors
from .state_space import evaluate_ss
from .subspace import SubspaceResult

__all__ = ["IdentificationResult", "StabilisationReport", "ModelMatrices"]


@dataclass(frozen=True)
class ModelMatrices:
    """A discrete state-space model as plain arrays: what :func:`sysid.identify` builds, turned into a
    ``control.StateSpace`` only when :attr:`IdentificationResult.model` is first read (python-control and
    the matplotlib it imports cost about 1.5 s of imports, and fitting does not need them).

    Attributes
    ----------
    A, B, C, D : ndarray, shapes (n, n), (n, m), (p, n), (p, m), real
    dt : float
        Sampling period ``T``.
    input_labels, output_labels : tuple of str
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    dt: float
    input_labels: tuple
    output_labels: tuple

    def __post_init__(self):
        freeze_array_fields(self)

    def to_control(self):
        """The ``control.StateSpace`` (``dt``, named inputs and outputs)."""
        import control

        return control.ss(self.A, self.B, self.C, self.D, self.dt, inputs=list(self.input_labels),
                          outputs=list(self.output_labels))

    @classmethod
    def of(cls, model) -> "ModelMatrices":
        """The matrices of a ``control.StateSpace`` (or of another :class:`ModelMatrices`)."""
        if isinstance(model, cls):
            return model
        return cls(*(np.array(getattr(model, k), dtype=float) for k in "ABCD"), float(model.dt),
                   tuple(model.input_labels), tuple(model.output_labels))


class _LazyModel:
    """Data descriptor of :attr:`IdentificationResult.model`: holds a :class:`ModelMatrices` (or a
    ``control.StateSpace``) and builds the ``control.StateSpace`` on first read."""

    def __set_name__(self, owner, name):
        self._slot = "_" + name

    def __get__(self, obj, objtype=None):
        if obj is None:
            raise AttributeError("model has no default")   # dataclasses: a required field
        value = obj.__dict__[self._slot]
        if isinstance(value, ModelMatrices):
            value = value.to_control()
            obj.__dict__[self._slot] = value
        return value

    def __set__(self, obj, value):
        obj.__dict__["_model_matrices"] = ModelMatrices.of(value)
        obj.__dict__[self._slot] = value


@dataclass(frozen=True)
class StabilisationReport:
    """What stability enforcement did.

    Attributes
    ----------
    method : str
        ``"lmi"``, ``"reflect"`` or ``"none"`` (``A`` was already stable with the margin) on the subspace
        path; ``"relocation"`` on the relocation path, whose poles are stable by construction (nothing was
        changed after the fit: the before/after fields are equal).
    status : str
        Solver / method status from :func:`sysid.stability.stabilise`.
    spectral_radius_before, spectral_radius_after : float
    relative_change : float
        ``||A_new - A||_F / ||A||_F``.
    rms_error_before, rms_error_after : float
        RMS relative FRF error of the refitted model with the original and with the stabilised ``A``
        (same constraints); equal when nothing was changed.
    max_error_before, max_error_after : float
        The same for the max relative error.
    """

    method: str
    status: str
    spectral_radius_before: float
    spectral_radius_after: float
    relative_change: float
    rms_error_before: float
    rms_error_after: float
    max_error_before: float
    max_error_after: float


@dataclass(frozen=True)
class IdentificationResult:
    """Result of :func:`identify`.

    Attributes
    ----------
    model : control.StateSpace
        Discrete model, ``dt = T``, named inputs and outputs of the data (built on first read; the
        constructor also takes a :class:`ModelMatrices`, and :attr:`matrices` gives the arrays without
        importing python-control).
    order : int
    method : str
        ``"mckelvey1"`` or ``"mckelvey2"``.
    hankel_sv : ndarray, shape (k,)
        Singular values of the subspace step (guide for the order), decreasing
        (:attr:`sysid.subspace.HankelSVD.sv`: ``k = min(q p, r m)`` for Algorithm 1, ``q p`` for Algorithm 2).
    errors : FitErrors
        FRF errors over the data (see :mod:`sysid.metrics`).
    max_error, rms_error : float
        Shortcuts for ``errors.max_rel`` and ``errors.rms_rel``.
    dc_error : float or None
        Relative DC-gain error ``max|G(1) - H(0)| / max|H(0)|`` when the data have an ``omega = 0`` sample.
    enforced : dict
        ``{"dc_gain": bool, "feedthrough": bool, "stable": bool}``: which constraints hold by
        construction. ``"stable"`` is True on the relocation path whatever ``stable`` asked (its poles are
        stable by construction), and on the subspace path when ``stable=True`` was requested (see
        ``stabilisation``).
    spectral_radius : float
        Of the final ``A``.
    stabilisation : StabilisationReport or None
        Subspace path: ``None`` when ``stable=False``. Relocation path: always a report of method
        ``"relocation"`` (nothing changed after the fit).
    subspace : SubspaceResult
        ``A``, ``C`` and Hankel data before stabilisation (on both paths: the relocation starts from it).
    refit : BDFit, AlternatingFit or None
        Subspace path: the :class:`sysid.refit.BDFit` of the final model, or the
        :class:`sysid.refit.AlternatingFit` when ``C`` was refitted too. None on the relocation path, whose
        residue fits are in ``relocation``.
    T : float
        Sampling period of the data and of the model (convective time, ``c / U``).
    q, r : int, int or None
        Hankel sizes.
    data : FrequencyResponse
        The data identified (for :meth:`frequency_response` and plots).
    algorithm : str
        ``"subspace"`` (McKelvey + stabilisation + convex refits) or ``"relocation"`` (pole relocation,
        Gauss-Newton and convex residue fits, :mod:`sysid.relocation`).
    relocation : RelocationResult or None
        Details of the relocation path (winning start, residue fit, candidates); None for ``"subspace"``.
    """

    model: Any = _LazyModel()
    order: int
    method: str
    hankel_sv: np.ndarray = field(repr=False)
    errors: FitErrors = field(repr=False)
    max_error: float = float("nan")
    rms_error: float = float("nan")
    dc_error: float | None = None
    enforced: Mapping[str, bool] = field(default_factory=dict)
    spectral_radius: float = float("nan")
    stabilisation: StabilisationReport | None = None
    subspace: SubspaceResult | None = field(default=None, repr=False)
    refit: Any = field(default=None, repr=False)
    T: float = float("nan")
    q: int = 0
    r: int | None = None
    data: FrequencyResponse | None = field(default=None, repr=False)
    algorithm: str = "subspace"
    relocation: Any = field(default=None, repr=False)

    def __post_init__(self):
        for name in self.__dataclass_fields__:   # the arrays of a frozen result are read-only too (the model's
            value = self.matrices if name == "model" else getattr(self, name)   # own, in ModelMatrices)
            if isinstance(value, np.ndarray):
                object.__setattr__(self, name, read_only(value))

    def __reduce__(self):
        # control.StateSpace (0.10) cannot be pickled; ship its matrices and rebuild it (process pools)
        fields = {f: getattr(self, f) for f in self.__dataclass_fields__ if f != "model"}
        return (_rebuild_result, (self.matrices, fields))

    def __repr__(self):
        shown = ", ".join(f"{f}={getattr(self, f)!r}" for f, d in self.__dataclass_fields__.items()
                          if d.repr and f != "model")
        return f"IdentificationResult({shown})"

    @property
    def matrices(self) -> ModelMatrices:
        """The model's ``A``, ``B``, ``C``, ``D``, ``dt`` and labels as arrays (no python-control import)."""
        return self.__dict__["_model_matrices"]

    def evaluate(self, omega_d: Any) -> np.ndarray:
        """Model response ``G(exp(1j omega_d))``, shape (p, m, K), for discrete frequencies (rad/sample, finite;
        a :class:`FrequencyGridError` for text, complex values, NaN or inf)."""
        wd = real_frequencies(omega_d, "omega_d")
        if not np.all(np.isfinite(wd)):
            raise FrequencyGridError(f"omega_d[{int(np.flatnonzero(~np.isfinite(wd))[0])}] is infinite; discrete "
                                     "frequencies are finite (omega = inf is omega_d = pi)")
        z = np.exp(1j * wd)
        m = self.matrices
        return evaluate_ss(m.A, m.B, m.C, m.D, z)

    def evaluate_continuous(self, omega: Any) -> np.ndarray:
        """Model response at continuous frequencies ``omega`` (U_inf / c units, ``inf`` allowed), shape (p, m, K).

        Uses the bilinear map ``omega_d = 2 arctan(omega T / 2)``, so it equals the continuous model
        :meth:`continuous` at ``s = 1j omega``; a negative ``omega`` gives the complex conjugate of the response
        at ``-omega`` (a real system's).
        """
        from .frd import continuous_to_discrete

        w = real_frequencies(omega, "omega")
        G = self.evaluate(continuous_to_discrete(np.abs(w), self.T))
        return np.where(w < 0, np.conj(G), G)

    @property
    def diagnostics(self):
        """:class:`sysid.diagnostics.DataDiagnostics` of the data identified from (computed on first use: a few
        FFTs): whether they are consistent with a causal, stable, real LTI system, and by how much not."""
        cached = self.__dict__.get("_diagnostics")
        if cached is None:
            from .diagnostics import diagnose

            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                cached = diagnose(self.data)
            object.__setattr__(self, "_diagnostics", cached)
        return cached

    def _between(self) -> tuple[np.ndarray, np.ndarray]:
        """(:attr:`between_error_per_output`, :attr:`between_uncertainty_per_output`), computed together on first
        use."""
        cached = self.__dict__.get("_between_cache")
        if cached is None:
            from .between import between_estimate

            m = self.matrices
            if self.data is not None:
                cached = tuple(read_only(x) for x in between_estimate(m.A, m.B, m.C, m.D, self.data.omega_d,
                                                                      self.data.H))
            else:
                cached = (read_only(np.full(len(m.output_labels), np.nan)),) * 2
            object.__setattr__(self, "_between_cache", cached)
        return cached

    @property
    def between_error_per_output(self) -> np.ndarray:
        """Estimated error per output between the data's samples (fraction of each output's data peak;
        :func:`sysid.between.between_error`: the model against local readings of the samples at every interval's
        midpoint and at its own resonances; computed on first use). Compare with ``errors.max_rel_per_output``, the
        error on the samples: far above it, the samples do not pin the model down between them. Where
        :attr:`between_uncertainty_per_output` is larger, it is a lower bound."""
        return self._between()[0]

    @property
    def between_error(self) -> float:
        """The largest of :attr:`between_error_per_output`."""
        return float(np.max(self.between_error_per_output))

    @property
    def between_uncertainty_per_output(self) -> np.ndarray:
        """How far the samples leave each output open between them (fraction of its data peak;
        :func:`sysid.between.between_uncertainty`: the largest disagreement of their local readings). Far above the
        error on the samples and the estimate between them, the samples cannot say how far off the model is there
        (e.g. Cm above k = 2 on the paper's grid: 0.58 of the peak for T5, whose fits are 0.36 - 0.77 off there)."""
        return self._between()[1]

    @property
    def between_uncertainty(self) -> float:
        """The largest of :attr:`between_uncertainty_per_output`."""
        return float(np.max(self.between_uncertainty_per_output))

    def summary(self) -> str:
        """Plain-text summary: order, method, errors, constraints, stability, and one line on the data's
        consistency (:attr:`diagnostics`)."""
        enf = ", ".join(k for k, v in self.enforced.items() if v) or "none"
        if self.algorithm == "relocation" and self.relocation is not None:
            rl = self.relocation
            head = (f"order {self.order} (pole relocation from the {rl.start} start, {rl.residues} residues"
                    f"{', Gauss-Newton refined' if rl.refined else ''}; Hankel SVD {self.method}, q={self.q}, "
                    f"r={self.r}), T={self.T:.6g}")
        else:
            head = f"order {self.order} ({self.method}, q={self.q}, r={self.r}), T={self.T:.6g}"
        labels = self.matrices.output_labels
        per = ", ".join(f"{name} {e:.3e}" for name, e in zip(labels, self.errors.max_rel_per_output))
        lines = [
            head,
            f"FRF error: max {self.max_error:.3e}, RMS {self.rms_error:.3e}"
            + (f", DC {self.dc_error:.3e}" if self.dc_error is not None else ""),
            f"max error per output: {per}",
            "between the samples (estimate, sysid.between): " + ", ".join(
                f"{name} {e:.3e}" for name, e in zip(self.matrices.output_labels, self.between_error_per_output))
            + "; left open by the samples (their readings disagree by): " + ", ".join(
                f"{name} {u:.2e}" for name, u in zip(self.matrices.output_labels, self.between_uncertainty_per_output)),
            f"enforced: {enf}; spectral radius {self.spectral_radius:.6f}",
        ]
        st = self.stabilisation
        if st is not None and st.method not in ("none", "relocation"):
            lines.append(
                f"stabilised by {st.method}: radius {st.spectral_radius_before:.6f} -> {st.spectral_radius_after:.6f}, "
                f"|dA|/|A| = {st.relative_change:.3e}, RMS error {st.rms_error_before:.3e} -> {st.rms_error_after:.3e}"
            )
        if self.data is not None:
            lines.append(_diagnostics_line(self.diagnostics))
        return "\n".join(lines)

    def frequency_response(self, omega_d: Any = None) -> FrequencyResponse:
        """Model response as a :class:`FrequencyResponse` on the data grid (or on ``omega_d``)."""
        wd = self.data.omega_d if omega_d is None else real_frequencies(omega_d, "omega_d")
        return FrequencyResponse(
            self.evaluate(wd), wd, self.T, inputs=list(self.matrices.input_labels),
            outputs=list(self.matrices.output_labels), metadata={"source": "sysid.identify", "order": self.order},
        )

    def continuous(self):
        """The continuous model by the inverse bilinear map (paper Eq. 26)."""
        from .transforms import d2c_bilinear

        return d2c_bilinear(self.model)


def _diagnostics_line(d) -> str:
    """One line of :class:`sysid.diagnostics.DataDiagnostics` for :meth:`IdentificationResult.summary`."""
    parts = []
    for c in d.channels():
        nte = "" if c["neg_time_energy"] is None else f"negative-time energy {c['neg_time_energy']:.1e}, "
        parts.append(f"{c['output']}/{c['input']} {'FLAG' if c['flagged'] else 'ok'} ({nte}KK residual "
                     f"{c['kk_residual']:.1e})")
    verdict = ("consistent with a causal, stable, real LTI system" if d.ok else
               "not consistent with a causal, stable, real LTI system (sysid.diagnose(data).summary() says why)")
    return f"data: {verdict}; " + "; ".join(parts)


def _rebuild_result(matrices, fields):
    return IdentificationResult(model=matrices, **fields)
