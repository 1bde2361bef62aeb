"""sysid.minimax_socp: the dedicated interior-point method for the complex minimax programme, against known
answers (analytic minimax fits), against Clarabel (the general conic solver it stands in for) on programmes
captured from the paper fits and on random ones, and its fallback to Clarabel on an infeasible programme."""

import warnings
from pathlib import Path

import numpy as np
import pytest

import sysid
from sysid import residues
from sysid.minimax_socp import minimax_socp

ROOT = Path(__file__).resolve().parents[2]
NONE = np.zeros((0, 1))


def level(Q, g, y):
    return float(np.abs(Q @ y - g).max())


# ------------------------------------------------------------------------------------------ known answers
@pytest.mark.parametrize("x", [[3.0, -1.0, 7.0, 2.0], [0.5], [-2.0, -2.0, 5.0], list(np.linspace(-1, 4, 9))])
def test_constant_fit_is_midrange(x):
    """min_c max_k |x_k - c| = (max - min) / 2 at the midpoint. The level is certified to the gap tolerance
    (1e-9 of the unit-sized data); the minimiser of this linear (non-smooth, sharp) minimum to the same order."""
    x = np.asarray(x, dtype=float)
    y, info = minimax_socp(np.ones((x.size, 1), complex), x.astype(complex), NONE, np.zeros(0))
    assert info["reason"] == "converged"
    half = (x.max() - x.min()) / 2
    assert info["level"] == pytest.approx(half, abs=1e-8)
    assert y[0] == pytest.approx((x.max() + x.min()) / 2, abs=1e-8)


@pytest.mark.parametrize("a, b", [(4.0, 3.0), (1.0, 1.0), (0.2, 5.0)])
@pytest.mark.parametrize("corner", [0.0, 1.0 - 2.0j])
def test_enclosing_circle_of_right_triangle(a, b, corner):
    """The smallest circle around the vertices of a right triangle (legs a, b at ``corner``) has the
    hypotenuse as diameter: radius hypot(a, b) / 2 at the hypotenuse midpoint. ``y = (Re c, Im c)`` with
    ``Q_k = (1, 1j)``. The level is accurate to the gap (1e-9 relative); the centre only to about
    sqrt(1e-9) * radius = 3e-5 radius: along the hypotenuse's normal the level grows quadratically away from the
    centre (two active points), so the tolerance is three times that (measured 6e-6 radius for the 3-4-5 one)."""
    p = corner + np.array([0.0, a, 1j * b])
    Q = np.tile([1.0, 1.0j], (3, 1))
    y, info = minimax_socp(Q, p, np.zeros((0, 2)), np.zeros(0))
    r = np.hypot(a, b) / 2
    assert info["level"] == pytest.approx(r, rel=1e-8)
    centre = corner + (a + 1j * b) / 2
    assert abs(y[0] + 1j * y[1] - centre) <= 3.0 * np.sqrt(1e-9) * r


@pytest.mark.parametrize("K", [5, 11, 40])
def test_chebyshev_line_with_equality(K):
    """min max_k |x_k^2 - (c0 + c1 x_k)| on a grid of [0, 1] with c0 = 0 imposed. Continuum answer: the error
    x^2 - c1 x is extreme at x = c1 / 2 (-c1^2 / 4) and x = 1 (1 - c1); equal ripple gives c1 = 2 (sqrt 2 - 1)
    and level 3 - 2 sqrt 2. On the grid the level is that of the best c1 of a fine scan (step 1e-7, which
    moves the level by at most 1e-7), and for K = 40 within the grid's resolution of the continuum answer
    (an extremum off the grid by at most h / 2 changes it by (h / 2)^2)."""
    x = np.linspace(0.0, 1.0, K)
    Q = np.stack([np.ones(K), x], axis=1).astype(complex)
    g = (x ** 2).astype(complex)
    y, info = minimax_socp(Q, g, np.array([[1.0, 0.0]]), np.array([0.0]))
    assert info["reason"] == "converged"
    assert abs(y[0]) <= 1e-15  # the equality holds exactly (null space basis)
    # discrete level as a function of c1: max(max_k (c1 x_k - x_k^2), 1 - c1) (x = 1 is on the grid)
    c1s = np.linspace(0.8, 0.86, 600001)
    lev = np.maximum(np.max(np.outer(c1s, x) - x ** 2, axis=1), 1.0 - c1s)
    assert lev.min() - 2e-7 <= info["level"] <= lev.min() + 1e-9  # no worse than the scan, its step apart
    if K == 40:  # the grid resolves the continuum answer to (1 / 39)^2 / 4 in the level
        assert info["level"] == pytest.approx(3 - 2 * np.sqrt(2), abs=(1 / 39) ** 2)


