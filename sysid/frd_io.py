"""Files and python-control for :class:`sysid.FrequencyResponse`: the ``.npz`` format (arrays plus a JSON
header with names, ``T`` and metadata) and conversion to and from :class:`control.FrequencyResponseData`.

The functions take the class as an argument where they build one, so this module does not import
:mod:`sysid.frd` (the methods ``FrequencyResponse.save``, ``load``, ``to_control`` and ``from_control`` call them).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from .errors import ArgumentTypeError, FrequencyDataError, FrequencyFileError, FrequencyGridError

__all__ = ["save_frf", "load_frf", "frf_to_control", "frf_from_control"]


def save_frf(frf, path: str | Path) -> Path:
    """Write ``frf`` (a :class:`sysid.FrequencyResponse`) to a ``.npz`` file; the path written (``.npz`` appended
    when missing). Metadata must be JSON-serialisable."""
    given = Path(path)
    path = given
    if path.suffix != ".npz":
        path = path.with_suffix(path.suffix + ".npz") if path.suffix else path.with_suffix(".npz")
    for p in dict.fromkeys((given, path)):   # "folder" used to write folder.npz beside the directory
        if p.is_dir():
            raise FrequencyFileError(f"{p} is a directory; give a file name, e.g. {p / 'frf.npz'}")
    try:
        meta = json.dumps(dict(frf.metadata))
    except (TypeError, ValueError) as exc:
        raise FrequencyDataError(
            f"metadata is not JSON-serialisable ({exc}); store plain numbers, strings, lists and dicts"
        ) from None
    header = json.dumps(
        {"format": "lfdrom.FrequencyResponse", "version": 1, "inputs": list(frf.inputs),
         "outputs": list(frf.outputs), "T": frf.T}
    )
    arrays = {"H": frf.H, "header": np.array(header), "metadata": np.array(meta)}
    if frf.omega_d is not None:
        arrays["omega_d"] = frf.omega_d
    if frf.omega is not None:
        arrays["omega"] = frf.omega
    try:
        np.savez(path, **arrays)
    except OSError as exc:
        raise FrequencyFileError(f"cannot write {path}: {exc.strerror or exc}; give a path in a folder that exists "
                                 "and that you may write") from None
    return path


def load_frf(cls, path: str | Path):
    """Read a file written by :func:`save_frf` as an instance of ``cls`` (:class:`sysid.FrequencyResponse`).
    ``FrequencyFileError`` when the file is not an ``.npz`` archive (numpy said "pickled data" of a text file)."""
    import zipfile

    path = Path(path)
    if not path.exists():
        raise FrequencyFileError(f"{path} does not exist; give the path of a file written by FrequencyResponse.save")
    if path.is_dir():
        raise FrequencyFileError(f"{path} is a directory; give the path of a file written by FrequencyResponse.save")
    if path.is_file() and not zipfile.is_zipfile(path):
        raise FrequencyFileError(f"{path} is not an .npz file written by FrequencyResponse.save (not a zip "
                                 "archive); read other formats with numpy or scipy.io and build the data with "
                                 "FrequencyResponse(...) or FrequencyResponse.from_continuous(...)")
    with np.load(path, allow_pickle=False) as f:
        if "header" not in f or "H" not in f:
            raise FrequencyDataError(f"{path} is not a FrequencyResponse file (no 'header'/'H' entries)")
        if "metadata" not in f:
            raise FrequencyDataError(f"{path}: no 'metadata' entry (FrequencyResponse.save writes one, '{{}}' when "
                                     "empty); add it or write the file with FrequencyResponse.save")
        try:
            header = json.loads(str(f["header"]))
            meta = json.loads(str(f["metadata"]))
        except ValueError as exc:
            header = meta = None
            detail = f"not JSON ({exc})"
        else:
            detail = "not JSON objects, or the header lacks 'inputs' and 'outputs'"
        if not (isinstance(header, dict) and isinstance(meta, dict) and {"inputs", "outputs"} <= header.keys()):
            raise FrequencyDataError(f"{path}: 'header' or 'metadata' is not what FrequencyResponse.save writes "
                                     f"({detail}); write the file with FrequencyResponse.save")
        H = f["H"]
        wd = f["omega_d"] if "omega_d" in f else None
        w = f["omega"] if "omega" in f else None
    return cls(H, wd, header.get("T"), inputs=header["inputs"], outputs=header["outputs"], metadata=meta,
               omega=w)


def frf_to_control(frf):
    """``frf`` as a continuous-time :class:`control.FrequencyResponseData` on its frequencies ``omega``.

    The FRD is a continuous-time object (python-control's discrete FRD uses ``z = exp(j omega dt)``, not the
    bilinear map). An ``omega = inf`` sample is dropped, because FRD interpolation and plots cannot use it; pass
    ``frf.feedthrough`` back to :func:`frf_from_control` to restore it. ``FrequencyGridError`` without ``omega``.
    """
    import control

    if frf.omega is None:
        raise FrequencyGridError("no continuous frequencies: this response has omega_d but no T; give T")
    keep = np.isfinite(frf.omega)
    return control.frd(
        frf.H[:, :, keep], frf.omega[keep], inputs=list(frf.inputs), outputs=list(frf.outputs)
    )


def frf_from_control(cls, frd, T: float | None = None, *, feedthrough: Any = None,
                     metadata: Mapping[str, Any] | None = None):
    """An instance of ``cls`` (:class:`sysid.FrequencyResponse`) from a continuous-time
    :class:`control.FrequencyResponseData`; ``feedthrough`` (p, m) is appended at ``omega = inf``."""
    import control

    if not isinstance(frd, control.FrequencyResponseData):
        raise ArgumentTypeError(f"from_control() expects a control.FrequencyResponseData, got {type(frd).__name__}")
    if getattr(frd, "dt", 0) not in (0, None):
        raise FrequencyGridError(
            "from_control() expects a continuous-time FRD (dt = 0); a discrete FRD's frequencies follow "
            "z = exp(j omega dt), not the bilinear map"
        )
    H = np.asarray(frd.frdata if hasattr(frd, "frdata") else frd.fresp, dtype=complex)
    w = np.asarray(frd.omega, dtype=float)
    order = np.argsort(w, kind="stable")
    H, w = H[:, :, order], w[order]
    if feedthrough is not None:
        Dv = np.asarray(feedthrough, dtype=complex)
        if Dv.ndim == 0:
            Dv = Dv.reshape(1, 1)
        if Dv.shape != H.shape[:2]:
            raise FrequencyDataError(f"feedthrough has shape {Dv.shape}, expected (p, m) = {H.shape[:2]}")
        H = np.concatenate([H, Dv[:, :, None]], axis=2)
        w = np.append(w, np.inf)
    return cls.from_continuous(
        H, w, T, inputs=list(frd.input_labels), outputs=list(frd.output_labels), metadata=metadata
    )
