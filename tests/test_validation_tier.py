"""The validation tier's list (tests/validation_tier.py) names real CI tests, and the docs'
table lists each (docs/validation.md, "The validation tier")."""

import ast
import pathlib

from validation_tier import TIER

ROOT = pathlib.Path(__file__).resolve().parent.parent


def test_every_tier_entry_is_a_ci_test():
    """Each entry's file defines the test, and the test is not marked slow (the tier is
    what CI runs)."""
    for nodeid in TIER:
        path, name = nodeid.split("::")
        tree = ast.parse((ROOT / path).read_text())
        found = [f for f in tree.body if isinstance(f, ast.FunctionDef) and f.name == name]
        assert found, f"{nodeid}: no such test"
        marks = [ast.unparse(d) for d in found[0].decorator_list]
        assert "pytest.mark.slow" not in marks, f"{nodeid} is marked slow"


def test_the_docs_table_lists_the_tier():
    """docs/validation.md's tier table names every test of the tier."""
    docs = (ROOT / "docs" / "validation.md").read_text()
    section = docs.split("## The validation tier", 1)[-1].split("\n## ", 1)[0]
    missing = [nodeid for nodeid in TIER if nodeid.split("::")[1] not in section]
    assert not missing, missing
