"""Where a result came from: code version, package versions, machine and time.

Two uses:

- :func:`code_version` is part of every cache key (``studies.store.cache``): the ``lfdrom`` package version and
  a sha256 of the Python sources of the packages a piece depends on (e.g. ``cfd`` for an FRF, ``sysid``
  for a ROM). The git commit is *not* in the key: a commit that touches only docs or another package would
  otherwise invalidate every stored result, and uncommitted edits would not change it; the source hash
  changes exactly when code that can change the result changes (committed or not).
- :func:`provenance` is stored with every result: the configuration, the code version, the git commit (and
  whether the tree had uncommitted changes), the versions of numpy, scipy, cvxpy, clarabel, control and
  lfdrom, the Python version, the platform, the host name, the process id and the UTC time.
"""

from __future__ import annotations

import datetime as _dt
import functools
import hashlib
import importlib.metadata
import importlib.util
import os
import platform
import socket
import subprocess
import sys
from pathlib import Path
from typing import Iterable, Optional

__all__ = [
    "PACKAGES",
    "package_versions",
    "source_hash",
    "code_version",
    "git_commit",
    "provenance",
]

PACKAGES = ("numpy", "scipy", "cvxpy", "clarabel", "control", "lfdrom")
"""Distributions whose versions are recorded."""

_REPO_ROOT = Path(__file__).resolve().parents[2]


def package_versions(packages: Iterable[str] = PACKAGES) -> dict:
    """Installed versions, ``{"numpy": "2.4.6", ...}``; ``None`` for a package that is not installed."""
    out = {}
    for name in packages:
        try:
            out[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            out[name] = None
    return out


def _sources(name: str) -> Optional[list]:
    """``(relative name, path)`` of the sources of a package (its ``*.py`` files) or of a single module."""
    try:
        spec = importlib.util.find_spec(name)
    except (ImportError, ValueError):
        return None
    if spec is None:
        return None
    if spec.submodule_search_locations:
        root = Path(list(spec.submodule_search_locations)[0])
        return [(p.relative_to(root).as_posix(), p) for p in sorted(root.rglob("*.py")) if "__pycache__" not in p.parts]
    if spec.origin and spec.origin.endswith(".py"):
        return [(Path(spec.origin).name, Path(spec.origin))]
    return None


@functools.lru_cache(maxsize=None)
def source_hash(packages: tuple = ("sysid", "cfd")) -> str:
    """sha256 (hex) of the Python sources of ``packages``: packages (all their ``*.py`` files) or single
    modules (dotted names such as ``"studies.config"``), each with its files' relative paths, sorted.

    Computed once per process and per tuple. A name that cannot be found contributes itself and
    ``"missing"`` (so the hash changes once when it appears).
    """
    h = hashlib.sha256()
    for name in sorted(packages):
        h.update(f"package {name}\n".encode())
        files = _sources(name)
        if files is None:
            h.update(b"missing\n")
            continue
        for rel, path in files:
            data = path.read_bytes()
            h.update(f"file {rel} {len(data)}\n".encode())
            h.update(data)
    return h.hexdigest()


def code_version(packages: Iterable[str] = ("sysid", "cfd")) -> dict:
    """The code part of a cache key: ``{"lfdrom": version, "packages": [...], "sources": sha256}``."""
    pk = tuple(sorted(set(packages)))  # packages or dotted module names
    return {"lfdrom": package_versions(("lfdrom",))["lfdrom"], "packages": list(pk), "sources": source_hash(pk)}


@functools.lru_cache(maxsize=1)
def git_commit() -> Optional[dict]:
    """``{"commit": sha, "dirty": bool}`` of the repository holding this package, or None without git.

    ``dirty`` is True when tracked files under ``sysid/``, ``cfd/`` or ``studies/`` differ from the commit.
    Computed once per process.
    """
    if not (_REPO_ROOT / ".git").exists():
        return None
    try:
        commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=_REPO_ROOT, capture_output=True, text=True,
                                timeout=10, check=True).stdout.strip()
        diff = subprocess.run(["git", "diff", "--quiet", "HEAD", "--", "sysid", "cfd", "studies"], cwd=_REPO_ROOT,
                              capture_output=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return None
    return {"commit": commit, "dirty": diff.returncode != 0}


def provenance(config=None, *, piece: Optional[str] = None, code: Optional[dict] = None,
               extra: Optional[dict] = None) -> dict:
    """The provenance record stored with a result.

    Parameters
    ----------
    config : JSON-ready object, optional
        The configuration that produced the result.
    piece : str, optional
        The kind of result (``"frf"``, ``"rom"``...).
    code : dict, optional
        :func:`code_version` used for the key.
    extra : dict, optional
        More fields (e.g. the compute time), merged in.

    Returns
    -------
    dict
        ``config``, ``piece``, ``code``, ``git``, ``packages``, ``python``, ``platform``, ``hostname``, ``pid``,
        ``timestamp`` (UTC, ISO 8601) and the ``extra`` fields.
    """
    rec = {
        "config": config,
        "piece": piece,
        "code": code,
        "git": git_commit(),
        "packages": package_versions(),
        "python": sys.version.split()[0],
        "implementation": platform.python_implementation(),
        "platform": platform.platform(),
        "hostname": socket.gethostname(),
        "pid": os.getpid(),
        "timestamp": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
    }
    if extra:
        rec.update(extra)
    return rec
