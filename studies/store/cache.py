"""A content-addressed results store on disk: NumPy arrays + JSON metadata, keyed by what produced them.

Keys
----
``key = sha256(canonical JSON of {"piece", "config", "code"})`` where ``config`` is the piece's own
sub-configuration (``studies.sections.gust_rom.pieces.steady_piece``, ``frf_piece``, ``rom_piece``, ``ltd_piece``,
``sim_piece``: an FRF's key holds the aerofoil, Mach, grid, T and M_base but not N_r, so changing N_r keeps
the FRF) and ``code`` is :func:`studies.store.provenance.code_version` of the code the piece depends on: the
lfdrom version and a sha256 of the Python sources of those packages and modules (:func:`piece_dependencies`,
declared by each study section with its piece kinds, :class:`studies.sections.protocol.PieceKind`: ``cfd`` for
the steady flow, FRF and LTD pieces; ``cfd``, ``sysid`` and the study modules that define and compute them for the
ROM and ROM-simulation pieces). Editing ``cfd/`` thus invalidates everything, editing ``sysid/`` or the ROM tasks
only the (cheap) identifications and ROM simulations. The git commit is recorded in the provenance, not in the key
(see ``studies.store.provenance``).

Layout and atomicity
--------------------
An entry is two files in ``root/<piece>/<key[:2]>/``: ``<key>.<h>.npz`` (the arrays; ``h`` = first 16 hex
digits of its sha256) and ``<key>.json`` (metadata, provenance, the npz's name, size and sha256, and a
sha256 of the JSON body itself). Each file is written to a hidden temporary file in the same folder,
flushed, fsync'ed and renamed over its final name (``os.replace``, atomic on POSIX); the JSON is written
last and is the commit point. A crash at any moment leaves either the old entry, no entry, or a complete
new one, plus at most some hidden temporary files or an unreferenced npz (removed by
:meth:`ResultStore.clean`). Several processes may write the same key at once: each writes its own npz (its
name holds its hash) and the last JSON rename wins; both are complete, valid entries.

Corruption
----------
On read the JSON's own checksum and the npz's size and checksum are verified. A damaged, truncated or
inconsistent entry is logged (``logging`` warning on ``studies.store.cache``), deleted, and treated as missing,
so :meth:`ResultStore.get_or_compute` recomputes it.
"""

from __future__ import annotations

import hashlib
import io
import json
import logging
import re
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterator, Mapping, Optional

import numpy as np

from ..config.hashing import canonical_json
from ..sections.protocol import piece_kinds
from .files import TEMP_PREFIX, atomic_write_bytes, jsonable
from .provenance import code_version, provenance

__all__ = [
    "CacheError",
    "StoreReadError",
    "Entry",
    "ResultStore",
    "piece_dependencies",
    "DEFAULT_DEPENDENCIES",
    "FORMAT_VERSION",
    "atomic_write_bytes",
    "export_rom_npz",
    "export_rom_mat",
    "load_rom_npz",
]

log = logging.getLogger(__name__)

FORMAT_VERSION = 1



def piece_dependencies() -> dict:
    """Piece kind -> packages and modules whose sources enter its keys, as the registered study sections declare
    them (:func:`studies.sections.protocol.piece_kinds`); other pieces depend on :data:`DEFAULT_DEPENDENCIES`.

    The CFD pieces (expensive) depend on ``cfd`` only: the tasks' wrappers around ``cfd`` are expected to be thin.
    The identification pieces (cheap) also depend on ``sysid`` (identification, simulation, metrics) and on the
    study modules that define and compute them
    (:data:`studies.sections.gust_rom.pieces.ROM_DEPENDENCIES`).
    """
    return {name: tuple(kind.dependencies) for name, kind in piece_kinds().items()}


def __getattr__(name):
    if name == "PIECE_DEPENDENCIES":  # the table of earlier releases: piece_dependencies()
        return piece_dependencies()
    raise AttributeError(f"module 'studies.store.cache' has no attribute {name!r}")


DEFAULT_DEPENDENCIES = ("cfd", "sysid", "studies")
"""Sources of a piece kind that no section declares: everything it may depend on."""

_PIECE_RE = re.compile(r"^[a-z][a-z0-9_]{0,39}$")
_ARRAY_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_.\-]{0,99}$")


class CacheError(ValueError):
    """Bad use of the store: invalid piece name, arrays that cannot be stored, a bad compute result."""


