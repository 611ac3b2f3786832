"""Inria 3D Gaussian Splatting PLY files.

One ``vertex`` element, one row per Gaussian, written by the reference implementation as
``binary_little_endian`` float32 properties in this order::

    x y z  nx ny nz  f_dc_0..2  f_rest_0..f_rest_{3(K-1)-1}  opacity  scale_0..2  rot_0..3

``opacity`` is a logit, ``scale_*`` are natural-log standard deviations, ``rot_*`` a ``wxyz``
quaternion, ``K = (d+1)^2`` SH coefficients per colour channel. ``f_rest`` is channel-major:
property ``f_rest_{c(K-1)+k}`` holds coefficient ``k+1`` of channel ``c``. The normals are unused
(the reference writes zeros).

:func:`read_ply` accepts any property order, extra properties (nerfstudio/gsplat exports add
some), files without normals (gsplat's export), uchar ``red green blue`` in place of ``f_dc_*``
(nerfstudio's export of a degree-0 model), other scalar types and ASCII files. Values are kept raw in float32, so reading an Inria
file and writing it back reproduces it byte for byte, and writing then reading a float32
:class:`GaussianScene` gives bit-identical tensors.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import torch

from ..errors import InputError
from ._io import atomic_write
from .model import GaussianScene, rgb_to_sh_dc

# PLY scalar type names (both spellings of the spec) -> numpy type codes.
_PLY_TYPES = {
    "char": "i1",
    "int8": "i1",
    "uchar": "u1",
    "uint8": "u1",
    "short": "i2",
    "int16": "i2",
    "ushort": "u2",
    "uint16": "u2",
    "int": "i4",
    "int32": "i4",
    "uint": "u4",
    "uint32": "u4",
    "float": "f4",
    "float32": "f4",
    "double": "f8",
    "float64": "f8",
}
_FORMATS = {"ascii": None, "binary_little_endian": "<", "binary_big_endian": ">"}
_REQUIRED = (
    "x",
    "y",
    "z",
    "f_dc_0",
    "f_dc_1",
    "f_dc_2",
    "opacity",
    "scale_0",
    "scale_1",
    "scale_2",
    "rot_0",
    "rot_1",
    "rot_2",
    "rot_3",
)
_RGB = {"f_dc_0": "red", "f_dc_1": "green", "f_dc_2": "blue"}
_F_REST = re.compile(r"f_rest_(\d+)")
_MAX_HEADER_LINES = 10_000  # a real header has < 100 lines; stop early on a binary non-PLY


@dataclass
class _Element:
    name: str
    count: int
    properties: list[tuple[str, str]] = field(default_factory=list)  # (name, numpy type code)
    has_list: bool = False


def _parse_header(f, source: str) -> tuple[str, list[_Element]]:
    """Read the header from an open binary file, leaving it positioned at the first data byte.

    Returns the format name and the elements in file order.
    """
    if f.readline().rstrip(b"\r\n") != b"ply":
        raise InputError("not a PLY file (does not start with 'ply')", source=source)
    fmt, elements = None, []
    for _ in range(_MAX_HEADER_LINES):
        raw = f.readline()
        if not raw:
            raise InputError("truncated PLY header (no 'end_header' line)", source=source)
        words = raw.decode("ascii", errors="replace").split()
        if not words or words[0] in ("comment", "obj_info"):
            continue
        if words[0] == "end_header":
            break
        if words[0] == "format" and len(words) == 3 and words[1] in _FORMATS:
            fmt = words[1]
        elif words[0] == "element" and len(words) == 3 and words[2].isdigit():
            elements.append(_Element(words[1], int(words[2])))
        elif words[0] == "property" and elements and len(words) >= 3:
            element = elements[-1]
            if words[1] == "list":
                element.has_list = True
                continue
            if len(words) != 3 or words[1] not in _PLY_TYPES:
                raise InputError(f"unsupported PLY property line {raw.strip()!r}", source=source)
            if any(name == words[2] for name, _ in element.properties):
                raise InputError(f"property '{words[2]}' is declared twice", source=source)
            element.properties.append((words[2], _PLY_TYPES[words[1]]))
        else:
            raise InputError(f"malformed PLY header line {raw.strip()!r}", source=source)
    else:
        raise InputError("not a PLY file (no 'end_header' in the first lines)", source=source)
    if fmt is None:
        raise InputError("PLY header has no valid 'format' line (ascii or binary_*_endian 1.0)", source=source)
    return fmt, elements


def _read_vertex(path: Path, source: str) -> tuple[list[str], Callable[[list[str]], np.ndarray]]:
    """The vertex element's property names, and a function gathering named properties into a
    float32 (N, len(names)) array (one copy, whatever the file's types and order)."""
    with open(path, "rb") as f:
        fmt, elements = _parse_header(f, source)
        names = [e.name for e in elements]
        if "vertex" not in names:
            raise InputError(f"PLY has no 'vertex' element (elements: {names})", source=source)
        index = names.index("vertex")
        vertex = elements[index]
        if vertex.count == 0:
            raise InputError("holds no Gaussians ('element vertex 0'); expected at least one", source=source)
        if vertex.has_list:
            raise InputError("the 'vertex' element has list properties; expected scalars only", source=source)
        props = [name for name, _ in vertex.properties]
        column = {name: i for i, name in enumerate(props)}
        n = vertex.count
        if fmt == "ascii":
            # One line per record; records of earlier elements are skipped line by line.
            skip = sum(e.count for e in elements[:index])
            lines = f.read().decode("ascii", errors="replace").splitlines()[skip : skip + n]
            tokens = " ".join(lines).split()
            if len(lines) < n or len(tokens) != n * len(props):
                raise InputError(
                    f"truncated or malformed ASCII data: expected {n} vertex lines of {len(props)} values",
                    source=source,
                )
            try:
                table = np.array(tokens, dtype=np.float64).reshape(n, len(props))
            except ValueError:
                raise InputError("non-numeric value in the ASCII vertex data", source=source) from None
            return props, lambda wanted: table[:, [column[w] for w in wanted]].astype(np.float32, copy=False)
        if any(e.has_list for e in elements[:index]):
            raise InputError("an element with list properties precedes 'vertex'; cannot locate the data", source=source)
        endian = _FORMATS[fmt]
        dtypes = [np.dtype([(p, endian + t) for p, t in e.properties]) for e in elements[: index + 1]]
        start = f.tell() + sum(e.count * d.itemsize for e, d in zip(elements[:index], dtypes))
        need = n * dtypes[-1].itemsize
        size = path.stat().st_size
        if size < start + need:
            raise InputError(
                f"truncated data: the header declares {n} vertices ({start + need} bytes in all) but the file has {size} bytes",
                source=source,
            )
        f.seek(start)
        types = {t for _, t in vertex.properties}
        if len(types) == 1:  # the usual all-float file: a plain 2D array gathers columns fastest
            table = np.fromfile(f, dtype=endian + types.pop(), count=n * len(props)).reshape(n, len(props))
            return props, lambda wanted: table[:, [column[w] for w in wanted]].astype(np.float32, copy=False)
        records = np.fromfile(f, dtype=dtypes[-1], count=n)
        return props, lambda wanted: np.stack([records[w] for w in wanted], axis=1).astype(np.float32, copy=False)


def ply_element_names(path: str | Path) -> list[str]:
    """The names of a PLY file's elements, in file order (only the header is read)."""
    with open(path, "rb") as f:
        return [e.name for e in _parse_header(f, str(path))[1]]


def read_binary_elements(path: str | Path) -> dict[str, np.ndarray]:
    """Every element of a binary PLY file as a structured array (count,) of its scalar properties.

    For formats that spread a scene over several elements (PlayCanvas's ``chunk``, ``vertex`` and
    ``sh``). Raises :class:`InputError` naming the file for ASCII data, list properties and
    truncated data.
    """
    path, source = Path(path), str(path)
    with open(path, "rb") as f:
        fmt, elements = _parse_header(f, source)
        if fmt == "ascii":
            raise InputError("ASCII PLY; this layout is only written as binary", source=source)
        listed = [e.name for e in elements if e.has_list]
        if listed:
            raise InputError(f"elements {listed} have list properties; expected scalars only", source=source)
        dtypes = [np.dtype([(p, _FORMATS[fmt] + t) for p, t in e.properties]) for e in elements]
        need = f.tell() + sum(e.count * d.itemsize for e, d in zip(elements, dtypes))
        size = path.stat().st_size
        if size < need:
            raise InputError(f"truncated data: the header declares {need} bytes in all but the file has {size}", source=source)
        return {e.name: np.fromfile(f, dtype=d, count=e.count) for e, d in zip(elements, dtypes)}


def _sh_rest_count(props: list[str], source: str) -> int:
    """Number M of ``f_rest_*`` properties, checked to be 0..M-1 with M = 3((d+1)^2 - 1), d <= 3."""
    indices = sorted(int(m.group(1)) for p in props if (m := _F_REST.fullmatch(p)))
    m = len(indices)
    if m not in (0, 9, 24, 45):
        raise InputError(
            f"{m} f_rest_* properties; expected 0, 9, 24 or 45 (3 x ((d+1)^2 - 1) for SH degree d = 0..3)",
            source=source,
        )
    if indices != list(range(m)):
        missing = sorted(set(range(m)) - set(indices))
        raise InputError(f"f_rest_* properties are not numbered 0..{m - 1} (missing f_rest_{missing[0]})", source=source)
    return m


def read_ply(path: str | Path) -> GaussianScene:
    """Read a 3DGS PLY file into a float32 :class:`GaussianScene` (on the CPU, no labels).

    Raises :class:`InputError` naming the file for: not a PLY, truncated data, missing required
    properties (all listed), an f_rest count that is no SH degree 0-3, NaN/Inf values and
    all-zero quaternions.
    """
    path = Path(path)
    source = str(path)
    if not path.is_file():
        raise InputError("file not found", source=source)
    props, gather = _read_vertex(path, source)
    # nerfstudio's export of a degree-0 model (or in its "rgb" colour mode) stores uchar red, green,
    # blue instead of f_dc_*; they become the DC coefficients that evaluate to that colour.
    rgb_instead = not {"f_dc_0", "f_dc_1", "f_dc_2"} & set(props) and {"red", "green", "blue"} <= set(props)
    columns = [_RGB.get(p, p) for p in _REQUIRED] if rgb_instead else list(_REQUIRED)
    missing = [p for p in columns if p not in props]
    if missing:
        raise InputError(
            f"missing required properties {', '.join(missing)}; expected the Inria 3DGS layout "
            "(x, y, z, f_dc_0..2, f_rest_*, opacity, scale_0..2, rot_0..3)",
            source=source,
        )
    rest_count = _sh_rest_count(props, source)
    table = torch.from_numpy(gather(columns + [f"f_rest_{i}" for i in range(rest_count)]))
    if rgb_instead:
        table[:, 3:6] = rgb_to_sh_dc(table[:, 3:6] / 255.0)
    n, k = table.shape[0], rest_count // 3  # k: SH coefficients per channel beyond DC
    # Column slices below follow the order of _REQUIRED.
    rest = table[:, len(_REQUIRED) :].reshape(n, 3, k).transpose(1, 2)  # f_rest is channel-major
    scene = GaussianScene(
        means=table[:, 0:3].contiguous(),
        quats=table[:, 10:14].contiguous(),
        log_scales=table[:, 7:10].contiguous(),
        opacity_logits=table[:, 6].contiguous(),
        sh=torch.cat([table[:, None, 3:6], rest], dim=1),
    )
    scene.check_finite(source=source)
    return scene


def _inria_property_names(num_sh_coeffs: int) -> list[str]:
    """Property names in the reference order for ``K = num_sh_coeffs`` SH coefficients per channel."""
    return (
        ["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"]
        + [f"f_rest_{i}" for i in range(3 * (num_sh_coeffs - 1))]
        + ["opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"]
    )


def write_ply(scene: GaussianScene, path: str | Path) -> None:
    """Write ``scene`` as an Inria 3DGS PLY (binary little-endian float32, zero normals), atomically.

    The header and layout match the reference writer, so the file loads in any 3DGS viewer.
    Raises :class:`InputError` for non-finite values or zero quaternions rather than writing a
    file that :func:`read_ply` would reject. Labels are not stored (see ``labels.npy``).
    """
    scene.check_finite(source=str(path))
    n, k = len(scene), scene.sh.shape[1]

    def numpy(t: torch.Tensor) -> np.ndarray:
        return t.detach().to("cpu", torch.float32).numpy()

    names = _inria_property_names(k)
    table = np.zeros((n, len(names)), dtype="<f4")  # little-endian whatever the machine; normals stay 0
    table[:, 0:3] = numpy(scene.means)
    sh = numpy(scene.sh)
    table[:, 6:9] = sh[:, 0, :]
    table[:, 9 : 9 + 3 * (k - 1)] = sh[:, 1:, :].transpose(0, 2, 1).reshape(n, 3 * (k - 1))  # channel-major
    table[:, -8] = numpy(scene.opacity_logits)
    table[:, -7:-4] = numpy(scene.log_scales)
    table[:, -4:] = numpy(scene.quats)
    header = "".join(
        ["ply\n", "format binary_little_endian 1.0\n", f"element vertex {n}\n"]
        + [f"property float {name}\n" for name in names]
        + ["end_header\n"]
    )
    atomic_write(path, header, table)
