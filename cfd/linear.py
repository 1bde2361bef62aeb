"""Linearisation of the gust equations about a steady state: ``V dq/dt + J q + b(t) = 0``, ``y = C q + D u``.

All operators are derivatives of the one residual, ``cfd.euler.residual(grid, q, flow, face_velocity,
source)``; nothing here re-implements the flow equations:

- ``J = dR/dq`` from ``cfd.jacobian.jacobian`` (exact, coloured complex step);
- ``Bi = dR/dw_y`` on the i-faces and ``Bj = dR/dw_y`` on the j-faces (the vertical components of the
  face grid velocities), sparse, by coloured complex step through the same residual (each face
  influences at most the four cells of its row or column nearest to it, so four colours per face
  family suffice);
- ``dR/dsource = -I`` (the residual subtracts the cell-integrated sources);
- with the point-vortex far field (``scheme.vortex``), the circulation feedback that ``cfd.jacobian``
  freezes, as a rank-one term ``(dR/dCl)(dCl/dq)`` added in every solve (``LinearSystem.solver``).

Linear systems are factorised by :func:`factorise`: nested dissection without pivoting, checked, with
complex matrices in their real 2n form.

For a gust with face averages ``g`` of ``v_g / U`` (``cfd.gust``) the face velocity is
``w_y = -mach g`` and the SVM adds the source ``cfd.gust.svm_source``; the forcing is therefore
``b = -mach (Bi g_i + Bj g_j) - source(g)`` (the source term only for ``method="svm"``).

Units: the state and ``J`` are in solver units (``a_inf = 1``; time ``t_solver = s / mach``), so in the
project's convective time ``mach V dq/ds + J q + b = 0`` and a harmonic input ``exp(i omega s)`` needs
``(i omega mach V + J) q = -b``. Outputs are perturbation coefficients per unit input ``u = v_g(x_ref)/U``
(per radian of gust angle); ``D = 0`` (the loads depend on the state only).

Outputs
-------
``Cl``, ``Cm`` (quarter chord, nose up positive) and ``Cd``, in the axes of the steady free stream,
as given by ``cfd.loads.force_coefficients`` (wall pressure ``cfd.boundary.wall_pressure`` from the
first two cells, integrated over the wall faces). The loads are linear in the wall pressures, so
``C = d(loads)/d(p_w) d(p_w)/dq``: the second factor by complex step through ``cfd.flow.pressure``
and ``cfd.boundary.wall_pressure`` (8 evaluations), the first from the face geometry; the tests check
``C`` against finite differences of ``force_coefficients``.
"""

import warnings
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from .superlu import splu_nested, splu_pivoted
from .boundary import wall_pressure
from .checks import kind_of, not_a_grid, real_array
from .euler import Scheme, residual
from .flow import NON_PHYSICAL, FlowCondition, is_physical, pressure
from .gust import cell_x_gradient, svm_source
from .jacobian import H_STEP, coloured_complex_step, jacobian
from .loads import force_coefficients
from .mesh.metrics import Grid
from .ordering import nested_dissection, unknown_permutation

__all__ = ["LinearSystem", "linearise", "linearise_state", "wall_loads", "factorise", "OUTPUTS", "METHODS",
           "LinearError", "check_linear_system"]

OUTPUTS = ("Cl", "Cm", "Cd")
METHODS = ("svm", "fvm")


class LinearError(ValueError):
    """Bad argument to the linear solvers (unknown output or gust method, wrong shapes...)."""


def check_gust_method(method):
    """The gust method name, checked against :data:`METHODS`."""
    if method not in METHODS:
        raise LinearError(f"gust method must be one of {METHODS} (split or field velocity method); got {method!r}")
    return method


