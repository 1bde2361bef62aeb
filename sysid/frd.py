"""Frequency-response data (the grids and the bilinear frequency map: :mod:`sysid.grids`).

A :class:`FrequencyResponse` holds complex samples ``H`` of shape ``(p, m, K)`` (outputs, inputs,
frequencies, as in python-control) together with their frequencies, in two linked forms:

- ``omega_d``: discrete frequencies in ``[0, pi]`` (radians per sample), the frequencies at which the
  identified discrete model ``G(z)`` is evaluated with ``z = exp(1j * omega_d)``;
- ``omega``: continuous angular frequencies in units of ``U_inf / c`` (convective), linked to ``omega_d``
  through the bilinear (Tustin) map of the paper's Eq. 28::

      omega = (2 / T) * tan(omega_d / 2),      omega_d = 2 * arctan(omega * T / 2)

  so that ``omega_d = pi`` is ``omega = inf`` (the continuous feedthrough) and ``omega_d = 0`` is DC.

Either form may be missing: data given on continuous frequencies without a sampling period ``T`` have
``omega_d = None`` and ``T = None``; data given on a discrete grid without ``T`` have ``omega = None``.
Identification needs both (see :func:`sysid.identify`).
"""

from __future__ import annotations

import copy
import types
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from .arrays import read_only
from .errors import ArgumentTypeError, FrequencyDataError, FrequencyGridError, FrequencyIndexError
from .grids import (GRID_RTOL, check_period, continuous_to_discrete, discrete_to_continuous, mckelvey_grid,
                    real_frequencies)
from .state_space import shifted_solve

__all__ = ["FrequencyResponse", "mckelvey_grid", "discrete_to_continuous", "continuous_to_discrete"]  # (the last three
# from sysid.grids)


# --------------------------------------------------------------------------------------------------
# validation helpers
# --------------------------------------------------------------------------------------------------
def _as_H(H: Any) -> np.ndarray:
    """Coerce ``H`` to a complex (p, m, K) array; SISO (K,) -> (1, 1, K); (p, K) -> (p, 1, K)."""
    try:
        arr = np.array(H, dtype=complex)
    except (TypeError, ValueError) as exc:
        raise FrequencyDataError(f"H must be a numeric array of shape (p, m, K): {exc}") from None
    if arr.ndim == 1:
        arr = arr.reshape(1, 1, -1)
    elif arr.ndim == 2:
        # (p, K): one input, p outputs (single-input convenience)
        arr = arr.reshape(arr.shape[0], 1, arr.shape[1])
    elif arr.ndim != 3:
        raise FrequencyDataError(
            f"H must have shape (p, m, K) (outputs, inputs, frequencies), got {arr.ndim}-D shape {arr.shape}; "
            "a 1-D array is read as SISO (K,) and a 2-D one as single-input (p, K)"
        )
    if arr.size == 0 or arr.shape[2] == 0:
        raise FrequencyDataError(f"H is empty (shape {arr.shape}); give at least one output, input and frequency")
    bad = ~np.isfinite(arr)
    if bad.any():
        i, j, k = np.argwhere(bad)[0]
        raise FrequencyDataError(
            f"H contains {int(bad.sum())} NaN/inf value(s), first at H[{i}, {j}, {k}]; remove or recompute "
            "those frequencies (the omega = inf point carries the finite feedthrough value, not inf)"
        )
    return arr


def _as_freq(x: Any, name: str, K: int) -> np.ndarray:
    """Coerce a frequency vector to a float (K,) array; NaN is refused, inf is left to the caller."""
    if np.ndim(x) > 1:
        raise FrequencyGridError(f"{name} must be 1-D, got shape {np.shape(x)}")
    arr = real_frequencies(x, name, allow_nan=True).copy()   # a copy: the caller's array is not held
    if arr.shape[0] != K:
        raise FrequencyDataError(
            f"{name} has {arr.shape[0]} frequencies but H has K={K} (H.shape[2]); give one frequency per sample"
        )
    if np.isnan(arr).any():
        raise FrequencyGridError(f"{name} contains NaN at index {int(np.flatnonzero(np.isnan(arr))[0])}")
    return arr


