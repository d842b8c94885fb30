"""The numerical core's modules import one another without a cycle, counting imports inside functions too
(a lazy import hides a cycle from Python, not from the reader)."""

import ast
from pathlib import Path

import footprint.core

CORE = Path(footprint.core.__file__).parent
PACKAGE = "footprint.core"


def core_imports(path: Path) -> set[str]:
    """The footprint.core modules one file imports, anywhere in it (module level or inside a function)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            found.add(node.module)
            found.update(f"{node.module}.{a.name}" for a in node.names)  # `from footprint.core import aero`
    modules = {f"{PACKAGE}.{p.stem}" for p in CORE.glob("*.py")} | {
        f"{PACKAGE}.{p.name}" for p in CORE.iterdir() if (p / "__init__.py").exists()}
    return {m for m in found if m in modules}


def import_graph() -> dict[str, set[str]]:
    graph = {}
    for path in sorted(CORE.rglob("*.py")):
        rel = path.relative_to(CORE).with_suffix("")
        parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
        name = ".".join((PACKAGE,) + parts)
        graph[name] = core_imports(path) - {name}
    return graph


def cycles(graph) -> list[list[str]]:
    """Every elementary cycle's first sighting in a depth-first walk (enough to name each offender)."""
    found, state, stack = [], {}, []

    def visit(m):
        state[m] = "open"
        stack.append(m)
        for n in sorted(graph.get(m, ())):
            if state.get(n) == "open":
                found.append(stack[stack.index(n):] + [n])
            elif n not in state:
                visit(n)
        stack.pop()
        state[m] = "done"

    for m in sorted(graph):
        if m not in state:
            visit(m)
    return found


def test_the_core_has_no_import_cycle():
    found = cycles(import_graph())
    assert not found, "import cycles in footprint.core: " + "; ".join(" -> ".join(c) for c in found)


if __name__ == "__main__":
    for c in cycles(import_graph()):
        print(" -> ".join(c))
