"""Atomic outputs: write to a staging place next to the target, then rename.

A file is written into a hidden staging folder in the target's folder
(``.OUT.gpkg.tmp-XXXX/OUT.gpkg``), so GDAL drivers see a real path with the right
name and extension, and side files such as a shapefile's ``.shx``/``.dbf``/``.prj``
are staged with it. On success every staged file is moved over its target with
:func:`os.replace`; on any failure the staging folder is removed, so a failed
write leaves the target untouched. Existing outputs are refused unless
``overwrite=True``.
"""

from __future__ import annotations

import logging
import os
import secrets
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from types import TracebackType

from coastmesh.errors import ConfigError, OutputExistsError

__all__ = [
    "AtomicOutputs",
    "atomic_directory",
    "atomic_write",
    "check_directory",
    "check_output",
]

logger = logging.getLogger(__name__)

_SHAPEFILE_SIDECARS = (".shx", ".dbf", ".prj", ".cpg", ".qix", ".sbn", ".sbx")


def check_output(path: str | os.PathLike[str], *, overwrite: bool = False) -> Path:
    """Check that a file may be written at ``path``.

    Parameters
    ----------
    path : str or path-like
        The output file.
    overwrite : bool, default False
        Whether an existing file may be replaced.

    Returns
    -------
    pathlib.Path
        The path.

    Raises
    ------
    OutputExistsError
        If ``path`` exists and ``overwrite`` is false, or ``path`` is a folder.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> target = pathlib.Path(tempfile.mkdtemp()) / "mesh.msh"
    >>> check_output(target).name
    'mesh.msh'
    >>> _ = target.write_text("old")
    >>> check_output(target)
    Traceback (most recent call last):
    ...
    coastmesh.errors.OutputExistsError: .../mesh.msh already exists; use ...
    """
    target = Path(path)
    if target.is_dir():
        raise OutputExistsError(f"{target} is a folder; give a file name")
    if target.exists() and not overwrite:
        raise OutputExistsError(
            f"{target} already exists; use --overwrite (overwrite=True) to replace it"
        )
    return target


class AtomicOutputs:
    """Stage several output files and publish them together.

    Use as a context manager: :meth:`stage` returns the path to write each output
    to; leaving the block without an exception moves every staged file to its
    target, and an exception removes them all.

    Parameters
    ----------
    overwrite : bool, default False
        Whether existing targets may be replaced.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> with AtomicOutputs() as outputs:
    ...     _ = outputs.stage(folder / "a.txt").write_text("a")
    >>> sorted(p.name for p in folder.iterdir())
    ['a.txt']
    """

    def __init__(self, *, overwrite: bool = False) -> None:
        self.overwrite = overwrite
        self._staged: list[tuple[Path, Path]] = []
        self._made_dirs: list[Path] = []

    def __enter__(self) -> AtomicOutputs:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        if exc_type is not None:
            self.discard()
            return
        try:
            self.commit()
        except BaseException:
            self.discard()
            raise

    def stage(self, path: str | os.PathLike[str]) -> Path:
        """Return the path to write the output ``path`` to.

        Parameters
        ----------
        path : str or path-like
            The final output file.

        Returns
        -------
        pathlib.Path
            A path with the same name, in a new hidden folder next to ``path``.

        Raises
        ------
        OutputExistsError
            If ``path`` exists and ``overwrite`` is false.
        ConfigError
            If ``path`` was already staged in this set.
        """
        target = check_output(path, overwrite=self.overwrite)
        if any(_same(target, staged) for staged, _ in self._staged):
            raise ConfigError(f"{target} is given for two outputs; use two names")
        self._made_dirs += _make_parents(target.parent)
        staging = Path(
            tempfile.mkdtemp(prefix=f".{target.name}.tmp-", dir=target.parent)
        )
        self._staged.append((target, staging))
        return staging / target.name

    def commit(self) -> None:
        """Move every staged file over its target.

        Raises
        ------
        FileNotFoundError
            If nothing was written to a staged path.
        OutputExistsError
            If a target appeared meanwhile and ``overwrite`` is false.
        """
        for target, staging in self._staged:
            if not (staging / target.name).exists():
                raise FileNotFoundError(
                    f"{target}: the writer produced no file; nothing was written"
                )
            check_output(target, overwrite=self.overwrite)
        for target, staging in self._staged:
            if target.suffix.lower() == ".shp":
                _remove_sidecars(target)
            for produced in sorted(staging.iterdir()):
                os.replace(produced, target.parent / produced.name)
            staging.rmdir()
            logger.debug("wrote %s", target)
        self._staged.clear()
        self._made_dirs.clear()

    def discard(self) -> None:
        """Remove every staged file and any folder made for them."""
        for _, staging in self._staged:
            shutil.rmtree(staging, ignore_errors=True)
        self._staged.clear()
        _remove_folders(self._made_dirs)
        self._made_dirs.clear()


