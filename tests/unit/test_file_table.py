"""A target's files: two paths that differ only in case are refused (one file on some file
systems), and the check holds for thousands of files without looking at each every time."""

from __future__ import annotations

import pytest

from earl_m2t.gen.errors import GenError
from earl_m2t.gen.rendered import FileTable, put_file


def test_a_path_differing_only_in_case_is_refused() -> None:
    files = FileTable()
    put_file(files, "user/Arm/cs/move_pf.hpp", b"a")
    with pytest.raises(GenError, match="two generated files map to the path user/arm/cs/Move_pf.hpp"):
        put_file(files, "user/arm/cs/Move_pf.hpp", b"b")
    assert files == {"user/Arm/cs/move_pf.hpp": b"a"}


def test_ten_thousand_distinct_paths_are_kept_in_order() -> None:
    files = FileTable()
    names = [f"user/a/cs/p{k}_pp.hpp" for k in range(10_000)]
    for name in names:
        put_file(files, name, name.encode())
    assert list(files) == names
