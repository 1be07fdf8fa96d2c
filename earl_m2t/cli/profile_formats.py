"""The names of the ``earl-m2t profile --format`` values, read from ``transforms/profile/target.toml``.

Kept apart from :mod:`earl_m2t.profile_export` so that the command line can list the formats
without importing Jinja and the profile reader."""

from __future__ import annotations

import tomllib

from earl_m2t import resources


def profile_formats() -> tuple[str, ...]:
    """Every format of ``earl-m2t profile``, in the order of ``transforms/profile/target.toml``."""
    path = resources.data_dir("transforms") / "profile" / "target.toml"
    return tuple(tomllib.loads(path.read_text(encoding="utf-8"))["formats"])
