"""The numerical core imports nothing from the service, the CLI, pydantic, FastAPI, SQLAlchemy or Dask
(DESIGN.md: a pure core, a service around it)."""

import ast
import json
import subprocess
import sys
from pathlib import Path

import footprint.core

CORE = Path(footprint.core.__file__).parent
FORBIDDEN = (
    "footprint.service",
    "footprint.cli",
    "footprint.contracts.case",
    "pydantic",
    "fastapi",
    "starlette",
    "sqlalchemy",
    "alembic",
    "distributed",
    "dask",
    "uvicorn",
    "psycopg",
)


def _imports(path: Path) -> set[str]:
    names = set()
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            names |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module)
    return names


def test_no_core_source_names_a_forbidden_module():
    offenders = {
        f"{p.name}: {name}"
        for p in CORE.rglob("*.py")
        for name in _imports(p)
        if any(name == f or name.startswith(f + ".") for f in FORBIDDEN)
    }
    assert offenders == set()


def test_importing_every_core_module_loads_none_of_them():
    modules = sorted(f"footprint.core.{p.stem}" for p in CORE.glob("*.py") if p.stem != "__init__")
    code = (
        "import importlib, json, sys\n"
        f"for m in {modules!r}: importlib.import_module(m)\n"
        "print(json.dumps(sorted(sys.modules)))"
    )
    loaded = json.loads(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout)
    assert len(modules) > 10
    assert [m for m in loaded if any(m == f or m.startswith(f + ".") for f in FORBIDDEN)] == []