class StoreReadError(CacheError):
    """An entry of the store cannot be read (a folder where its file should be, no permission, a store path
    that is a file): not corruption that recomputing would mend, so it is reported, not deleted."""


def _unreadable(path, e: OSError) -> StoreReadError:
    return StoreReadError(f"the results store cannot be read at {path} ({type(e).__name__}: {e.strerror or e}); "
                          "check the store folder (--store, [store] of the study) or remove that entry")


class _Corrupt(Exception):
    """Internal: an entry failed verification."""


@dataclass(frozen=True)
class Entry:
    """A stored result.

    Attributes
    ----------
    piece, key : str
    arrays : dict of str -> numpy.ndarray
    metadata : dict
        What the computation returned besides arrays (JSON values).
    provenance : dict
        See :func:`studies.store.provenance.provenance`; ``compute_s`` is the compute time.
    config : JSON value
        The piece's configuration (canonical form).
    hit : bool
        True when read from the store, False when just computed.
    path : pathlib.Path
        The entry's JSON file.
    """

    piece: str
    key: str
    arrays: dict
    metadata: dict
    provenance: dict
    config: Any
    hit: bool
    path: Path

    def __getitem__(self, name: str) -> np.ndarray:
        return self.arrays[name]


def _jsonable(obj):
    """Metadata to plain JSON types (:func:`studies.store.files.jsonable`); CacheError for values without one."""
    try:
        return jsonable(obj)
    except TypeError as e:
        raise CacheError(str(e)) from None


def _body_checksum(body: dict) -> str:
    return hashlib.sha256(json.dumps(body, sort_keys=True, separators=(",", ":")).encode()).hexdigest()


