"""The core data types check themselves when built."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from coastmesh.types import Features


def make(**changes):
    values = {
        "geometry": [shapely.box(0, 0, 1, 1), None],
        "crs": "EPSG:4326",
        "fields": {"name": ["a", "b"]},
        "fids": [1, 2],
        "path": "coast.gpkg",
        "layer": "land",
    }
    values.update(changes)
    return Features(**values)


def test_features_are_converted():
    features = make()
    assert len(features) == 2
    assert features.geometry.dtype == object
    assert features.fids.dtype == np.int64
    assert features.crs.to_epsg() == 4326
    assert isinstance(features.fields["name"], np.ndarray)


def test_field_length_is_checked():
    with pytest.raises(ValueError, match=r"field 'name' has 3 values.*expected 2"):
        make(fields={"name": ["a", "b", "c"]})


def test_fid_length_is_checked():
    with pytest.raises(ValueError, match=r"fids has shape \(1,\), expected \(2,\)"):
        make(fids=[1])


def test_geometry_must_be_one_dimensional():
    with pytest.raises(ValueError, match="one-dimensional"):
        make(geometry=np.empty((2, 2), dtype=object))


def test_take_keeps_fields_aligned():
    features = make().take(np.array([False, True]))
    assert features.fids.tolist() == [2]
    assert features.fields["name"].tolist() == ["b"]
    assert features.path == "coast.gpkg" and features.layer == "land"


def test_features_are_frozen():
    with pytest.raises(AttributeError):
        make().path = "other.gpkg"
