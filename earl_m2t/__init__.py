"""earl-m2t: read EARL robot-controller models from SysML tools, check them, generate code.

Stages: read (XMI → raw index) → lift (typed EARL model) → check (rules) → generate.

The public names are imported on first use (PEP 562), so that ``import earl_m2t`` and the
command line's ``--help`` do not load the rules, the grammars and the solver.
"""

from __future__ import annotations

import importlib
import sys
import types
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from earl_m2t.api import Loaded, check, load
    from earl_m2t.check.engine import CheckOptions
    from earl_m2t.diagnostics import Diagnostic, ModelReadError, Severity

from earl_m2t.version import __version__

__all__ = ["CheckOptions", "Diagnostic", "Loaded", "ModelReadError", "Severity", "__version__", "check", "load"]

_HOME = {
    "CheckOptions": "earl_m2t.check.engine",
    "Diagnostic": "earl_m2t.diagnostics",
    "Loaded": "earl_m2t.api",
    "ModelReadError": "earl_m2t.diagnostics",
    "Severity": "earl_m2t.diagnostics",
    "check": "earl_m2t.api",
    "load": "earl_m2t.api",
}


def __getattr__(name: str) -> Any:
    home = _HOME.get(name)
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(home), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


class _Package(types.ModuleType):
    """This package, where a subpackage does not hide a public name of the same spelling.

    Importing ``earl_m2t.check.engine`` makes Python set the attribute ``check`` of this package
    to the subpackage; ``from earl_m2t import check`` must still give the function.
    """

    def __setattr__(self, name: str, value: object) -> None:
        if name in _HOME and isinstance(value, types.ModuleType):
            return
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package
