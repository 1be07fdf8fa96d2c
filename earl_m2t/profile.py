"""The EARL profile, loaded from ``profiles/earl.sysml`` (SysML v2 textual notation).

The profile file is the single definition of the EARL concepts. Every definition of package
``EARL::Model`` is one :class:`~earl_m2t.profile_types.Concept`:

- its name and short name (``part def <cs> ControlSubsystem``) give the concept name and the
  paper's abbreviation;
- ``:>`` gives its supertypes, ``abstract`` marks concepts that are never instantiated;
- ``@Stereotype { metaclass = "..."; }`` names the UML metaclass its stereotype extends;
- its usages are its :class:`~earl_m2t.profile_types.Feature` s, with the multiplicities of
  the general model; usages marked ``#Tag`` are stereotype attributes (tagged values);
- its ``doc`` is its meaning.

Enumerations (``enum def``) anywhere in package ``EARL`` are the value sets of tags.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

from earl_m2t import resources
from earl_m2t.cache import cached
from earl_m2t.profile_types import Profile

__all__ = ["load_profile"]


def load_profile(path: Path | None = None) -> Profile:
    """Load the EARL profile; by default the installed ``profiles/earl.sysml`` (cached).

    Raises ProfileError when the file cannot be read, does not parse, or is inconsistent.
    """
    if path is None:
        return _default_profile()
    return _load(Path(path))


@cache
def _default_profile() -> Profile:
    path = resources.profile_path()
    return cached("profile", path, lambda: _load(path))


def _load(path: Path) -> Profile:
    from earl_m2t.profile_reader import read_profile  # the grammar (textX) only on a cache miss

    return read_profile(path)
