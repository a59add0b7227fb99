"""Tests and tools share code only through the package: no test imports or executes a
file of tools/ (a package of folders: tools/benchmarks/, tools/studies/, ...), no tool
imports a test (what they share lives in taisph/, e.g. taisph.validation.seed_scenes and
taisph.validation.accuracy_cost)."""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
TESTS = sorted((ROOT / "tests").glob("*.py"))
TOOLS = sorted(p for p in (ROOT / "tools").rglob("*.py") if p.name != "__init__.py")


def imported_modules(path):
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            yield node.module.split(".")[0]


def code_strings(path):
    """String constants of the code, docstrings left out."""
    tree = ast.parse(path.read_text())
    docstrings = {id(node.body[0].value) for node in ast.walk(tree)
                  if isinstance(node, (ast.Module, ast.FunctionDef, ast.ClassDef)) and node.body
                  and isinstance(node.body[0], ast.Expr) and isinstance(node.body[0].value, ast.Constant)}
    return [node.value for node in ast.walk(tree)
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docstrings]


def test_tools_are_found():
    """The glob above sees the tools in their folders."""
    assert len(TOOLS) > 10 and any(p.parent != ROOT / "tools" for p in TOOLS)


def test_no_test_imports_or_executes_a_tool():
    """No test imports the tools package or a module named like a tool, or names tools/
    in its code (a path to load, execute or run, or a module for ``python -m``); this
    file, which looks for them, excepted."""
    tool_names = {p.stem for p in TOOLS} | {"tools"}
    for path in TESTS:
        if path.name == Path(__file__).name:
            continue
        assert not tool_names & set(imported_modules(path)), path.name
        assert not [s for s in code_strings(path)
                    if s == "tools" or s.startswith(("tools/", "tools."))], path.name


def test_no_tool_imports_a_test():
    """No tool imports a test module or conftest, or names tests/ in its code (to put it
    on its path)."""
    test_names = {p.stem for p in TESTS}
    for path in TOOLS:
        assert not test_names & set(imported_modules(path)), path.name
        assert not [s for s in code_strings(path) if s == "tests" or s.startswith("tests/")], path.name
