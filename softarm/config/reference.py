"""The config reference as Markdown, generated from its three sources so that it cannot drift from them: the
schema (which keys exist, their types), `default.toml` (each default and, in its comments, each meaning) and
`keys.KEYS` (each unit and range, the same rules `check_ranges` enforces). The documentation site renders it.
"""

import dataclasses
import re
import tomllib
import typing
from dataclasses import dataclass
from typing import Any, Union

from softarm.config.keys import KEYS
from softarm.config.load import DEFAULT_CONFIG_TEXT
from softarm.config.schema import Config

ASSIGNMENT = re.compile(r"^(#\s)?\s*([A-Za-z_][A-Za-z0-9_]*)\s*=\s*(.*)$")
HEADER = re.compile(r"^\[\[?([A-Za-z0-9_.]+)\]\]?\s*(#.*)?$")


@dataclass(frozen=True)
class KeyDoc:
    """One key as the reference shows it."""
    key: str        # dotted; array tables as `table[].key`
    type: str
    default: str
    unit: str
    range: str
    meaning: str


def schema_keys(cls: type = Config, prefix: str = "") -> list[tuple[str, Any]]:
    """Every key the schema knows, in its order, with its type hint; an array table's keys as `table[].key`."""
    out: list[tuple[str, Any]] = []
    for field in dataclasses.fields(cls):
        hint = typing.get_type_hints(cls)[field.name]
        key = f"{prefix}{field.name}"
        if dataclasses.is_dataclass(hint):
            out += schema_keys(hint, f"{key}.")
            continue
        item = _array_table(hint)
        out.append((key, hint))
        if item is not None:
            out += schema_keys(item, f"{key}[].")
    return out


def comments(text: str = DEFAULT_CONFIG_TEXT) -> tuple[dict[str, str], dict[str, str]]:
    """(meaning of each key, introduction of each table) read from the TOML file's comments: a key's meaning is
    the comment block right above it plus its own trailing comment; a table's introduction is the comment block
    after its header that a blank line parts from the first key. Commented-out assignments of a table's own
    optional keys (`# driven = [0, 1, 2]`) count as keys."""
    fields = {key for key, _ in schema_keys()}
    meanings: dict[str, str] = {}
    intros: dict[str, str] = {}
    table, block, after_header = "", [], False
    for line in text.splitlines() + [""]:
        stripped = line.strip()
        header = HEADER.match(stripped)
        assignment = ASSIGNMENT.match(stripped)
        key = f"{table}{assignment.group(2)}" if assignment else ""
        if header:
            name = header.group(1)
            table = f"{name}[]." if stripped.startswith("[[") else f"{name}."
            block, after_header = [], True
        elif assignment and key in fields and key not in meanings:
            value = assignment.group(3)
            trailing = value.split("#", 1)[1].strip() if "#" in value and not assignment.group(1) else ""
            meanings[key] = " ".join([*block, trailing]).strip()
            block, after_header = [], False
        elif assignment and key in fields:
            block = []
        elif stripped.startswith("#"):
            block.append(stripped.lstrip("#").strip())
        elif not stripped:
            if after_header and block:
                intros[table.rstrip(".")] = " ".join(block)
            block, after_header = [], False
    return meanings, intros


def key_docs() -> list[KeyDoc]:
    """Every key of the schema, documented (an array table's own short meaning before the long example its
    comment in `default.toml` gives)."""
    defaults = tomllib.loads(DEFAULT_CONFIG_TEXT)
    meanings, _ = comments()
    docs = []
    for key, hint in schema_keys():
        spec = KEYS[key]
        docs.append(KeyDoc(key, _type_name(hint), _default(defaults, key), spec.unit,
                           spec.rule.text.removeprefix("must be ").removeprefix("must ") if spec.rule else "",
                           spec.meaning or meanings.get(key, "")))
    return docs


def config_reference() -> str:
    """The reference page: a heading per config table (`[body]`, `[[muscles.groups]]`) with its introduction, then a
    row per key of it, named as the table spells it."""
    _, intros = comments()
    lines = ["# Config reference", "",
             "Every key of `softarm config`, generated from the schema, the documented defaults and the declared "
             "ranges (`softarm/config/keys.py`). Units are SI. Give only the keys you change in a TOML file "
             "(`--config FILE`) or as a dotted override (`load_config(overrides={\"body.rows\": 21})`); a value out "
             "of range is refused in one line that names the key.", ""]
    table = None
    for doc in key_docs():
        if doc.type == "array of tables":  # a heading of its own, its keys below it
            table = f"{doc.key}[]"
            lines += ["", f"{_heading(doc.key)} `[[{doc.key}]]`", "", _escape(doc.meaning), "", *_TABLE_HEAD]
            continue
        owner, _, name = doc.key.rpartition(".")
        if owner != table:
            table = owner
            lines += ["", f"{_heading(owner)} `[{owner}]`", ""]
            if intros.get(owner):
                lines += [_escape(intros[owner]), ""]
            lines += _TABLE_HEAD
        lines.append(f"| `{name}` | {doc.type} | {_escape(doc.default)} | {doc.unit} | {_escape(doc.range)} | "
                     f"{_escape(doc.meaning)} |")
    return "\n".join(lines) + "\n"


_TABLE_HEAD = ["| key | type | default | unit | range | meaning |", "|---|---|---|---|---|---|"]


def _heading(table: str) -> str:
    """`##` for a top-level table, `###` for one inside another (`[excitation.sum_of_sines]`)."""
    return "###" if "." in table.replace("[]", "") else "##"


def _array_table(hint: Any) -> Union[type, None]:
    args = typing.get_args(hint)
    if (typing.get_origin(hint) is tuple and len(args) == 2 and args[1] is Ellipsis
            and dataclasses.is_dataclass(args[0])):
        return args[0]
    return None


def _type_name(hint: Any) -> str:
    origin, args = typing.get_origin(hint), typing.get_args(hint)
    if origin is Union:
        return _type_name(next(a for a in args if a is not type(None))) + " (optional)"
    if _array_table(hint) is not None:
        return "array of tables"
    if origin is tuple:
        if len(args) == 2 and args[1] is Ellipsis:
            return f"list of {_type_name(args[0])}"
        return f"[{', '.join(_type_name(a) for a in args)}]"
    return {bool: "bool", int: "int", float: "float", str: "string"}.get(hint, str(hint))


def _default(defaults: dict[str, Any], key: str) -> str:
    """The default as TOML spells it; an array table's as its tables' values in turn; '' where unset."""
    values: list[Any] = [defaults]
    for part in key.split("."):
        name = part.removesuffix("[]")
        values = [v[name] for v in values if isinstance(v, dict) and name in v]
        if part.endswith("[]"):
            values = [item for v in values for item in v]
    return " / ".join(_toml(v) for v in values)


def _toml(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {_toml(v)}" for k, v in value.items()) + "}"
    return repr(value)


def _escape(text: str) -> str:
    return text.replace("|", "\\|")
