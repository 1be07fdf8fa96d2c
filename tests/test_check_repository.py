"""``earl-m2t check`` as a CI linter of a model repository, end to end through the command line.

The repository is laid out as a user would: a folder of models (derived from the reference
sample and a guide fixture), a configuration with select / ignore / severity / per-file
ignores, a file of the team's own rules, and models carrying suppression comments.
"""

from __future__ import annotations

import io
import json
import os
import pty
import re
import select
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest
from lxml import etree

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
GUIDE = ROOT / "tests" / "fixtures" / "guide"

XMI_ID = "{http://www.omg.org/spec/XMI/20131001}id"
XMI_TYPE = "{http://www.omg.org/spec/XMI/20131001}type"

CONFIG = """\
# earl-m2t configuration of the robot team's model repository
select = ["S", "C", "R", "team."]
ignore = ["S006"]                      # the guide's one-agent models are zombies on purpose
rules = ["rules/team.ocl"]

[severity]
input-buffer-unfed = "error"           # C007, a warning by default

[per-file-ignores]
"models/legacy/*.uml" = ["C008"]
"""

TEAM_RULES = """\
-- The team's own rules.

-- severity: warning
-- message: agent {path} has more than 4 virtual effectors
context Agent inv team.max-effectors: self.ve->size() <= 4

-- A naming policy: dataTypes are UpperCamelCase.
-- severity: info
context DataType inv team.datatype-names: self.name.matches('[A-Z][A-Za-z0-9]*')
"""


def earl(*args: str, cwd: Path, stderr: int | None = subprocess.PIPE) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run([sys.executable, "-m", "earl_m2t", "check", *args], cwd=cwd, stdout=subprocess.PIPE,
                          stderr=stderr, text=True, timeout=300, env=env)


# ---- the repository -----------------------------------------------------------------------


def _element(root: etree._Element, tag: str, name: str) -> etree._Element:
    (found,) = root.xpath(f"//{tag}[@name=$n]", n=name)
    return found


def _comment(element: etree._Element, text: str) -> None:
    """A Papyrus comment on ``element`` (``ownedComment`` with a ``body`` child)."""
    comment = etree.Element("ownedComment", {XMI_TYPE: "uml:Comment", XMI_ID: f"_note{id(element)}",
                                               "annotatedElement": element.get(XMI_ID) or ""})
    etree.SubElement(comment, "body").text = text
    element.insert(0, comment)