def check_outputs(outputs):
    """Validate output names; returns the tuple of row indices into ``LinearSystem.C``."""
    if isinstance(outputs, str):
        outputs = (outputs,)
    try:
        outputs = tuple(outputs)
    except TypeError:
        raise LinearError(f"outputs must be a name or a sequence of names from {OUTPUTS}; got {outputs!r}") from None
    bad = [o for o in outputs if o not in OUTPUTS]
    if bad or not outputs:
        raise LinearError(f"unknown output(s) {bad or outputs!r}; choose from {OUTPUTS}")
    return outputs, [OUTPUTS.index(o) for o in outputs]


def check_linear_system(lin, name="lin"):
    """Raise :class:`LinearError` unless ``lin`` is a :class:`LinearSystem` (e.g. a steady solution passed instead)."""
    if not isinstance(lin, LinearSystem):
        hint = "pass cfd.linearise(sol)" if hasattr(lin, "grid") and hasattr(lin, "q") else \
            "build it with cfd.linearise(cfd.solve_steady(grid, mach, alpha_deg))"
        raise LinearError(f"expected a LinearSystem as {name}, got {type(lin).__name__}; {hint}")
    return lin


def _load_coefficients(grid, flow):
    """d(Cl, Cm, Cd)/d(p_wall) per wall face, shape (3, n_surface), and the face centres."""
    w = grid.wall
    sx, sy = grid.sj[0, w, 0], grid.sj[1, w, 0]
    xf = 0.5 * (grid.x[:-1, 0] + grid.x[1:, 0])[w]
    yf = 0.5 * (grid.y[:-1, 0] + grid.y[1:, 0])[w]
    a = flow.alpha
    qd = flow.dynamic_pressure
    # Force on the body from the wall faces: dF = -(p_w - p_inf) S (S points into the fluid).
    dcl = (sx * np.sin(a) - sy * np.cos(a)) / qd
    dcd = -(sx * np.cos(a) + sy * np.sin(a)) / qd
    # Pitching moment about (0.25, 0), nose up positive: Cm = -(sum (x - 0.25) dFy - y dFx) / q.
    dcm = ((xf - 0.25) * sy - yf * sx) / qd
    return np.stack([dcl, dcm, dcd])


def wall_loads(grid, q, flow):
    """Force and moment coefficients from the wall pressure (complex-safe).

    Parameters
    ----------
    grid : Grid
    q : ndarray, shape (..., ni-1, nj-1, 4)
    flow : FlowCondition

    Returns
    -------
    ndarray, shape (..., 3)
        ``(Cl, Cm, Cd)``: lift and drag in the free-stream axes of ``flow``, moment about the quarter
        chord, nose up positive; pressure forces only.
    """
    cl, cd, cm = force_coefficients(grid, q, flow)
    return np.stack([cl, cm, cd], axis=-1)


def _output_matrix(grid, q, flow):
    """``C = d(Cl, Cm, Cd)/dq``, shape (3, 4N), by complex step through pressure and wall_pressure."""
    NI, NJ = grid.cell_shape
    w = np.arange(NI)[grid.wall]
    coef = _load_coefficients(grid, flow)
    C = np.zeros((3, NI * NJ * 4))
    h = H_STEP
    for jrow in (0, 1):  # 8 evaluations of the (per-cell) pressure: the derivative is diagonal per row
        for k in range(4):
            qc = q[w, :2, :].astype(complex)
            qc[:, jrow, k] += 1j * h
            p = pressure(qc, flow.gamma)
            dpw = wall_pressure(p[:, 0], p[:, 1]).imag / h
            C[:, 4 * (w * NJ + jrow) + k] = coef * dpw
    return C


