"""Reading frequency-response files for `lfdrom fit`: ``.npz`` (ours), MATLAB ``.mat`` and CSV, checked, into a
:class:`sysid.FrequencyResponse` (formats and units: docs/fit.md). Bad files raise :class:`FitInputError` naming the
line or key and the fix."""

from __future__ import annotations

import csv
import io
import math
import zipfile
import zlib
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["FitInputError", "load_data", "FREQ_UNITS", "frequency_axis"]

FREQ_UNITS = ("omega", "k", "omega_d", "rad/s", "Hz")
"""Units of a frequency column (``--frequency-unit``): ``omega`` (angular, in the data's own time unit: ``U/c`` for
an aerofoil), ``k`` (reduced frequency, ``omega = 2k``), ``omega_d`` (rad/sample, with ``T``), ``rad/s`` (angular,
per second) and ``Hz`` (cycles per second, ``omega = 2 pi f``)."""

_SI = ((1e12, "T"), (1e9, "G"), (1e6, "M"), (1e3, "k"), (1.0, ""))


def frequency_axis(frf) -> tuple:
    """How the data's frequencies are shown: ``(label, scale, unit)`` with ``omega * scale`` the shown values.

    The unit is ``frf.metadata["frequency_unit"]`` (the file's frequency column or key, or ``--frequency-unit``);
    lfdrom's own ``.npz`` responses without one are an aerofoil's, in reduced frequency ``k``. Hz and rad/s take
    an SI prefix that puts the largest finite frequency below 1000 (75 - 110 GHz is shown in GHz, not as 7.5e+10).
    """
    unit = str(frf.metadata.get("frequency_unit") or ("k" if frf.metadata.get("file") else "omega"))
    if unit == "k":
        return "reduced frequency k = omega c / (2U)", 0.5, "k"
    if unit in ("Hz", "rad/s"):
        w = np.asarray(frf.omega, dtype=float)
        top = float(w[np.isfinite(w)].max()) if np.isfinite(w).any() else 1.0
        base = 1.0 / (2.0 * np.pi) if unit == "Hz" else 1.0
        factor, prefix = next(((f, pre) for f, pre in _SI if top * base >= f), _SI[-1])
        if unit == "Hz":
            return f"frequency f [{prefix}Hz]", base / factor, f"{prefix}Hz"
        return f"angular frequency omega [{prefix}rad/s]", base / factor, f"{prefix}rad/s"
    if unit == "omega_d":
        return "angular frequency omega = (2/T) tan(omega_d / 2)", 1.0, "1/T"
    return "angular frequency omega", 1.0, ""


class FitInputError(ValueError):
    """A data file or an option of ``lfdrom fit`` is unusable. Names the file and where.

    Attributes
    ----------
    file : str
    where : str or None
        ``"line 7"`` (CSV), ``"key 'omega'"`` (``.npz``/``.mat``), ``"--T"`` (an option), or None.
    problem : str
        What was wrong and what to do.
    """

    def __init__(self, file: Any, where: str | None, problem: str):
        self.file, self.where, self.problem = str(file), where, problem
        super().__init__(f"{self.file}: {where}: {problem}" if where else f"{self.file}: {problem}")


# ---------------------------------------------------------------------------------------------
# Reading
# ---------------------------------------------------------------------------------------------

