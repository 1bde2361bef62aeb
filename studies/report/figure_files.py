"""Saving a figure: atomically, as a small palette PNG when the figure is a PNG, and closed afterwards."""

from __future__ import annotations

from pathlib import Path

from ..store.files import atomic_path
from .plot_style import pyplot

__all__ = ["save_figure"]


def save_figure(fig, path, *, dpi: int = 120, palette: bool = True, text: dict | None = None) -> Path:
    """Save ``fig`` to ``path`` atomically (parent folders created) and close it.

    The figure is drawn to a temporary file beside ``path`` and renamed over it
    (:func:`studies.store.files.atomic_path`): a failure while drawing or writing leaves an existing file as it was.

    Parameters
    ----------
    fig : Figure
    path : path-like
        The format follows the suffix (``.png``, ``.pdf``, ``.svg``).
    dpi : int
    palette : bool
        PNG only: store with a 256-colour palette (no dithering), about three times smaller than RGBA and
        indistinguishable for line plots, so that generated figures can be committed.
    text : dict of str, optional
        PNG only: text chunks (key: value) stored in the file, e.g. ``lfdrom fit``'s generator marker.

    Returns
    -------
    pathlib.Path
    """
    path = Path(path)
    fmt = path.suffix[1:].lower() or None
    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=dpi, format=fmt, **({"metadata": dict(text)} if text and fmt == "png" else {}))
            if palette and fmt == "png":
                from PIL import Image, PngImagePlugin

                with Image.open(tmp) as im:
                    q = im.convert("RGB").quantize(colors=256, method=Image.Quantize.FASTOCTREE,
                                                   dither=Image.Dither.NONE)
                info = PngImagePlugin.PngInfo()
                for key, value in (text or {}).items():
                    info.add_text(key, value)
                q.save(tmp, format="PNG", optimize=True, pnginfo=info)
    finally:
        pyplot().close(fig)
    return path
