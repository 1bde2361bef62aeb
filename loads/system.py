"""The gust system of a flight point: any accepted model as one continuous state-space model in modal form.

Every model :func:`loads.tuned_gust` and :func:`loads.continuous_turbulence` take is brought to a continuous
model in convective time ``s = t U / c`` with the single input ``gust`` (gust angle ``v_g / U`` at the leading
edge, rad) and diagonalised once, ``A = V diag(lambda) V^-1``::

    z' = diag(lambda) z + b u,    y = Re(C_m z) + d u,     b = V^-1 B_gust,  C_m = C V

- a :class:`sysid.IdentificationResult` or a discrete :class:`control.StateSpace` (``dt = T``, convective) is
  mapped to continuous time by the inverse bilinear map (:func:`sysid.d2c_bilinear`, the paper's Eq. 26), which
  keeps its frequency response exactly (``G_c(i omega) = G_d(exp(i omega_d))``);
- a continuous :class:`control.StateSpace` is taken as it is (convective time);
- an :class:`aeroelastic.MotionModel` gives its rigid gust model (outputs ``Cl``, ``Cm`` about its axis);
- a :class:`loads.FlexibleSection` is coupled at the flight point (:mod:`loads.flexible`).

Each output carries the factor that makes it dimensional at the flight point (``Cl``: ``q c``, N/m;
``Cm``: ``q c^2``, N m/m; see :class:`GustSystem`).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .atmosphere import FlightPoint, check_point
from .checks import real_values
from .errors import LoadsModelError

__all__ = ["GustSystem", "gust_system", "moment_output_name", "moment_outputs", "check_moment_axes",
           "check_distinct_outputs", "EIGENVECTOR_CONDITION_LIMIT"]

EIGENVECTOR_CONDITION_LIMIT = 1e8
"""Condition number of the eigenvector matrix above which the modal form is refused (it would lose more than half
of the digits: a defective or nearly defective ``A``)."""


@dataclass(frozen=True)
class GustSystem:
    """A continuous gust model in modal form at one flight point (arrays read-only).

    Attributes
    ----------
    lam : ndarray, complex, shape (n,)
        Eigenvalues of ``A`` (per unit convective time ``c / U``).
    b : ndarray, complex, shape (n,)
        Modal input ``V^-1 B``.
    C : ndarray, complex, shape (p, n)
        Modal outputs ``C V``.
    d : ndarray, shape (p,)
        Feedthrough of the gust.
    outputs : tuple of str
        Output names (model units: coefficients, ``h / c``, rad, ...).
    scale : ndarray, shape (p,)
        Factor making each output dimensional at the flight point.
    units : tuple of str
        Unit of each dimensional output (``"N/m"``, ``"N m/m"``, ``"m"``, ...).
    point : FlightPoint
    condition : float
        Condition number of the eigenvector matrix (the modal form's loss of digits is about ``eps`` times it).
    """

    lam: np.ndarray = field(repr=False)
    b: np.ndarray = field(repr=False)
    C: np.ndarray = field(repr=False)
    d: np.ndarray = field(repr=False)
    outputs: tuple
    scale: np.ndarray = field(repr=False)
    units: tuple
    point: FlightPoint
    condition: float = 1.0

    def frequency_response(self, omega: Any) -> np.ndarray:
        """``G(i omega)`` per unit gust angle, shape (p, K), at convective ``omega`` (rad per ``c / U``).

        Parameters
        ----------
        omega : array_like
            Real, finite frequencies, any shape (read as K values in order; a negative one gives the conjugate).

        Returns
        -------
        ndarray, complex, shape (p, K)

        Raises
        ------
        LoadsModelError
            ``omega`` not real numbers (a string gave a bare ValueError), or a NaN or inf among them (the response
            was NaN; at ``omega = inf`` it is the feedthrough ``d``).
        """
        w = real_values(omega)
        if w is None:
            raise LoadsModelError(f"omega must be real convective frequencies (rad per c/U: a number or an array of "
                                  f"numbers), got {omega!r}")
        w = w.reshape(-1)
        if not np.all(np.isfinite(w)):
            raise LoadsModelError(f"omega must be finite (rad per c/U), got {np.count_nonzero(~np.isfinite(w))} NaN or "
                                  f"inf value(s) (first {float(w[~np.isfinite(w)][0])!r}); the response at omega = inf "
                                  "is the feedthrough d")
        R = self.b[None, :] / (1j * w[:, None] - self.lam[None, :])          # (K, n)
        return (R @ self.C.T).T + self.d[:, None]

    def index(self, name: str) -> int:
        """Position of output ``name``; :class:`LoadsModelError` listing the outputs if absent."""
        if name not in self.outputs:
            raise LoadsModelError(f"no output {name!r}; the model's outputs are {list(self.outputs)}")
        return self.outputs.index(name)


def moment_output_name(axis: float) -> str:
    """Name of the moment coefficient about ``axis`` (chords from the leading edge), e.g. ``"Cm@0.400"``."""
    return f"Cm@{axis:.3f}"


def _first_repeat(names: list[str]) -> str | None:
    """The first name in ``names`` that an earlier one equals, else None."""
    seen = set()
    for n in names:
        if n in seen:
            return n
        seen.add(n)
    return None


def check_distinct_outputs(names: list[str]) -> None:
    """:class:`LoadsModelError` naming an output that ``names`` (the ``outputs`` asked for) repeats: the results are
    keyed by output name (``outputs=["Cl", "Cl"]`` gave a result with outputs ``("Cl", "Cl")``)."""
    dup = _first_repeat(names)
    if dup is not None:
        raise LoadsModelError(f"outputs names {dup!r} more than once ({names}); give each output once")


def moment_outputs(axes: list[float], outputs: list[str]) -> list[str]:
    """Names of the moment outputs about ``axes`` (:func:`moment_output_name`) to add to ``outputs``.

    Raises
    ------
    LoadsModelError
        Two axes, or an axis and an output already there, share a name: ``moment_axes=[0.5, 0.5]`` gave two outputs
        ``Cm@0.500`` (names are rounded to 0.001 chord).
    """
    names = [moment_output_name(x) for x in axes]
    dup = _first_repeat(list(outputs) + names)
    if dup is not None:
        raise LoadsModelError(f"moment_axes {axes} would give two outputs named {dup!r} (the model's outputs are "
                              f"{list(outputs)}; an axis is named to 0.001 chord): give each axis once, at least "
                              "0.001 chord apart")
    return names


def _position(name: str, v: Any) -> float:
    """``v`` as a finite position in chords from the leading edge, else :class:`LoadsModelError` naming ``name``."""
    bad = isinstance(v, (bool, np.bool_, str, bytes)) or (isinstance(v, np.ndarray) and v.ndim > 0)
    try:
        f = math.nan if bad else float(v)
    except (TypeError, ValueError):
        bad = True
    if bad:
        raise LoadsModelError(f"{name} must be a position in chords from the leading edge (a real number such as "
                              f"0.25), got {v!r}")
    if not math.isfinite(f):
        raise LoadsModelError(f"{name} must be a finite position in chords from the leading edge, got {v!r}")
    return f


def check_moment_axes(moment_axes: Any, moment_reference: Any) -> tuple[list[float], float]:
    """``(axes, reference)`` as floats, or :class:`LoadsModelError` naming the bad one.

    ``moment_axes`` is one position or a sequence of them (empty for none), ``moment_reference`` one position;
    positions are real, finite numbers (chords from the leading edge). A NaN gave ``Cm@x`` peaks of NaN, a string
    a bare NumPy error.
    """
    ref = _position("moment_reference", moment_reference)
    if (isinstance(moment_axes, (str, bytes)) or not isinstance(moment_axes, Iterable)
            or (isinstance(moment_axes, np.ndarray) and moment_axes.ndim == 0)):
        return [_position("moment_axes", moment_axes)], ref
    return [_position(f"moment_axes[{i}]", x) for i, x in enumerate(moment_axes)], ref


def _check_finite(A, B, C, D) -> None:
    """:class:`LoadsModelError` naming the first matrix with a NaN or inf entry (its loads would be NaN)."""
    for name, M in (("A", A), ("B", B), ("C", C), ("D", D)):
        M = np.asarray(M, dtype=float)
        bad = np.argwhere(~np.isfinite(M))
        if bad.size:
            at = tuple(int(i) for i in bad[0])
            raise LoadsModelError(f"the model's {name} matrix has {len(bad)} non-finite entr"
                                  f"{'y' if len(bad) == 1 else 'ies'} ({M[at]} at {list(at)}): its gust loads would "
                                  "be NaN; repair or re-identify the model")


def _ss_parts(model: Any):
    """``(A, B, C, D, inputs, outputs)`` of a continuous model in convective time from an accepted model type."""
    import control
    import sysid

    if isinstance(model, sysid.IdentificationResult):
        model = model.model
    try:
        from aeroelastic import MotionModel
    except ImportError:  # pragma: no cover
        MotionModel = ()
    if isinstance(model, MotionModel):
        if model.gust is None:
            raise LoadsModelError("the aeroelastic.MotionModel has no gust model; fit data with a 'gust' input")
        model = model.gust
    if not isinstance(model, control.StateSpace):
        raise LoadsModelError(
            f"model must be a sysid.IdentificationResult, a control.StateSpace (discrete with dt = T or continuous, "
            f"convective time, a 'gust' input), an aeroelastic.MotionModel with a gust model or a "
            f"loads.FlexibleSection; got {type(model).__name__}")
    _check_finite(model.A, model.B, model.C, model.D)
    dt = model.dt
    from aeroelastic.coupling import STATE_OUTPUTS

    if not dt and set(STATE_OUTPUTS) <= set(model.output_labels):
        raise LoadsModelError(
            "this looks like an aeroelastic.coupled_model system (outputs plunge, pitch, ... ), whose time is "
            "omega_alpha t, not the convective c/U that loads takes; give loads.FlexibleSection(aero, mass, a, x_alpha, "
            "r_alpha2, omega_h, omega_alpha), which couples the section at each flight point")
    if dt is True or dt is None:
        raise LoadsModelError("the StateSpace has an unspecified time step (dt=True/None); give dt = T (convective "
                              "time c/U) for a discrete ROM or dt = 0 for a continuous one")
    if dt:
        model = sysid.d2c_bilinear(model)
    inputs, outputs = list(model.input_labels), list(model.output_labels)
    return (np.asarray(model.A, dtype=float), np.asarray(model.B, dtype=float), np.asarray(model.C, dtype=float),
            np.asarray(model.D, dtype=float), inputs, outputs)


def gust_system(model: Any, point: FlightPoint, *, moment_axes=(), moment_reference: float = 0.25) -> GustSystem:
    """Bring ``model`` to a :class:`GustSystem` at ``point``.

    Parameters
    ----------
    model : sysid.IdentificationResult, control.StateSpace, aeroelastic.MotionModel, loads.FlexibleSection or GustSystem
        With an input named ``"gust"`` (gust angle at the leading edge, rad; convective time ``c / U``). A
        :class:`GustSystem` built at ``point`` is returned as it is (so that one flight point's tuned gusts and
        turbulence share one diagonalisation).
    point : FlightPoint
    moment_axes : sequence of float
        Extra moment outputs ``Cm`` about these axes (chords from the leading edge), named by
        :func:`moment_output_name`: ``Cm_x = Cm + (x - x_ref) Cl`` (needs outputs ``Cl`` and ``Cm``).
    moment_reference : float
        The axis of the model's ``Cm`` (chords from the leading edge; 0.25 for the project's CFD; the elastic axis
        for a :class:`loads.FlexibleSection`, which sets it itself).

    Returns
    -------
    GustSystem

    Raises
    ------
    LoadsModelError
        An unsupported type, no ``"gust"`` input, a NaN or inf in the model's matrices, an unstable model, a
        defective state matrix, a moment axis without ``Cl`` and ``Cm`` outputs, a moment axis or
        ``moment_reference`` that is not a finite number, two moment axes that would share an output name.
    FlightPointError
        ``point`` not a :class:`FlightPoint`.
    """
    check_point(point)
    from .flexible import FlexibleSection

    moment_axes, moment_reference = check_moment_axes(moment_axes, moment_reference)
    if isinstance(model, GustSystem):
        if model.point != point or moment_axes:
            raise LoadsModelError("a GustSystem is reused only at its own flight point and as built (no moment_axes); "
                                  "build another with loads.gust_system(model, point, ...)")
        return model
    scales: dict[str, tuple[float, str]] = {}
    if isinstance(model, FlexibleSection):
        A, B, C, D, inputs, outputs, scales = model.state_space(point)
        _check_finite(A, B, C, D)
        moment_reference = model.elastic_axis
    else:
        A, B, C, D, inputs, outputs = _ss_parts(model)
    if "gust" not in inputs:
        raise LoadsModelError(f"the model has no input named 'gust' (its inputs are {inputs}); name the gust-angle "
                              "input 'gust' (control.StateSpace(..., inputs=[...]))")
    j = inputs.index("gust")
    Bg, Dg = B[:, j], D[:, j]
    C, Dg, outputs = _add_moment_axes(C, Dg, list(outputs), moment_axes, moment_reference)
    q, c = point.q, point.chord_m
    default = {"Cl": (q * c, "N/m")}
    sc, un = [], []
    for name in outputs:
        if name in scales:
            s, u = scales[name]
        elif name in default:
            s, u = default[name]
        elif name.startswith("Cm"):
            s, u = q * c * c, "N m/m"
        else:
            s, u = 1.0, "-"
        sc.append(s)
        un.append(u)
    lam, b, Cm, cond = _modal(A, Bg, C)
    return GustSystem(_ro(lam), _ro(b), _ro(Cm), _ro(Dg), tuple(outputs), _ro(np.array(sc)), tuple(un), point,
                      float(cond))


def _add_moment_axes(C, D, outputs, axes, x_ref):
    axes, x_ref = check_moment_axes(axes, x_ref)
    if not axes:
        return C, D, outputs
    if "Cl" not in outputs or "Cm" not in outputs:
        raise LoadsModelError(f"moment_axes needs outputs 'Cl' and 'Cm'; the model's outputs are {outputs}")
    il, im = outputs.index("Cl"), outputs.index("Cm")
    names = moment_outputs(axes, outputs)
    rowsC, rowsD = [C], [D]
    for x in axes:
        rowsC.append((C[im] + (x - x_ref) * C[il])[None, :])
        rowsD.append(np.atleast_1d(D[im] + (x - x_ref) * D[il]))
    return np.vstack(rowsC), np.concatenate(rowsD), outputs + names


def _modal(A, B, C):
    n = A.shape[0]
    if n == 0:
        return np.zeros(0, complex), np.zeros(0, complex), np.zeros((C.shape[0], 0), complex), 1.0
    lam, V = np.linalg.eig(A)
    cond = np.linalg.cond(V)
    if not np.isfinite(cond) or cond > EIGENVECTOR_CONDITION_LIMIT:
        raise LoadsModelError(f"the state matrix is (nearly) defective: its eigenvector matrix has condition number "
                              f"{cond:.3g} > {EIGENVECTOR_CONDITION_LIMIT:g}, so the modal response would lose most of "
                              "its digits; perturb repeated poles or reduce the model (balanced truncation)")
    scale = max(1.0, float(np.abs(lam).max()))
    if np.any(lam.real > 1e-9 * scale):
        worst = lam[np.argmax(lam.real)]
        raise LoadsModelError(f"the model is unstable (pole {worst:.4g} per unit c/U): its gust response grows without "
                              "bound; for a flexible section the flight point is above its flutter or divergence speed")
    b = np.linalg.solve(V, B.astype(complex))
    return lam, b, C @ V, cond


def _ro(a):
    a = np.array(a)
    a.setflags(write=False)
    return a
