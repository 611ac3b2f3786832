"""One entry point for the 3DGS file formats found in the wild.

=====================  ======================================  =============================
suffix                 format                                  reader
=====================  ======================================  =============================
``.ply``               Inria 3DGS PLY (also gsplat/nerfstudio)  :func:`.ply.read_ply`
``.ply`` with chunks   PlayCanvas compressed PLY                :func:`.playcanvas.read_compressed_ply`
``.splat``             antimatter15 splat                       :func:`.splat.read_splat`
``.spz``               Niantic spz, versions 2-4                :func:`.spz.read_spz`
=====================  ======================================  =============================

A PLY is told apart by its header: the compressed layout has a ``chunk`` element.
"""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from .model import GaussianScene
from .playcanvas import read_compressed_ply
from .ply import ply_element_names, read_ply
from .splat import read_splat
from .spz import read_spz

SUFFIXES = (".ply", ".splat", ".spz")


def read_gaussians(path: str | Path) -> GaussianScene:
    """Read any supported 3DGS file (see the module doc) into a float32 :class:`GaussianScene`.

    Raises :class:`InputError` naming the file for an unknown suffix and for anything its
    reader rejects.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".splat":
        return read_splat(path)
    if suffix == ".spz":
        return read_spz(path)
    if suffix == ".ply":
        if path.is_file() and "chunk" in ply_element_names(path):
            return read_compressed_ply(path)
        return read_ply(path)
    raise InputError(f"unknown 3DGS file type '{path.suffix}'; expected one of {', '.join(SUFFIXES)}", source=str(path))
