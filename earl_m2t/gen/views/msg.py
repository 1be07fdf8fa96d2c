"""The view of the ROS message target: one message per dataType a buffer, memory or link uses.

Model names become ROS names deterministically: message names ``[A-Z][A-Za-z0-9]*``
(``motor state`` → ``MotorState``), field names ``[a-z][a-z0-9_]*`` without ``__`` or a
trailing ``_`` (``jointPosSetpoint`` → ``joint_pos_setpoint``), constants
``[A-Z][A-Z0-9_]*`` (``holdPosition`` → ``HOLD_POSITION``) and the package
``[a-z][a-z0-9_]*`` (``PickAndPlace`` → ``pick_and_place_msgs``). A name that is not an
identifier or maps to a reserved word (D003), and two names that map to the same ROS name
(D004), are refused unless ``strict`` is false; then they are mangled (suffixes, ``2``,
``_2`` …) in sorted dataType order, so the output is the same on every run.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

from earl_m2t.gen.errors import GenError
from earl_m2t.model.datatypes import DataType, Field
from earl_m2t.model.elements import EarlModel
from earl_m2t.model.location import Location
from earl_m2t.model.naming import _table, field_name, identifier_problem, message_name

Data = dict[str, Any]

MESSAGE_NAME = re.compile(r"^[A-Z][A-Za-z0-9]*$")
FIELD_NAME = re.compile(r"^[a-z](?:[a-z0-9]|_(?!_))*(?<!_)$")
CONSTANT_NAME = re.compile(r"^[A-Z](?:[A-Z0-9]|_(?!_))*(?<!_)$")
PACKAGE_NAME = FIELD_NAME

# exclusive upper bound of the values each ROS integer type holds (enumeration literals)
_INTEGER_VALUES = {"uint8": 2**8, "uint16": 2**16, "uint32": 2**32, "uint64": 2**64,
                   "int8": 2**7, "int16": 2**15, "int32": 2**31, "int64": 2**63}


@dataclass(frozen=True)
class MsgTarget:
    """The data of ``transforms/msg/target.toml`` the view needs."""

    types: dict[str, str]  # primitive kind -> ROS type
    primitive_names: dict[str, str]  # primitive dataType name -> ROS type
    enumeration: str  # ROS integer type of enumeration values
    package_suffix: str
    reserved_messages: frozenset[str]
    reserved_fields: frozenset[str]

    @classmethod
    def from_spec(cls, spec: dict[str, Any]) -> MsgTarget:
        names = spec.get("names", {})
        table = _table()
        enumeration = str(spec.get("enumerations", {}).get("type", "uint8"))
        if enumeration not in _INTEGER_VALUES:
            raise GenError(f"target.toml: [enumerations] type {enumeration!r} is not a ROS integer type")
        return cls(types=dict(spec["types"]), primitive_names=dict(spec.get("primitive_names", {})),
                   enumeration=enumeration, package_suffix=str(spec.get("package_suffix", "_msgs")),
                   reserved_messages=frozenset(names.get("reserved_messages", ())),
                   reserved_fields=frozenset(names.get("reserved_fields", ()))
                   | frozenset(table["ros_reserved"]) | frozenset(table["cpp_keywords"]))


@dataclass(frozen=True)
class NameProblem:
    """A name the messages cannot use as it is: ``rule`` D003 (not a ROS name) or D004 (two
    names map to one ROS name); ``text`` as gen prints it after the rule, ``path`` and
    ``location`` of the element whose name it is. Rules D003 and D004 of ``check`` report these
    too (:func:`name_problems`), so that a model check passes is one gen accepts."""

    rule: str
    text: str
    path: str
    location: Location

    def __str__(self) -> str:
        return f"{self.rule} {self.text}"


@dataclass
class MsgView:
    package: str
    model: str  # the model's name, for the header comments
    messages: list[Data]  # sorted by name; each: name, what, constants, fields


# ---------------------------------------------------------------------- names


def constant_name(name: str) -> str:
    """``holdPosition`` → ``HOLD_POSITION``; a leading digit gets ``N``."""
    return field_name(name).upper()


def package_name(model_name: str, suffix: str) -> str:
    """``PickAndPlace`` → ``pick_and_place_msgs``."""
    return field_name(model_name) + suffix


def _comment(text: str) -> str:
    """One line of ASCII, safe after ``#`` (non-ASCII characters as ``\\u`` escapes)."""
    return " ".join(text.split()).encode("ascii", "backslashreplace").decode("ascii")