def _face_pattern(grid, family):
    """Pattern (4N x n_faces) of dR/dw_y and a 4-colouring of its columns."""
    ni, nj = grid.shape
    NI, NJ = grid.cell_shape
    if family == "i":
        fi, fj = np.meshgrid(np.arange(ni), np.arange(nj - 1), indexing="ij")
        along, cross, n_along = fi, fj, NI
    else:
        fi, fj = np.meshgrid(np.arange(ni - 1), np.arange(nj), indexing="ij")
        along, cross, n_along = fj, fi, NJ
    face = np.arange(fi.size).reshape(fi.shape)
    rows, cols = [], []
    for d in (-2, -1, 0, 1):  # cells along - 2 .. along + 1 of the face's row/column
        c = along + d
        ok = (c >= 0) & (c < n_along)
        ic, jc = (c, cross) if family == "i" else (cross, c)
        cell = (ic * NJ + jc)[ok]
        for k in range(4):
            rows.append(4 * cell + k)
            cols.append(face[ok])
    r, c = np.concatenate(rows), np.concatenate(cols)
    P = sp.csr_matrix((np.ones(r.size, bool), (r, c)), shape=(4 * NI * NJ, fi.size))
    P.sum_duplicates()
    P.sort_indices()
    colours = (along % 4).ravel()
    return P, colours


def _face_matrix(grid, q, flow, scheme, family):
    ni, nj = grid.shape
    P, colours = _face_pattern(grid, family)
    shape_i, shape_j = (2, ni, nj - 1), (2, ni - 1, nj)

    def func(X):
        b = X.shape[0]
        wi = np.zeros((b,) + shape_i, complex)
        wj = np.zeros((b,) + shape_j, complex)
        if family == "i":
            wi[:, 1] = X.reshape((b,) + shape_i[1:])
        else:
            wj[:, 1] = X.reshape((b,) + shape_j[1:])
        qb = np.broadcast_to(q.astype(complex), (b,) + q.shape)
        return residual(grid, qb, flow, face_velocity=(wi, wj), scheme=scheme).reshape(b, -1)

    return coloured_complex_step(func, np.zeros(P.shape[1]), P, colours, chunk=4)