class ResultStore:
    """Content-addressed results on disk (see the module docstring).

    Parameters
    ----------
    root : path-like
        Folder of the store (created when first written).
    dependencies : mapping, optional
        Piece -> packages whose sources enter its key; default :func:`piece_dependencies`.
    code : dict, optional
        A fixed code version for every key instead of :func:`studies.store.provenance.code_version` (tests, or to
        pin a store to a release).
    required : mapping, optional
        Piece -> names of the arrays an entry of that piece must hold unless it records a failure (metadata
        ``status = "failed"``); an entry without them is treated as corrupted (deleted, recomputed), e.g. one
        written with another payload layout under a key that hashes only the computing code.

    Examples
    --------
    >>> store = ResultStore("results/store")                                   # doctest: +SKIP
    >>> e = store.get_or_compute("frf", frf_piece(case, T, 256, cfd), lambda: {"H": H})   # doctest: +SKIP
    >>> e.hit, e["H"].shape                                                     # doctest: +SKIP
    """

    def __init__(self, root, *, dependencies: Optional[Mapping[str, tuple]] = None, code: Optional[dict] = None,
                 required: Optional[Mapping[str, tuple]] = None):
        self.root = Path(root)
        self.dependencies = dict(piece_dependencies() if dependencies is None else dependencies)
        self._code = code
        self._required = {piece: tuple(names) for piece, names in (required or {}).items()}

    # ---- keys and paths -------------------------------------------------------------------------
    def _check_piece(self, piece: str) -> str:
        if not isinstance(piece, str) or not _PIECE_RE.match(piece):
            raise CacheError(f"piece {piece!r} must be a short lower-case name such as 'frf' or 'rom'")
        return piece

    def code_version(self, piece: str) -> dict:
        """The code part of ``piece``'s keys."""
        if self._code is not None:
            return dict(self._code)
        return code_version(self.dependencies.get(piece, DEFAULT_DEPENDENCIES))

    def key(self, piece: str, config) -> str:
        """sha256 (hex) of the canonical JSON of ``{"piece", "config", "code"}``."""
        self._check_piece(piece)
        return hashlib.sha256(canonical_json(
            {"piece": piece, "config": config, "code": self.code_version(piece), "format": FORMAT_VERSION}
        ).encode()).hexdigest()

    def _folder(self, piece: str, key: str) -> Path:
        return self.root / piece / key[:2]

    def path(self, piece: str, config) -> Path:
        """The JSON file of the entry of ``(piece, config)`` (whether or not it exists)."""
        key = self.key(piece, config)
        return self._folder(piece, key) / f"{key}.json"

    # ---- reading --------------------------------------------------------------------------------
    def _read(self, piece: str, key: str) -> Optional[Entry]:
        jpath = self._folder(piece, key) / f"{key}.json"
        try:
            raw = jpath.read_bytes()
        except FileNotFoundError:
            return None
        except OSError as e:
            raise _unreadable(jpath, e) from None
        try:
            try:
                doc = json.loads(raw)
            except (json.JSONDecodeError, UnicodeDecodeError) as e:
                raise _Corrupt(f"metadata is not valid JSON ({e})") from None
            if not isinstance(doc, dict) or "body" not in doc or "checksum" not in doc:
                raise _Corrupt("metadata lacks its body or checksum")
            body = doc["body"]
            if _body_checksum(body) != doc["checksum"]:
                raise _Corrupt("metadata checksum mismatch")
            if body.get("key") != key or body.get("piece") != piece:
                raise _Corrupt("metadata belongs to another key")
            npz = body["npz"]
            if not isinstance(npz.get("file"), str) or "/" in npz["file"] or not npz["file"].startswith(key):
                raise _Corrupt("bad npz file name")
            npath = jpath.parent / npz["file"]
            try:
                data = npath.read_bytes()
            except FileNotFoundError:
                raise _Corrupt(f"array file {npz['file']} is missing") from None
            except OSError as e:
                raise _unreadable(npath, e) from None
            if len(data) != npz["size"]:
                raise _Corrupt(f"array file has {len(data)} bytes, expected {npz['size']} (truncated?)")
            if hashlib.sha256(data).hexdigest() != npz["sha256"]:
                raise _Corrupt("array file checksum mismatch")
            try:
                with np.load(io.BytesIO(data), allow_pickle=False) as z:
                    arrays = {name: z[name] for name in z.files}
            except Exception as e:  # noqa: BLE001 - any failure to decode is corruption
                raise _Corrupt(f"array file cannot be read ({e})") from None
            lacking = [n for n in self._required.get(piece, ()) if n not in arrays]
            if lacking and (body.get("metadata") or {}).get("status") != "failed":
                raise _Corrupt(f"arrays {', '.join(lacking)} are missing (another layout of the piece, e.g. written "
                               "by another version)")
        except (_Corrupt, KeyError, TypeError, AttributeError) as e:
            reason = str(e) if isinstance(e, _Corrupt) else f"malformed metadata ({type(e).__name__}: {e})"
            log.warning("corrupted entry %s/%s (%s): deleted, it will be recomputed",
                        piece, key, reason)
            self._delete(piece, key)
            return None
        return Entry(piece=piece, key=key, arrays=arrays, metadata=body.get("metadata", {}),
                     provenance=body.get("provenance", {}), config=body.get("config"), hit=True, path=jpath)

    def get(self, piece: str, config) -> Optional[Entry]:
        """The stored entry of ``(piece, config)``, or None (missing, or corrupted: then deleted and logged)."""
        return self._read(piece, self.key(piece, config))

    def __contains__(self, item) -> bool:
        piece, config = item
        return self.get(piece, config) is not None

    # ---- writing --------------------------------------------------------------------------------
    def put(self, piece: str, config, arrays: Mapping[str, Any], metadata: Optional[Mapping] = None, *,
            extra_provenance: Optional[Mapping] = None) -> Entry:
        """Store a result (atomically; replaces an existing entry of the same key).

        Parameters
        ----------
        piece : str
        config : JSON-ready
            The piece's configuration.
        arrays : mapping of str -> array_like
            Numeric arrays (no object arrays).
        metadata : mapping, optional
            JSON-ready values (NumPy scalars accepted).
        extra_provenance : mapping, optional
            Added to the provenance record (e.g. ``compute_s``).

        Returns
        -------
        Entry
            With ``hit=False``.
        """
        self._check_piece(piece)
        key = self.key(piece, config)
        arrs = {}
        for name, value in dict(arrays).items():
            if not isinstance(name, str) or not _ARRAY_RE.match(name):
                raise CacheError(f"array name {name!r} must be a short identifier (letters, digits, _ . -)")
            a = np.asarray(value)
            if a.dtype == object:
                raise CacheError(f"array {name!r} has dtype object; store numeric arrays only (no pickles)")
            arrs[name] = a
        buf = io.BytesIO()
        np.savez(buf, **arrs)
        data = buf.getvalue()
        digest = hashlib.sha256(data).hexdigest()
        folder = self._folder(piece, key)
        npz_name = f"{key}.{digest[:16]}.npz"
        code = self.code_version(piece)
        canon_config = json.loads(canonical_json(config))
        prov = provenance(canon_config, piece=piece, code=code, extra=dict(extra_provenance or {}))
        body = {
            "format": FORMAT_VERSION, "key": key, "piece": piece, "config": canon_config, "code": code,
            "metadata": _jsonable(dict(metadata or {})), "provenance": _jsonable(prov),
            "arrays": {n: {"shape": list(a.shape), "dtype": a.dtype.str} for n, a in arrs.items()},
            "npz": {"file": npz_name, "size": len(data), "sha256": digest},
        }
        doc = {"checksum": _body_checksum(body), "body": body}
        atomic_write_bytes(folder / npz_name, data)
        atomic_write_bytes(folder / f"{key}.json", json.dumps(doc, indent=1, sort_keys=True).encode())
        return Entry(piece=piece, key=key, arrays=arrs, metadata=body["metadata"], provenance=body["provenance"],
                     config=canon_config, hit=False, path=folder / f"{key}.json")

    def get_or_compute(self, piece: str, config, compute_fn: Callable[[], Any]) -> Entry:
        """The stored result of ``(piece, config)``, or compute, store and return it.

        Parameters
        ----------
        piece : str
        config : JSON-ready
        compute_fn : callable
            Called with no arguments on a miss; returns a mapping of arrays, or a tuple
            ``(arrays, metadata)``.

        Returns
        -------
        Entry
            ``hit`` tells which happened. A corrupted entry is logged, deleted and recomputed.
        """
        entry = self.get(piece, config)
        if entry is not None:
            return entry
        t0 = time.perf_counter()
        result = compute_fn()
        seconds = time.perf_counter() - t0
        if isinstance(result, tuple) and len(result) == 2 and isinstance(result[0], Mapping):
            arrays, metadata = result
        elif isinstance(result, Mapping):
            arrays, metadata = result, {}
        else:
            raise CacheError(f"compute_fn for piece {piece!r} must return a mapping of arrays or a tuple "
                             f"(arrays, metadata); got {type(result).__name__}")
        return self.put(piece, config, arrays, metadata, extra_provenance={"compute_s": seconds})

    # ---- maintenance ----------------------------------------------------------------------------
    def _delete(self, piece: str, key: str) -> None:
        folder = self._folder(piece, key)
        for p in [folder / f"{key}.json", *folder.glob(f"{key}.*.npz")]:
            try:
                p.unlink()
            except FileNotFoundError:
                pass

    def delete(self, piece: str, config) -> bool:
        """Remove the entry of ``(piece, config)``; True if there was one."""
        key = self.key(piece, config)
        existed = (self._folder(piece, key) / f"{key}.json").exists()
        self._delete(piece, key)
        return existed

    def keys(self, piece: Optional[str] = None) -> Iterator[tuple]:
        """``(piece, key)`` of the committed entries (those with a JSON file), unverified."""
        pieces = [piece] if piece else sorted(p.name for p in self.root.glob("*") if p.is_dir())
        for pc in pieces:
            for j in sorted((self.root / pc).glob("*/*.json")):
                if not j.name.startswith("."):
                    yield pc, j.stem

    def clean(self, max_age: float = 3600.0) -> int:
        """Remove temporary files and unreferenced array files older than ``max_age`` seconds.

        Young files are kept: they may belong to a write in progress in another process.

        Returns
        -------
        int
            Number of files removed.
        """
        now = time.time()
        removed = 0
        for f in self.root.glob("*/*/*"):
            if not f.is_file() or now - f.stat().st_mtime < max_age:
                continue
            if f.name.startswith(TEMP_PREFIX):
                orphan = True
            elif f.suffix == ".npz":
                key = f.name.split(".")[0]
                try:
                    ref = json.loads((f.parent / f"{key}.json").read_bytes())["body"]["npz"]["file"]
                except (OSError, ValueError, KeyError, TypeError):
                    ref = None
                orphan = ref != f.name
            else:
                orphan = False
            if orphan:
                try:
                    f.unlink()
                    removed += 1
                except FileNotFoundError:
                    pass
        return removed


from .rom_export import export_rom_mat, export_rom_npz, load_rom_npz  # noqa: E402  (re-exported for the runner)