class _Names:
    """Hands out distinct ROS names in one scope and records what had to be changed."""

    def __init__(self, problems: list[NameProblem], fold_case: bool, joiner: str) -> None:
        self._taken: dict[str, str] = {}  # key -> the model name that has it
        self._last_number: dict[str, int] = {}
        self._problems = problems
        self._fold = fold_case
        self._joiner = joiner

    def take(self, name: str, ros: str, where: str, what: str, reserved: frozenset[str], suffix: str,
             path: str, location: Location) -> str:
        problem = identifier_problem(name) if name.strip() else "the name is empty"
        if ros in reserved:
            problem = problem or f"'{ros}' is reserved in ROS messages or their generated code"
            ros += suffix
        base, n = ros, 1
        if self._key(ros) in self._taken:  # numbering resumes where this base's last ended: linear
            n = self._last_number.get(self._key(base), 1)
            while self._key(ros) in self._taken:
                n += 1
                ros = f"{base}{self._joiner}{n}"
            self._last_number[self._key(base)] = n
        if problem:
            self._problems.append(NameProblem("D003", f"{where}: '{name}' cannot become a ROS {what}: {problem} "
                                                      f"(--force: '{ros}')", path, location))
        if n > 1:
            self._problems.append(NameProblem("D004", f"{where}: '{name}' and '{self._taken[self._key(base)]}' "
                                                      f"both map to the ROS {what} '{base}' (--force: '{ros}')",
                                              path, location))
        self._taken[self._key(ros)] = name
        return ros

    def _key(self, text: str) -> str:
        return text.lower() if self._fold else text


# ---------------------------------------------------------------------- view


def build_view(model: EarlModel, target: MsgTarget, strict: bool = True) -> MsgView:
    """The messages of a model; raises GenError when it cannot be generated (or, with
    ``strict``, when a name cannot become a ROS name or two names collide)."""
    if model.system is None:
        raise GenError("the model has no EARL System to generate")
    problems: list[NameProblem] = []
    name, package, result = _mapped(model, target, problems)
    if problems and strict:
        raise GenError(f"{len(problems)} name(s) cannot become ROS names (--force maps them anyway): "
                       + "; ".join(map(str, problems)))
    for message in result:
        if not MESSAGE_NAME.match(message["name"]):  # the mapping guarantees it; a last guard
            raise GenError(f"internal: '{message['name']}' is not a ROS message name")
    return MsgView(package=package, model=_comment(name),
                   messages=sorted(result, key=lambda m: m["name"]))


def name_problems(model: EarlModel, target: MsgTarget) -> list[NameProblem]:
    """What :func:`build_view` refuses in the names of a model. A model it cannot generate for
    another reason (no System, an unresolved or recursive dataType: other rules report them)
    gives the problems found before that."""
    if model.system is None:
        return []
    problems: list[NameProblem] = []
    try:
        _mapped(model, target, problems)
    except GenError:
        pass
    return problems


def refused_names(model: EarlModel) -> list[NameProblem]:
    """:func:`name_problems` under the settings of ``transforms/msg/target.toml``, as ``gen
    --target msg`` reads them; [] when the installation lacks the target (gen says so). What
    rules D003 and D004 of ``check`` ask, so that the two cannot disagree."""
    from earl_m2t.gen.engine import load_target

    try:
        settings = MsgTarget.from_spec(load_target("msg"))
    except GenError:
        return []
    return name_problems(model, settings)


def model_name(model: EarlModel) -> str:
    """The name the package is named after: the model's, else its System's."""
    system = model.system
    return model.name or (system.name if system is not None else "") or "model"


def _mapped(model: EarlModel, target: MsgTarget, problems: list[NameProblem]) -> tuple[str, str, list[Data]]:
    """The model's name, the package name and the messages, each name mapped to a ROS name;
    what had to be changed is added to ``problems``."""
    system = model.system
    name = model_name(model)
    package = package_name(name, target.package_suffix)
    if identifier_problem(name):
        problems.append(NameProblem("D003", f"model '{name}': cannot become a ROS package name: "
                                            f"{identifier_problem(name)} (--force: '{package}')", "model",
                                    system.location if system is not None else Location(model.file, 0, 0)))
    keys = _reachable(model)
    messages = _Names(problems, fold_case=True, joiner="")  # file names: compared without case
    names = {key: messages.take(model.datatypes[key].name, message_name(model.datatypes[key].name),
                                f"dataType {key}", "message name", target.reserved_messages, "Msg",
                                key, model.datatypes[key].location)
             for key in keys}
    return name, package, [_message(model, key, names, target, problems) for key in keys]


