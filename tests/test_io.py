"""Files: atomic writes leave nothing half-written and give outputs the usual permissions."""

from __future__ import annotations

import os
import stat

import pytest

from cloth.io import atomic_output, sha256


def test_an_atomic_output_follows_the_umask_and_a_failure_leaves_nothing(tmp_path):
    old = os.umask(0o022)
    try:
        with atomic_output(tmp_path / "out.txt") as tmp:
            tmp.write_text("done")
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "out.txt").stat().st_mode) == 0o644  # not mkstemp's 0600
    with pytest.raises(RuntimeError), atomic_output(tmp_path / "half.txt") as tmp:
        tmp.write_text("half")
        raise RuntimeError
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.txt"]
    # sha256 of b"done"
    assert sha256(tmp_path / "out.txt") == (
        "a4c3ed04a95a3da14a9d235c83d868bed7c0f45cf7f3faa751ee8f50598d2211"
    )