@dataclass(frozen=True, eq=False)
class LinearSystem:
    """The gust equations linearised about a steady state (solver units, see module docstring).

    Attributes
    ----------
    grid : Grid
    flow : FlowCondition
    q : ndarray, shape (ni-1, nj-1, 4)
        Steady state (solver units).
    scheme : Scheme or None
        Passed to the residual.
    V : ndarray, shape (4N,)
        Diagonal of the mass matrix: cell areas (chords^2) in the flat order
        ``4 * (ic * (nj-1) + jc) + k``.
    J : scipy.sparse.csr_matrix, shape (4N, 4N)
        ``dR/dq``.
    Bi : scipy.sparse.csr_matrix, shape (4N, ni (nj-1))
        ``dR/dw_y`` on the i-faces (flat C order of ``(i, jc)``).
    Bj : scipy.sparse.csr_matrix, shape (4N, (ni-1) nj)
        ``dR/dw_y`` on the j-faces.
    C : ndarray, shape (3, 4N)
        ``d(Cl, Cm, Cd)/dq`` (rows in the order of ``OUTPUTS``).
    loads : ndarray, shape (3,)
        Steady ``(Cl, Cm, Cd)`` from ``wall_loads``.
    D : ndarray, shape (3, 1)
        Feedthrough of the gust: the response at ``omega = inf`` (the ``omega_d = pi`` sample of McKelvey's
        grid, returned without a solve); zeros, as the discrete system has no direct gust-to-load path.
    vortex : tuple (u, v) of ndarray, shape (4N,), or None
        With the point-vortex far field (``scheme.vortex``) the residual depends on the state also through
        the circulation, which ``cfd.jacobian`` holds frozen: the full Jacobian is ``J + u v^T`` with
        ``u = dR/dCl`` (complex step through ``residual(circulation=...)``) and ``v = dCl/dq`` (the first row
        of ``C``). :meth:`solver` adds this rank-one term by the Sherman-Morrison formula. None otherwise.
    """

    grid: object
    flow: FlowCondition
    q: np.ndarray
    scheme: object
    V: np.ndarray
    J: sp.csr_matrix
    Bi: sp.csr_matrix
    Bj: sp.csr_matrix
    C: np.ndarray
    loads: np.ndarray
    D: np.ndarray = field(default_factory=lambda: np.zeros((3, 1)))
    vortex: tuple = None

    @property
    def mach(self):
        """Free-stream Mach number: the factor from convective to solver velocity and frequency."""
        return self.flow.mach

    @property
    def n(self):
        """Number of state variables, ``4 N``."""
        return self.J.shape[0]

    def to_solver_time(self, s):
        """Convective time ``s`` (chords / U) to solver time (chords / a_inf): ``s / mach``."""
        return np.asarray(s) / self.mach

    def to_solver_frequency(self, omega):
        """Convective angular frequency (U / c) to solver units (a_inf / c): ``mach * omega``."""
        return np.asarray(omega) * self.mach

    def apply_jacobian(self, X, transpose=False):
        """The full Jacobian ``J + u v^T`` (with the vortex rank-one term, when the system has one) times ``X``.

        Parameters
        ----------
        X : ndarray, shape (4N,) or (4N, k), real or complex
        transpose : bool
            ``(J + u v^T)^T X`` instead.

        Returns
        -------
        ndarray, the shape of ``X``
        """
        out = np.asarray((self.J.T if transpose else self.J) @ X)
        if self.vortex is not None:
            u, v = self.vortex
            left, right = (v, u) if transpose else (u, v)
            out = out + np.multiply.outer(left, right @ X)
        return out

    def solver(self, diagonal, perm=None, native_complex=False):
        """Factorise ``diag(diagonal) + J`` (plus the vortex rank-one term) for repeated solves.

        Parameters
        ----------
        diagonal : ndarray, shape (4N,), real or complex
            E.g. ``1j * omega_solver * V`` (LFD) or ``1.5 V / dt_solver`` (BDF2).
        perm : ndarray of int, optional
            Ordering of the unknowns (default: nested dissection of the grid).
        native_complex : bool
            For a complex ``diagonal``: SciPy's complex SuperLU instead of the real 2n form (see
            :func:`factorise`).

        Returns
        -------
        callable
            ``solve(b)`` for ``b`` of shape (4N,) or (4N, k).
        """
        A = self.J + sp.diags(diagonal)
        solve0, _ = factorise(A, grid_permutation(self.grid) if perm is None else perm, native_complex=native_complex)
        if self.vortex is None:
            return solve0
        u, v = self.vortex
        z = solve0(u)
        denom = 1.0 + v @ z

        def solve(b):
            y = solve0(b)
            return y - np.multiply.outer(z, (v @ y) / denom)

        return solve

    def forcing(self, gi, gj, method="svm"):
        """Gust forcing ``b`` of ``V dq/dt + J q + b = 0`` from face averages of ``v_g / U``.

        Parameters
        ----------
        gi : ndarray, shape (..., ni, nj-1), real or complex
        gj : ndarray, shape (..., ni-1, nj)
        method : {"svm", "fvm"}

        Returns
        -------
        ndarray, shape (..., 4N)
        """
        check_gust_method(method)
        gi = np.asarray(gi)
        gj = np.asarray(gj)
        batch = gi.shape[:-2]
        Gi = gi.reshape((-1, self.Bi.shape[1]))
        Gj = gj.reshape((-1, self.Bj.shape[1]))
        b = -self.mach * (self.Bi @ Gi.T + self.Bj @ Gj.T).T
        if method == "svm":
            src = svm_source(self.q, self.mach, cell_x_gradient(self.grid, gi, gj), self.flow.gamma)
            b = b - src.reshape(b.shape)  # dR/dsource = -I
        return b.reshape(batch + (self.n,))


def _lu_nopivot(A, perm):
    Ap = sp.csr_matrix(A)[perm][:, perm].tocsc()
    lu = splu_nested(Ap)
    inv = np.empty_like(perm)
    inv[perm] = np.arange(perm.size)
    return lambda r: lu.solve(r[perm])[inv], lu.L.nnz + lu.U.nnz