def _as_indices(indices: Any, K: int) -> np.ndarray:
    """Sample indices (or a boolean mask of length ``K``) as a 1-D int array in ``0 .. K-1``."""
    raw = np.asarray(indices)
    if raw.ndim > 1:
        raise FrequencyIndexError(f"indices must be 1-D, got shape {raw.shape}")
    raw = raw.reshape(-1)
    if raw.dtype == bool:
        if raw.size != K:
            raise FrequencyIndexError(f"a boolean mask of {raw.size} values but the data have {K} frequencies; "
                                      "give one value per sample")
        return np.flatnonzero(raw)
    if raw.size and (raw.dtype.kind not in "iuf" or not np.all(np.isfinite(raw)) or np.any(raw != np.round(raw))):
        raise FrequencyIndexError(f"indices must be whole numbers, got {indices!r}")
    idx = raw.astype(int)
    bad = np.flatnonzero((idx < -K) | (idx >= K))
    if bad.size:
        raise FrequencyIndexError(f"index {int(idx[bad[0]])} is outside the data's frequencies 0 .. {K - 1} "
                                  f"(K = {K})")
    return idx


def _check_names(names: Any, n: int, what: str, default_prefix: str) -> tuple[str, ...]:
    if names is None:
        return tuple(f"{default_prefix}[{i}]" for i in range(n))
    if isinstance(names, str):
        names = [names]
    names = list(names)
    if len(names) != n:
        raise FrequencyDataError(
            f"{what} has {len(names)} name(s) {names!r} but H has {n} {what} (H.shape[{0 if what == 'outputs' else 1}]); "
            f"give one name per {what[:-1]}"
        )
    if not all(isinstance(s, str) for s in names):
        raise FrequencyDataError(f"{what} names must be strings, got {names!r}")
    dup = sorted({s for s in names if names.count(s) > 1})
    if dup:
        raise FrequencyDataError(f"{what} names must be distinct (results are keyed by them), got {dup[0]!r} "
                                 f"more than once in {names!r}")
    return tuple(names)




# --------------------------------------------------------------------------------------------------
# FrequencyResponse
# --------------------------------------------------------------------------------------------------
def _rebuild(H, omega_d, T, inputs, outputs, metadata, omega):
    return FrequencyResponse(H, omega_d, T, inputs=inputs, outputs=outputs, metadata=metadata, omega=omega)


