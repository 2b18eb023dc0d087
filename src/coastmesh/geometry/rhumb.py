"""Loxodromes (rhumb lines) and blended loxodromes on the WGS84 ellipsoid.

A loxodrome crosses every meridian at the same azimuth ``alpha`` (degrees clockwise
from true north). With the isometric latitude
``psi(phi) = atanh(sin phi) - e atanh(e sin phi)``, it is the straight line
``lambda - lambda0 = tan(alpha) (psi - psi0)``, which is a straight line on the
ellipsoidal Mercator projection (EPSG:3395, ``y = a psi``). Its length is
``|m(phi1) - m(phi0)| / |cos alpha|``, with ``m`` the meridian arc, or
``N(phi0) cos(phi0) |dlambda|`` along a parallel.

No maintained Python library computes ellipsoidal rhumb lines (GeographicLib's
``Rhumb`` class is C++ only; its Python port and pyproj have geodesics only), so
the closed forms above are written here. The meridian arc and its inverse come from
pyproj's geodesics along a meridian, which are exact to rounding.

The paper (Avdis et al. 2015, section III.C) gives bearings such as "20 deg W",
measured westward from north: that is the azimuth ``360 - 20 = 340`` here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from pyproj import Geod

from coastmesh.errors import ConfigError

__all__ = ["Loxodrome", "blend_loxodromes", "great_circle", "paper_bearing"]

_GEOD = Geod(ellps="WGS84")
_E = np.sqrt(_GEOD.es)


def paper_bearing(degrees_west: float) -> float:
    """Convert a bearing given in degrees west of north to an azimuth.

    Parameters
    ----------
    degrees_west : float
        Angle from north, measured westward (anticlockwise), in degrees.

    Returns
    -------
    float
        Azimuth in degrees clockwise from north, in ``[0, 360)``.

    Examples
    --------
    >>> paper_bearing(20)
    340.0
    >>> paper_bearing(0)
    0.0
    """
    return float((-degrees_west) % 360.0)


def _isometric(lat: NDArray[np.float64]) -> NDArray[np.float64]:
    s = np.sin(np.radians(lat))
    return np.arctanh(s) - _E * np.arctanh(_E * s)


def _latitude_of_isometric(psi: NDArray[np.float64]) -> NDArray[np.float64]:
    """Invert the isometric latitude by Newton's method (converges in ~5 steps)."""
    phi = np.arctan(np.sinh(psi))  # the spherical value as a start
    for _ in range(8):
        s = np.sin(phi)
        f = np.arctanh(s) - _E * np.arctanh(_E * s) - psi
        # d psi / d phi = (1 - e^2) / ((1 - e^2 sin^2) cos)
        deriv = (1 - _E**2) / ((1 - (_E * s) ** 2) * np.cos(phi))
        phi = phi - f / deriv
    return np.degrees(phi)


def _meridian_arc(lat: NDArray[np.float64]) -> NDArray[np.float64]:
    """Signed meridian arc from the equator to ``lat``, in metres."""
    lat = np.asarray(lat, dtype=float)
    zeros = np.zeros_like(lat)
    _, _, dist = _GEOD.inv(zeros, zeros, zeros, lat)
    return np.sign(lat) * dist


def _latitude_of_arc(arc: NDArray[np.float64]) -> NDArray[np.float64]:
    """Latitude at signed meridian arc ``arc`` (metres) from the equator."""
    arc = np.asarray(arc, dtype=float)
    zeros = np.zeros_like(arc)
    _, lat, _ = _GEOD.fwd(zeros, zeros, np.where(arc >= 0, 0.0, 180.0), np.abs(arc))
    return np.asarray(lat)


# What a loxodrome ending at a latitude or a longitude runs along, the ways it
# can head there, the way it never gets there, and what to give instead.
_ENDS = {
    "end_lat": ("latitude", "north", "south", "east or west", "end_lon", ""),
    "end_lon": (
        "longitude",
        "east",
        "west",
        "north or south",
        "end_lat",
        " (longitudes are not wrapped)",
    ),
}


