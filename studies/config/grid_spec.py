"""Sizes of a study's C-grid (:class:`GridSpec`), checked before any grid is built, and the memory limits
that refuse grids a worker cannot hold."""

from __future__ import annotations

from dataclasses import asdict, dataclass

from .case_fields import CaseError, check_integer, check_real

__all__ = ["GridSpec", "PAPER_GRID", "COARSE_GRID", "GRID_PRESETS", "WALL_SPACING", "MAX_CELLS", "MAX_FARFIELD", "worker_memory_bytes"]


WALL_SPACING = 0.004
"""First cell height at the wall of ``cfd.c_grid`` (its ``wall_spacing`` default, chords)."""

MAX_CELLS = 2_000_000
"""Most cells ``(ni - 1) (nj - 1)`` of a study grid on any machine (memory of the exact Jacobian's LU); a grid
whose estimated worker memory (:func:`worker_memory_bytes`) exceeds twice the machine's is refused too."""

MAX_FARFIELD = 200.0
"""Farthest far field (chords) a study grid may ask of ``cfd.c_grid``."""


def worker_memory_bytes(cells: int) -> float:
    """Estimated peak memory of one study worker on a grid of ``cells`` cells (bytes).

    Anchored on the paper grid (10,620 cells: about 1.5 GB at the peak of the fast sweep, measured, see
    ``studies.run.runner.auto_workers``) and scaled as ``cells^1.2``, the growth of a nested-dissection LU's fill
    on 2-D grids over this range (``N log N``). Right to a factor of two; used to refuse grids that cannot fit.
    """
    return 1.5e9 * (max(int(cells), 1) / 10_620) ** 1.2


def _physical_memory_bytes():
    import os

    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):  # pragma: no cover - not POSIX
        return None


@dataclass(frozen=True)
class GridSpec:
    """Sizes of the C-grid (``cfd.c_grid`` arguments); the paper's 181 x 60 grid by default.

    Parameters
    ----------
    ni, nj : int
        Nodes around the C and outward.
    n_surface : int
        Cells on the aerofoil (even); ``ni - 1 - n_surface`` must be even and >= 2 (the wake cells).
    farfield : float
        Far-field radius in chords (>= 3).

    Raises
    ------
    CaseError
        Sizes that ``cfd.c_grid`` would reject (checked here, before any grid is built).
    """

    ni: int = 181
    nj: int = 60
    n_surface: int = 100
    farfield: float = 25.0

    def __post_init__(self):
        for name in ("ni", "nj", "n_surface"):
            object.__setattr__(self, name, check_integer("grid", name, getattr(self, name)))
        object.__setattr__(self, "farfield", check_real("grid", "farfield", self.farfield))
        if self.n_surface < 8 or self.n_surface % 2:
            raise CaseError(f"grid: n_surface = {self.n_surface} must be even and at least 8 (paper: 100)")
        wake = self.ni - 1 - self.n_surface
        if wake < 2 or wake % 2:
            raise CaseError(
                f"grid: ni - 1 - n_surface = {wake} wake cells must be even and >= 2; use ni = n_surface + 1 "
                f"+ 2 * n_wake, e.g. ni = {self.n_surface + 81} for 40 wake cells per branch")
        if self.nj < 16:
            raise CaseError(f"grid: nj = {self.nj} is too few; use nj >= 16 (paper: 60)")
        if self.farfield < 3.0:
            raise CaseError(f"grid: farfield = {self.farfield} chords is too close; use at least 3 (default 25)")
        if self.farfield > MAX_FARFIELD:
            raise CaseError(f"grid: farfield = {self.farfield:g} chords is farther than the grid can reach from the wall "
                            f"spacing {WALL_SPACING} without folding (1000 chords on 16 nodes did); use at most "
                            f"{MAX_FARFIELD:g} (the far-field vortex correction makes 20 - 50 enough; paper: 25)")
        if self.farfield / (self.nj - 1) <= WALL_SPACING:
            raise CaseError(
                f"grid: nj = {self.nj} nodes outward over {self.farfield:g} chords leaves a uniform spacing below the "
                f"wall spacing {WALL_SPACING} that cfd.c_grid grows from; use nj < {int(self.farfield / WALL_SPACING) + 1} "
                "(paper: 60)")
        cells = (self.ni - 1) * (self.nj - 1)
        need = worker_memory_bytes(cells)
        have = _physical_memory_bytes()
        if cells > MAX_CELLS or (have is not None and need > 2 * have):
            raise CaseError(
                f"grid: {self.ni} x {self.nj} has {cells:,} cells: a worker would need about {need / 2**30:.3g} GiB "
                f"for the exact Jacobian's sparse LU (1.5 GB for the paper grid's 10,620 cells, growing as cells^1.2)"
                + (f", more than twice this machine's {have / 2**30:.3g} GiB" if have is not None else "")
                + f" (at most {MAX_CELLS:,} cells in any case); use a coarser grid, e.g. 361 x 120")

    def kwargs(self) -> dict:
        """Keyword arguments of ``cfd.c_grid``."""
        return asdict(self)


PAPER_GRID = GridSpec()

COARSE_GRID = GridSpec(ni=65, nj=17, n_surface=48)
"""A 65 x 17 C-grid (48 cells on the wall, 1,024 cells against the paper grid's 10,620): a case in seconds, for
trying things (``lfdrom rom --grid coarse``); its accuracy against the paper grid: docs/mesh.md. The same sizes as
``cfd.GRID_PRESETS["coarse"]`` (a test checks)."""

GRID_PRESETS = {"paper": PAPER_GRID, "coarse": COARSE_GRID}
"""Grid sizes by name (``lfdrom rom --grid NAME``)."""