# ------------------------------------------------------------------------------------- against Clarabel
_CAPTURED = {}


def captured(case, n):
    """The programmes ``socp_minimax`` receives in ``identify(frf, n, dc_gain="match", stable=True)`` (Clarabel
    path), recorded by wrapping it."""
    if (case, n) not in _CAPTURED:
        frf = sysid.FrequencyResponse.load(str(ROOT / "docs" / "data" / f"frf-{case}.npz"))
        seen = []
        original = residues.socp_minimax

        def record(Q, g, E, f, tol=1e-9, Qb=None, ub=None, within=None):
            seen.append((Q, g, E, f, Qb, ub))
            return original(Q, g, E, f, tol=tol, Qb=Qb, ub=ub, within=within)

        mp = pytest.MonkeyPatch()
        mp.setattr(residues, "socp_minimax", record)
        mp.setattr(residues, "DEDICATED_SOLVER", False)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # the fits' own quality warnings are not under test here
                sysid.identify(frf, n, dc_gain="match", stable=True)
        finally:
            mp.undo()
        _CAPTURED[(case, n)] = seen
    return _CAPTURED[(case, n)]


def clarabel(Q, g, E, f, Qb=None, ub=None):
    mp = pytest.MonkeyPatch()
    mp.setattr(residues, "DEDICATED_SOLVER", False)
    try:
        return residues.socp_minimax(Q, g, E, f, Qb=Qb, ub=ub)[0]
    finally:
        mp.undo()


def check_against_clarabel(Q, g, E, f, Qb, ub):
    """Both solvers certify the level to the gap tolerance 1e-9 on the unit-scaled data (|g| <= 1, Q with
    orthonormal columns: a unit change of y moves the residuals by at most 1), and to 1e-9 relative for the
    dedicated one; Clarabel's absolute gap tolerance allows 1e-9 absolute, its bounds round-off violations of
    1e-9 relative (measured 2.4e-9 on T4 N_r 55) - so the levels agree to 1e-7 relative + 5e-9 absolute."""
    y, info = minimax_socp(Q, g, E, f, Qb=Qb, ub=ub)
    assert y is not None, info
    yc = clarabel(Q, g, E, f, Qb, ub)
    assert yc is not None
    l1, l2 = level(Q, g, y), level(Q, g, yc)
    assert l1 == pytest.approx(l2, rel=1e-7, abs=5e-9)
    # equalities to round-off: E y = f from an orthonormal null-space basis, |E|, |f| <= about 1
    if E.shape[0]:
        assert np.abs(E @ y - f).max() <= 1e-13 * max(1.0, np.abs(f).max())
    if Qb is not None and Qb.shape[0]:  # the bounds hold to the primal feasibility tolerance
        assert np.max(np.abs(Qb @ y) - ub) <= 1e-8 * max(1.0, ub.max())


@pytest.mark.parametrize("n", [10, 25, 55])
@pytest.mark.parametrize("case", ["T1", "T2", "T3", "T4", "T5", "T6"])
def test_captured_programmes_match_clarabel(case, n):
    progs = captured(case, n)
    assert progs, "the fit solved no minimax programme"
    for p in progs:
        check_against_clarabel(*p)


