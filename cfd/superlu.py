"""SuperLU factorisations used by every linear solve in ``cfd``, with the C heap prepared for them.

SciPy's SuperLU grows its work arrays as the factors fill in. With glibc's default heap settings that
growth can cost far more than the arithmetic: on the 181 x 60 paper grid (42 480 unknowns), a complex
factorisation of ``J + i w V`` took 76 s right after a real factorisation of ``J`` in the same process,
and 2.5 s with the heap's top pad raised to 256 MiB (``mallopt(M_TOP_PAD)``; 64 MiB gave 6.4 s), measured
side by side on an idle machine. :func:`reserve_heap` sets that pad once per process (glibc only; elsewhere
it does nothing). The pad is address space the heap keeps when it grows or trims, not memory in use.
"""

import ctypes
import ctypes.util

import scipy.sparse as sp
import scipy.sparse.linalg as spla

__all__ = ["reserve_heap", "splu_nested", "splu_pivoted", "HEAP_TOP_PAD"]

HEAP_TOP_PAD = 256 * 2**20
"""Bytes of glibc ``M_TOP_PAD`` set by :func:`reserve_heap`."""

_M_TOP_PAD = -2   # glibc <malloc.h>
_done = False


def reserve_heap():
    """Raise glibc's heap top pad to :data:`HEAP_TOP_PAD` (once per process).

    Returns
    -------
    bool
        True if the setting is in effect (glibc found and ``mallopt`` accepted it).
    """
    global _done
    if _done:
        return _done == "ok"
    _done = "no"
    try:
        name = ctypes.util.find_library("c")
        libc = ctypes.CDLL(name) if name else None
        if libc is not None and hasattr(libc, "mallopt") and libc.mallopt(_M_TOP_PAD, HEAP_TOP_PAD) == 1:
            _done = "ok"
    except OSError:
        pass
    return _done == "ok"


def splu_nested(Ap):
    """SuperLU of a matrix already in nested-dissection order: no column ordering, no row pivoting.

    Parameters
    ----------
    Ap : scipy.sparse matrix, shape (n, n), real or complex
        The permuted matrix ``A[perm][:, perm]``.

    Returns
    -------
    scipy.sparse.linalg.SuperLU
    """
    reserve_heap()
    return spla.splu(sp.csc_matrix(Ap), permc_spec="NATURAL", diag_pivot_thresh=0.0,
                     options=dict(SymmetricMode=True))


def splu_pivoted(A):
    """SuperLU with COLAMD column ordering and partial pivoting (the robust fallback).

    Parameters
    ----------
    A : scipy.sparse matrix, shape (n, n)

    Returns
    -------
    scipy.sparse.linalg.SuperLU
    """
    reserve_heap()
    return spla.splu(sp.csc_matrix(A), permc_spec="COLAMD")