def factorise(A, perm=None, rtol=1e-9, native_complex=False):
    """Sparse LU of a real or complex matrix for repeated solves, with a checked accuracy.

    The unknowns are ordered by ``perm`` (geometric nested dissection of the grid, ``cfd.ordering``) and
    factorised by SuperLU without row pivoting, which fills several times less than COLAMD with
    pivoting. A complex matrix ``A = Ar + i Ai`` is factorised as its real equivalent
    ``[[Ar, -Ai], [Ai, Ar]]`` with the real and imaginary parts of each unknown interleaved. SciPy's
    complex SuperLU is faster when it behaves (1.9 - 2.8 s against 8 - 9.6 s for the real form on the
    42 480-unknown paper grid, fill 20 against 39, measured side by side), but its time is erratic: the
    first complex factorisation in a process took 20 s on a 2 880-unknown grid where the real form takes
    0.3 s, and 76 - 156 s on the paper grid, even with :func:`cfd.superlu.reserve_heap` (not understood).
    The reference path uses the predictable real form; ``native_complex=True`` takes SciPy's complex SuperLU
    (with the heap prepared, as the fast sweep does: its solves read about half the bytes of the real form's).
    The factors are checked on a random right-hand side (``|A x - b| <= rtol |b|``); if the check
    fails, COLAMD with partial pivoting is used instead (with a RuntimeWarning).

    Parameters
    ----------
    A : scipy.sparse matrix, shape (n, n)
    perm : ndarray of int, shape (n,), optional
        Symmetric fill-reducing permutation; None: COLAMD with pivoting directly.
    rtol : float
    native_complex : bool
        Complex ``A``: factorise it as it is (complex SuperLU) instead of its real 2n form.

    Returns
    -------
    solve : callable
        ``solve(b)``, ``b`` of shape (n,), returns ``x`` (complex if ``A`` is).
    fill : float
        ``nnz(L + U) / nnz(A)`` of the factorisation used (of the real 2n form for complex ``A``, unless
        ``native_complex``).
    """
    A = sp.csr_matrix(A)
    n = A.shape[0]
    cplx = np.iscomplexobj(A.data) and not native_complex
    if cplx:
        K = sp.bmat([[A.real, -A.imag], [A.imag, A.real]], format="csr")
        K.eliminate_zeros()

        def wrap(solve_real):
            def solve(b):
                b = np.asarray(b)
                y = solve_real(np.concatenate([b.real, b.imag]).astype(float))
                return y[:n] + 1j * y[n:]
            return solve
    else:
        K = A

        def wrap(solve_real):
            return solve_real
    if perm is not None:
        p = np.stack([perm, perm + n], axis=1).ravel() if cplx else perm
        try:
            solve_real, nnz = _lu_nopivot(K, p)
            solve = wrap(solve_real)
            rng = np.random.default_rng(0)
            b = rng.normal(size=n) + (1j * rng.normal(size=n) if np.iscomplexobj(A.data) else 0.0)
            x = solve(b)
            if np.all(np.isfinite(x)) and np.linalg.norm(A @ x - b) <= rtol * np.linalg.norm(b):
                return solve, nnz / K.nnz
        except RuntimeError:
            pass
        warnings.warn("unpivoted nested-dissection LU was inaccurate; re-factorising with COLAMD and pivoting",
                      RuntimeWarning, stacklevel=2)
    lu = splu_pivoted(K)
    return wrap(lu.solve), (lu.L.nnz + lu.U.nnz) / K.nnz


def grid_permutation(grid):
    """Nested-dissection ordering of the 4N unknowns of a grid (for :func:`factorise`)."""
    return unknown_permutation(nested_dissection(grid))


