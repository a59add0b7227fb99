"""The shape of the package: no import cycles, a library that never imports its command
line, functions and lines small enough to read, no lab notes in the code, an engine that
names no particular term or solver, one home for gravity's value (docs/architecture.md).

The import graph is built from every import statement of every module, those inside
functions included (a function-level import is a dependency all the same, only a later
one). ``import taisph`` or ``from taisph import x`` from inside the package depends on
``taisph/__init__.py`` and so on everything it imports.
"""

import ast
import re
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "taisph"
CASES = PACKAGE.parent / "cases"
MAX_FUNCTION_LINES = 80  # a function (a kernel closure included) a reader takes in at once
MAX_LINE = 120


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


def functions_over(limit: int, path: Path) -> list[str]:
    """``name:line (n lines)`` of every function of `path` longer than `limit` lines (a nested
    function counts on its own, and within the function around it)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return [f"{node.name}:{node.lineno} ({node.end_lineno - node.lineno + 1} lines)" for node in ast.walk(tree)
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.end_lineno - node.lineno + 1 > limit]


def test_the_function_measure_counts_nested_functions():
    """The check itself, on a made-up module: an outer function is as long as what it holds."""
    import tempfile

    body = "\n".join(f"        x{k} = {k}" for k in range(85))
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "m.py"
        path.write_text(f"def outer():\n    def inner():\n{body}\n    return inner\n", encoding="utf-8")
        assert functions_over(MAX_FUNCTION_LINES, path) == ["outer:1 (88 lines)", "inner:2 (86 lines)"]


def test_functions_and_lines_stay_readable():
    """No function over 80 lines and no line over 120 characters: a module splits where a
    second concern hides, never by squeezing statements together."""
    long_functions = {str(p.relative_to(PACKAGE.parent)): found for p in sorted(PACKAGE.rglob("*.py"))
                      if (found := functions_over(MAX_FUNCTION_LINES, p))}
    long_lines = [f"{p.relative_to(PACKAGE.parent)}:{k}" for p in sorted(PACKAGE.rglob("*.py"))
                  for k, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1) if len(line) > MAX_LINE]
    assert long_functions == {}, f"functions over {MAX_FUNCTION_LINES} lines: {long_functions}"
    assert long_lines == [], f"lines over {MAX_LINE} characters: {long_lines}"


DATED = re.compile(r"\b20[0-9]{2}-[01][0-9](-[0-3][0-9])?\b")


def test_no_dated_notes_in_the_code():
    """Measurements and their dates live in docs/ with their commands; the code keeps the
    equation, the reference and the invariant (a dated note goes stale unseen)."""
    found = [f"{p.relative_to(PACKAGE.parent)}:{k}" for p in sorted(PACKAGE.rglob("*.py"))
             for k, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1) if DATED.search(line)]
    assert found == [], f"dated notes in the code (move them to docs/): {found}"


def engine_modules():
    """The engine's modules, but a solver's own folder (engine/<solver>/)."""
    from taisph.scene.names import SOLVERS

    engine = PACKAGE / "engine"
    return [p for p in sorted(engine.rglob("*.py")) if p.relative_to(engine).parts[0] not in SOLVERS]


def test_the_engine_imports_and_names_no_particular_term():
    """Terms plug in through taisph.terms.base's protocol: the engine imports no term module
    and never writes a term's name (what a term needs of the engine, it declares)."""
    import taisph.terms as terms

    classes = [c for c in (getattr(terms, n) for n in terms.__all__) if isinstance(c, type) and getattr(c, "name", "")]
    # a name that is also a quantity or a parameter ("pressure", "gravity") is the quantity's
    quantities = {"pressure", "density"} | {k for c in classes for k in (*c.params, *c.scalars, *c.vectors)}
    names = sorted({c.name for c in classes} - quantities)
    quoted = re.compile("|".join(rf"[\"']{re.escape(name)}[\"']" for name in names))
    graph = import_graph()
    imports, mentions = {}, []
    for path in engine_modules():
        module = module_name(path)
        bad = sorted(m for m in graph[module] if m.startswith("taisph.terms") and m != "taisph.terms.base")
        if bad:
            imports[module] = bad
        text = path.read_text(encoding="utf-8")
        mentions += [f"{module}: {m.group(0)}" for m in quoted.finditer(text)]
        mentions += [f"{module}: {m.group(0)}" for m in re.finditer(r"open.boundar\w*|rigid.bod\w*", text, re.I)]
    assert imports == {}, f"the engine imports particular terms: {imports}"
    assert mentions == [], f"the engine names particular terms: {mentions}"


def test_dfsph_lives_in_its_folder():
    """A solver is a folder behind the registry's interface (engine/solvers.py): the rest of
    the engine mentions DFSPH only in the registry's import and entry (3 times; issue 49 asked for at most 6)."""
    count = sum(len(re.findall("dfsph", p.read_text(encoding="utf-8"), re.I)) for p in engine_modules())
    assert count <= 3, f"the engine outside engine/dfsph/ mentions DFSPH {count} times (the registry: 3)"


def test_gravity_has_one_home():
    """Gravity's standard value is written in taisph/terms/gravity.py (STANDARD_GRAVITY) and
    nowhere else in the package or the cases: they take it from there."""
    places = [f"{p.relative_to(PACKAGE.parent)}:{k}" for p in sorted([*PACKAGE.rglob("*.py"), *CASES.glob("*.py")])
              for k, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1) if "9.81" in line]
    assert len(places) <= 2 and all(p.startswith("taisph/terms/gravity.py") for p in places), places
