"""The shape of the package: no import cycles, a library that never imports its command
line, modules small enough to read (docs/architecture.md).

The import graph is built from every import statement of every module, those inside
functions included (a function-level import is a dependency all the same, only a later
one). ``import taisph`` or ``from taisph import x`` from inside the package depends on
``taisph/__init__.py`` and so on everything it imports.
"""

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "taisph"
MAX_LINES = 400


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imported(path: Path):
    """Every module name an import statement of `path` names: the module itself and,
    for ``from M import x``, ``M.x`` too (x may be a submodule)."""
    name = module_name(path)
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = package[: len(package) - node.level + 1] if node.level else []
            module = ".".join(base + ([node.module] if node.module else []))
            yield module
            yield from (f"{module}.{alias.name}" for alias in node.names)


def import_graph() -> dict[str, set[str]]:
    modules = {module_name(p): p for p in PACKAGE.rglob("*.py")}
    return {name: {m for m in imported(path) if m in modules and m != name} for name, path in modules.items()}


def cycles(graph) -> list[list[str]]:
    """One cycle per strongly connected component of more than one module (Tarjan)."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_the_cycle_finder_finds_a_cycle():
    """The check itself: a three-module loop and a self-contained chain."""
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": {"c"}, "c": set()}) == []


def test_the_graph_sees_function_level_and_package_imports():
    """taisph/__init__ imports taisph.sweeps only inside a function; it must still count."""
    graph = import_graph()
    assert "taisph.sweeps" in graph["taisph"]
    assert "taisph.engine.runtime" in graph["taisph.run.simulation"]


def test_no_import_cycles():
    found = cycles(import_graph())
    assert found == [], "import cycles (modules that import each other, directly or not): " + "; ".join(
        " <-> ".join(c) for c in found)


def test_nothing_outside_the_command_line_imports_it():
    """The command line is the library's user, never its dependency."""
    graph = import_graph()
    offenders = {name: sorted(m for m in deps if m == "taisph.cli" or m.startswith("taisph.cli."))
                 for name, deps in graph.items()
                 if not (name == "taisph.cli" or name.startswith("taisph.cli.") or name == "taisph.__main__")}
    assert {k: v for k, v in offenders.items() if v} == {}


def test_modules_stay_readable():
    long = {str(p.relative_to(PACKAGE.parent)): n for p in PACKAGE.rglob("*.py")
            if (n := len(p.read_text(encoding="utf-8").splitlines())) > MAX_LINES}
    assert long == {}, f"modules over {MAX_LINES} lines: split where a second concern hides inside"
