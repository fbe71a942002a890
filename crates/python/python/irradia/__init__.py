"""Irradia from Python: scenes, rendering, ray casting, radiosity and sort-last
compositing on numpy arrays.

Every function calls the Rust library the ``irradia`` command calls: an array equals
the command's image bit for bit, and bad input raises :class:`IrradiaError` (a
``ValueError``) with the command's message (file, line and field for scene files),
``OSError`` for files that cannot be read or written. Rust work runs with the GIL
released; Ctrl-C stops a render cleanly (``KeyboardInterrupt``).

Quick start::

    import irradia
    scene = irradia.builtin("cornell")
    image = scene.render(spp=16, width=128, height=128)   # float32 (128, 128, 3), linear
    irradia.write_image("cornell.png", image)
"""

import json as _json
import os as _os

from . import _irradia
from ._irradia import (  # noqa: F401  (re-exported)
    INVALID_ID,
    IrradiaError,
    Scene,
    __version__,
    builtin,
    builtins,
    display_grid,
    form_factor,
    form_factor_cases,
    load,
    mpi_available,
    radiosity,
    read_image,
    write_image,
)

__all__ = [
    "INVALID_ID",
    "IrradiaError",
    "Scene",
    "builtin",
    "builtins",
    "composite",
    "display_grid",
    "form_factor",
    "form_factor_cases",
    "load",
    "load_dict",
    "mpi_available",
    "radiosity",
    "read_image",
    "write_image",
]


def load_dict(d, base_dir=None):
    """A scene from a dict in the scene-file schema (docs/scene-format.md), the same
    tables and fields as a TOML scene file: ``{"camera": {...}, "objects": [...]}``.

    The dict is written as JSON and read by the JSON scene reader, so errors name the
    field (``objects[2].radius: must be positive``). Relative file names (meshes,
    textures) resolve against ``base_dir`` (default: the current folder).
    """
    if not isinstance(d, dict):
        raise IrradiaError("load_dict: expected a dict in the scene-file schema, got %s" % type(d).__name__)
    try:
        text = _json.dumps(d, indent=1, allow_nan=False)
    except (TypeError, ValueError) as e:
        raise IrradiaError("load_dict: the dict cannot be written as JSON: %s" % e) from None
    return _irradia._load_json(text, _os.fspath(base_dir) if base_dir is not None else None)


def composite(color, depth=None, strategy="binary-swap", comm=None, *, op=None, order=None,
              root=0, rle=True, timeout=60.0, tiles=None):
    """Sort-last compositing of premultiplied RGBA images (uint8 or float32) with
    Irradia's compositors.

    With ``comm`` (an mpi4py communicator, e.g. ``MPI.COMM_WORLD``) every rank passes
    its own layer, ``color`` of shape (h, w, 4) and ``depth`` (h, w) float32 (inf for
    the background), and all ranks call together; rank ``root`` gets
    ``(color, depth)``, the others ``None``. ``strategy``: "direct-send", "tree",
    "binary-swap", "radix-k" or "radix-N". ``op``: "depth" (opaque, the nearer pixel
    wins; the default when ``depth`` is given) or "over" (ordered Porter-Duff over,
    front first in ``order``, a list of ranks; the default without depth).

    With ``tiles``, a list of display tiles ``(rank, x, y, width, height)`` (see
    ``display_grid``), the composite goes straight onto the displays: each display
    rank gets ``(color, depth)`` of its tile, the other ranks ``None``.

    With ``comm=None`` the layers of this process, a stack ``color`` of shape
    (n, h, w, 4) and ``depth`` (n, h, w), are composited one after another (a single
    layer is returned as it is): the serial result every parallel strategy equals;
    with ``tiles`` a list of the tiles' ``(color, depth)``, in the order given.
    """
    if op is None:
        op = "depth" if depth is not None else "over"
    if order is not None:
        order = [int(r) for r in order]
    if tiles is not None:
        tiles = [tuple(int(v) for v in t) for t in tiles]
    if comm is None:
        return _irradia._composite_serial(color, depth, op=op, order=order, tiles=tiles)
    if not mpi_available():
        raise IrradiaError(
            "composite: this irradia was built without MPI; rebuild with "
            "`pip install ./crates/python --config-settings=build-args='--features extension-module,mpi'` "
            "(needs OpenMPI's libopenmpi-dev and libclang-dev), or pass comm=None"
        )
    py2f = getattr(comm, "py2f", None)
    if py2f is None:
        raise IrradiaError("composite: comm must be an mpi4py communicator (it has no py2f())")
    try:
        from mpi4py import MPI
    except ImportError:
        raise IrradiaError("composite: comm given but mpi4py cannot be imported") from None
    if comm == MPI.COMM_NULL:
        raise IrradiaError("composite: comm is MPI.COMM_NULL")
    if comm.Is_inter():
        raise IrradiaError("composite: comm must be an intra-communicator")
    return _irradia._composite_mpi(color, depth, strategy, op, order, int(root), bool(rle),
                                   int(py2f()), float(timeout), tiles)