def _write(root: etree._Element, path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(etree.tostring(root, xml_declaration=True, encoding="UTF-8"))


def _sample() -> etree._Element:
    return etree.fromstring(SAMPLE.read_bytes())


@pytest.fixture()
def repo(tmp_path: Path) -> Path:
    repo = tmp_path / "robots"
    (repo / ".git").mkdir(parents=True)
    (repo / "earl-m2t.toml").write_text(CONFIG, encoding="utf-8")
    (repo / "rules").mkdir()
    (repo / "rules" / "team.ocl").write_text(TEAM_RULES, encoding="utf-8")

    # models/pick_and_place.uml: two renamed links, one suppressed with a reason, one without;
    # a suppression on a link that has nothing to suppress
    root = _sample()
    renamed = _element(root, "ownedConnector", "task/a,grip/a")
    renamed.set("name", "gripperCommand")
    _comment(renamed, "earl-m2t: ignore[C008] named after the gripper vendor's interface document")
    reasonless = _element(root, "ownedConnector", "manip/a,task/a")
    reasonless.set("name", "manipulatorStatus")
    _comment(reasonless, "earl-m2t: ignore[link-name-convention]")
    _comment(_element(root, "ownedConnector", "grip/a,task/a"), "earl-m2t: ignore[C008] kept from the old layout")
    _write(root, repo / "models" / "pick_and_place.uml")

    # models/legacy/old.uml: a renamed link (per-file ignore) and a six-joint arm (suppressed team rule)
    root = _sample()
    _element(root, "ownedConnector", "task/a,grip/a").set("name", "gripperCommand")
    _comment(_element(root, "ownedAttribute", "manip/a"),
             "earl-m2t: ignore[team.max-effectors] the legacy arm has six joints")
    _write(root, repo / "models" / "legacy" / "old.uml")

    # models/guide/datatypes.uml: C007 (severity raised to error) and S006 (ignored)
    (repo / "models" / "guide").mkdir()
    shutil.copy(GUIDE / "datatypes.uml", repo / "models" / "guide" / "datatypes.uml")

    # what a directory search passes over
    (repo / "models" / "notes.xml").write_text("<notes><note>not a model</note></notes>\n", encoding="utf-8")
    (repo / "models" / "pick_and_place.notation").write_text("<notation/>\n", encoding="utf-8")
    shutil.copy(SAMPLE, repo / "models" / "earl.profile.uml")
    (repo / "models" / ".backup").mkdir()
    shutil.copy(SAMPLE, repo / "models" / ".backup" / "copy.uml")
    return repo


def _findings(document: dict) -> set[tuple[str, str, str]]:
    return {(Path(d["file"]).as_posix(), d["code"], d["severity"]) for d in document["diagnostics"]}


# ---- the tests ----------------------------------------------------------------------------


def test_a_model_repository_is_linted_with_its_configuration_rules_and_suppressions(repo: Path) -> None:
    result = earl("models", "--format", "json", cwd=repo)
    assert result.returncode == 1, result.stderr  # C007 is an error by the configuration
    assert result.stderr == ""  # no progress on a pipe, nothing to complain about
    document = json.loads(result.stdout)
    assert document["files"] == ["models/guide/datatypes.uml", "models/legacy/old.uml", "models/pick_and_place.uml"]
    found = _findings(document)
    by_file = {(f, c) for f, c, _ in found}

    # severity: C007 raised to error; ignore: S006 gone
    assert ("models/guide/datatypes.uml", "C007", "error") in found
    assert not any(c == "S006" for _, c in by_file)
    # select: B/T/D rules do not run
    assert {c[0] for _, c in by_file} <= {"S", "C", "R", "t"}
    # suppression with a reason: C008 on gripperCommand silenced; without a reason: silenced and R006
    assert ("models/pick_and_place.uml", "C008") not in by_file
    (r006,) = [d for d in document["diagnostics"] if d["code"] == "R006"]
    assert "manipulatorStatus" in r006["message"] and r006["severity"] == "warning"
    # unused suppression on grip/a,task/a
    (r005,) = [d for d in document["diagnostics"] if d["code"] == "R005"]
    assert r005["file"] == "models/pick_and_place.uml" and "C008" in r005["message"]
    assert "grip/a,task/a" in r005["message"] and r005["xmi_id"].startswith("_note")
    # per-file ignore: the legacy model's renamed link is not reported
    assert ("models/legacy/old.uml", "C008") not in by_file
    # the team's rule: reported with its name as code, message and severity; suppressed in legacy
    (team,) = [d for d in document["diagnostics"] if d["code"] == "team.max-effectors"]
    assert team["file"] == "models/pick_and_place.uml" and team["severity"] == "warning"
    assert team["message"] == "agent manip/a has more than 4 virtual effectors" and team["element"] == "manip/a"
    assert not any(c == "team.datatype-names" for _, c in by_file)  # the sample's dataTypes comply


def test_without_the_configuration_every_rule_runs_and_the_team_rule_is_unknown(repo: Path) -> None:
    document = json.loads(earl("models", "--format", "json", "--no-config", cwd=repo).stdout)
    found = _findings(document)
    assert ("models/legacy/old.uml", "C008", "info") in found
    assert ("models/guide/datatypes.uml", "C007", "warning") in found
    assert ("models/guide/datatypes.uml", "S006", "warning") in found
    unknown = [d for d in document["diagnostics"] if d["code"] == "R005" and d["file"] == "models/legacy/old.uml"]
    assert unknown and "'team.max-effectors', which is no rule" in unknown[0]["message"]


def test_a_naming_policy_of_the_team_finds_a_lower_case_datatype(repo: Path) -> None:
    root = _sample()
    _element(root, "packagedElement", "ManipulatorCommand").set("name", "manipulatorCommand")
    _write(root, repo / "models" / "pick_and_place.uml")
    document = json.loads(earl("models/pick_and_place.uml", "--format", "json", cwd=repo).stdout)
    (naming,) = [d for d in document["diagnostics"] if d["code"] == "team.datatype-names"]
    assert naming["severity"] == "info" and naming["message"] == "datatype manipulatorCommand breaks rule " \
        "team.datatype-names"


def test_exit_codes(repo: Path) -> None:
    assert earl("models", cwd=repo).returncode == 1
    # the command line replaces the configuration's select and ignore
    relaxed = earl("models", "--ignore", "C007,S006", cwd=repo)
    assert relaxed.returncode == 0, relaxed.stdout
    assert "S006" not in relaxed.stdout and "team.max-effectors" in relaxed.stdout
    only_team = earl("models", "--select", "team.", cwd=repo)
    assert only_team.returncode == 0
    codes = {line.split()[1] for line in only_team.stdout.splitlines()[:-1]}
    assert codes == {"team.max-effectors"}
    (repo / "models" / "broken.uml").write_text("<xmi:XMI", encoding="utf-8")
    assert earl("models", cwd=repo).returncode == 2


def test_jobs_give_the_same_output_and_no_progress_on_a_pipe(repo: Path) -> None:
    shutil.copy(GUIDE / "fsm.uml", repo / "models" / "guide" / "fsm.uml")
    shutil.copy(GUIDE / "stages.uml", repo / "models" / "guide" / "stages.uml")
    for output in ("text", "json"):
        one = earl("models", "--jobs", "1", "--format", output, cwd=repo)
        two = earl("models", "--jobs", "2", "--format", output, cwd=repo)
        assert one.stdout == two.stdout and one.returncode == two.returncode == 1
        assert one.stderr == two.stderr == ""
    lines = one.stdout  # json: the files sorted, the diagnostics sorted by file then line
    document = json.loads(lines)
    keys = [(d["file"], d["line"]) for d in document["diagnostics"]]
    assert keys == sorted(keys) and document["files"] == sorted(document["files"])


def test_progress_is_shown_on_a_terminal_and_cleared(repo: Path) -> None:
    primary, secondary = pty.openpty()
    try:
        result = earl("models", "--jobs", "2", cwd=repo, stderr=secondary)
        os.close(secondary)
        secondary = -1
        seen = b""
        while select.select([primary], [], [], 1)[0]:
            try:
                chunk = os.read(primary, 4096)
            except OSError:
                break
            if not chunk:
                break
            seen += chunk
    finally:
        os.close(primary)
        if secondary >= 0:
            os.close(secondary)
    assert result.returncode == 1
    text = seen.decode()
    assert re.search(r"checking [123]/3 models/", text)
    assert text.endswith("\r")  # the line is cleared at the end
    assert "checking" not in result.stdout


# ---- configuration ------------------------------------------------------------------------


def test_the_configuration_is_found_from_a_subfolder_and_globs_are_relative_to_it(repo: Path) -> None:
    result = earl(".", "--format", "json", cwd=repo / "models" / "legacy")
    document = json.loads(result.stdout)
    assert document["files"] == ["old.uml"]
    codes = {d["code"] for d in document["diagnostics"]}
    assert "C008" not in codes and "team.max-effectors" not in codes


def test_pyproject_table_is_read_and_earl_m2t_toml_wins(repo: Path) -> None:
    config = (repo / "earl-m2t.toml").read_text(encoding="utf-8")
    (repo / "earl-m2t.toml").unlink()
    pyproject = ("[project]\nname = 'robots'\n\n[tool.earl-m2t]\n"
                 + config.replace("[severity]", "[tool.earl-m2t.severity]"))
    pyproject = pyproject.replace("[per-file-ignores]", "[tool.earl-m2t.per-file-ignores]")
    (repo / "pyproject.toml").write_text(pyproject, encoding="utf-8")
    document = json.loads(earl("models", "--format", "json", cwd=repo).stdout)
    assert ("models/guide/datatypes.uml", "C007", "error") in _findings(document)
    (repo / "earl-m2t.toml").write_text('select = ["C007"]\n', encoding="utf-8")
    document = json.loads(earl("models", "--format", "json", cwd=repo).stdout)
    assert {d["code"] for d in document["diagnostics"]} == {"C007"}
    assert ("models/guide/datatypes.uml", "C007", "warning") in _findings(document)


def test_discovery_stops_at_the_repository_root(repo: Path) -> None:
    (repo / "earl-m2t.toml").unlink()
    (repo.parent / "earl-m2t.toml").write_text("selekt = []\n", encoding="utf-8")
    result = earl("models", cwd=repo)
    assert result.returncode == 0 and result.stderr == ""
    assert "S006" in result.stdout  # no configuration: every rule
    outside = earl(str(repo / "models"), cwd=repo.parent)
    assert outside.returncode == 2 and "selekt" in outside.stderr


def test_config_option_overrides_discovery(repo: Path) -> None:
    (repo / "strict.toml").write_text('select = ["C007"]\n[severity]\nC007 = "info"\n', encoding="utf-8")
    result = earl("models", "--config", "strict.toml", cwd=repo)
    assert result.returncode == 0
    assert result.stdout.splitlines()[-1] == "3 files checked: 0 error(s), 0 warning(s), 1 info"


def test_the_permitted_link_table_can_be_replaced(repo: Path) -> None:
    (repo / "links.toml").write_text(
        'select = ["C002"]\n[permitted-links]\ninter_subsystem = [["ve", "cs"], ["ve", "re"], ["re", "ve"]]\n',
        encoding="utf-8")
    result = earl("models/pick_and_place.uml", "--config", "links.toml", cwd=repo)
    assert result.returncode == 1
    assert "C002 error" in result.stdout and "cs → ve inside an agent" in result.stdout
    assert earl("models/pick_and_place.uml", "--select", "C002", cwd=repo).returncode == 0
    # the same table kept in a file of its own
    (repo / "tables").mkdir()
    (repo / "tables" / "links.toml").write_text('inter_subsystem = [["ve", "cs"]]\n', encoding="utf-8")
    (repo / "links.toml").write_text('select = ["C002"]\npermitted-links = "tables/links.toml"\n', encoding="utf-8")
    assert "cs → ve inside an agent" in earl("models/pick_and_place.uml", "--config", "links.toml", cwd=repo).stdout
    (repo / "tables" / "links.toml").write_text('inter_subsystem = [["ve", "cs", "re"]]\n', encoding="utf-8")
    broken = earl("models/pick_and_place.uml", "--config", "links.toml", cwd=repo)
    assert broken.returncode == 2 and broken.stderr.startswith("tables/links.toml: error: ")


@pytest.mark.parametrize(("text", "expected"), [
    ("selekt = []\n", "unknown key 'selekt'"),
    ('[severity]\nC008 = "fatal"\n', "'severity.C008' must be error, warning or info"),
    ('select = ["X999"]\n', "'select': unknown rule code or name 'X999'"),
    ('[per-file-ignores]\n"a/*.uml" = ["team.nope"]\n', "'per-file-ignores': unknown rule code or name 'team.nope'"),
    ('[permitted-links]\ninter_agent = [["cs", "xx"]]\n', "'permitted-links': 'inter_agent'"),
    ('[permitted-links]\nintra = []\n', "unknown key 'intra'"),
    ("select = [\n", "not valid TOML"),
    ("select = " + "[" * 100_000 + "]" * 100_000 + "\n", "nested too deeply"),
    ("x = " + "{a = " * 100_000 + "1" + "}" * 100_000 + "\n", "nested too deeply"),
])
def test_configuration_errors_are_one_line_naming_file_and_key_with_exit_2(repo: Path, text: str,
                                                                         expected: str) -> None:
    (repo / "earl-m2t.toml").write_text(text, encoding="utf-8")
    result = earl("models", cwd=repo)
    assert result.returncode == 2 and result.stdout == ""
    assert result.stderr.count("\n") == 1, result.stderr
    assert result.stderr.startswith("earl-m2t.toml: error: ") and expected in result.stderr


def test_pyproject_unknown_key_names_the_table(repo: Path) -> None:
    (repo / "earl-m2t.toml").unlink()
    (repo / "pyproject.toml").write_text("[tool.earl-m2t]\nexclude = []\n", encoding="utf-8")
    result = earl("models", cwd=repo)
    assert result.returncode == 2 and "unknown key 'tool.earl-m2t.exclude'" in result.stderr
    assert "pyproject.toml" in result.stderr


@pytest.mark.parametrize(("text", "where", "expected"), [
    ("context Agent inv team.x: self.ve->size() <=\n", "rules/team.ocl:2:1:", ""),
    ("-- ok\ncontext Robott inv team.x: true\n", "rules/team.ocl:2:1:", "unknown context 'Robott'"),
    ("-- severity: fatal\ncontext Agent inv team.x: true\n", "rules/team.ocl:1:1:", "severity must be"),
    ("context Agent inv S003: true\n", "rules/team.ocl:1:1:", "is a built-in rule"),
    ("context Agent inv team.x: " + "(" * 50_000 + "true" + ")" * 50_000, "rules/team.ocl:1:227:",
     "nested more than 200 levels deep"),
    ("context Agent inv team.x: " + "let a = 1 in " * 5_000 + "true", "rules/team.ocl:1:1:", "nested too deeply"),
])
def test_rule_file_errors_are_one_line_with_file_line_column_and_exit_2(repo: Path, text: str, where: str,
                                                                      expected: str) -> None:
    (repo / "rules" / "team.ocl").write_text(text, encoding="utf-8")
    result = earl("models", cwd=repo)
    assert result.returncode == 2 and result.stdout == ""
    assert result.stderr.count("\n") == 1 and result.stderr.startswith(where), result.stderr
    assert expected in result.stderr


def test_an_empty_folder_is_reported_and_nothing_checked(tmp_path: Path) -> None:
    (tmp_path / ".git").mkdir()
    (tmp_path / "empty").mkdir()
    result = earl("empty", cwd=tmp_path)
    assert result.returncode == 0
    assert result.stderr == "empty: warning: no model files found\n"


def test_a_folder_is_searched_for_sysml_text_too(tmp_path: Path) -> None:
    (tmp_path / ".git").mkdir()
    (tmp_path / "models").mkdir()
    shutil.copy(ROOT / "samples" / "pick_and_place" / "pick_and_place.sysml", tmp_path / "models" / "arm.sysml")
    (tmp_path / "models" / "notes.txt").write_text("not a model\n", encoding="utf-8")
    result = earl("models", "--format", "json", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["files"] == ["models/arm.sysml"]


def test_the_pre_commit_hook_matches_model_files_only() -> None:
    text = (ROOT / ".pre-commit-hooks.yaml").read_text(encoding="utf-8")
    assert "id: earl-m2t-check" in text and "entry: earl-m2t check" in text
    assert "language: python" in text and "pass_filenames: true" in text
    (files,) = re.findall(r"^\s*files: '(.*)'$", text, re.MULTILINE)
    pattern = re.compile(files)
    for name in ("models/arm.uml", "a/b.xmi", "Robot.mdzip", "models/Arm.UML", "models/arm.sysml"):
        assert pattern.search(name), name
    for name in ("models/arm.notation", "models/arm.di", "profiles/earl.profile.uml", "README.md", "pom.xml"):
        assert not pattern.search(name), name


def test_the_documented_configuration_and_rules_are_valid(tmp_path: Path) -> None:
    from earl_m2t.check.user_rules import parse_user_rules
    from earl_m2t.config import load_config

    page = (ROOT / "docs" / "check.md").read_text(encoding="utf-8")
    (example,) = [block for block in re.findall(r"```toml\n(.*?)```", page, re.DOTALL) if "per-file-ignores" in block]
    (tmp_path / "earl-m2t.toml").write_text(example, encoding="utf-8")
    config = load_config(tmp_path / "earl-m2t.toml")
    assert config.ignore == ("S006",) and config.permitted_links is not None
    assert ("vr", "ve") in config.permitted_links["inter_subsystem"]
    guide = (ROOT / "docs" / "rule-language.md").read_text(encoding="utf-8").partition("## A repository's own rules")[2]
    blocks = [b for b in re.findall(r"```\n(.*?)```", guide, re.DOTALL) if "context " in b]
    names = {info.code for block in blocks for info, _ in parse_user_rules(block, "doc.ocl")}
    assert names == {"team.max-effectors", "team.datatype-names", "team.buffer-names"}


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_progress_of_a_single_model_appears_only_after_a_moment(monkeypatch: pytest.MonkeyPatch) -> None:
    from earl_m2t.cli import progress

    quick = _Terminal()
    shown = progress.Progress(1, quick)
    shown.show(1, "models/arm.uml")
    shown.clear()
    assert quick.getvalue() == ""  # done before the delay: nothing shown
    monkeypatch.setattr(progress, "DELAY", 0.0)
    slow = _Terminal()
    shown = progress.Progress(1, slow)
    shown.show(1, "models/arm.uml")
    time.sleep(0.2)
    shown.clear()
    assert slow.getvalue().startswith("\rchecking 1/1 models/arm.uml") and slow.getvalue().endswith("\r")
    piped = io.StringIO()
    shown = progress.Progress(3, piped)
    shown.show(1, "models/arm.uml")
    shown.clear()
    assert piped.getvalue() == ""
