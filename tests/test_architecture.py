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


# The harness: one shared layer ---------------------------------------------------------------------
import ast  # noqa: E402
from pathlib import Path  # noqa: E402

import pytest  # noqa: E402

HARNESS = Path(__file__).resolve().parents[1] / "harness" / "pipeplug_harness"

#: what only one part of the harness may do: imported module (or called method) -> the modules
#: allowed to (paths under harness/pipeplug_harness)
ONLY = {
    "tomllib": {"spec/toml.py"}, "tomli": {"spec/toml.py"},
    "csv": {"io/files.py"}, "pyarrow.parquet": {"io/files.py"},
    "matplotlib.pyplot": {"io/files.py"}, ".savefig": {"io/files.py"},
    "fmpy": {"session.py"}, "fmpy.fmi2": {"session.py"},
    "pipeplug_fmu.blows": {"spec/blows.py", "spec/tables.py", "cosim.py", "system/checks.py"},
}
#: keys of the blow train (its rule set is the Hammer's, read in spec/) and the rigid parameters
#: (the core's table, named in paper.py): a literal naming several of them is a second copy
BLOW_KEYS = {"amplitude", "duration", "period", "count", "start"}
RIGID_NAMES = {"L1", "L2", "R1", "h1", "rho1", "rho2", "tau1", "tau2"}
NAMED_ONCE = {"spec/tables.py", "spec/blows.py", "paper.py"}


def _uses(tree: ast.AST) -> set:
    """Modules a module imports (function-level imports too) and methods it calls (``.name``)."""
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.add(node.module)
            found |= {f"{node.module}.{alias.name}" for alias in node.names}
        elif isinstance(node, ast.Attribute) and node.attr == "savefig":
            found.add(".savefig")
    return found


def _literals(tree: ast.AST):
    """The sets of strings of every tuple, list and set literal (lists of names)."""
    for node in ast.walk(tree):
        if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
            yield {e.value for e in node.elts if isinstance(e, ast.Constant)
                   and isinstance(e.value, str)}


def violations(root: Path) -> list[str]:
    """Every place under ``root`` that breaks :data:`ONLY` or names the blow keys or the rigid
    parameters a second time."""
    found = []
    for path in sorted(root.rglob("*.py")):
        name = path.relative_to(root).as_posix()
        tree = ast.parse(path.read_text())
        for used in sorted(_uses(tree)):
            if used in ONLY and name not in ONLY[used]:
                found.append(f"{name}: {used}")
        if name not in NAMED_ONCE:
            for names in _literals(tree):
                if len(names & BLOW_KEYS) >= 3:
                    found.append(f"{name}: the blow keys {sorted(names & BLOW_KEYS)}")
                if len(names & RIGID_NAMES) >= 4:
                    found.append(f"{name}: the rigid parameters {sorted(names & RIGID_NAMES)}")
    return found


def test_the_harness_has_one_place_for_each_concern():
    """Only spec reads TOML, only io writes CSV, Parquet or PNG, only session imports fmpy, and
    the blow train's keys and the rigid parameters are named once."""
    assert violations(HARNESS) == []


@pytest.mark.parametrize("module, text, expected", [
    ("scene/x.py", "import csv\n", "scene/x.py: csv"),
    ("drive/x.py", "def f(fig):\n    fig.savefig('a.png')\n", "drive/x.py: .savefig"),
    ("sweep/x.py", "def f():\n    import pyarrow.parquet as pq\n", "sweep/x.py: pyarrow.parquet"),
    ("fuzz/x.py", "from fmpy.fmi2 import FMU2Slave\n", "fuzz/x.py: fmpy.fmi2"),
    ("cost/x.py", "import tomllib\n", "cost/x.py: tomllib"),
    ("scene/x.py", "KEYS = ('amplitude', 'duration', 'period')\n", "the blow keys"),
    ("cost/x.py", "P = ['L1', 'L2', 'R1', 'h1']\n", "the rigid parameters"),
])
def test_a_second_copy_would_be_found(tmp_path, module, text, expected):
    """The check itself: a planted violation of each kind is reported."""
    path = tmp_path / module
    path.parent.mkdir(parents=True)
    path.write_text(text)
    assert any(expected in v for v in violations(tmp_path)), violations(tmp_path)
