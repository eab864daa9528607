"""The papers a reusable project carries are there and say what they must: a licence the package metadata names,
a citation file valid against the Citation File Format 1.2.0 schema, a changelog whose newest release is the
package's version, contributing notes, and the PEP 561 marker that lets type checkers read softarm's types."""

import json
import re
import tomllib
from pathlib import Path

import jsonschema
import yaml

import softarm

ROOT = Path(__file__).resolve().parents[2]
CFF_SCHEMA = ROOT / "tests" / "helpers" / "cff-1.2.0.schema.json"  # the schema the CFF project publishes, as is


def test_the_licence_is_apache_2_and_the_package_says_so():
    assert "Apache License" in (ROOT / "LICENSE").read_text() and "Version 2.0, January 2004" in (ROOT / "LICENSE").read_text()
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert project["license"] == "Apache-2.0" and project["license-files"] == ["LICENSE"]
    assert project["urls"]


def test_the_citation_file_is_valid_cff_1_2_and_cites_the_paper():
    citation = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    citation["date-released"] = str(citation["date-released"])  # YAML reads a date; CFF holds the string
    schema = json.loads(CFF_SCHEMA.read_text())
    jsonschema.validators.validator_for(schema)(schema, format_checker=jsonschema.FormatChecker()).validate(citation)
    assert citation["version"] == softarm.__version__
    assert any("Bodily aware soft robots" in ref["title"] for ref in citation["references"])


def test_the_changelog_names_the_package_version_as_its_newest_release():
    releases = re.findall(r"^## \[(\d+\.\d+\.\d+)\] - (\d{4}-\d{2}-\d{2})$", (ROOT / "CHANGELOG.md").read_text(), re.M)
    assert releases[0][0] == softarm.__version__
    assert [version for version, _ in releases][-1] == "0.1.0"


def test_contributing_notes_and_the_type_marker_are_there():
    assert "## Where new things go" in (ROOT / "CONTRIBUTING.md").read_text()
    assert (ROOT / "softarm" / "py.typed").exists()
    assert "py.typed" in tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["package-data"]["softarm"]


def test_editors_see_every_public_name_with_its_signature():
    """`import softarm` loads its functions lazily (PEP 562); the `TYPE_CHECKING` imports give type checkers and
    editors each public name from the module it lazily comes from."""
    import ast

    tree = ast.parse((ROOT / "softarm" / "__init__.py").read_text())
    guarded = next(node for node in tree.body if isinstance(node, ast.If) and getattr(node.test, "id", "") == "TYPE_CHECKING")
    seen = {alias.name: node.module for node in guarded.body for alias in node.names}
    assert seen == softarm._API
