"""Field export: derived flow quantities and VTK files that ParaView opens (through meshio).

Nondimensional conventions of the flow solver: ``rho_inf = 1``, ``a_inf = 1``,
``p_inf = 1 / gamma``, ``|u_inf| = M_inf``; conserved variables ``q = (rho, rho u, rho v, rho E)``
per cell with ``p = (gamma - 1) (rho E - rho |u|^2 / 2)``.
"""

import numpy as np

from .checks import kind_of, real_array, real_number
from .errors import FlowConditionError, MeshError

__all__ = ["primitives", "write_vtk"]


def primitives(q, mach, gamma=1.4):
    """Derived cell fields from conserved variables.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Conserved variables ``rho, rho u, rho v, rho E`` (nondimensional, see module docstring).
    mach : float
        Free-stream Mach number (the free-stream speed in these units).
    gamma : float
        Ratio of specific heats.

    Returns
    -------
    dict of str to ndarray
        ``rho`` (...), ``velocity`` (..., 2), ``pressure`` (...), ``mach`` (...) local Mach number,
        ``cp`` (...) pressure coefficient ``(p - p_inf) / (rho_inf M^2 / 2)``.

    Raises
    ------
    MeshError
        If ``q`` is not an array of real numbers (complex, text, None), or its last axis is not 4.
    FlowConditionError
        If ``mach`` is not a positive finite real number.
    """
    q_given, q = q, real_array(q)   # None for text and None, and for complex (it lost its imaginary part)
    if q is None:
        raise MeshError(f"q must be an array of real conserved states (rho, rho u, rho v, rho E), shape (..., 4); "
                        f"got {kind_of(q_given)} {q_given!r:.80}")
    if q.ndim == 0 or q.shape[-1] != 4:   # a plain ValueError before (a scalar q: a bare IndexError)
        raise MeshError(f"q must have a last axis of 4 (rho, rho u, rho v, rho E), shape (..., 4); got shape "
                        f"{q.shape}")
    m = real_number(mach)
    if m is None or not (np.isfinite(m) and m > 0):   # text raised a bare TypeError, NaN a plain ValueError
        raise FlowConditionError(f"mach must be a positive finite real number (the free-stream Mach number); got "
                                 f"{kind_of(mach)} {mach!r:.80}")
    mach = m
    rho = q[..., 0]
    vel = q[..., 1:3] / rho[..., None]
    p = (gamma - 1.0) * (q[..., 3] - 0.5 * rho * np.sum(vel**2, axis=-1))
    c = np.sqrt(gamma * p / rho)
    return {
        "rho": rho,
        "velocity": vel,
        "pressure": p,
        "mach": np.hypot(vel[..., 0], vel[..., 1]) / c,
        "cp": (p - 1.0 / gamma) / (0.5 * mach**2),
    }


def write_vtk(grid, path, cell_data=None):
    """Write the grid and cell fields to a VTK file (``.vtu`` or legacy ``.vtk``).

    Parameters
    ----------
    grid : Grid
        The C-grid; each cell becomes a quad with its nodes counter-clockwise.
    path : str or path-like
        Output file; the format follows the suffix (meshio).
    cell_data : dict of str to array_like, optional
        Fields of shape ``(ni-1, nj-1)`` (scalars) or ``(ni-1, nj-1, 2 or 3)`` (vectors; 2-component
        vectors get a zero third component so that ParaView shows them as vectors).

    Raises
    ------
    MeshError
        If a field is not an array of real numbers (complex, text, None) or does not have the cell shape of the
        grid.
    """
    try:
        import meshio
    except ImportError:
        raise ImportError("cfd.export.write_vtk needs meshio: pip install 'lfdrom[vtk]' (or meshio>=5.3)") from None

    ni, nj = grid.shape
    pts = np.column_stack([grid.x.ravel(), grid.y.ravel(), np.zeros(ni * nj)])
    node = np.arange(ni * nj).reshape(ni, nj)
    quads = np.stack([node[:-1, :-1], node[1:, :-1], node[1:, 1:], node[:-1, 1:]], axis=-1).reshape(-1, 4)
    data = {}
    for name, arr in (cell_data or {}).items():
        a = real_array(arr)   # None for text and None, and for complex (it lost its imaginary part)
        if a is None:
            raise MeshError(f"cell field {name!r} must be an array of real numbers (one value per cell, shape "
                            f"{grid.cell_shape}, or a vector per cell); got {kind_of(arr)} {arr!r:.80}")
        if a.shape[:2] != grid.cell_shape or a.ndim not in (2, 3) or (a.ndim == 3 and a.shape[2] not in (2, 3)):
            raise MeshError(
                f"cell field {name!r} has shape {a.shape}; expected {grid.cell_shape} or "
                f"{grid.cell_shape + (2,)} / {grid.cell_shape + (3,)} (one value per cell, cells (ic, jc))"
            )
        if a.ndim == 3 and a.shape[2] == 2:
            a = np.concatenate([a, np.zeros(a.shape[:2] + (1,))], axis=2)
        data[name] = [a.reshape(grid.n_cells, -1) if a.ndim == 3 else a.ravel()]
    meshio.Mesh(pts, [("quad", quads)], cell_data=data).write(str(path))
