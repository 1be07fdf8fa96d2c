"""The test suite's root: the checkout is importable (``tests.support``), as pyproject's
``pythonpath`` says for pytest, also for test modules loaded by other means."""

from __future__ import annotations

import sys

from tests.support.paths import ROOT

if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))
