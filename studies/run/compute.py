"""Computing pieces inside a task: the store with the code versions the main process pinned, one piece computed
and stored (a failure stored as such), and the report of a stored piece.

Every section's tasks use these (:mod:`studies.sections.protocol`): a task opens the store with
:func:`pinned_store`, skips what is stored (:func:`needs_compute`), stores each piece through
:func:`compute_piece` and returns one :func:`piece_report` per piece.
"""

from __future__ import annotations

import time
import warnings
from typing import Callable

from ..store.cache import ResultStore
from ..store.entries import failure_payload, is_failed, payload_arrays, store_dependencies

__all__ = ["PinnedStore", "pinned_store", "needs_compute", "compute_piece", "piece_report"]


class PinnedStore(ResultStore):
    """A :class:`ResultStore` whose per-piece code versions are fixed (computed once, in the main process).

    The sources' hash is computed once per process; pinning it keeps the keys of a run consistent across
    worker processes even if a source file changes while the study runs.
    """

    def __init__(self, root, codes: dict):
        super().__init__(root, dependencies=store_dependencies(), required=payload_arrays())
        self._codes = dict(codes)

    def code_version(self, piece: str) -> dict:
        """The pinned code version of ``piece`` (or the store's own for a piece not pinned)."""
        return dict(self._codes[piece]) if piece in self._codes else super().code_version(piece)

    @property
    def codes(self) -> dict:
        """The pinned code versions (piece -> code version): a task reopens this store in a worker process with
        ``pinned_store(str(store.root), store.codes)``."""
        return dict(self._codes)


def pinned_store(root, codes) -> ResultStore:
    """The store at ``root`` with the code versions ``codes`` (piece -> ``ResultStore.code_version``) pinned."""
    return PinnedStore(root, codes)


def needs_compute(store, piece, cfg, force) -> bool:
    """Whether a piece must be computed: ``force``, or not stored, or stored as a failure, or unreadable (a
    file in the place of its folder, no permission: its task then meets the :class:`studies.store.cache.StoreReadError`
    again and is recorded as failed, so that the run goes on with the other pieces and ends with exit status 3
    instead of stopping in its plan)."""
    from ..store.cache import StoreReadError

    if force:
        return True
    try:
        e = store.get(piece, cfg)
    except StoreReadError:
        return True
    return e is None or is_failed(e)


def piece_report(piece, label, entry, seconds, computed=True) -> dict:
    """The report of one stored piece (``piece``, ``label``, ``status``, ``error``, ``seconds``, ``computed``)."""
    md = entry.metadata if entry is not None else {}
    return dict(piece=piece, label=label, status=md.get("status", "ok"), error=md.get("error"),
                seconds=float(seconds), computed=computed)


def compute_piece(store, piece, cfg, compute: Callable[[], tuple], catch=True):
    """Compute a piece with ``compute() -> (arrays, metadata)`` and store it (a failure is stored as such, unless
    ``catch`` is False: then it raises). Returns ``(entry, seconds)``."""
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            arrays, metadata = compute()
        notes = sorted({f"{w.category.__name__}: {w.message}"[:500] for w in caught})
        if notes:
            metadata = dict(metadata, warnings=notes)
    except Exception as e:  # noqa: BLE001 - any failure of a piece is recorded and the study goes on
        if not catch:
            raise
        arrays, metadata = failure_payload(e)
    seconds = time.perf_counter() - t0
    entry = store.put(piece, cfg, arrays, metadata, extra_provenance={"compute_s": seconds})
    return entry, seconds