@contextmanager
def atomic_write(
    path: str | os.PathLike[str], *, overwrite: bool = False
) -> Iterator[Path]:
    """Write one output file atomically.

    Parameters
    ----------
    path : str or path-like
        The final output file.
    overwrite : bool, default False
        Whether an existing file may be replaced.

    Yields
    ------
    pathlib.Path
        The staging path to write to; it has the same name and extension.

    Raises
    ------
    OutputExistsError
        If ``path`` exists and ``overwrite`` is false.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> target = pathlib.Path(tempfile.mkdtemp()) / "b.txt"
    >>> with atomic_write(target) as tmp:
    ...     _ = tmp.write_text("b")
    >>> target.read_text()
    'b'
    """
    with AtomicOutputs(overwrite=overwrite) as outputs:
        yield outputs.stage(path)


@contextmanager
def atomic_directory(
    path: str | os.PathLike[str], *, overwrite: bool = False
) -> Iterator[Path]:
    """Fill an output folder atomically: write into ``<path>.partial-XXXX/``.

    The partial folder is renamed to ``path`` when the block ends without an
    exception, and removed otherwise.

    Parameters
    ----------
    path : str or path-like
        The final output folder. An existing empty folder counts as absent.
    overwrite : bool, default False
        Whether an existing, non-empty folder may be replaced (with all its files).

    Yields
    ------
    pathlib.Path
        The partial folder to write into.

    Raises
    ------
    OutputExistsError
        If ``path`` is a file, or a non-empty folder and ``overwrite`` is false.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp()) / "run"
    >>> with atomic_directory(folder) as partial:
    ...     _ = (partial / "a.txt").write_text("a")
    ...     folder.exists()
    False
    >>> sorted(p.name for p in folder.iterdir())
    ['a.txt']
    """
    target = Path(path)
    check_directory(target, overwrite=overwrite)
    made_dirs = _make_parents(target.parent)
    partial = _unique_folder(target.parent, f"{target.name}.partial-")
    try:
        yield partial
        check_directory(target, overwrite=overwrite)
        _publish_directory(partial, target)
    except BaseException:
        shutil.rmtree(partial, ignore_errors=True)
        _remove_folders(made_dirs)
        raise


def check_directory(path: str | os.PathLike[str], *, overwrite: bool = False) -> Path:
    """Check that an output folder may be filled at ``path``.

    Parameters
    ----------
    path : str or path-like
        The folder. An absent or empty folder may be filled.
    overwrite : bool, default False
        Whether a non-empty folder may be replaced.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    OutputExistsError
        If ``path`` is a file, or a non-empty folder and ``overwrite`` is false.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> check_directory(folder) == folder  # empty: may be filled
    True
    >>> _ = (folder / "a.txt").write_text("a")
    >>> check_directory(folder, overwrite=True) == folder
    True
    """
    target = Path(path)
    if target.exists() and not target.is_dir():
        raise OutputExistsError(f"{target} exists and is not a folder")
    if target.is_dir() and any(target.iterdir()) and not overwrite:
        raise OutputExistsError(
            f"{target} already exists and is not empty; use --overwrite "
            "(overwrite=True) to replace it"
        )
    return target


def _publish_directory(partial: Path, target: Path) -> None:
    old = None
    if target.is_dir():
        old = target.parent / f".{target.name}.old-{secrets.token_hex(4)}"
        os.replace(target, old)
    try:
        os.replace(partial, target)
    except BaseException:
        if old is not None:
            os.replace(old, target)
        raise
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)


def _unique_folder(parent: Path, prefix: str) -> Path:
    """Make a new folder ``<prefix>XXXXXXXX`` with the usual (umask) permissions."""
    while True:
        candidate = parent / f"{prefix}{secrets.token_hex(4)}"
        try:
            candidate.mkdir()
        except FileExistsError:
            continue
        return candidate


def _make_parents(folder: Path) -> list[Path]:
    """Make ``folder`` and its missing parents; return those made, outermost first."""
    missing = []
    while not folder.exists():
        missing.append(folder)
        folder = folder.parent
    made = []
    for new in reversed(missing):
        new.mkdir()
        made.append(new)
    return made


def _remove_folders(made: list[Path]) -> None:
    """Remove folders made by :func:`_make_parents`, innermost first, if empty."""
    for folder in reversed(made):
        try:
            folder.rmdir()
        except OSError:
            break


def _remove_sidecars(target: Path) -> None:
    for suffix in _SHAPEFILE_SIDECARS:
        sidecar = target.with_suffix(suffix)
        if sidecar.is_file():
            sidecar.unlink()


def _same(a: Path, b: Path) -> bool:
    return os.path.abspath(a) == os.path.abspath(b)
