"""Core data types of coastmesh.

Types are few, immutable and validated when built. Constructors never read files:
the readers in :mod:`coastmesh.io` return these types.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from pyproj import CRS

__all__ = ["Features"]


@dataclass(frozen=True, slots=True)
class Features:
    """Vector features: geometries, their CRS, attributes and source ids.

    Parameters
    ----------
    geometry : array_like of shapely geometries, shape (N,)
        One geometry (or None) per feature.
    crs : pyproj.CRS or None
        Coordinate reference system of the coordinates; anything
        :meth:`pyproj.CRS.from_user_input` takes is converted. None if unknown.
    fields : mapping of str to array_like of shape (N,)
        Attribute columns by name; stored as a new dict of arrays.
    fids : array_like of int, shape (N,)
        Feature ids in the source layer, used to name features in error messages.
    path : str
        The source file, or a description such as ``"<memory>"``.
    layer : str or None
        The layer inside the source file.

    Raises
    ------
    ValueError
        If ``geometry`` or ``fids`` is not one-dimensional, or a field or ``fids``
        does not have one value per geometry.

    Examples
    --------
    >>> import shapely
    >>> f = Features(
    ...     geometry=[shapely.box(0, 0, 1, 1)],
    ...     crs="EPSG:4326",
    ...     fields={"name": ["a"]},
    ...     fids=[1],
    ...     path="<memory>",
    ...     layer=None,
    ... )
    >>> len(f), f.crs.to_epsg()
    (1, 4326)
    """

    geometry: NDArray[np.object_]
    crs: CRS | None
    fields: Mapping[str, NDArray]
    fids: NDArray[np.int64]
    path: str
    layer: str | None = None

    def __post_init__(self) -> None:
        geometry = _as_object_array(self.geometry)
        if geometry.ndim != 1:
            raise ValueError(
                f"geometry must be one-dimensional, got shape {geometry.shape}"
            )
        size = geometry.shape[0]
        fids = np.asarray(self.fids)
        if fids.ndim != 1 or fids.shape[0] != size:
            raise ValueError(
                f"fids has shape {fids.shape}, expected ({size},): one id per geometry"
            )
        if fids.size and not np.issubdtype(fids.dtype, np.integer):
            raise ValueError(f"fids must be integers, got dtype {fids.dtype}")
        fields = {}
        for name, values in self.fields.items():
            column = np.asarray(values)
            if column.ndim != 1 or column.shape[0] != size:
                raise ValueError(
                    f"field {name!r} has {column.shape[0] if column.ndim else 0} "
                    f"values (shape {column.shape}), expected {size}: one per geometry"
                )
            fields[str(name)] = column
        crs = self.crs
        if crs is not None and not isinstance(crs, CRS):
            crs = CRS.from_user_input(crs)
        object.__setattr__(self, "geometry", geometry)
        object.__setattr__(self, "fids", fids.astype(np.int64, copy=False))
        object.__setattr__(self, "fields", fields)
        object.__setattr__(self, "crs", crs)
        object.__setattr__(self, "path", str(self.path))

    def __len__(self) -> int:
        return int(self.geometry.shape[0])

    def take(self, indices: ArrayLike) -> Features:
        """Return the features at ``indices`` (integers or a boolean mask).

        Parameters
        ----------
        indices : array_like of int or bool
            Positions to keep, or a mask of shape (N,).

        Returns
        -------
        Features
            A new instance; this one is unchanged.
        """
        index = np.asarray(indices)
        return Features(
            geometry=self.geometry[index],
            crs=self.crs,
            fields={name: values[index] for name, values in self.fields.items()},
            fids=self.fids[index],
            path=self.path,
            layer=self.layer,
        )

    def with_geometry(self, geometry: ArrayLike) -> Features:
        """Return a copy with the geometries replaced and everything else kept.

        Parameters
        ----------
        geometry : array_like of shapely geometries, shape (N,)
            The new geometries, one per feature.

        Returns
        -------
        Features
        """
        return Features(
            geometry=_as_object_array(geometry),
            crs=self.crs,
            fields=self.fields,
            fids=self.fids,
            path=self.path,
            layer=self.layer,
        )


def _as_object_array(values: ArrayLike) -> NDArray[np.object_]:
    """Return ``values`` as an object array without letting numpy unpack shapes."""
    if isinstance(values, np.ndarray):
        return values.astype(object, copy=False)
    items = list(values)  # type: ignore[arg-type]
    array = np.empty(len(items), dtype=object)
    array[:] = items
    return array
