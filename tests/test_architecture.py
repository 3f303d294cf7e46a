"""The architecture, checked: no import cycles in the core; the import contracts of
pyproject.toml ([tool.importlinter]) are run by the test command itself (``lint-imports``)."""
from __future__ import annotations

import grimp


def test_no_import_cycles_in_the_core():
    """No module of the core reaches itself through its imports (function-level ones too)."""
    graph = grimp.build_graph("pipeplug")
    cycles = [(a, b) for a in sorted(graph.modules)
              for b in sorted(graph.find_modules_directly_imported_by(a))
              if graph.chain_exists(importer=b, imported=a)]
    assert cycles == []


def test_a_cycle_would_be_found():
    """The check itself: a graph with a cycle is reported."""
    graph = grimp.ImportGraph()
    graph.add_import(importer="p.a", imported="p.b")
    graph.add_import(importer="p.b", imported="p.a")
    assert graph.chain_exists(importer="p.b", imported="p.a")


def test_every_test_cited_by_the_corrections_exists():
    """docs/corrections.md says which test keeps each correction checked: those tests exist."""
    import re
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    cited = set(re.findall(r"\btest_\w+", (root / "docs" / "corrections.md").read_text()))
    cited -= {name for name in cited if name.endswith("_")}       # file-name fragments
    defined = set()
    for path in (root / "tests").rglob("test_*.py"):
        defined |= set(re.findall(r"^def (test_\w+)", path.read_text(), re.M))
        defined.add(path.stem)
    assert cited and cited <= defined, sorted(cited - defined)
