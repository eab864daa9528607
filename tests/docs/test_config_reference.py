"""The config reference is generated from the schema, the documented defaults and the declared ranges, and lists
every key that `softarm config` prints, each with a meaning; each declared range is the one the checks enforce."""

import re
import typing
import tomllib

import pytest

from softarm.config import DEFAULT_CONFIG_TEXT, load_config
from softarm.config.keys import KEYS
from softarm.config.reference import config_reference, key_docs, schema_keys
from softarm.errors import ConfigError


def printed_keys(table: dict, prefix: str = "") -> set[str]:
    """Every key of the TOML `softarm config` prints, an array table's as `table[].key`."""
    keys = set()
    for name, value in table.items():
        key = f"{prefix}{name}"
        if isinstance(value, dict):
            keys |= printed_keys(value, f"{key}.")
        else:
            keys.add(key)
            if isinstance(value, list) and value and isinstance(value[0], dict):
                for item in value:
                    keys |= printed_keys(item, f"{key}[].")
    return keys


def listed_keys(page: str) -> set[str]:
    """The dotted keys the reference documents: its table headings (an array table's heading is its key) and their
    rows, named relative to them."""
    keys, table = set(), ""
    for line in page.splitlines():
        heading = re.match(r"^#{2,3} `(\[\[?)([\w.]+)\]\]?`", line)
        row = re.match(r"^\| `(\w+)` \|", line)
        if heading:
            array = heading.group(1) == "[["
            table = heading.group(2) + ("[]" if array else "")
            if array:
                keys.add(heading.group(2))
        elif row:
            keys.add(f"{table}.{row.group(1)}")
    return keys


def test_the_reference_lists_every_key_of_softarm_config():
    listed = listed_keys(config_reference())
    assert printed_keys(tomllib.loads(DEFAULT_CONFIG_TEXT)) <= listed
    assert listed == {key for key, _ in schema_keys()}  # and nothing the schema does not know


def test_every_key_has_a_meaning_and_a_declared_entry():
    assert {key for key, _ in schema_keys()} == set(KEYS)
    assert [doc.key for doc in key_docs() if len(doc.meaning) < 8] == []


def test_the_reference_shows_the_defaults():
    docs = {doc.key: doc for doc in key_docs()}
    assert docs["springs.stiffness"].default == "1000.0" and docs["springs.stiffness"].unit == "N/m"
    assert docs["muscles.groups[].name"].default == '"left_upper" / "right_upper" / "left_lower" / "right_lower"'


CANDIDATES = (-10**6, 10**6, 0, [], [-1.0, -1.0], [2.0, 1.0], "no such kind")


@pytest.mark.parametrize("key", [key for key, spec in KEYS.items() if spec.rule is not None and "[]" not in key])
def test_a_value_outside_the_declared_range_is_refused_naming_the_key(key):
    rule = KEYS[key].rule
    bad = next(v for v in CANDIDATES if type(v) is type(_default(key)) or (isinstance(v, int) and
               isinstance(_default(key), float)) if not _ok(rule, v))
    with pytest.raises(ConfigError, match=re.escape(key)):
        load_config(overrides={key: bad})


def _default(key: str):
    """The key's default; for an optional key the default leaves out, a value of its declared type."""
    value = load_config().to_dict()
    for part in key.split("."):
        if part not in value:
            hint = dict(schema_keys())[key]
            return next(t for t in typing.get_args(hint) if t is not type(None))()
        value = value[part]
    return value


def _ok(rule, value) -> bool:
    try:
        return bool(rule.ok(value))
    except (TypeError, IndexError):
        return False
