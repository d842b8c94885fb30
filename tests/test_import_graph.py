"""The package's modules import one another without a cycle, counting imports inside functions too (a lazy import
hides a cycle from Python, not from the reader). Issue 14 found core.footprints <-> core.constrained."""

import ast
from pathlib import Path

import footprint

ROOT = Path(footprint.__file__).parent
PACKAGE = "footprint"


def module_names() -> dict[str, Path]:
    names = {}
    for path in sorted(ROOT.rglob("*.py")):
        rel = path.relative_to(ROOT).with_suffix("")
        parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
        names[".".join((PACKAGE,) + parts)] = path
    return names


def imports(path: Path, modules) -> set[str]:
    """The package's modules one file imports, anywhere in it (module level or inside a function); `from pkg import
    sub` imports the submodule sub, not pkg's own code."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            subs = {f"{node.module}.{a.name}" for a in node.names} & set(modules)
            found |= subs if len(subs) == len(node.names) else subs | {node.module}
    return {m for m in found if m in modules}


def import_graph() -> dict[str, set[str]]:
    modules = module_names()
    return {name: imports(path, modules) - {name} for name, path in modules.items()}


def cycles(graph) -> list[list[str]]:
    """Every elementary cycle's first sighting in a depth-first walk (enough to name each offender)."""
    found, state, stack = [], {}, []

    def visit(m):
        state[m] = "open"
        stack.append(m)
        for n in sorted(graph.get(m, ())):
            if state.get(n) == "open":
                found.append(stack[stack.index(n) :] + [n])
            elif n not in state:
                visit(n)
        stack.pop()
        state[m] = "done"

    for m in sorted(graph):
        if m not in state:
            visit(m)
    return found


def test_the_package_has_no_import_cycle():
    found = cycles(import_graph())
    assert not found, "import cycles in footprint: " + "; ".join(" -> ".join(c) for c in found)


def test_the_core_imports_nothing_from_the_layers_above():
    above = [
        (m, n)
        for m, deps in import_graph().items()
        if m.startswith("footprint.core")
        for n in deps
        if not n.startswith("footprint.core")
    ]
    assert not above, above


if __name__ == "__main__":
    for c in cycles(import_graph()):
        print(" -> ".join(c))
