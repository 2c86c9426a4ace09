"""The wheel must carry every package, the grammar and the standard library."""
from __future__ import annotations

import tomllib

from conftest import ROOT


def test_every_package_in_the_source_tree_is_listed_in_pyproject():
    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    on_disk = {".".join(p.parent.relative_to(ROOT).parts) for p in (ROOT / "rcl").rglob("__init__.py")}
    assert on_disk - listed == set(), "add these packages to [tool.setuptools] packages"
    assert {"rcl.grammar", "rcl.stdlib", "rcl.docs"} <= listed


def test_the_installed_package_finds_its_grammar_and_stdlib():
    from rcl.resources import grammar_path, stdlib_dir

    assert grammar_path().is_file()
    assert (stdlib_dir() / "frames.rcl").is_file()
    from rcl.resources import docs_dir

    assert (docs_dir() / "language.md").is_file()  # the REPL's :help quotes it
    from rcl.robots import builtin_models

    assert builtin_models() == ["al5d", "puma560", "smartarms"]


def test_the_built_in_cell_description_is_package_data():
    listed = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["package-data"]
    assert "*.toml" in listed["rcl.cell"]
    from rcl.cell.config import DEFAULT

    assert DEFAULT.is_file() and DEFAULT.parent.name == "cell"