def _check_end(name: str, end: float, start: float, heading: float, az: float) -> None:
    """Raise unless a loxodrome from ``start`` at azimuth ``az`` reaches ``end``.

    ``heading`` is the azimuth's cosine for ``end_lat``, its sine for ``end_lon``.
    """
    coordinate, ahead, back, across, other, note = _ENDS[name]
    if np.isclose(heading, 0.0, atol=1e-12):
        raise ConfigError(
            f"loxodrome azimuth = {az}: a line due {across} never reaches "
            f"{name} = {end}; give {other}"
        )
    if name == "end_lat" and not -90 < end < 90:
        raise ConfigError(f"loxodrome end_lat = {end}: not in (-90, 90)")
    if (end > start) != (heading > 0) or end == start:
        raise ConfigError(
            f"loxodrome from {coordinate} {start} at azimuth {az} heads "
            f"{ahead if heading > 0 else back} and never reaches {name} = {end}{note}"
        )


@dataclass(frozen=True, slots=True)
class Loxodrome:
    """A rhumb line from ``start`` at ``azimuth`` to a given latitude or longitude.

    Parameters
    ----------
    start : (float, float)
        ``(lon, lat)`` of the start, degrees.
    azimuth : float
        Degrees clockwise from true north, ``[0, 360)``.
    end_lat, end_lon : float, optional
        Where it ends: exactly one of the two. ``end_lat`` for a line that is not
        due east or west; ``end_lon`` for one that is not due north or south.

    Examples
    --------
    >>> line = Loxodrome((-15.0, 57.0), paper_bearing(20), end_lat=70.0)
    >>> lon, lat = line.end
    >>> round(lat, 6), round(lon, 3)
    (70.0, -25.804)
    >>> round(line.length / 1000)
    1542
    """

    start: tuple[float, float]
    azimuth: float
    end_lat: float | None = None
    end_lon: float | None = None

    def __post_init__(self) -> None:
        lon0, lat0 = (float(v) for v in self.start)
        if not (np.isfinite(lon0) and -90 < lat0 < 90):
            raise ConfigError(
                f"loxodrome start = {self.start}: needs a finite longitude and a "
                "latitude strictly between -90 and 90"
            )
        if (self.end_lat is None) == (self.end_lon is None):
            raise ConfigError(
                "loxodrome: give exactly one of end_lat and end_lon "
                f"(got end_lat={self.end_lat}, end_lon={self.end_lon})"
            )
        az = float(self.azimuth) % 360.0
        object.__setattr__(self, "azimuth", az)
        if self.end_lat is not None:
            _check_end("end_lat", self.end_lat, lat0, np.cos(np.radians(az)), az)
        elif self.end_lon is not None:  # one of the two, checked above
            _check_end("end_lon", self.end_lon, lon0, np.sin(np.radians(az)), az)

    @classmethod
    def between(cls, start: tuple[float, float], end: tuple[float, float]) -> Loxodrome:
        """Return the loxodrome from ``start`` to ``end`` (``(lon, lat)``, degrees).

        The azimuth solves ``tan(alpha) = (lambda1 - lambda0) / (psi1 - psi0)`` on
        the ellipsoid; the shorter way round in longitude is not sought
        (longitudes are not wrapped).

        Examples
        --------
        >>> line = Loxodrome.between((-15.0, 57.0), (-4.0, 48.5))
        >>> round(line.azimuth, 3), [round(v, 9) for v in line.end]
        (141.974, [-4.0, 48.5])
        """
        (lon0, lat0), (lon1, lat1) = (tuple(float(v) for v in p) for p in (start, end))
        if (lon0, lat0) == (lon1, lat1):
            raise ConfigError(f"loxodrome from {start} to {end}: the ends coincide")
        dpsi = float(_isometric(np.array([lat1]))[0] - _isometric(np.array([lat0]))[0])
        azimuth = float(np.degrees(np.arctan2(np.radians(lon1 - lon0), dpsi)) % 360.0)
        if lat1 == lat0:
            return cls((lon0, lat0), azimuth, end_lon=lon1)
        return cls((lon0, lat0), azimuth, end_lat=lat1)

    @property
    def _end_longitude(self) -> float:
        """``end_lon``: given whenever ``end_lat`` is not (or the line is a parallel).

        ``__post_init__`` checks it: exactly one is given, and a parallel never
        reaches a latitude.
        """
        assert self.end_lon is not None
        return self.end_lon

    @property
    def _parallel(self) -> bool:
        return bool(np.isclose(np.cos(np.radians(self.azimuth)), 0.0, atol=1e-12))

    @property
    def end(self) -> tuple[float, float]:
        """``(lon, lat)`` of the end, degrees."""
        (lon,), (lat,) = self.points(np.array([1.0]))
        return float(lon), float(lat)

    @property
    def length(self) -> float:
        """Length along the ellipsoid, metres."""
        lon0, lat0 = self.start
        alpha = np.radians(self.azimuth)
        if self._parallel:
            phi = np.radians(lat0)
            n = _GEOD.a / np.sqrt(1 - (_E * np.sin(phi)) ** 2)
            return float(n * np.cos(phi) * np.radians(abs(self._end_longitude - lon0)))
        lat1 = self._end_latitude()
        arc = _meridian_arc(np.array([lat0, lat1]))
        return float(abs(arc[1] - arc[0]) / abs(np.cos(alpha)))

    def _end_latitude(self) -> float:
        lon0, lat0 = self.start
        if self.end_lat is not None:
            return float(self.end_lat)
        tan = np.tan(np.radians(self.azimuth))
        psi = (
            _isometric(np.array([lat0]))[0]
            + np.radians(self._end_longitude - lon0) / tan
        )
        return float(_latitude_of_isometric(np.array([psi]))[0])

    def points(self, fractions: NDArray[np.float64]) -> NDArray[np.float64]:
        """Return the points at the given fractions of the arc length.

        Parameters
        ----------
        fractions : array_like of shape (k,)
            Fractions of the length from the start, in ``[0, 1]``.

        Returns
        -------
        ndarray of shape (2, k)
            Longitudes and latitudes, degrees.
        """
        t = np.asarray(fractions, dtype=float)
        lon0, lat0 = self.start
        if self._parallel:
            return np.stack(
                [lon0 + t * (self._end_longitude - lon0), np.full_like(t, lat0)]
            )
        arc0, arc1 = _meridian_arc(np.array([lat0, self._end_latitude()]))
        lat = _latitude_of_arc(arc0 + t * (arc1 - arc0))
        lat = np.where(t == 0, lat0, lat)
        tan = np.tan(np.radians(self.azimuth))
        lon = lon0 + np.degrees(tan * (_isometric(lat) - _isometric(np.array(lat0))))
        if self.end_lon is not None:
            lon = np.where(t == 1, self.end_lon, lon)
        if self.end_lat is not None:
            lat = np.where(t == 1, self.end_lat, lat)
        return np.stack([lon, lat])

    def sample(self, spacing: float) -> NDArray[np.float64]:
        """Return points at most ``spacing`` metres apart along the line.

        Parameters
        ----------
        spacing : float
            Largest distance between consecutive points, metres (> 0).

        Returns
        -------
        ndarray of shape (k, 2)
            ``(lon, lat)`` rows from start to end, ``k >= 2``.
        """
        if not spacing > 0:
            raise ConfigError(f"spacing = {spacing}: must be > 0 metres")
        count = max(2, int(np.ceil(self.length / spacing)) + 1)
        return self.points(np.linspace(0.0, 1.0, count)).T