def linearise_state(grid, q, flow, scheme=None):
    """Build the :class:`LinearSystem` of a steady state.

    Parameters
    ----------
    grid : Grid
    q : ndarray, shape (ni-1, nj-1, 4)
        Converged steady state (solver units).
    flow : FlowCondition
    scheme : Scheme, optional

    Returns
    -------
    LinearSystem

    Raises
    ------
    LinearError
        ``grid``, ``flow`` or ``scheme`` of the wrong type; ``q`` not a real array of the grid's shape, or holding
        NaN, inf or a non-positive density or pressure (:func:`cfd.flow.is_physical`).
    """
    if not isinstance(grid, Grid):
        raise LinearError(not_a_grid(grid))
    if not isinstance(flow, FlowCondition):
        raise LinearError(f"flow must be a cfd.FlowCondition; got {type(flow).__name__}")
    if scheme is not None and not isinstance(scheme, Scheme):
        raise LinearError(f"scheme must be a cfd.Scheme or None (the solution's or the default); got {scheme!r}")
    q_given, q = q, real_array(q)   # None for text, and for complex (it lost its imaginary part, a ComplexWarning)
    if q is None:
        raise LinearError(f"the steady state q must be an array of real numbers; got {kind_of(q_given)}")
    if q.shape != grid.cell_shape + (4,):
        raise LinearError(f"steady state has shape {q.shape}; this grid needs {grid.cell_shape + (4,)}")
    if not is_physical(q, flow.gamma):
        raise LinearError(f"the steady state q {NON_PHYSICAL}; linearise a converged cfd.solve_steady solution")
    V = np.repeat(grid.area.ravel(), 4)
    J = jacobian(grid, q, flow, scheme=scheme)
    Bi = _face_matrix(grid, q, flow, scheme, "i")
    Bj = _face_matrix(grid, q, flow, scheme, "j")
    C = _output_matrix(grid, q, flow)
    loads = wall_loads(grid, q, flow)
    vortex = None
    if scheme is not None and getattr(scheme, "vortex", False):
        cl0 = loads[0]
        u = residual(grid, q.astype(complex), flow, scheme=scheme, circulation=cl0 + 1j * H_STEP).imag / H_STEP
        vortex = (u.ravel(), C[0].copy())
        for a in vortex:
            a.setflags(write=False)
    for a in (V, C, loads):
        a.setflags(write=False)
    qf = q.copy()
    qf.setflags(write=False)
    return LinearSystem(grid=grid, flow=flow, q=qf, scheme=scheme, V=V, J=J.tocsr(), Bi=Bi, Bj=Bj, C=C,
                        loads=loads, vortex=vortex)


def linearise(sol, scheme=None):
    """Linearise a steady solution (``cfd.solve_steady``) for the gust solvers.

    Parameters
    ----------
    sol : object
        With ``grid``, the steady state ``q`` (shape (ni-1, nj-1, 4), solver units) and either ``flow``
        (FlowCondition) or ``mach`` and ``alpha_deg``; ``scheme`` is taken from it when present.
    scheme : Scheme, optional
        Overrides ``sol.scheme``.

    Returns
    -------
    LinearSystem

    Raises
    ------
    LinearError
        ``sol`` without ``grid`` and ``q`` (e.g. None or a Grid), a state of the wrong shape or with NaN, inf or a
        non-positive density or pressure, a ``scheme`` that is not a ``cfd.Scheme``.
    """
    if not (hasattr(sol, "grid") and hasattr(sol, "q")):
        hint = ("solve the flow first: cfd.linearise(cfd.solve_steady(grid, mach, alpha_deg))" if isinstance(sol, Grid)
                else "pass the result of cfd.solve_steady")
        raise LinearError(f"sol must be a steady solution with grid and q; got {type(sol).__name__}: {hint}")
    flow = getattr(sol, "flow", None)
    if flow is None:
        flow = FlowCondition(sol.mach, getattr(sol, "alpha_deg", 0.0))
    if scheme is None:
        scheme = getattr(sol, "scheme", None)
    return linearise_state(sol.grid, sol.q, flow, scheme)
