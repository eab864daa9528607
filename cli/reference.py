"""The command-line reference as Markdown, generated from the Typer app itself (every command, its usage, its
arguments and options with their help and defaults), so that the documentation says what `--help` says."""

from typing import Any

import typer


def cli_reference(app: typer.Typer) -> str:
    """One section per command of `app`, in the order `softarm --help` lists them."""
    group: Any = typer.main.get_command(app)  # Typer's own click: typed loosely, read by its public methods
    root = group.context_class(group, info_name="softarm")
    lines = ["# Command line", "",
             "Generated from the command line itself: each section says what `softarm COMMAND --help` says. "
             "Options override the config file (`--config`), which overrides the defaults (`softarm config`). "
             "Every error a user can cause prints one line and exits 1; an interrupted command exits 130 "
             "([Errors and interruptions](behaviour.md)).", ""]
    for name in group.list_commands(root):
        command = group.get_command(root, name)
        lines += command_section(name, command, command.context_class(command, info_name=name, parent=root))
    return "\n".join(lines) + "\n"


def command_section(name: str, command: Any, context: Any) -> list[str]:
    """A command's heading, its help (its example as a code block), its usage and a table of its parameters."""
    summary, example = split_example(command.help or "")
    lines = [f"## softarm {name}", "", summary, ""]
    if example:
        lines += ["```bash", example, "```", ""]
    lines += ["```text", command.get_usage(context), "```", "", "| argument or option | help |", "|---|---|"]
    for param in command.get_params(context):
        if getattr(param, "hidden", False):
            continue
        record = param.get_help_record(context)
        if record is None:  # an argument: Typer keeps its help on the parameter
            record = (param.human_readable_name, getattr(param, "help", "") or "")
        names, text = record
        lines.append(f"| `{names}` | {text.replace('|', chr(92) + '|')} |")
    return lines + [""]


def split_example(help_text: str) -> tuple[str, str]:
    """(the help's prose, its `Example:` command), the click paragraph marker dropped."""
    prose, example = [], []
    for line in help_text.replace("\b", "").splitlines():
        stripped = line.strip()
        if stripped.startswith("Example:"):
            example.append(stripped.removeprefix("Example:").strip())
        elif example and stripped:
            example.append(stripped)
        else:
            prose.append(stripped)
    return " ".join(p for p in prose if p).strip(), "\n".join(example)