def blend_loxodromes(
    first: Loxodrome, second: Loxodrome, *, spacing: float
) -> NDArray[np.float64]:
    """Blend two loxodromes into one curve, as the paper's open boundaries.

    ``P(s) = (1 - s) L1(s) + s L2(1 - s)`` for ``s`` in ``[0, 1]``, where ``L(t)``
    is the point at fraction ``t`` of the arc length of ``L``, combined linearly in
    longitude and latitude. ``P`` runs from the start of ``first`` to the start of
    ``second``.

    Parameters
    ----------
    first, second : Loxodrome
        The two lines.
    spacing : float
        Largest distance between consecutive points, metres; the sampling is refined
        until every step of the blended curve is at most this long.

    Returns
    -------
    ndarray of shape (k, 2)
        ``(lon, lat)`` rows.

    Examples
    --------
    >>> a = Loxodrome((-15.0, 57.0), paper_bearing(20), end_lat=70.0)
    >>> b = Loxodrome((5.45, 62.0), 0.0, end_lat=70.0)
    >>> p = blend_loxodromes(a, b, spacing=10_000)
    >>> p[0].tolist(), p[-1].round(6).tolist()
    ([-15.0, 57.0], [5.45, 62.0])
    """
    if not spacing > 0:
        raise ConfigError(f"spacing = {spacing}: must be > 0 metres")
    count = max(2, int(np.ceil(max(first.length, second.length) / spacing)) + 1)
    while True:
        s = np.linspace(0.0, 1.0, count)
        curve = ((1 - s) * first.points(s) + s * second.points(1 - s)).T
        _, _, steps = _GEOD.inv(
            curve[:-1, 0], curve[:-1, 1], curve[1:, 0], curve[1:, 1]
        )
        if np.max(steps) <= spacing:
            return curve
        count = int(np.ceil(count * np.max(steps) / spacing)) + 1


