"""What makes ``convert`` a round trip by construction: the SysML v2 text it wrote is read back
and lifted, and must be the same EARL model as its source (``diff`` finds no change), or convert
writes nothing and names the first element the text does not carry."""

from __future__ import annotations

import tempfile
from pathlib import Path

from earl_m2t.diagnostics import ModelReadError, SourceTextError
from earl_m2t.diff import Change, diff_models
from earl_m2t.model.elements import EarlModel


class NotARoundTrip(Exception):
    """The text does not read back as the model: the message says what, in one line."""


def check_round_trip(model: EarlModel, text: str) -> None:
    """Raises NotARoundTrip when ``text`` (``model`` as SysML v2) does not lift to ``model``."""
    from earl_m2t.api import load  # the whole read path, as a user's next command; imported when used

    with tempfile.TemporaryDirectory(prefix="earl-m2t-convert-") as folder:
        path = Path(folder) / "converted.sysml"
        path.write_text(text, encoding="utf-8")
        try:
            reread = load(path).model
        except (ModelReadError, SourceTextError) as error:
            first = str(error).splitlines()[0] if str(error) else type(error).__name__
            raise NotARoundTrip(f"the SysML v2 text it would write cannot be read back ({_without(first, folder)})") \
                from None
    changes = diff_models(model, reread)
    if changes:
        raise NotARoundTrip(f"SysML v2 text cannot say {_described(changes[0])}"
                            + (f" (and {len(changes) - 1} more change(s))" if len(changes) > 1 else ""))


def _described(change: Change) -> str:
    what = f"{change.kind} {change.old_path or change.path}"
    if change.change != "changed" or not change.fields:
        return f"{what} (it would be {change.change})"
    field = change.fields[0]
    return f"{what}: its {field.field} {field.old!r} would become {field.new!r}"


def _without(message: str, folder: str) -> str:
    return message.replace(str(Path(folder) / "converted.sysml"), "converted text")
