"""The narrow stretches kept, ranked and described, against the literal loop."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from reference import rank_channels_loop

from coastmesh.sizing.narrow import narrow_channels, rank_channels


@settings(max_examples=80, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    shape=st.tuples(st.integers(1, 12), st.integers(1, 12)),
    count=st.integers(0, 60),  # over 16: numpy sorts those unstably unless asked
    share=st.floats(0.0, 1.0),
    ties=st.booleans(),
)
def test_ranking_matches_the_loop(seed, shape, count, share, ties):
    rng = np.random.default_rng(seed)
    labels = rng.integers(0, count + 1, shape)
    count = int(labels.max())
    # widths with ties (the first in row-major order wins) or without
    width = rng.integers(1, 4, shape).astype(float) if ties else rng.random(shape)
    area = rng.integers(1, 4, count + 1) * 2.5 if ties else rng.random(count + 1)
    kept = rng.random(count + 1) < share
    kept &= np.isin(np.arange(count + 1), labels)  # a kept label has nodes
    kept[0] = rng.random() < 0.5  # the background is never kept, asked or not
    before = labels.copy()
    got, found = rank_channels(labels, width, area, kept)
    want, want_found = rank_channels_loop(labels, width, area, kept)
    np.testing.assert_array_equal(got, want)
    assert got.dtype == np.int32
    assert len(found) == len(want_found)
    for (row, col, a, w), (*first, widest) in zip(found, want_found, strict=True):
        assert (a, w) == (first[2], first[3])
        assert (row, col) in widest  # the first of them when the widest is alone
        assert all(isinstance(v, int) for v in (row, col))
        assert all(isinstance(v, float) for v in (a, w))
    np.testing.assert_array_equal(labels, before)


def test_a_min_length_of_zero_keeps_every_stretch_and_never_the_background():
    # before rank_channels the plane's copy kept label 0 when min_length <= 0,
    # numbering every node outside a channel as the last channel
    width = np.full((6, 6), 900.0)
    width[2:4, :] = 150.0
    width[5, 5] = 80.0  # a stretch one node long
    inside = np.ones((6, 6), bool)
    labels, found = narrow_channels(width, inside, h_min=100.0, cell=50.0, min_length=0)
    assert int(labels.max()) == len(found) == 2
    assert (labels[width >= 200.0] == 0).all()
    assert [f[2] for f in found] == [12 * 2500.0, 2500.0]
    default, _ = narrow_channels(width, inside, h_min=100.0, cell=50.0)
    np.testing.assert_array_equal(default, np.where(labels == 1, 1, 0))
