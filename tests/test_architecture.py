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
