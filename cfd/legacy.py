"""The module paths of the flat ``cfd`` package (before its sub-packages ``cfd.mesh``, ``cfd.sweep`` and
``cfd.ltd``), kept for one release.

``import cfd.mesh_metrics`` (or ``from cfd.sweep_basis import SweepBasis``) still works: :class:`LegacyFinder`,
put on ``sys.meta_path`` by ``import cfd``, answers each old module name of :data:`MOVED` with the module at its
new home (the same module object, so that patching one patches the other) and a ``DeprecationWarning`` that
names the new path. ``cfd.mesh``, ``cfd.sweep`` and ``cfd.ltd`` were modules and are packages now whose names
(``cfd.mesh.c_grid``, ``cfd.sweep.fast_sweep``, ``cfd.ltd.ltd_response``, ...) are unchanged; the names of
``cfd`` itself (``cfd.c_grid``, ``cfd.lfd_response``, ...) are unchanged too.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys
import warnings

__all__ = ["MOVED", "LegacyFinder", "install"]

MOVED = {f"cfd.{old}": f"cfd.{new}" for old, new in {
    "geometry": "mesh.geometry",
    "mesh_spacing": "mesh.spacing",
    "mesh_elliptic": "mesh.elliptic",
    "mesh_generation": "mesh.generation",
    "mesh_metrics": "mesh.metrics",
    "mesh_quality": "mesh.quality",
    "grid_presets": "mesh.presets",
    "sweep_basis": "sweep.basis",
    "sweep_workers": "sweep.workers",
    "orthonormal": "sweep.orthonormal",
    "radau": "ltd.radau",
    "coupled": "ltd.coupled",
}.items()}
"""Old module name -> its new home."""


class _Alias(importlib.abc.Loader):
    """Loads an old module name as the module at its new home."""

    def __init__(self, target: str):
        self.target = target

    def create_module(self, spec):
        warnings.warn(f"{spec.name} moved to {self.target}: import it from there (the old path is kept for one "
                      "release)", DeprecationWarning, stacklevel=2)
        module = importlib.import_module(self.target)
        self.spec = module.__spec__
        return module

    def exec_module(self, module):
        """Nothing to run (the module at the new home is imported); the import system has just replaced the
        module's ``__spec__`` by the old name's: put its own back (``importlib.util.find_spec`` of the new name,
        e.g. for the sources hashed into the store's keys, reads it)."""
        module.__spec__ = self.spec


class LegacyFinder(importlib.abc.MetaPathFinder):
    """Finds the old module names of a mapping ``moved`` (old dotted name -> new dotted name; see the module
    docstring). One finder per mapping: ``studies.legacy`` installs one for the studies package's old paths."""

    def __init__(self, moved: dict):
        self.moved = moved

    def find_spec(self, fullname, path=None, target=None):
        new = self.moved.get(fullname)
        if new is None:
            return None
        return importlib.util.spec_from_loader(fullname, _Alias(new))


def install(moved: dict = MOVED) -> None:
    """Put one :class:`LegacyFinder` of ``moved`` (default :data:`MOVED`) on ``sys.meta_path`` (once)."""
    if not any(isinstance(f, LegacyFinder) and f.moved is moved for f in sys.meta_path):
        sys.meta_path.insert(0, LegacyFinder(moved))  # before the editable install's finder
