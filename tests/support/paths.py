"""Where the checkout, the shared reference material and the sample are."""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SHARED = ROOT.parent / "shared"
SAMPLE_DIR = ROOT / "samples" / "pick_and_place"
SAMPLE = SAMPLE_DIR / "pick_and_place.uml"