def _frequencies(file, where, values, unit: str, T: float | None):
    """``(omega, omega_d)``: one of them from ``values`` in ``unit``; the other None."""
    try:
        v = np.asarray(values, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise FitInputError(file, where, f"is not numeric (dtype {np.asarray(values).dtype}); store the frequencies "
                                         "as real numbers") from None
    if np.isnan(v).any():
        raise FitInputError(file, where, f"frequency {int(np.flatnonzero(np.isnan(v))[0]) + 1} is NaN; remove it")
    if (v < 0).any():
        raise FitInputError(file, where, f"negative frequency {v[v < 0][0]!r}; give omega >= 0 (the response at "
                                         "-omega is the complex conjugate)")
    if unit in ("omega", "rad/s"):
        return v, None
    if unit == "k":
        return 2.0 * v, None
    if unit == "Hz":
        return 2.0 * np.pi * v, None
    if T is None:
        raise FitInputError(file, where, "discrete frequencies omega_d need the sampling period T: give a 'T' "
                                         "entry (or '# T: ...' in a CSV) or --T")
    if (v > np.pi * (1 + 1e-9)).any():
        raise FitInputError(file, where, f"omega_d must lie in [0, pi] rad/sample, found {v.max()!r}")
    return None, v


def _build(file, where_H, where_w, H, omega, omega_d, T, inputs, outputs):
    import sysid

    H = np.asarray(H, dtype=complex)
    K = (omega if omega is not None else omega_d).size
    if H.ndim == 2 and H.shape[1] == 1 and H.shape[0] == K:  # a MATLAB column vector
        H = H.T
    if H.ndim == 1:
        H = H.reshape(1, 1, -1)
    elif H.ndim == 2:
        H = H.reshape(H.shape[0], 1, H.shape[1])
    if H.ndim != 3:
        raise FitInputError(file, where_H, f"has {H.ndim} dimensions (shape {H.shape}); give (p, m, K) = "
                                           "(outputs, inputs, frequencies), or (p, K) for one input")
    if H.shape[2] != K:
        raise FitInputError(file, where_H, f"has {H.shape[2]} frequencies (last axis of shape {H.shape}) but "
                                           f"{where_w} has {K}; give one response per frequency (H is (p, m, K))")
    bad = ~np.isfinite(H)
    if bad.any():
        i, j, k = np.argwhere(bad)[0]
        raise FitInputError(file, where_H, f"H[{i}, {j}, {k}] is NaN or inf; recompute or drop that frequency (the "
                                           "omega = inf sample holds the finite feedthrough, usually 0)")
    for what, names, n in (("outputs", outputs, H.shape[0]), ("inputs", inputs, H.shape[1])):
        if names is not None and len(names) != n:
            raise FitInputError(file, f"key '{what}'", f"has {len(names)} names {list(names)} but H has {n} {what}")
    w = omega if omega is not None else omega_d
    order = np.argsort(w, kind="stable")
    if np.unique(w).size != w.size:
        dup = w[order][np.flatnonzero(np.diff(w[order]) == 0)[0]]
        raise FitInputError(file, where_w, f"frequency {dup!r} appears twice; average or drop the repeated samples")
    H = H[:, :, order]
    try:
        if omega is not None:
            return sysid.FrequencyResponse.from_continuous(H, omega[order], T, inputs=inputs, outputs=outputs,
                                                           metadata={"source": Path(file).name})
        return sysid.FrequencyResponse(H, omega_d[order], T, inputs=inputs, outputs=outputs,
                                       metadata={"source": Path(file).name})
    except ValueError as e:
        raise FitInputError(file, None, str(e)) from None


def _names(v) -> list[str] | None:
    """Names from a MATLAB cell array / char matrix / NumPy string array."""
    if v is None:
        return None
    a = np.asarray(v, dtype=object)
    out = []
    for x in a.reshape(-1):
        if isinstance(x, np.ndarray):
            x = "".join(str(c) for c in x.reshape(-1)) if x.dtype.kind in "US" else str(x.reshape(-1)[0])
        out.append(str(x).strip())
    return out


def _read_arrays(path: Path, d: dict, T_opt: float | None):
    """The ``.mat``-style variables of a dict (``.mat`` or plain ``.npz``)."""
    keys = [k for k in d if not k.startswith("__")]
    if "H" in d:
        H, where_H = d["H"], "key 'H'"
        if not np.issubdtype(np.asarray(H).dtype, np.number):
            raise FitInputError(path, where_H, f"is not numeric (dtype {np.asarray(H).dtype}); store a complex array")
    elif "H_re" in d and "H_im" in d:
        for key in ("H_re", "H_im"):
            if not np.issubdtype(np.asarray(d[key]).dtype, np.number):
                raise FitInputError(path, f"key '{key}'", f"is not numeric (dtype {np.asarray(d[key]).dtype}); store "
                                                          "a real array")
            part = np.asarray(d[key])
            if np.iscomplexobj(part) and np.any(part.imag != 0):   # (float() would drop it with a ComplexWarning)
                raise FitInputError(path, f"key '{key}'", f"is complex (dtype {part.dtype}) with non-zero imaginary "
                                                          "parts: H_re and H_im must be real arrays (the real and the "
                                                          "imaginary part of H); store the complex response as H "
                                                          "instead")
        re, im = (np.asarray(d[key]).real.astype(float) for key in ("H_re", "H_im"))
        if re.shape != im.shape:
            raise FitInputError(path, "key 'H_im'", f"has shape {im.shape} but H_re has {re.shape}; they must match")
        H, where_H = re + 1j * im, "key 'H_re'"
    else:
        raise FitInputError(path, "key 'H'", f"missing: found keys {keys}; store the response as H (complex, "
                                             "(p, m, K)) or as H_re and H_im")
    given = [k for k in ("omega", "k", "omega_d") if k in d]
    if len(given) != 1:
        raise FitInputError(path, "key 'omega'", ("missing" if not given else f"ambiguous: found {given}") +
                            "; give exactly one frequency vector: omega (U/c), k (reduced, omega = 2k) or omega_d "
                            "(rad/sample, with T)")
    T = T_opt
    if T is None and "T" in d:
        try:
            values = np.asarray(d["T"], dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise FitInputError(path, "key 'T'", f"is not a number: {d['T']!r}") from None
        if values.size != 1:   # (the first of several was taken)
            raise FitInputError(path, "key 'T'", f"must be one number (the sampling period), got {values.size}: "
                                f"{values[:4].tolist()}")
        T = float(values[0])
        if not (math.isfinite(T) and T > 0):
            raise FitInputError(path, "key 'T'", f"must be positive and finite, got {T!r}")
    unit = given[0]
    omega, omega_d = _frequencies(path, f"key '{unit}'", d[unit], unit, T)
    frf = _build(path, where_H, f"key '{unit}'", H, omega, omega_d, T, _names(d.get("inputs")),
                 _names(d.get("outputs")))
    return frf.replace(metadata={**frf.metadata, "frequency_unit": unit})


def _load_npz(path: Path, T_opt):
    import sysid

    with open(path, "rb") as f:
        magic = f.read(4)
    if magic and not magic.startswith(b"PK"):
        # not a zip (a truncated one still starts with PK): np.load would read it as a pickle or as one .npy array
        raise FitInputError(path, None, "not a .npz file (a .npz is a zip archive of arrays); write it with "
                                        "numpy.savez or FrequencyResponse.save, or give the data as .csv or .mat")
    try:
        with np.load(path, allow_pickle=False) as z:
            d = {k: z[k] for k in z.files}
    except ValueError as e:
        if "allow_pickle" in str(e):  # an object array (e.g. names saved as dtype=object)
            raise FitInputError(path, None, "not readable as a .npz of plain arrays: it holds Python objects (e.g. "
                                            "names saved with dtype=object); save names as strings "
                                            "(np.array(names, dtype=str))") from None
        raise FitInputError(path, None, f"not readable as a .npz file ({e}); write it with numpy.savez or "
                                        "FrequencyResponse.save") from None
    except (OSError, EOFError, zipfile.BadZipFile, zlib.error) as e:
        raise FitInputError(path, None, f"not readable as a .npz file ({type(e).__name__}: {e}; empty "
                                        "or truncated?); write it again with numpy.savez or "
                                        "FrequencyResponse.save") from None
    if "header" in d:
        try:
            frf = sysid.FrequencyResponse.load(path)
        except (ValueError, KeyError) as e:
            raise FitInputError(path, "key 'header'", f"an lfdrom FrequencyResponse file that does not load: {e}")
        if T_opt is not None and frf.omega is not None:
            frf = frf.with_T(T_opt)
        elif T_opt is not None:  # discrete frequencies saved without a T: this T places them
            frf = sysid.FrequencyResponse(frf.H, frf.omega_d, T_opt, inputs=frf.inputs, outputs=frf.outputs,
                                          metadata=frf.metadata)
        return frf.replace(metadata={**frf.metadata, "file": path.name})
    return _read_arrays(path, d, T_opt)


def _load_mat(path: Path, T_opt):
    import scipy.io
    from scipy.io.matlab import MatReadError

    try:
        d = scipy.io.loadmat(path, squeeze_me=False)
    except NotImplementedError:
        raise FitInputError(path, None, "MATLAB v7.3 (HDF5) files are not supported; save with "
                                        "save('file.mat', ..., '-v7')") from None
    except (ValueError, OSError, TypeError, EOFError, MatReadError, zlib.error) as e:
        raise FitInputError(path, None, f"not readable as a MATLAB .mat file ({type(e).__name__}: {e}; empty or "
                                        "truncated?); save it again with save('file.mat', ..., '-v7')") from None
    d = {k: (np.squeeze(v) if k in ("omega", "k", "omega_d", "T") else v) for k, v in d.items()}
    return _read_arrays(path, d, T_opt)


def _load_csv(path: Path, T_opt, freq_unit: str | None, input_name: str | None):
    raw = path.read_bytes()
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        line = raw[: e.start].count(b"\n") + 1
        raise FitInputError(path, f"line {line}", f"not readable as UTF-8 text (byte 0x{raw[e.start]:02x}); save the "
                                                  "file as UTF-8 (e.g. iconv -f latin1 -t utf-8)") from None
    meta: dict[str, tuple[str, int]] = {}
    rows: list[tuple[int, list[str]]] = []
    for n, row in enumerate(csv.reader(io.StringIO(text)), start=1):
        if not row or all(not c.strip() for c in row):
            continue
        first = row[0].strip()
        if first.startswith("#"):
            body = ",".join(row).lstrip("#").strip()
            if ":" in body:
                key, val = body.split(":", 1)
                meta[key.strip().lower()] = (val.strip(), n)
            continue
        rows.append((n, [c.strip() for c in row]))
    if not rows:
        raise FitInputError(path, None, "no header line and no data: give a header such as 'omega,Cl_re,Cl_im' "
                                        "and one line per frequency")
    hline, header = rows[0]
    data = rows[1:]
    if not data:
        raise FitInputError(path, f"line {hline}", "a header but no data lines; add one line per frequency")
    unit = freq_unit
    if unit is None and "frequency" in meta:
        unit, ln = meta["frequency"]
        if unit not in FREQ_UNITS:
            raise FitInputError(path, f"line {ln}", f"'# frequency: {unit}' is not one of {FREQ_UNITS} (omega in U/c, "
                                                    "k = omega/2, omega_d in rad/sample, rad/s, Hz)")
    fname = header[0]
    if freq_unit is None and "frequency" in meta and fname in FREQ_UNITS and fname != unit:
        raise FitInputError(path, f"line {hline}", f"the frequency column is named {fname!r} but line "
                                                   f"{meta['frequency'][1]} says '# frequency: {unit}'; make them "
                                                   "agree (or give --freq-unit)")
    if len(header) == 1 and any(sep in fname for sep in (";", "\t", " ")):
        raise FitInputError(path, f"line {hline}", f"one column only ({fname!r}): separate the columns with commas "
                                                   "(k,Cl_re,Cl_im,...)")
    if unit is None:
        if fname not in FREQ_UNITS:
            raise FitInputError(path, f"line {hline}", f"the first column {fname!r} is not a frequency column I "
                                                       f"know: name it one of {FREQ_UNITS} (omega in U/c, k = "
                                                       "omega/2), or declare '# frequency: k' or use --freq-unit")
        unit = fname
    T = T_opt
    if T is None and "t" in meta:
        val, ln = meta["t"]
        try:
            T = float(val)
        except ValueError:
            raise FitInputError(path, f"line {ln}", f"'# T: {val}' is not a number") from None
        if not (math.isfinite(T) and T > 0):
            raise FitInputError(path, f"line {ln}", f"T must be positive and finite, got {val}")
    # response columns: NAME_re / NAME_im, NAME = output or output/input
    cols: dict[tuple[str, str], dict[str, int]] = {}
    default_in = input_name or (meta["input"][0] if "input" in meta else "u[0]")
    for c, name in enumerate(header[1:], start=1):
        low = name.lower()
        part = next((s for s in ("_re", "_im", "_real", "_imag") if low.endswith(s)), None)
        if part is None or len(name) == len(part):
            raise FitInputError(path, f"line {hline}", f"column {c + 1} {name!r}: response columns are named "
                                                       "NAME_re and NAME_im (e.g. Cl_re, Cl_im), one pair per output")
        base = name[: -len(part)]
        out, _, inp = base.partition("/")
        key = (out, inp or default_in)
        kind = "re" if part in ("_re", "_real") else "im"
        if kind in cols.setdefault(key, {}):
            raise FitInputError(path, f"line {hline}", f"column {name!r} appears twice")
        cols[key][kind] = c
    if not cols:
        raise FitInputError(path, f"line {hline}", "no response columns: add NAME_re and NAME_im columns")
    for (o, i), parts in cols.items():
        for kind in ("re", "im"):
            if kind not in parts:
                label = o if i == default_in else f"{o}/{i}"
                raise FitInputError(path, f"line {hline}", f"{label}_{kind} is missing: every output needs both "
                                                           f"{label}_re and {label}_im")
    outputs = list(dict.fromkeys(o for o, _ in cols))
    inputs = list(dict.fromkeys(i for _, i in cols))
    for o in outputs:
        for i in inputs:
            if (o, i) not in cols:
                raise FitInputError(path, f"line {hline}", f"no columns for output {o!r} and input {i!r}: give every "
                                                           "output/input pair (NAME/INPUT_re, NAME/INPUT_im)")
    K = len(data)
    vals = np.empty((K, len(header)))
    for r, (n, row) in enumerate(data):
        if len(row) != len(header):
            raise FitInputError(path, f"line {n}", f"{len(row)} values but the header (line {hline}) has "
                                                   f"{len(header)} columns")
        for c, cell in enumerate(row):
            try:
                vals[r, c] = float(cell)
            except ValueError:
                raise FitInputError(path, f"line {n}", f"column {header[c]!r}: {cell!r} is not a number") from None
            if math.isnan(vals[r, c]) or (c > 0 and math.isinf(vals[r, c])):
                raise FitInputError(path, f"line {n}", f"column {header[c]!r}: {cell!r}; responses must be finite "
                                                       "numbers (only the frequency may be inf)")
            if c == 0 and vals[r, c] < 0:
                raise FitInputError(path, f"line {n}", f"negative frequency {cell}; give frequencies >= 0")
    H = np.empty((len(outputs), len(inputs), K), dtype=complex)
    for (o, i), parts in cols.items():
        H[outputs.index(o), inputs.index(i)] = vals[:, parts["re"]] + 1j * vals[:, parts["im"]]
    omega, omega_d = _frequencies(path, f"line {hline}", vals[:, 0], unit, T)
    w = omega if omega is not None else omega_d
    _, first = np.unique(w, return_index=True)
    if first.size != K:
        dup = sorted(set(range(K)) - set(first.tolist()))[0]
        raise FitInputError(path, f"line {data[dup][0]}", f"frequency {data[dup][1][0]} appears twice; average or "
                                                          "drop the repeated line")
    frf = _build(path, "H", f"line {hline}", H, omega, omega_d, T, inputs, outputs)
    return frf.replace(metadata={**frf.metadata, "frequency_unit": unit})


def load_data(path, *, T: float | None = None, freq_unit: str | None = None,
              input_name: str | None = None):
    """Read frequency-response data from ``.npz``, ``.mat`` or ``.csv`` (formats in the module docstring).

    Parameters
    ----------
    path : path-like
    T : float, optional
        Sampling period; overrides the file's. Data on continuous frequencies without any keep ``T = None``
        (:func:`fit_data` then picks the default).
    freq_unit : {"omega", "k", "omega_d", "rad/s", "Hz"}, optional
        CSV: unit of the frequency column (overrides ``# frequency:`` and the column name). ``.npz``/``.mat``:
        the unit in which their angular frequencies ``omega`` are to be shown (``rad/s``, ``Hz`` as ``omega /
        (2 pi)``, ``k`` as ``omega / 2``; :func:`frequency_axis`); ``omega_d`` is refused there.
    input_name : str, optional
        CSV only: the input's name for single-input files (overrides ``# input:``; default ``u[0]``).

    Returns
    -------
    sysid.FrequencyResponse
        Frequencies sorted increasing.

    Raises
    ------
    FitInputError
        Missing file, unknown suffix, or a bad entry (the message names the line or key and the fix).
    """
    path = Path(path)
    if freq_unit is not None and freq_unit not in FREQ_UNITS:
        raise FitInputError(path, "--frequency-unit", f"{freq_unit!r} is not one of {FREQ_UNITS}")
    if T is not None and not (math.isfinite(T) and T > 0):
        raise FitInputError(path, "--T", f"must be positive and finite, got {T!r}")
    if input_name is not None and not str(input_name).strip():
        raise FitInputError(path, "--input", f"{input_name!r} is empty; give the input's name (e.g. --input gust), or "
                                             "leave --input out for '# input:' or u[0]")
    if not path.is_file():
        raise FitInputError(path, None, "no such file")
    suffix = path.suffix.lower()
    if suffix in (".npz", ".mat"):
        if freq_unit == "omega_d":
            raise FitInputError(path, "--frequency-unit", "omega_d applies to a CSV column only; a .npz/.mat file "
                                                          "names its frequencies by its key (omega, k or omega_d)")
        frf = _load_npz(path, T) if suffix == ".npz" else _load_mat(path, T)
        if freq_unit is not None:
            return frf.replace(metadata={**frf.metadata, "frequency_unit": freq_unit})
        return frf
    if suffix in (".csv", ".txt"):
        return _load_csv(path, T, freq_unit, input_name)
    raise FitInputError(path, None, f"unknown suffix {path.suffix!r}: give a .npz, .mat or .csv file")