class FrequencyResponse:
    """Immutable MIMO frequency-response samples on a discrete and/or continuous frequency grid.

    Parameters
    ----------
    H : array_like, complex, shape (p, m, K)
        Response samples (outputs, inputs, frequencies). A 1-D array ``(K,)`` is read as SISO and a 2-D
        array ``(p, K)`` as single-input.
    omega_d : array_like, shape (K,) or None
        Discrete frequencies in ``[0, pi]`` (rad/sample). ``None`` only together with ``omega=``.
    T : float or None
        Sampling period (convective time units). With ``omega_d`` it defines ``omega`` by Eq. 28.
    inputs, outputs : list of str, optional
        Channel names (lengths ``m`` and ``p``); default ``u[i]`` and ``y[i]``.
    metadata : dict, optional
        Free-form JSON-serialisable information (case, solver settings...). Stored as a read-only copy.
    omega : array_like, shape (K,), optional (keyword only)
        Continuous frequencies (U_inf / c units, ``>= 0``, ``inf`` allowed). Normally built by
        :meth:`from_continuous`; when given together with ``omega_d`` and ``T`` the two must agree by
        Eq. 28.

    Attributes
    ----------
    H : ndarray, complex, shape (p, m, K), read-only
    omega_d : ndarray, shape (K,) or None, read-only
    omega : ndarray, shape (K,) or None, read-only
    T : float or None
    inputs, outputs : tuple of str
    metadata : mapping (read-only view)

    Raises
    ------
    FrequencyDataError
        NaN/inf in ``H``, inconsistent lengths, wrong number of names.
    FrequencyGridError
        ``omega_d`` outside ``[0, pi]``, negative ``omega``, ``T <= 0`` or not finite, no frequencies.
    """

    __slots__ = ("H", "omega_d", "omega", "T", "inputs", "outputs", "metadata")

    def __init__(
        self,
        H: Any,
        omega_d: Any,
        T: float | None = None,
        inputs: Sequence[str] | None = None,
        outputs: Sequence[str] | None = None,
        metadata: Mapping[str, Any] | None = None,
        *,
        omega: Any = None,
    ) -> None:
        Harr = _as_H(H)
        p, m, K = Harr.shape
        Tf = None if T is None else check_period(T)

        wd = None
        if omega_d is not None:
            wd = _as_freq(omega_d, "omega_d", K)
            tol = GRID_RTOL * np.pi
            if (wd < -tol).any() or (wd > np.pi + tol).any():
                bad = wd[(wd < -tol) | (wd > np.pi + tol)][0]
                raise FrequencyGridError(
                    f"omega_d must lie in [0, pi] (rad/sample), found {float(bad)!r}; discrete frequencies above pi are "
                    "aliases: map continuous frequencies with FrequencyResponse.from_continuous(H, omega, T)"
                )
            wd = np.clip(wd, 0.0, np.pi)
            wd[np.isclose(wd, np.pi, rtol=0.0, atol=tol)] = np.pi

        w = None
        if omega is not None:
            w = _as_freq(omega, "omega", K)
            if (w < 0).any():
                raise FrequencyGridError(
                    f"omega must be nonnegative (U_inf/c units), found {float(w[w < 0][0])!r}; the response at -omega "
                    "is the complex conjugate and is implied"
                )
            if wd is not None and Tf is not None:
                wd_chk = continuous_to_discrete(w, Tf)
                if not np.allclose(wd_chk, wd, rtol=1e-9, atol=1e-12):
                    raise FrequencyGridError(
                        "omega and omega_d disagree with the bilinear map omega = (2/T) tan(omega_d/2) for "
                        f"T={Tf}; give only one of them"
                    )
        elif wd is not None and Tf is not None:
            w = discrete_to_continuous(wd, Tf)
        if wd is None and w is None:
            raise FrequencyGridError("give the frequencies: omega_d (discrete, [0, pi]) or omega= (continuous)")
        if wd is None and Tf is not None:
            wd = continuous_to_discrete(w, Tf)

        if metadata is not None and not isinstance(metadata, Mapping):
            raise FrequencyDataError(f"metadata must be a mapping (a dict of names to values), got "
                                     f"{type(metadata).__name__}")
        try:
            md = {} if metadata is None else copy.deepcopy(dict(metadata))
        except (TypeError, copy.Error) as exc:   # e.g. a generator: "cannot pickle 'generator' object"
            raise FrequencyDataError(f"metadata must hold plain data (numbers, strings, lists, dicts; save() writes "
                                     f"it as JSON), but a value cannot be copied: {exc}") from None
        sa = object.__setattr__
        sa(self, "H", read_only(Harr))
        sa(self, "omega_d", read_only(wd))
        sa(self, "omega", read_only(w))
        sa(self, "T", Tf)
        sa(self, "outputs", _check_names(outputs, p, "outputs", "y"))
        sa(self, "inputs", _check_names(inputs, m, "inputs", "u"))
        sa(self, "metadata", types.MappingProxyType(md))

    # immutability ---------------------------------------------------------------------------------
    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError(f"FrequencyResponse is immutable; cannot set {name!r} (build a new object)")

    def __delattr__(self, name: str) -> None:
        raise AttributeError(f"FrequencyResponse is immutable; cannot delete {name!r}")

    def __reduce__(self):
        # pickling / copying (e.g. for process pools) rebuilds through the validating constructor
        return (_rebuild, (self.H, self.omega_d, self.T, self.inputs, self.outputs, dict(self.metadata), self.omega))

    def __repr__(self) -> str:
        p, m, K = self.H.shape
        grid = f"M={self.M}" if self.is_equispaced else f"K={K}"
        return (
            f"FrequencyResponse(p={p}, m={m}, {grid}, T={self.T}, outputs={list(self.outputs)}, "
            f"inputs={list(self.inputs)})"
        )

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, FrequencyResponse):
            return NotImplemented

        def same(a, b):
            if a is None or b is None:
                return a is None and b is None
            return a.shape == b.shape and np.array_equal(a, b)

        return (
            same(self.H, other.H)
            and same(self.omega_d, other.omega_d)
            and same(self.omega, other.omega)
            and self.T == other.T
            and self.inputs == other.inputs
            and self.outputs == other.outputs
            and dict(self.metadata) == dict(other.metadata)
        )

    __hash__ = None  # type: ignore[assignment]

    # constructors ---------------------------------------------------------------------------------
    @classmethod
    def from_continuous(
        cls,
        H: Any,
        omega: Any,
        T: float | None = None,
        inputs: Sequence[str] | None = None,
        outputs: Sequence[str] | None = None,
        metadata: Mapping[str, Any] | None = None,
    ) -> "FrequencyResponse":
        """Build from samples at continuous frequencies.

        Parameters
        ----------
        H : array_like, complex, shape (p, m, K)
            Response samples (``(K,)`` is read as SISO, ``(p, K)`` as single-input).
        omega : array_like, shape (K,)
            Continuous frequencies (U_inf / c units), ``>= 0``; ``np.inf`` allowed (its value is the
            feedthrough).
        T : float, optional
            Sampling period (convective time units, c / U_inf). When given, ``omega_d = 2 arctan(omega T / 2)``
            (``inf -> pi``); otherwise ``omega_d`` and ``T`` are ``None`` (the data cannot be identified until a
            ``T`` is chosen: see :meth:`with_T`).
        inputs, outputs : list of str, optional
            Channel names (lengths ``m`` and ``p``); default ``u[i]`` and ``y[i]``.
        metadata : dict, optional
            Free-form JSON-serialisable information, stored as a read-only copy.

        Returns
        -------
        FrequencyResponse
            With ``omega`` as given and, when ``T`` is given, ``omega_d`` in ``[0, pi]`` (rad/sample).

        Raises
        ------
        FrequencyDataError
            NaN/inf in ``H``, ``omega`` of another length than ``K``, wrong number of names.
        FrequencyGridError
            Negative or NaN ``omega``, ``T <= 0`` or not finite.
        """
        return cls(H, None, T, inputs=inputs, outputs=outputs, metadata=metadata, omega=omega)

    @classmethod
    def from_model(cls, model, omega_d: Any, T: float | None = None, metadata: Mapping[str, Any] | None = None
                   ) -> "FrequencyResponse":
        """Sample a :class:`control.StateSpace` model on discrete frequencies.

        Parameters
        ----------
        model : control.StateSpace
            Discrete (``dt = T``): evaluated at ``z = exp(1j omega_d)``. Continuous (``dt = 0``): evaluated
            at ``s = 1j omega`` with ``omega = (2/T) tan(omega_d / 2)`` (``omega = inf`` gives ``D``), so
            the samples equal those of its Tustin discretisation.
        omega_d : array_like, shape (K,)
            Discrete frequencies in ``[0, pi]`` (rad/sample).
        T : float, optional
            Sampling period (convective time units, c / U_inf); defaults to ``model.dt`` for a discrete model,
            required for a continuous one.
        metadata : dict, optional
            Free-form JSON-serialisable information, stored as a read-only copy.

        Returns
        -------
        FrequencyResponse
            Samples of shape ``(p, m, K)`` on ``omega_d`` with period ``T`` (so ``omega`` by Eq. 28), channel
            names from ``model.input_labels`` and ``model.output_labels``.

        Raises
        ------
        TypeError
            ``model`` is not a ``control.StateSpace``.
        FrequencyDataError
            When a sampled point is a pole of the model (an infinite response).
        FrequencyGridError
            A continuous model without ``T``, ``T <= 0`` or not finite, a discrete model with a ``T`` other than its
            ``dt``, ``omega_d`` not 1-D, NaN or outside ``[0, pi]``.
        """
        import control

        if not isinstance(model, control.StateSpace):
            raise ArgumentTypeError(f"from_model() expects a control.StateSpace, got {type(model).__name__}")
        A, B, C, D = (np.asarray(x, dtype=float) for x in (model.A, model.B, model.C, model.D))
        wd = _as_freq(omega_d, "omega_d", np.size(omega_d))
        discrete = bool(model.dt) and model.dt is not True
        if T is None:
            if not discrete:
                raise FrequencyGridError("a continuous model needs T to map omega_d to omega; pass T")
            T = model.dt
        T = check_period(T)
        if discrete and not np.isclose(T, float(model.dt), rtol=1e-12, atol=0.0):
            raise FrequencyGridError(
                f"T = {T!r} contradicts the discrete model's own sampling period dt = {model.dt!r}: its samples at "
                "omega_d would be labelled with frequencies omega of another period; leave T out (it defaults to "
                "model.dt) or resample the model (control.sample_system) at the period you want"
            )
        if discrete:
            pts = np.exp(1j * wd)
            finite = np.ones(wd.size, dtype=bool)
        else:
            w = discrete_to_continuous(np.clip(wd, 0.0, np.pi), T)
            finite = np.isfinite(w)
            pts = 1j * np.where(finite, w, 0.0)
        with np.errstate(invalid="ignore"):  # inf at a pole: reported below
            H = (C[None] @ shifted_solve(A, B, pts) + D[None]).transpose(1, 2, 0)
        H[:, :, ~finite] = D[:, :, None]
        if not np.all(np.isfinite(H)):
            k = int(np.argwhere(~np.isfinite(H))[0][2])
            raise FrequencyDataError(
                f"the model has a pole on the sampled axis at omega_d = {wd[k]:.6g} (sample {k}): its response is "
                "infinite there; sample other frequencies or move the pole"
            )
        return cls(H, wd, T, inputs=list(model.input_labels), outputs=list(model.output_labels), metadata=metadata)

    def with_T(self, T: float) -> "FrequencyResponse":
        """Return a copy with sampling period ``T``, mapping the continuous frequencies to ``omega_d``.

        Parameters
        ----------
        T : float
            Sampling period (convective time units, c / U_inf); replaces any previous ``T``.

        Returns
        -------
        FrequencyResponse
            The same ``H``, ``omega``, names and metadata, with ``omega_d = 2 arctan(omega T / 2)`` (``inf -> pi``).

        Raises
        ------
        FrequencyGridError
            No continuous frequencies ``omega`` (discrete data without ``T``), or ``T <= 0`` or not finite.
        """
        if self.omega is None:
            raise FrequencyGridError("this response has no continuous frequencies to map; it already has omega_d")
        return FrequencyResponse.from_continuous(
            self.H, self.omega, T, inputs=self.inputs, outputs=self.outputs, metadata=self.metadata
        )

    def replace(self, **changes: Any) -> "FrequencyResponse":
        """Return a copy with some of ``H``, ``inputs``, ``outputs``, ``metadata`` replaced.

        Parameters
        ----------
        **changes
            Keyword arguments among ``H`` (array_like, complex, shape (p, m, K) with the same ``K``),
            ``inputs``, ``outputs`` (list of str) and ``metadata`` (dict); the others, the frequencies and ``T``
            are kept.

        Returns
        -------
        FrequencyResponse

        Raises
        ------
        TypeError
            A keyword other than ``H``, ``inputs``, ``outputs``, ``metadata``.
        FrequencyDataError
            As in the constructor: e.g. a new ``H`` with another ``K``, or names that no longer match its
            ``p``, ``m``.
        """
        allowed = {"H", "inputs", "outputs", "metadata"}
        unknown = set(changes) - allowed
        if unknown:
            raise TypeError(f"replace() accepts only {sorted(allowed)}, got {sorted(unknown)}")
        kw = dict(H=self.H, inputs=self.inputs, outputs=self.outputs, metadata=self.metadata)
        kw.update(changes)
        return FrequencyResponse(kw.pop("H"), self.omega_d, self.T, omega=self.omega, **kw)

    # shape and grid properties --------------------------------------------------------------------
    @property
    def shape(self) -> tuple[int, int, int]:
        """``(p, m, K)``: outputs, inputs, frequencies."""
        return tuple(self.H.shape)  # type: ignore[return-value]

    @property
    def noutputs(self) -> int:
        return self.H.shape[0]

    @property
    def ninputs(self) -> int:
        return self.H.shape[1]

    @property
    def nfreq(self) -> int:
        return self.H.shape[2]

    @property
    def z(self) -> np.ndarray:
        """Points on the unit circle ``exp(1j omega_d)``, shape (K,); needs ``omega_d``."""
        if self.omega_d is None:
            raise FrequencyGridError("no discrete frequencies: give T (FrequencyResponse.with_T(T))")
        return np.exp(1j * self.omega_d)

    @property
    def is_equispaced(self) -> bool:
        """True when ``omega_d`` is McKelvey's grid ``pi k / M``, ``k = 0..M`` (in increasing order)."""
        wd = self.omega_d
        if wd is None or wd.size < 2:
            return False
        M = wd.size - 1
        return bool(np.allclose(wd, np.pi * np.arange(M + 1) / M, rtol=0.0, atol=GRID_RTOL * np.pi))

    @property
    def M(self) -> int | None:
        """Number of grid intervals ``M`` (``K - 1``) for an equispaced grid, else ``None``."""
        return self.nfreq - 1 if self.is_equispaced else None

    def _index_of(self, target: str) -> int | None:
        tol = GRID_RTOL * np.pi
        if target == "dc":
            if self.omega_d is not None:
                idx = np.flatnonzero(np.abs(self.omega_d) <= tol)
            else:
                idx = np.flatnonzero(self.omega == 0.0)
        else:
            if self.omega_d is not None:
                idx = np.flatnonzero(np.abs(self.omega_d - np.pi) <= tol)
            else:
                idx = np.flatnonzero(np.isinf(self.omega))
        return int(idx[0]) if idx.size else None

    def with_real_ends(self) -> "FrequencyResponse":
        """The data with the samples at ``omega = 0`` and ``omega = inf`` (``omega_d = 0, pi``) replaced by their
        real parts, where an imaginary part is above ``1e-6`` of the peak (the threshold of :attr:`dc_gain`'s
        warning); ``self`` when nothing changes.

        A real system's response is real there, so no real model can follow such an imaginary part, and a fit
        that keeps it spends the model on it (:func:`sysid.identify` and :func:`sysid.order_sweep` fit this).

        Returns
        -------
        FrequencyResponse
        """
        scale = max(float(np.abs(self.H).max()), np.finfo(float).tiny)
        ends = [k for k in (self._index_of("dc"), self._index_of("inf")) if k is not None]
        ends = [k for k in ends if np.abs(self.H[:, :, k].imag).max() > 1e-6 * scale]
        if not ends:
            return self
        H = np.array(self.H, dtype=complex)
        H[:, :, ends] = H[:, :, ends].real
        return self.replace(H=H)

    def _real_value(self, k: int | None, what: str) -> np.ndarray | None:
        if k is None:
            return None
        v = self.H[:, :, k]
        scale = max(float(np.abs(self.H).max()), np.finfo(float).tiny)
        if np.abs(v.imag).max() > 1e-6 * scale:
            import warnings

            warnings.warn(
                f"the {what} sample has a non-negligible imaginary part (max {np.abs(v.imag).max():.3g}); "
                "a real system's response there is real, so only the real part is used",
                RuntimeWarning,
                stacklevel=3,
            )
        out = np.array(v.real)
        out.setflags(write=False)
        return out

    @property
    def dc_gain(self) -> np.ndarray | None:
        """Real ``(p, m)`` value at ``omega = 0`` (``omega_d = 0``), or ``None`` if not sampled.

        The imaginary part is dropped (a ``RuntimeWarning`` says so when it is not negligible).
        """
        return self._real_value(self._index_of("dc"), "omega = 0")

    @property
    def feedthrough(self) -> np.ndarray | None:
        """Real ``(p, m)`` value at ``omega = inf`` (``omega_d = pi``), or ``None`` if not sampled.

        This is the continuous model's feedthrough ``D_c`` and the discrete model's ``G(z = -1)``.
        """
        return self._real_value(self._index_of("nyquist"), "omega = inf")

    # grid operations --------------------------------------------------------------------------------
    def subsample(self, M_new: int) -> "FrequencyResponse":
        """Coarser equispaced grid: keep every ``M / M_new``-th sample (e.g. M = 256 -> 128, 64, 32).

        Parameters
        ----------
        M_new : int
            Number of intervals of the coarse grid, a positive divisor of ``M``.

        Returns
        -------
        FrequencyResponse
            ``M_new + 1`` samples at ``omega_d = pi k / M_new``, ``k = 0..M_new`` (same ``T``, names, metadata).

        Raises
        ------
        FrequencyGridError
            The grid is not equispaced, or ``M_new`` does not divide ``M``.
        """
        if not self.is_equispaced:
            raise FrequencyGridError(
                "subsample() needs an equispaced McKelvey grid omega_d = pi k / M, k = 0..M; "
                "select frequencies with take(indices) instead"
            )
        M = self.M
        if isinstance(M_new, bool) or not isinstance(M_new, (int, np.integer)) or M_new < 1 or M % M_new:
            divisors = [d for d in range(1, M + 1) if M % d == 0]
            raise FrequencyGridError(
                f"M_new={M_new!r} must be a positive divisor of M={M} so that the coarse grid is a subset; "
                f"choose one of {divisors}"
            )
        return self.take(np.arange(0, M + 1, M // M_new))

    def take(self, indices: Any) -> "FrequencyResponse":
        """Return the samples at the given frequency indices (order kept as given).

        Parameters
        ----------
        indices : array_like of int, shape (K_new,), or array_like of bool, shape (K,)
            Frequency indices into ``0..K-1`` (negative ones count from the end, as in NumPy), or a mask with
            one value per sample.

        Returns
        -------
        FrequencyResponse
            ``H[:, :, indices]`` of shape ``(p, m, K_new)`` with the matching ``omega_d`` and ``omega`` (same
            ``T``, names, metadata).

        Raises
        ------
        FrequencyIndexError
            An index outside ``-K .. K-1``, indices that are not whole numbers or not 1-D, a mask of another
            length than ``K``.
        """
        idx = _as_indices(indices, self.nfreq)
        return FrequencyResponse(
            self.H[:, :, idx],
            None if self.omega_d is None else self.omega_d[idx],
            self.T,
            inputs=self.inputs,
            outputs=self.outputs,
            metadata=self.metadata,
            omega=None if self.omega is None else self.omega[idx],
        )

    # persistence ------------------------------------------------------------------------------------
    def save(self, path: str | Path) -> Path:
        """Write to a ``.npz`` file (arrays) with names and metadata stored as JSON (:func:`sysid.frd_io.save_frf`).

        Parameters
        ----------
        path : str or Path
            File to write; ``.npz`` is appended when missing.

        Returns
        -------
        Path
            The path written.

        Raises
        ------
        FrequencyDataError
            The metadata are not JSON-serialisable.
        FrequencyFileError
            ``path`` (or ``path`` with ``.npz`` appended) is a directory.
        """
        from .frd_io import save_frf

        return save_frf(self, path)

    @classmethod
    def load(cls, path: str | Path) -> "FrequencyResponse":
        """Read a file written by :meth:`save` (:func:`sysid.frd_io.load_frf`).

        Parameters
        ----------
        path : str or Path
            The ``.npz`` file.

        Returns
        -------
        FrequencyResponse
            An instance of ``cls`` with the stored ``H``, frequencies, ``T``, names and metadata.

        Raises
        ------
        FrequencyDataError
            The file lacks the ``header``, ``H`` or ``metadata`` entries :meth:`save` writes, or they are not
            what it writes; otherwise as in the constructor.
        FrequencyFileError
            The file is not an ``.npz`` archive (another format, or not a zip file at all).
        FileNotFoundError
            No such file.
        """
        from .frd_io import load_frf

        return load_frf(cls, path)

    # python-control ---------------------------------------------------------------------------------
    def to_control(self):
        """Convert to :class:`control.FrequencyResponseData` on the continuous frequencies ``omega``
        (:func:`sysid.frd_io.frf_to_control`: an ``omega = inf`` sample is dropped).

        Raises
        ------
        FrequencyGridError
            No continuous frequencies (discrete data without ``T``).
        """
        from .frd_io import frf_to_control

        return frf_to_control(self)

    @classmethod
    def from_control(
        cls, frd, T: float | None = None, *, feedthrough: Any = None, metadata: Mapping[str, Any] | None = None
    ) -> "FrequencyResponse":
        """Build from a continuous-time :class:`control.FrequencyResponseData` (:func:`sysid.frd_io.frf_from_control`).

        Parameters
        ----------
        frd : control.FrequencyResponseData
            Continuous-time FRD (``omega`` in the project's U_inf / c units).
        T : float, optional
            Sampling period (convective time units, c / U_inf) for the discrete frequencies.
        feedthrough : array_like (p, m), optional
            Value at ``omega = inf`` to append (what :meth:`to_control` dropped); a scalar for SISO.
        metadata : dict, optional
            Free-form JSON-serialisable information, stored as a read-only copy.

        Returns
        -------
        FrequencyResponse
            Samples sorted by increasing ``omega`` (the ``omega = inf`` one last), names from the FRD's labels.

        Raises
        ------
        FrequencyGridError
            A discrete-time FRD (``dt`` not 0 or None); otherwise as in :meth:`from_continuous`.
        FrequencyDataError
            ``feedthrough`` not of shape ``(p, m)``; otherwise as in :meth:`from_continuous`.
        """
        from .frd_io import frf_from_control

        return frf_from_control(cls, frd, T, feedthrough=feedthrough, metadata=metadata)
