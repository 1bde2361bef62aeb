"""Named C-grid sizes: the paper's 181 x 60 grid and a coarse 65 x 17 grid for trying a case in seconds.

The coarse grid's accuracy against the paper grid is measured in docs/mesh.md ("The coarse grid").
"""

from __future__ import annotations

from types import MappingProxyType

from ..errors import MeshError
from .generation import c_grid

__all__ = ["GRID_PRESETS", "preset_grid"]

GRID_PRESETS = MappingProxyType({
    "paper": MappingProxyType({"ni": 181, "nj": 60, "n_surface": 100, "farfield": 25.0}),
    "coarse": MappingProxyType({"ni": 65, "nj": 17, "n_surface": 48, "farfield": 25.0}),
})
"""``cfd.c_grid`` sizes by name: ``"paper"`` (Bagheri, Jones & Gaitonde's 181 x 60, 100 cells on the wall) and
``"coarse"`` (65 x 17, 48 cells on the wall: 1,024 cells against 10,620)."""


def preset_grid(foil, name: str = "paper"):
    """The C-grid of a named size around ``foil``.

    Parameters
    ----------
    foil : Aerofoil
        From :func:`cfd.naca`.
    name : {"paper", "coarse"}
        A key of :data:`GRID_PRESETS`.

    Returns
    -------
    Grid
        ``cfd.c_grid(foil, **GRID_PRESETS[name])``.

    Raises
    ------
    MeshError
        An unknown name (the message lists the known ones).
    """
    if not isinstance(name, str) or name not in GRID_PRESETS:
        raise MeshError(f"unknown grid preset {name!r}; use one of {', '.join(map(repr, GRID_PRESETS))}, or call "
                        "cfd.c_grid with explicit sizes")
    return c_grid(foil, **GRID_PRESETS[name])