def _reachable(model: EarlModel) -> list[str]:
    """Keys of the non-primitive dataTypes buffers, memory and links use, nested ones included;
    sorted. Raises GenError for an unresolved type or a recursive dataType."""
    roots: list[tuple[str, str]] = []
    for sub in model.subsystems:
        roots += [(b.datatype, b.path) for b in sub.buffers]
        roots += [(m.datatype, m.path) for m in sub.memory]
    for link in model.links:
        for end in (link.source, link.target):
            buf = model.buffer(end) if end else None
            if buf is not None:
                roots.append((buf.datatype, link.path))
    found: set[str] = set()
    visiting: list[str] = []

    def visit(key: str, where: str) -> None:
        datatype = model.datatypes.get(key) if key else None
        if datatype is None:
            raise GenError(f"{where}: no dataType (rules S009, D001)")
        if datatype.kind == "primitive" or key in found:
            return
        if key in visiting:
            cycle = " → ".join(visiting[visiting.index(key):] + [key])
            raise GenError(f"dataType {key} contains itself ({cycle}); ROS messages cannot be recursive (rule D002)")
        visiting.append(key)
        for f in datatype.fields:
            visit(f.type, f"field {key}.{f.name}")
        visiting.pop()
        found.add(key)

    for key, where in roots:
        visit(key, where)
    return sorted(found)


def _message(model: EarlModel, key: str, names: dict[str, str], target: MsgTarget,
             problems: list[NameProblem]) -> Data:
    datatype = model.datatypes[key]
    name = names[key]
    if datatype.kind == "enumeration":
        if len(datatype.literals) > _INTEGER_VALUES[target.enumeration]:
            raise GenError(f"enumeration {key} has {len(datatype.literals)} literals; "
                           f"{target.enumeration} holds fewer")
        scope = _Names(problems, fold_case=False, joiner="_")
        constants = [{"type": target.enumeration,
                      "name": scope.take(lit, constant_name(lit), f"literal {key}.{lit}", "constant name",
                                         frozenset(), "_VALUE", f"{key}.{lit}", datatype.location),
                      "value": index, "comment": _comment(lit), "trace": key}
                     for index, lit in enumerate(datatype.literals)]
        fields: list[Data] = [{"type": target.enumeration, "name": "value",
                   "comment": f"one of the constants above; a field typed by {name} is a plain "
                              f"{target.enumeration} holding one of them"}]
        return {"name": name, "key": key, "what": _comment(f"enumeration {key}"), "trace": key,
                "constants": constants, "fields": fields}
    scope = _Names(problems, fold_case=False, joiner="_")
    fields = []
    for f in datatype.fields:
        ros = scope.take(f.name, field_name(f.name), f"field {key}.{f.name}", "field name",
                         target.reserved_fields, "_field", f"{key}.{f.name}", f.location)
        fields.append({"type": _field_type(model, f, names, target, f"field {key}.{f.name}"),
                       "name": ros, "comment": _field_comment(model, f, names), "trace": f"{key}.{f.name}",
                       # a variable array's bound (None: unbounded), for ROS 2's bounded sequences
                       "bound": f.upper if f.is_array and not f.is_fixed_array else None})
    return {"name": name, "key": key, "what": _comment(f"dataType {key}"), "constants": [], "fields": fields,
            "trace": key}


def ros_type(model: EarlModel, key: str, names: dict[str, str], target: MsgTarget, where: str) -> str:
    """The ROS type of one value of dataType ``key`` (no array suffix)."""
    datatype: DataType | None = model.datatypes.get(key)
    if datatype is None:
        raise GenError(f"{where}: no dataType (rule D001)")
    if datatype.kind == "primitive":
        mapped = target.primitive_names.get(datatype.name) or target.types.get(datatype.primitive)
        if mapped is None:
            raise GenError(f"{where}: primitive '{datatype.name}' has no ROS type in target.toml")
        return mapped
    if datatype.kind == "enumeration":
        return target.enumeration
    return names[key]  # same package: the plain name


def _field_type(model: EarlModel, f: Field, names: dict[str, str], target: MsgTarget, where: str) -> str:
    base = ros_type(model, f.type, names, target, where)
    if f.is_fixed_array:
        return f"{base}[{f.upper}]"
    if f.is_array:  # [*], [0..n], [m..n] and the optional [0..1]: a variable array
        return f"{base}[]"
    return base


def _field_comment(model: EarlModel, f: Field, names: dict[str, str]) -> str:
    datatype = model.datatypes[f.type]
    text = f"{f.name}: {datatype.name}"
    if f.is_fixed_array:
        text += f"[{f.upper}]"
    elif f.is_array:
        text += f"[{f.lower}..{'*' if f.upper is None else f.upper}]"
        if f.lower == 0 and f.upper == 1:
            text += ", optional: empty or one element"
        elif f.upper is not None:
            text += f", {f.lower} to {f.upper} elements" if f.lower else f", at most {f.upper} elements"
    if datatype.kind == "enumeration":
        text += f", one of the constants of {names[f.type]}"
    return _comment(text)