def great_circle(
    start: tuple[float, float], end: tuple[float, float], *, spacing: float
) -> NDArray[np.float64]:
    """Sample the geodesic (great-circle arc on WGS84) from ``start`` to ``end``.

    Parameters
    ----------
    start, end : (float, float)
        ``(lon, lat)`` of the two ends, degrees; distinct.
    spacing : float
        Largest distance between consecutive points, metres (> 0).

    Returns
    -------
    ndarray of shape (k, 2)
        ``(lon, lat)`` rows from ``start`` to ``end``, equally spaced along the
        geodesic (pyproj's ``Geod.npts``), ``k >= 2``.

    Examples
    --------
    >>> p = great_circle((-10.0, 50.0), (10.0, 50.0), spacing=50_000)
    >>> p[0].tolist(), p[-1].tolist(), bool(p[:, 1].max() > 50.4)  # bulges north
    ([-10.0, 50.0], [10.0, 50.0], True)
    """
    if not spacing > 0:
        raise ConfigError(f"spacing = {spacing}: must be > 0 metres")
    (lon0, lat0), (lon1, lat1) = (tuple(float(v) for v in p) for p in (start, end))
    for name, lat in (("start", lat0), ("end", lat1)):
        if not -90 <= lat <= 90:
            raise ConfigError(f"great circle {name} latitude = {lat}: not in [-90, 90]")
    _, _, length = _GEOD.inv(lon0, lat0, lon1, lat1)
    if not length > 0:
        raise ConfigError(f"great circle from {start} to {end}: the ends coincide")
    inner = max(0, int(np.ceil(length / spacing)) - 1)
    middle = np.array(_GEOD.npts(lon0, lat0, lon1, lat1, inner)).reshape(-1, 2)
    line = np.vstack([[lon0, lat0], middle, [lon1, lat1]])
    # npts wraps longitudes to [-180, 180]; keep the line continuous from start
    lon = line[1:, 0]
    jump = np.abs(lon - lon0) > 180.0
    lon[jump] = lon0 + (lon[jump] - lon0 + 180.0) % 360.0 - 180.0
    return line