def test_captured_include_bounded():
    """The captured set exercises the bounded programmes (cutting planes of the gap bounds)."""
    assert any(p[4] is not None and p[4].shape[0] for n in (25, 55) for case in ("T4", "T5")
               for p in captured(case, n))


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("K, N, c, J", [(65, 11, 2, 0), (129, 26, 1, 0), (257, 56, 2, 0), (130, 26, 2, 60),
                                        (257, 40, 0, 300)])
def test_random_programmes_match_clarabel(seed, K, N, c, J):
    """Random well-conditioned programmes in the form minimax_cd builds (Q with orthonormal real-stacked
    columns, |g| <= 1, unit-norm equality rows, bounds at half the reachable gain so some are active)."""
    rng = np.random.default_rng(seed)
    Qr, _ = np.linalg.qr(rng.standard_normal((2 * K, N)))
    Q = Qr[:K] + 1j * Qr[K:]
    g = rng.standard_normal(K) + 1j * rng.standard_normal(K)
    g /= np.abs(g).max()
    E = rng.standard_normal((c, N))
    E /= np.linalg.norm(E, axis=1, keepdims=True)
    f = 0.1 * rng.standard_normal(c)
    Qb = ub = None
    if J:
        Qb = 0.1 * (rng.standard_normal((J, N)) + 1j * rng.standard_normal((J, N)))
        ub = np.full(J, 0.5)
    check_against_clarabel(Q, g, E, f, Qb, ub)


# ------------------------------------------------------------------------------------------------ fallback
@pytest.mark.parametrize("N", [1, 3, 45])
def test_infeasible_bounded_falls_back_to_clarabel(N):
    """E fixes y_0 = 1 while a bound demands |y_0| <= 0.5: infeasible. The dedicated method must return None
    (never an answer), and socp_minimax then reports Clarabel's verdict - the same as the Clarabel path."""
    rng = np.random.default_rng(N)
    Qr, _ = np.linalg.qr(rng.standard_normal((120, N)))
    Q = Qr[:60] + 1j * Qr[60:]
    g = np.exp(1j * np.linspace(0, 3, 60))
    E = np.eye(N)[:1]
    f = np.array([1.0])
    Qb = np.eye(N)[:1].astype(complex)
    ub = np.array([0.5])
    y, info = minimax_socp(Q, g, E, f, Qb=Qb, ub=ub)
    assert y is None and info["reason"] != "converged"
    mp = pytest.MonkeyPatch()
    mp.setattr(residues, "DEDICATED_MIN_UNKNOWNS", 1)
    try:
        got = residues.socp_minimax(Q, g, E, f, Qb=Qb, ub=ub)
    finally:
        mp.undo()
    ref = (None, None)
    mp = pytest.MonkeyPatch()
    mp.setattr(residues, "DEDICATED_SOLVER", False)
    try:
        ref = residues.socp_minimax(Q, g, E, f, Qb=Qb, ub=ub)
    finally:
        mp.undo()
    assert got[0] is None and ref[0] is None
    assert got[1] == ref[1] and "nfeasible" in got[1]


@pytest.mark.parametrize("N", [24, 40, 56])
def test_socp_minimax_uses_dedicated_and_agrees(N):
    """Wired in from DEDICATED_MIN_UNKNOWNS on: socp_minimax's answer is the dedicated method's."""
    rng = np.random.default_rng(N)
    Qr, _ = np.linalg.qr(rng.standard_normal((2 * 257, N)))
    Q = Qr[:257] + 1j * Qr[257:]
    g = rng.standard_normal(257) + 1j * rng.standard_normal(257)
    g /= np.abs(g).max()
    E = np.ones((1, N)) / np.sqrt(N)
    f = np.array([0.05])
    y, status = residues.socp_minimax(Q, g, E, f)
    y2, _ = minimax_socp(Q, g, E, f)
    assert status == "optimal" and np.array_equal(y, y2)
