"""What the CI output formats (SARIF, JUnit, GitHub annotations) share: paths, rules, exit code."""

from __future__ import annotations

import os
from pathlib import Path, PurePosixPath

from earl_m2t.check.registry import RuleInfo, catalogue
from earl_m2t.diagnostics import Diagnostic, Severity
from earl_m2t.render.check_report import CheckReport


def repo_path(file: str, base: Path | None = None) -> tuple[str, bool]:
    """``file`` as a ``/``-separated path relative to ``base`` (default: the current directory).

    A relative path is kept as given (normalised: ``./`` and ``\\`` removed); an absolute one
    is made relative when it is inside ``base``. Returns the path and whether it is relative.
    """
    path = Path(file)
    if not path.is_absolute():
        return _posix(file), True
    root = (base or Path.cwd()).resolve()
    for candidate in (path, path.resolve()):
        try:
            return candidate.relative_to(root).as_posix(), True
        except ValueError:
            continue
    return path.as_posix(), False


def _posix(file: str) -> str:
    text = file.replace(os.sep, "/") if os.sep != "/" else file
    parts = [part for part in PurePosixPath(text).parts if part != "."]
    return "/".join(parts) if parts else text


def exit_code(report: CheckReport) -> int:
    """The exit code of ``earl-m2t check`` for this report: 2 unreadable input, 1 errors, else 0."""
    if report.unreadable:
        return 2
    return 1 if any(d.severity is Severity.ERROR for d in report.diagnostics) else 0


def rule_codes(report: CheckReport) -> list[str]:
    """The rules of the run in catalogue order (all of them unless the report names the ones
    that ran), followed by codes found in the diagnostics that the catalogue does not know."""
    known = catalogue()
    ran = list(known) if report.rules is None else [code for code in known if code in set(report.rules)]
    extra = {d.code for d in report.diagnostics} | set(report.rules or ())
    return ran + sorted(extra - set(ran))


def rule_info(code: str) -> RuleInfo | None:
    return catalogue().get(code)


def rule_title(code: str) -> str:
    """``B005 predicate-unknown-reference`` (just the code for a rule the catalogue does not have)."""
    info = rule_info(code)
    return f"{code} {info.name}" if info else code


def ordered(diagnostics: list[Diagnostic]) -> list[Diagnostic]:
    return sorted(diagnostics, key=lambda d: d.sort_key())


def files_of(report: CheckReport) -> list[str]:
    """Every file the report is about: checked ones in the given order, then others that
    findings point into (other files of a model), then unreadable ones."""
    files = list(dict.fromkeys(report.checked))
    seen = set(files)
    for file in sorted({d.location.file for d in report.diagnostics} - seen):
        files.append(file)
        seen.add(file)
    for item in report.unreadable:
        file = str(item.get("file", ""))
        if file not in seen:
            files.append(file)
            seen.add(file)
    return files
