"""The house stays tidy: no import cycle between any two modules of softarm or its command line, nor between any
two of softarm's packages (its rooms: arm, sim, record, model, ...), so no import points back up the data path;
read from the source itself."""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = {"softarm": ROOT / "softarm", "softarm_cli": ROOT / "cli"}


def modules() -> dict[str, Path]:
    """Every module of both packages by its dotted name (a package by its __init__)."""
    out = {}
    for package, folder in PACKAGES.items():
        for path in folder.rglob("*.py"):
            parts = [package, *path.relative_to(folder).with_suffix("").parts]
            out[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return out


def imported(path: Path, known: dict[str, Path]) -> set[str]:
    """The modules of both packages that a file imports anywhere in it when it runs (a function's own imports
    included; an `if TYPE_CHECKING:` block's, which only type checkers read, not): `from a.b import c` imports a.b,
    and a.b.c too where that is a module."""
    names = set()
    tree = ast.parse(path.read_text())
    for guarded in [n for n in ast.walk(tree)
                    if isinstance(n, ast.If) and getattr(n.test, "id", "") == "TYPE_CHECKING"]:
        guarded.body = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module)
            names.update(f"{node.module}.{alias.name}" for alias in node.names)
    return {name for name in names if name in known}


def cycle(graph: dict[str, set[str]]) -> list[str]:
    """One cycle of the graph as a list of modules, first repeated at the end; [] when there is none."""
    state: dict[str, int] = {}  # 1: on the current path, 2: done
    path: list[str] = []

    def visit(node: str) -> list[str]:
        state[node] = 1
        path.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                return path[path.index(nxt):] + [nxt]
            if nxt not in state and (found := visit(nxt)):
                return found
        state[node] = 2
        path.pop()
        return []

    for node in sorted(graph):
        if node not in state and (found := visit(node)):
            return found
    return []


def test_no_module_imports_itself_through_others():
    known = modules()
    graph = {name: imported(path, known) - {name} for name, path in known.items()}
    assert cycle(graph) == []


def test_the_cycle_finder_finds_a_cycle():
    assert cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}) == ["a", "b", "c", "a"]
    assert cycle({"a": {"b"}, "b": set()}) == []



def room(module: str) -> str:
    """The package a module lives in: softarm.model.tcn.rows -> softarm.model; a top-level module is its own."""
    return ".".join(module.split(".")[:2])


def test_no_package_imports_itself_through_others():
    """Packages form layers: with modules merged into their package, the imports still have no cycle (the root
    package, whose __init__ re-exports the public API lazily, imports none of them at all)."""
    known = modules()
    graph: dict[str, set[str]] = {}
    for name, path in known.items():
        graph.setdefault(room(name), set()).update(room(m) for m in imported(path, known) if room(m) != room(name))
    assert graph["softarm"] == set()
    assert cycle(graph) == []
