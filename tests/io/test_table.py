"""Text tables: the fixed-width writer and the line reader of fort.14 and MIKE files."""

from __future__ import annotations

import io

import numpy as np
import pytest

from coastmesh.errors import InputDataError
from coastmesh.io.meshes._table import TextLines, put_lines, write_table


def test_write_table_formats_columns():
    out = io.BytesIO()
    write_table(
        out,
        [
            (np.array([1, 12, -3]), None),
            (np.array([-0.4e-15, 123.456, -7.0]), 6),
        ],
    )
    # right-aligned, a column for the sign, no "-0.000"
    assert out.getvalue().decode().splitlines() == [
        "  1    0.000",
        " 12  123.456",
        " -3   -7.000",
    ]
    rng = np.random.default_rng(5)
    values = rng.normal(0, 1e4, 2000)
    out = io.BytesIO()
    write_table(out, [(values, 15)])
    text = out.getvalue().decode().splitlines()
    decimals = 15 - len(str(int(np.abs(values).max())))
    assert {len(line) for line in text} == {len(text[0])}  # one column width
    assert all(len(line.split(".")[1]) == decimals for line in text)
    back = np.array(text, dtype=float)
    # rounded to the decimals, within one unit in the last place
    assert np.abs(back - values).max() <= 10.0**-decimals


def test_write_table_checks_its_columns():
    with pytest.raises(ValueError, match="different lengths"):
        write_table(io.BytesIO(), [(np.arange(2), None), (np.arange(3), None)])
    with pytest.raises(ValueError, match="non-finite"):
        write_table(io.BytesIO(), [(np.array([1.0, np.nan]), 3)])
    with pytest.raises(ValueError, match="< 1e18"):
        write_table(io.BytesIO(), [(np.array([1e19]), 3)])


def test_put_lines_ends_every_line():
    out = io.BytesIO()
    put_lines(out, "a", "b c")
    assert out.getvalue() == b"a\nb c\n"


def test_text_lines_name_the_line_and_what_it_holds(tmp_path):
    path = tmp_path / "grid.txt"
    path.write_text("title\n2 x\n1 2.5 3\n4 5.0 6\n7 oops 9\n")
    lines = TextLines.read(path)
    assert lines.next_line() == "title"
    with pytest.raises(InputDataError, match=r"line 2 \(NE NP\): expected 2 integers"):
        lines.ints(2, "NE NP")
    np.testing.assert_array_equal(
        lines.table(2, 3, float, "A B C"), [[1, 2.5, 3], [4, 5, 6]]
    )
    with pytest.raises(InputDataError, match=r"grid.txt: line 5 \(A B C\): a value"):
        lines.table(1, 3, float, "A B C")
    assert lines.remaining() == 0
    with pytest.raises(InputDataError, match="ends at line 5"):
        lines.next_line()


def test_text_lines_count_and_rest():
    lines = TextLines("f", ["12 0 = Number of nodes", "x"])
    assert lines.count_and_rest("N") == (12, "0 = Number of nodes")
    with pytest.raises(InputDataError, match="expected an integer count"):
        lines.count_and_rest("N")
