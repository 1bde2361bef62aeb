"""The store of a study: its piece kinds (from the registered sections), and the failure records every section
writes and reads.

Each section declares its piece kinds (:class:`studies.sections.protocol.PieceKind`: store folder, the sources
that enter its keys, the arrays an entry holds); :func:`open_store` opens a study's
:class:`studies.store.cache.ResultStore` with all of them. A piece that raised is stored as a failure:
no arrays, ``status = "failed"`` and ``error = "ExceptionType: message"`` (:func:`failure_payload`,
:func:`is_failed`).
"""

from __future__ import annotations

from pathlib import Path

from ..sections.protocol import piece_kinds
from .cache import ResultStore

__all__ = ["store_dependencies", "payload_arrays", "open_store", "error_text", "failure_payload", "is_failed"]


def store_dependencies() -> dict:
    """Piece kind -> packages and modules whose sources enter its key, for every registered section.

    Returns
    -------
    dict of str -> tuple of str
    """
    return {name: tuple(kind.dependencies) for name, kind in piece_kinds().items()}


def payload_arrays() -> dict:
    """Piece kind -> the arrays an entry that is not a failure holds, for every registered section."""
    return {name: tuple(kind.arrays) for name, kind in piece_kinds().items() if kind.arrays}


def open_store(config, store_dir=None) -> ResultStore:
    """The :class:`studies.store.cache.ResultStore` of a study (``store_dir`` overrides ``config.store_dir``),
    with the keys of :func:`store_dependencies` and the payload layouts of :func:`payload_arrays`."""
    return ResultStore(Path(store_dir) if store_dir is not None else config.store_dir,
                       dependencies=store_dependencies(), required=payload_arrays())


def error_text(exc: BaseException) -> str:
    """``"ExceptionType: message"`` (first 2000 characters)."""
    return f"{type(exc).__name__}: {exc}"[:2000]


def failure_payload(exc_or_text, **extra) -> tuple:
    """``(arrays, metadata)`` of a failed piece: no arrays, ``status = "failed"`` and the error text."""
    text = exc_or_text if isinstance(exc_or_text, str) else error_text(exc_or_text)
    return {}, dict(extra, status="failed", error=text)


def is_failed(entry) -> bool:
    """Whether a store entry records a failure."""
    return entry is not None and entry.metadata.get("status") == "failed"
