"""Atomic outputs: all or nothing, never replacing without overwrite."""

from __future__ import annotations

import pytest

from coastmesh.errors import ConfigError, OutputExistsError
from coastmesh.io._atomic import (
    AtomicOutputs,
    atomic_directory,
    atomic_write,
    check_output,
)


class Boom(Exception):
    pass


def test_atomic_write_writes_only_the_target(tmp_path, folder_listing):
    target = tmp_path / "coast.gpkg"
    with atomic_write(target) as staged:
        assert staged.name == "coast.gpkg"
        assert staged.parent.parent == tmp_path
        assert staged.parent.name.startswith(".coast.gpkg.tmp-")
        staged.write_text("data")
        assert not target.exists()
    assert target.read_text() == "data"
    assert folder_listing(tmp_path) == ["coast.gpkg"]


def test_failure_leaves_nothing(tmp_path, folder_listing):
    with pytest.raises(Boom), atomic_write(tmp_path / "coast.gpkg") as staged:
        staged.write_text("half")
        raise Boom
    assert folder_listing(tmp_path) == []


def test_interrupt_leaves_nothing(tmp_path, folder_listing):
    with pytest.raises(KeyboardInterrupt), atomic_write(tmp_path / "x.tif") as staged:
        staged.write_text("half")
        raise KeyboardInterrupt
    assert folder_listing(tmp_path) == []


def test_existing_output_is_refused_and_kept(tmp_path, folder_listing):
    target = tmp_path / "coast.gpkg"
    target.write_text("old")
    with pytest.raises(OutputExistsError, match="--overwrite") as info:
        with atomic_write(target):
            pytest.fail("the block must not run")
    assert str(target) in str(info.value)
    assert target.read_text() == "old"
    assert folder_listing(tmp_path) == ["coast.gpkg"]


def test_overwrite_replaces(tmp_path, folder_listing):
    target = tmp_path / "coast.gpkg"
    target.write_text("old")
    with atomic_write(target, overwrite=True) as staged:
        staged.write_text("new")
        assert target.read_text() == "old"  # untouched until the end
    assert target.read_text() == "new"
    assert folder_listing(tmp_path) == ["coast.gpkg"]


def test_failed_overwrite_keeps_the_old_file(tmp_path):
    target = tmp_path / "coast.gpkg"
    target.write_text("old")
    with pytest.raises(Boom), atomic_write(target, overwrite=True) as staged:
        staged.write_text("new")
        raise Boom
    assert target.read_text() == "old"


def test_folder_is_not_an_output_file(tmp_path):
    with pytest.raises(OutputExistsError, match="folder"):
        check_output(tmp_path, overwrite=True)


def test_missing_parent_folders_are_made_and_removed_on_failure(tmp_path):
    target = tmp_path / "a" / "b" / "coast.gpkg"
    with pytest.raises(Boom), atomic_write(target) as staged:
        staged.write_text("x")
        raise Boom
    assert not (tmp_path / "a").exists()
    with atomic_write(target) as staged:
        staged.write_text("x")
    assert target.read_text() == "x"


def test_writer_that_writes_nothing_is_an_error(tmp_path, folder_listing):
    with pytest.raises(FileNotFoundError, match="no file"):
        with atomic_write(tmp_path / "coast.gpkg"):
            pass
    assert folder_listing(tmp_path) == []


def test_side_files_are_published_with_the_main_file(tmp_path, folder_listing):
    with atomic_write(tmp_path / "coast.shp") as staged:
        for suffix in (".shp", ".shx", ".dbf", ".prj"):
            staged.with_suffix(suffix).write_text(suffix)
    assert folder_listing(tmp_path) == [
        "coast.dbf",
        "coast.prj",
        "coast.shp",
        "coast.shx",
    ]


def test_overwriting_a_shapefile_removes_stale_side_files(tmp_path, folder_listing):
    for suffix in (".shp", ".shx", ".dbf", ".cpg"):
        (tmp_path / f"coast{suffix}").write_text("old")
    with atomic_write(tmp_path / "coast.shp", overwrite=True) as staged:
        for suffix in (".shp", ".shx", ".dbf"):
            staged.with_suffix(suffix).write_text("new")
    assert folder_listing(tmp_path) == ["coast.dbf", "coast.shp", "coast.shx"]
    assert (tmp_path / "coast.dbf").read_text() == "new"


def test_several_outputs_are_all_or_nothing(tmp_path, folder_listing):
    with pytest.raises(Boom), AtomicOutputs() as outputs:
        outputs.stage(tmp_path / "data.gpkg").write_text("data")
        outputs.stage(tmp_path / "plot.png")
        raise Boom
    assert folder_listing(tmp_path) == []
    with AtomicOutputs() as outputs:
        outputs.stage(tmp_path / "data.gpkg").write_text("data")
        outputs.stage(tmp_path / "plot.png").write_text("png")
    assert folder_listing(tmp_path) == ["data.gpkg", "plot.png"]


def test_second_output_existing_is_refused_before_writing(tmp_path):
    (tmp_path / "plot.png").write_text("old")
    with pytest.raises(OutputExistsError), AtomicOutputs() as outputs:
        outputs.stage(tmp_path / "data.gpkg").write_text("data")
        outputs.stage(tmp_path / "plot.png")
    assert not (tmp_path / "data.gpkg").exists()
    assert (tmp_path / "plot.png").read_text() == "old"


def test_same_target_twice_is_refused(tmp_path):
    with pytest.raises(ConfigError, match="two outputs"), AtomicOutputs() as outputs:
        outputs.stage(tmp_path / "a.png")
        outputs.stage(tmp_path / "a.png")
    assert list(tmp_path.iterdir()) == []


def test_atomic_directory_publishes_at_the_end(tmp_path, folder_listing):
    target = tmp_path / "out"
    with atomic_directory(target) as partial:
        assert partial.parent == tmp_path
        assert partial.name.startswith("out.partial-")
        (partial / "a.txt").write_text("a")
        assert not target.exists()
    assert folder_listing(tmp_path) == ["out"]
    assert folder_listing(target) == ["a.txt"]


def test_atomic_directory_failure_leaves_nothing(tmp_path, folder_listing):
    with pytest.raises(Boom), atomic_directory(tmp_path / "out") as partial:
        (partial / "a.txt").write_text("a")
        raise Boom
    assert folder_listing(tmp_path) == []


def test_atomic_directory_refuses_a_full_folder(tmp_path):
    target = tmp_path / "out"
    target.mkdir()
    (target / "keep.txt").write_text("keep")
    with pytest.raises(OutputExistsError, match="--overwrite"):
        with atomic_directory(target):
            pytest.fail("the block must not run")
    assert (target / "keep.txt").read_text() == "keep"


def test_atomic_directory_accepts_an_empty_folder(tmp_path, folder_listing):
    target = tmp_path / "out"
    target.mkdir()
    with atomic_directory(target) as partial:
        (partial / "a.txt").write_text("a")
    assert folder_listing(target) == ["a.txt"]


def test_atomic_directory_overwrite_replaces_everything(tmp_path, folder_listing):
    target = tmp_path / "out"
    target.mkdir()
    (target / "old.txt").write_text("old")
    with atomic_directory(target, overwrite=True) as partial:
        (partial / "new.txt").write_text("new")
    assert folder_listing(tmp_path) == ["out"]
    assert folder_listing(target) == ["new.txt"]


def test_atomic_directory_refuses_a_file(tmp_path):
    target = tmp_path / "out"
    target.write_text("file")
    with pytest.raises(OutputExistsError, match="not a folder"):
        with atomic_directory(target, overwrite=True):
            pytest.fail("the block must not run")
