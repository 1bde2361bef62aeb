"""Moving the pitch pivot and the moment axis of motion/gust frequency-response data.

Derivation (small motion, lengths in chords from the leading edge, ``h`` up, ``alpha`` nose up). A rigid motion
with plunge ``h_e`` at the elastic axis ``x_e`` and pitch ``alpha`` displaces the point ``x`` by
``z(x) = h_e - (x - x_e) alpha`` (nose up moves points aft of the axis down). The same motion described about
another pivot ``x_p`` has the same ``alpha`` and the plunge of the pivot point::

    h_p = h_e - (x_p - x_e) alpha          =>   [h_p, alpha]^T = T_in [h_e, alpha]^T,
                                                 T_in = [[1, -(x_p - x_e)], [0, 1]]

so pitch about ``x_e`` is pitch about ``x_p`` plus a plunge ``-(x_p - x_e) alpha`` of the pivot: changing the
pivot changes the plunge seen, not only the moment. A lift ``L`` (up) acting at ``x`` gives the nose-up
moment ``-L (x - x_0)`` about ``x_0``; summing, the moment about ``x_e`` from that about ``x_m``::

    Cm_e = Cm_m + (x_e - x_m) Cl           =>   [Cl, Cm_e]^T = T_out [Cl, Cm_m]^T,
                                                 T_out = [[1, 0], [x_e - x_m, 1]]

(e.g. lift at the quarter chord with ``Cm_{1/4} = 0`` gives ``Cm_e = (x_e - 1/4) Cl``, nose up when the axis is
aft of the quarter chord). Hence ``H_e = T_out H_p T_in`` for the motion columns and ``T_out H`` for a gust
column (the gust input does not depend on the pivot).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .errors import AeroModelError
from .fit import LOAD_OUTPUTS, MOTION_INPUTS, channel_indices
from .section import check_section

__all__ = ["change_axes", "to_elastic_axis", "MAX_AXIS"]


MAX_AXIS = 1e4
"""Largest distance (chords) of an axis from the leading edge that :func:`change_axes` takes: the transfer's terms
grow with the shift, and a pivot 1e300 chords away gave responses of 8e300 silently."""


def _x(name: str, v: Any) -> float:
    try:
        if isinstance(v, (bool, np.bool_, str, bytes)):
            raise TypeError
        f = float(v)
    except (TypeError, ValueError):
        raise AeroModelError(f"{name} must be a position in chords from the leading edge, got {v!r}") from None
    if not np.isfinite(f):
        raise AeroModelError(f"{name} must be finite, got {v!r}")
    if abs(f) > MAX_AXIS:
        raise AeroModelError(f"{name} = {f:g} chords is beyond MAX_AXIS = {MAX_AXIS:g} from the leading edge; positions "
                             "are in chords (the elastic axis of a typical section is x = (1 + a) / 2)")
    return f


_AXIS_TOL = 1e-9
"""Largest difference (chords) between ``pivot`` / ``moment_axis`` and the axis the data state (``metadata["axis"]``)
that :func:`change_axes` takes as the same axis (:func:`aeroelastic.flutter`'s check uses the same)."""


def _check_stated_axis(frf, xp: float, xm: float) -> None:
    """:class:`AeroModelError` when ``frf.metadata["axis"]`` (set by an earlier :func:`change_axes`) is not ``xp`` and
    ``xm``: moving the data again from an axis they are not about gave loads about neither axis, with the new axis
    stamped on them (a flutter speed 21 % low that ``flutter``'s own axis check then passed)."""
    md = frf.metadata
    if "axis" not in md:
        return
    try:
        xa = float(md["axis"])
    except (TypeError, ValueError):
        raise AeroModelError(f"the data's metadata['axis'] = {md['axis']!r} is not a position in chords; remove it "
                             "or set it to the axis of the data's pitch and Cm") from None
    wrong = [f"{n} = {v:.6g}" for n, v in (("pivot", xp), ("moment_axis", xm)) if abs(v - xa) > _AXIS_TOL]
    if wrong:
        raise AeroModelError(
            f"the data are about the axis {xa:.6g} chords from the leading edge (metadata['axis'], set by an earlier "
            f"change_axes) but {' and '.join(wrong)} were given; pass pivot={xa:.6g}, moment_axis={xa:.6g} (or move "
            "the original data, not the moved ones)")


def change_axes(frf, *, pivot: float, moment_axis: float, new_axis: float):
    """Re-express motion (and gust) data about a new pitch pivot and moment axis.

    Parameters
    ----------
    frf : sysid.FrequencyResponse
        Outputs containing ``"Cl"``, ``"Cm"`` (``Cm`` about ``moment_axis``); inputs containing ``"plunge"``
        (``h / c`` of the point ``pivot``, up) and ``"pitch"`` (about ``pivot``), optionally ``"gust"`` and
        others (only ``Cm`` changes for those).
    pivot : float
        Pitch pivot of the data, chords from the leading edge (e.g. 0.25).
    moment_axis : float
        Moment reference of the data's ``Cm``, chords from the leading edge (the project's CFD uses 0.25).
    new_axis : float
        The new pivot and moment axis (e.g. the section's ``elastic_axis = (1 + a) / 2``).

    Returns
    -------
    sysid.FrequencyResponse
        Same grid, names and order; ``metadata`` gains ``"axis": new_axis``.

    Raises
    ------
    AeroModelError
        ``frf`` not a :class:`sysid.FrequencyResponse`, missing ``"Cl"`` / ``"Cm"`` outputs, an axis position
        not a finite number, or ``pivot`` / ``moment_axis`` other than the axis the data state they are about
        (``metadata["axis"]``, set by an earlier :func:`change_axes`).
    """
    import sysid

    if not isinstance(frf, sysid.FrequencyResponse):
        raise AeroModelError(f"change_axes() expects a sysid.FrequencyResponse, got {type(frf).__name__}")
    xp, xm, xe = _x("pivot", pivot), _x("moment_axis", moment_axis), _x("new_axis", new_axis)
    _check_stated_axis(frf, xp, xm)
    oi = channel_indices(frf.outputs, LOAD_OUTPUTS, "outputs")
    H = np.array(frf.H, copy=True)
    # outputs: Cm_e = Cm_m + (x_e - x_m) Cl
    H[oi[1]] = H[oi[1]] + (xe - xm) * H[oi[0]]
    if all(n in frf.inputs for n in MOTION_INPUTS):
        ih, ia = (frf.inputs.index(n) for n in MOTION_INPUTS)
        # inputs: response to alpha about x_e = response to alpha about x_p + (-(x_p - x_e)) * response to plunge
        H[:, ia] = H[:, ia] - (xp - xe) * H[:, ih]
    md = dict(frf.metadata)
    md["axis"] = xe
    return frf.replace(H=H, metadata=md)


def to_elastic_axis(frf, section, *, pivot: float = 0.25, moment_axis: float = 0.25):
    """:func:`change_axes` to ``section.elastic_axis`` (quarter-chord pivot and moment by default).

    Parameters
    ----------
    frf : sysid.FrequencyResponse
        Motion (and gust) data as for :func:`change_axes`: outputs containing ``"Cl"``, ``"Cm"``; inputs
        ``"plunge"``, ``"pitch"``, optionally ``"gust"``.
    section : TypicalSection
        Gives the new axis, ``section.elastic_axis`` (chords from the leading edge).
    pivot : float
        Pitch pivot of the data, chords from the leading edge (default 0.25).
    moment_axis : float
        Moment reference of the data's ``Cm``, chords from the leading edge (default 0.25).

    Returns
    -------
    sysid.FrequencyResponse
        Same grid, names and order, pitch and ``Cm`` about the elastic axis; ``metadata`` gains
        ``"axis": section.elastic_axis``.

    Raises
    ------
    SectionError
        ``section`` not a :class:`TypicalSection`.
    AeroModelError
        ``frf`` not a :class:`sysid.FrequencyResponse`, missing ``"Cl"`` / ``"Cm"`` outputs, ``pivot`` /
        ``moment_axis`` not a finite number, or not the axis the data state they are about
        (``metadata["axis"]``, set by an earlier :func:`change_axes`).
    """
    check_section(section)
    return change_axes(frf, pivot=pivot, moment_axis=moment_axis, new_axis=section.elastic_axis)
