"""ROM files for loads teams: NumPy ``.npz`` and MATLAB ``.mat`` (``A, B, C, D, T``).

``T`` is the sampling period of a discrete model (convective time units, ``s = t U / c``) and 0 for a
continuous one, as MATLAB's ``ss(A, B, C, D, T)`` expects. Input and output names go as ``InputName`` and
``OutputName`` (cell arrays of strings in MATLAB), the metadata as a JSON string ``metadata``. Files are
written atomically (:func:`studies.store.files.atomic_write_bytes`: an existing file is replaced whole or left as
it was). Also available from ``studies.store.cache``; this module does not import it.
"""

from __future__ import annotations

import io
import json
from pathlib import Path
from typing import Mapping, Optional

import numpy as np

from .files import atomic_write_bytes, jsonable

__all__ = ["export_rom_npz", "export_rom_mat", "load_rom_npz"]


def _parts(model):
    try:
        A, B, C, D = (np.asarray(getattr(model, n), dtype=float) for n in ("A", "B", "C", "D"))
    except AttributeError:
        raise TypeError(f"expected a control.StateSpace, got {type(model).__name__}") from None
    dt = model.dt
    T = 0.0 if dt in (None, 0, False) else (float("nan") if dt is True else float(dt))
    inputs = list(getattr(model, "input_labels", [f"u[{i}]" for i in range(B.shape[1])]))
    outputs = list(getattr(model, "output_labels", [f"y[{i}]" for i in range(C.shape[0])]))
    return A, B, C, D, T, inputs, outputs


def _meta_json(metadata: Optional[Mapping]) -> str:
    try:
        return json.dumps(jsonable(dict(metadata or {})), sort_keys=True)
    except TypeError as e:
        raise TypeError(f"ROM metadata: {e}") from None


def export_rom_npz(path, model, metadata: Optional[Mapping] = None) -> Path:
    """Save a ROM as ``.npz``: ``A, B, C, D, T``, ``inputs``, ``outputs`` and ``metadata`` (JSON text).

    Parameters
    ----------
    path : path-like
    model : control.StateSpace
        Discrete (``T = dt``) or continuous (``T = 0``).
    metadata : mapping, optional
        JSON-ready description (case, order, errors, provenance...).

    Returns
    -------
    pathlib.Path

    Raises
    ------
    TypeError
        ``model`` is not a state-space model, or a metadata value has no JSON form.
    OSError
        The file cannot be written; an existing file at ``path`` is left as it was.
    """
    A, B, C, D, T, inputs, outputs = _parts(model)
    buf = io.BytesIO()
    np.savez(buf, A=A, B=B, C=C, D=D, T=np.float64(T), inputs=np.array(inputs, dtype=str),
             outputs=np.array(outputs, dtype=str), metadata=np.array(_meta_json(metadata)))
    path = Path(path)
    atomic_write_bytes(path, buf.getvalue())
    return path


def load_rom_npz(path):
    """Read a ROM written by :func:`export_rom_npz`.

    Returns
    -------
    model : control.StateSpace
    metadata : dict
    """
    import control

    with np.load(path, allow_pickle=False) as z:
        T = float(z["T"])
        model = control.ss(z["A"], z["B"], z["C"], z["D"], dt=(T if T > 0 else 0),
                           inputs=[str(s) for s in z["inputs"]], outputs=[str(s) for s in z["outputs"]])
        meta = json.loads(str(z["metadata"]))
    return model, meta


def export_rom_mat(path, model, metadata: Optional[Mapping] = None) -> Path:
    """Save a ROM as MATLAB ``.mat`` (v5): ``A, B, C, D, T, InputName, OutputName, metadata``.

    In MATLAB: ``r = load('rom.mat'); sys = ss(r.A, r.B, r.C, r.D, r.T, 'InputName', r.InputName,
    'OutputName', r.OutputName)``.

    Parameters
    ----------
    path : path-like
    model : control.StateSpace
    metadata : mapping, optional
        Stored as the JSON string ``metadata``.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    TypeError
        ``model`` is not a state-space model, or a metadata value has no JSON form.
    OSError
        The file cannot be written; an existing file at ``path`` is left as it was.
    """
    import scipy.io

    A, B, C, D, T, inputs, outputs = _parts(model)
    cell = lambda names: np.array([[n] for n in names], dtype=object)  # noqa: E731 - column cell array
    buf = io.BytesIO()
    scipy.io.savemat(buf, {"A": A, "B": B, "C": C, "D": D, "T": np.float64(T), "InputName": cell(inputs),
                           "OutputName": cell(outputs), "metadata": _meta_json(metadata)},
                     do_compression=True, oned_as="column")
    path = Path(path)
    atomic_write_bytes(path, buf.getvalue())
    return path
