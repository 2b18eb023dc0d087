"""Partition covariances from lag products, and their leading eigenvectors."""

from __future__ import annotations

import numpy as np
import scipy.linalg
from numpy.typing import NDArray
from scipy.sparse.linalg import ArpackError, ArpackNoConvergence, eigsh

from coastmesh.pca.checks import deterministic_start

__all__ = ["centred_covariance", "leading_eigenvectors"]

# Below this size, or when many modes are asked for, LAPACK's dense solver is as fast
# as a Krylov method; above it ARPACK's implicitly restarted Lanczos (scipy) finds the
# few leading modes of an L x L matrix in O(L^2) per iteration instead of O(L^3).
_DENSE_MAX_SIZE = 160


def centred_covariance(gram: NDArray[np.float64], count: int) -> NDArray[np.float64]:
    """Return ``C = Q G Q / M``, ``Q = I - 11^T/L``: the centred partition covariance.

    Parameters
    ----------
    gram : ndarray of shape (L, L)
        Sum of ``s_k s_k^T`` over the ``M`` partitions ``s_k`` (symmetric).
    count : int
        The number of partitions ``M``.

    Returns
    -------
    ndarray of shape (L, L)
        The covariance of the partitions, each less its own mean; exactly
        symmetric, as ``gram`` is.
    """
    row = gram.mean(axis=0)
    cov = np.add.outer(row, row)
    np.subtract(gram, cov, out=cov)
    cov += row.mean()
    cov /= count
    return cov


def leading_eigenvectors(
    cov: NDArray[np.float64], modes: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Return the ``modes`` leading eigenpairs of ``cov``, by decreasing eigenvalue.

    Parameters
    ----------
    cov : ndarray of shape (L, L)
        Symmetric covariance matrix.
    modes : int
        Number of leading eigenvectors, ``1 <= modes <= L``.

    Returns
    -------
    values : ndarray of shape (modes,)
        Eigenvalues, decreasing.
    vectors : ndarray of shape (L, modes)
        Orthonormal eigenvectors, column ``q`` for ``values[q]``.
    """
    size = cov.shape[0]
    if modes == size:
        values, vectors = np.linalg.eigh(cov)
    elif size <= _DENSE_MAX_SIZE or 4 * modes > size:
        values, vectors = scipy.linalg.eigh(
            cov,
            subset_by_index=(size - modes, size - 1),
            driver="evr",
            check_finite=False,
        )
    else:
        try:
            values, vectors = eigsh(
                cov,
                k=modes,
                which="LA",
                v0=deterministic_start(size),
                ncv=min(size, max(2 * modes + 1, 24)),
                tol=0.0,
            )
        except (ArpackNoConvergence, ArpackError):
            values, vectors = scipy.linalg.eigh(
                cov, subset_by_index=(size - modes, size - 1), driver="evr"
            )
    order = np.argsort(values)[::-1]
    return values[order], np.ascontiguousarray(vectors[:, order])
