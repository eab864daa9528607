"""Every command the README and the documentation show works as written: each `softarm ...` line parses with the
command line as it is (its command, options, option values and arguments), each `python -m bench.X`,
`python docs/scripts/X.py` and `python examples/X.py` names a file that exists, and the short ones run as written.

The long ones (a corpus, a general model's training, the suite and its evaluation, studies, the demo: minutes to
hours on defaults) are parsed here and run at small sizes by the tests of their own packages (tests/corpus,
tests/learn, tests/suite, tests/study, tests/imagine, tests/real)."""

import importlib.util
import re
import shlex
from pathlib import Path

import pytest
import typer
from softarm_cli.main import app

from tests.helpers.cli import softarm

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", ROOT / "CONTRIBUTING.md",
         *sorted(p for p in (ROOT / "docs").rglob("*.md") if "scripts" not in p.parts)]


def code_lines(text: str) -> list[str]:
    """The lines of fenced code blocks (```bash, ```text, ``` …, indented under tabs too) and of four-space
    indented blocks, backslash continuations joined."""
    lines, fenced, out = text.splitlines(), False, []
    for line in lines:
        stripped = line.strip()
        if stripped.startswith("```"):
            fenced = not fenced
            continue
        if fenced or (line.startswith("    ") and not stripped.startswith(("-", "*", "|"))):
            out.append(stripped)
    joined: list[str] = []
    for line in out:
        if joined and joined[-1].endswith("\\"):
            joined[-1] = joined[-1][:-1].rstrip() + " " + line
        else:
            joined.append(line)
    return joined


def commands(prefix: str) -> list[tuple[str, str]]:
    """(page, command) for every command starting with `prefix` in the pages' code, split at `&&`, comments
    dropped."""
    found = []
    for page in PAGES:
        for line in code_lines(page.read_text()):
            for part in line.split("&&"):
                part = part.split(" #")[0].strip()
                if part.startswith(prefix):
                    found.append((str(page.relative_to(ROOT)), part))
    return sorted(set(found))


SOFTARM_COMMANDS = commands("softarm ")
PYTHON_COMMANDS = commands("python ")


def test_the_pages_show_commands():
    assert len(SOFTARM_COMMANDS) >= 30 and len(PYTHON_COMMANDS) >= 10, (SOFTARM_COMMANDS, PYTHON_COMMANDS)


@pytest.mark.parametrize("page,command", SOFTARM_COMMANDS, ids=[f"{p}: {c[:60]}" for p, c in SOFTARM_COMMANDS])
def test_every_documented_softarm_command_parses(page, command):
    words = shlex.split(re.sub(r"\$\([^)]*\)", "RECORDINGS", command))[1:]  # a shell's $(ls ...) stands for paths
    if words in (["--version"], ["--help"]):
        return
    group = typer.main.get_command(app)
    context = group.context_class(group, info_name="softarm")  # the group has no options of its own to parse
    name, rest = words[0], words[1:]
    sub = group.get_command(context, name)
    assert sub is not None, f"{page}: no command {name!r}"
    sub.make_context(name, rest, parent=context)  # raises on an unknown option, a bad value or a missing argument


@pytest.mark.parametrize("page,command", PYTHON_COMMANDS, ids=[f"{p}: {c[:60]}" for p, c in PYTHON_COMMANDS])
def test_every_documented_python_command_names_a_file_that_exists(page, command):
    words = shlex.split(command)
    if words[1] == "-m":
        module = words[2]
        path = ROOT / (module.replace(".", "/") + ".py")
        assert path.exists() or importlib.util.find_spec(module) is not None, f"{page}: {command}: no module {module}"
    elif words[1] == "-c":
        return
    else:
        assert (ROOT / words[1]).exists(), f"{page}: {command}: no file {words[1]}"


RUN_AS_WRITTEN = [
    "softarm --version",
    "softarm sim --duration 1 --out recordings/check.mcap",
    "softarm sim --config world.toml --duration 20 --out recordings/world.mcap",
    "softarm sim --config pokes.toml --duration 10 --arms 8 --out recordings/pokes.mcap",
]


def config_files() -> dict[str, str]:
    """The TOML files the pages show, by the name their first line gives them (`# world.toml: ...`)."""
    files = {}
    for page in PAGES:
        for block in re.findall(r"```toml\n(.*?)```", page.read_text(), re.S):
            name = re.match(r"# (\S+\.toml):", block)
            if name:
                files[name.group(1)] = block
    return files


@pytest.mark.slow
def test_the_short_commands_run_as_written(tmp_path):
    documented = {command for _, command in SOFTARM_COMMANDS}
    for name, text in config_files().items():
        (tmp_path / name).write_text(text)
    for command in RUN_AS_WRITTEN:
        assert command in documented, f"{command!r} is no longer in the pages: update RUN_AS_WRITTEN"
        result = softarm(*shlex.split(command)[1:], cwd=tmp_path)
        assert result.returncode == 0, f"{command}: {result.stderr}"
    assert len(list((tmp_path / "recordings").glob("*.mcap"))) == 1 + 1 + 8
