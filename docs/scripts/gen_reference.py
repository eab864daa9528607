"""Writes the generated reference pages while `mkdocs build` runs (mkdocs-gen-files): the Python API from the
docstrings of `softarm.__all__` and the environments' classes, the command line from the Typer app, the config
from its schema, defaults and declared ranges. Nothing here is committed as Markdown, so nothing can go stale."""

import mkdocs_gen_files

import softarm
from softarm.config.reference import config_reference
from softarm_cli.main import app
from softarm_cli.reference import cli_reference

ENVIRONMENT_API = ["softarm.envs.single.SoftArmEnv", "softarm.envs.vector.SoftArmVectorEnv",
                   "softarm.envs.imagined.ImaginedBody", "softarm.envs.record.RecordEpisodes",
                   "softarm.envs.sb3.StableBaselinesVecEnv"]


def api_reference() -> str:
    """`softarm`'s public API, one entry per name of `softarm.__all__`, then the environments' classes."""
    lines = ["# Python API", "",
             "Everything the command line does is a function of the `softarm` package. `import softarm` is cheap: "
             "Taichi, torch and Rerun load when a function first needs them. The names below are `softarm.__all__`; "
             "each is documented from its own docstring.", "", "## softarm", ""]
    for name in softarm.__all__:
        lines += [f"::: {softarm._API[name]}.{name}", ""]
    lines += ["## softarm.envs", "",
              "`import softarm.envs` registers `softarm/Reach-v0`, `softarm/Track-v0` and `softarm/Hold-v0` with "
              "Gymnasium ([Environments](environments.md) has their cards).", ""]
    lines += [f"::: {path}" + "\n" for path in ENVIRONMENT_API]
    return "\n".join(lines) + "\n"


for page, text in {"reference/api.md": api_reference(), "reference/cli.md": cli_reference(app),
                   "reference/config.md": config_reference()}.items():
    with mkdocs_gen_files.open(page, "w") as file:
        file.write(text)
