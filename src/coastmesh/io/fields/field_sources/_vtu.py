"""VTK unstructured grids (``.vtu``) as field sources, read through meshio.

VTK's XML ``UnstructuredGrid`` files, parsed by meshio's reader
(``meshio/vtu/_vtu.py``, :func:`meshio.vtu.read`): the points (x, y; z is left
out), the triangle, quad and polygon cells (other cells are left out, and a
quad or polygon is split in a fan from its first node), point data on the
nodes and cell data on the triangles, a vector's components as ``name_x``,
``name_y``, ``name_z``. No time, no roles, and no CRS but the one given.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import NDArray
from pyproj import CRS

from coastmesh.errors import FormatError
from coastmesh.io.fields.field_sources._source import (
    FieldSource,
    build_source,
    split_faces,
)
from coastmesh.io.meshes._meshio import read_with_meshio

__all__ = ["read_vtu"]


def read_vtu(name: str, given: CRS | None) -> FieldSource:
    """Read a ``.vtu`` file: its surface cells, point data and cell data."""
    import meshio.vtu

    data = read_with_meshio(meshio.vtu.read, name, "VTU")
    points = np.asarray(data.points, dtype=np.float64)[:, :2]
    parts, owners, blocks, offset = [], [], [], 0
    for k, block in enumerate(data.cells):
        if block.type not in ("triangle", "quad", "polygon"):
            continue
        triangles, face_of = split_faces(
            block.data, 0, len(points), name, f"cells[{k}]"
        )
        count = len(block.data)
        parts.append(triangles)
        owners.append(offset + (np.arange(count) if face_of is None else face_of))
        blocks.append(k)
        offset += count
    if not parts:
        raise FormatError(
            f"{name}: no triangle, quad or polygon cells; cell types: "
            f"{', '.join(block.type for block in data.cells) or 'none'}"
        )
    face_of = np.concatenate(owners)
    variables: dict[str, xr.DataArray] = {}
    for key, values in data.point_data.items():
        variables |= _components(str(key), np.asarray(values), "node")
    for key, arrays in data.cell_data.items():
        values = np.concatenate([np.asarray(arrays[k]) for k in blocks])
        variables |= _components(str(key), values[face_of], "triangle")
    triangles = np.concatenate(parts)
    return build_source(name, "vtu", points, triangles, given, variables, None, {})


def _components(key: str, values: NDArray[Any], dim: str) -> dict[str, xr.DataArray]:
    """One DataArray of numbers, or one per component (``key_x``, ``key_y``...)."""
    if values.dtype.kind not in "iuf" or values.ndim not in (1, 2):
        return {}
    if values.ndim == 1:
        return {key: xr.DataArray(values, dims=(dim,))}
    width = values.shape[1]
    names = "xyz" if width <= 3 else [str(k) for k in range(width)]
    return {
        f"{key}_{names[k]}": xr.DataArray(values[:, k], dims=(dim,))
        for k in range(width)
    }
