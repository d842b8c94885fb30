"""The Dockerfile, read statically (no Docker engine runs here) and checked against the code: the CLI
command it runs, the settings it sets, the route its health check opens, the Python it builds on,
the numba cache it warms, the files it copies."""

import os
import re
import subprocess
import sys
import tomllib
import urllib.parse
from pathlib import Path

import pytest
from deploy_files import (
    DOCKERFILE,
    ROOT,
    DockerfileError,
    assert_real_settings,
    dockerignore_patterns,
    get_routes,
    health_url,
    ignored,
    parse_dockerfile,
    stages,
)
from packaging.specifiers import SpecifierSet

PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())


@pytest.fixture(scope="module")
def dockerfile():
    return parse_dockerfile(DOCKERFILE.read_text())


@pytest.fixture(scope="module")
def all_stages(dockerfile):
    return stages(dockerfile)


@pytest.fixture(scope="module")
def final(all_stages):
    return all_stages[-1]


# ---- the parser itself


def test_parser_joins_continuations_and_drops_comments():
    text = (
        "# syntax=docker/dockerfile:1\n"
        "FROM python:3.11-slim AS base\n"
        "RUN a \\\n"
        "    # a comment inside\n"
        "\n"
        "    && b\n"
        'CMD ["x", "y"]\n'
        "COPY --from=base --chown=u:g /a /b\n"
        "ENV A=1 B='two words'\n"
        'HEALTHCHECK --interval=5s CMD ["python", "-c", "print(1)"]\n'
    )
    ins = parse_dockerfile(text)
    assert [i.keyword for i in ins] == ["FROM", "RUN", "CMD", "COPY", "ENV", "HEALTHCHECK"]
    assert ins[5].flags == {"interval": "5s"} and ins[5].words() == ["CMD", "python", "-c", "print(1)"]
    assert ins[1].args == "a && b" and ins[1].line == 3
    assert ins[2].exec_form == ["x", "y"]
    assert ins[3].flags == {"from": "base", "chown": "u:g"} and ins[3].words() == ["/a", "/b"]
    assert stages(ins)[0].env() == {"A": "1", "B": "two words"}


@pytest.mark.parametrize(
    "text",
    ["RUN echo before any FROM\n", "FROM python:3.11\nRUNN echo typo\n", "FROM python:3.11\nRUN a \\\n"],
)
def test_parser_rejects_malformed_files(text):
    with pytest.raises(DockerfileError):
        parse_dockerfile(text)


def test_dockerignore_matcher():
    pats = ["tests", "**/__pycache__", "frontend/node_modules", "*.db"]
    assert ignored("tests/deploy/x.py", pats)
    assert ignored("backend/footprint/__pycache__/a.pyc", pats)
    assert ignored("frontend/node_modules/leaflet/package.json", pats)
    assert ignored("footprint.db", pats) and not ignored("data/footprint.db", pats)
    assert not ignored("frontend/package.json", pats) and not ignored("backend/footprint/cli.py", pats)


# ---- the Dockerfile


def test_multi_stage_builder_venv_copied_to_the_same_path(all_stages, final):
    assert len(all_stages) >= 2, "multi-stage build expected"
    names = {s.name for s in all_stages[:-1]}
    copies = [c for c in final.all("COPY") if "from" in c.flags]
    venv_copies = [c for c in copies if c.words()[0].startswith("/opt/venv")]
    assert venv_copies, "the runtime stage must copy the venv from the builder"
    (venv,) = venv_copies
    assert venv.flags["from"] in names
    # a venv's scripts carry its absolute path in their #! lines: it must land where it was made
    src, dest = venv.words()
    assert src.rstrip("/") == dest.rstrip("/")
    builder = next(s for s in all_stages if s.name == venv.flags["from"])
    runs = " ".join(r.args for r in builder.all("RUN"))
    assert f"venv {src}" in runs, "the builder creates the venv it hands over"
    assert re.search(r"\bpip install\b", runs), "the builder installs the package into the venv"
    assert "/opt/venv/bin" in final.env().get("PATH", ""), "the runtime finds the venv's commands"
    for c in copies:
        assert c.flags["from"] in names, f"line {c.line}: COPY --from an unknown stage"
        stage = next(s for s in all_stages if s.name == c.flags["from"])
        src = c.words()[0].rstrip("/")
        made_there = " ".join(i.args for i in stage.instructions)
        assert src in made_there, f"line {c.line}: {src} is not made in stage {stage.name}"


def test_python_base_matches_requires_python(all_stages):
    python_stages = [s for s in all_stages if s.image.split(":")[0] in ("python", "docker.io/library/python")]
    assert python_stages, "no python base image"
    versions = set()
    for s in python_stages:
        tag = s.image.split(":", 1)[1] if ":" in s.image else ""
        m = re.match(r"(\d+)\.(\d+)", tag)
        assert m, f"FROM {s.image}: pin the Python minor version"
        versions.add(m.group(0))
    # the venv is built in one stage and run in another: one Python
    assert len(versions) == 1, f"python stages disagree: {versions}"
    assert len({s.image for s in python_stages}) == 1, "builder and runtime on the same base image"
    spec = SpecifierSet(PYPROJECT["project"]["requires-python"])
    (version,) = versions
    assert spec.contains(f"{version}.0"), f"python {version} does not satisfy requires-python {spec}"


def test_runtime_runs_as_a_user_it_creates(final):
    users = final.all("USER")
    assert users, "the runtime stage must switch away from root"
    user = users[-1].args.split(":")[0]
    assert user not in ("root", "0")
    runs = " ".join(r.args for r in final.all("RUN") if r.line < users[-1].line)
    assert re.search(rf"useradd\b[^&;]*\b{re.escape(user)}\b", runs), f"user {user} is not created in the runtime stage"


def _user_home(final):
    user = final.all("USER")[-1].args.split(":")[0]
    runs = " ".join(r.args for r in final.all("RUN"))
    m = re.search(rf"useradd\b[^&;]*--home-dir\s+(\S+)[^&;]*\b{re.escape(user)}\b", runs)
    assert m, "useradd --home-dir HOME ... USER"
    return m.group(1)


def test_numba_cache_is_warmed_at_build_by_the_runtime_user(final):
    env = final.env()
    cache_vars = {k: env[k] for k in ("NUMBA_CACHE_DIR", "XDG_CACHE_HOME") if k in env}
    assert cache_vars, "set XDG_CACHE_HOME or NUMBA_CACHE_DIR so the cache is where the runtime user can write"
    home = _user_home(final)
    for k, v in cache_vars.items():
        assert v == home or v.startswith(home.rstrip("/") + "/"), f"{k}={v} is not under {home}, the user's home"
    user_line = final.all("USER")[-1].line
    env_line = max(e.line for e in final.all("ENV") if set(cache_vars) & set(_env_keys(e)))
    warm = [r for r in final.all("RUN") if "footprint fly" in r.args and "table2_lod22.json" in r.args]
    assert warm, "warm the cache by flying examples/table2_lod22.json"
    assert warm[0].line > user_line and warm[0].line > env_line, "warm as the runtime user, with the cache dir set"
    # the example flown is in the image, at the path the RUN uses (relative to WORKDIR)
    example = re.search(r"(\S*table2_lod22\.json)", warm[0].args).group(1)
    workdirs = [w for w in final.all("WORKDIR") if w.line < warm[0].line]
    path = example if example.startswith("/") else f"{workdirs[-1].args.rstrip('/')}/{example}"
    copied = [c.words() for c in final.all("COPY") if "from" not in c.flags]
    assert any(path.startswith(ws[-1].rstrip("/") + "/") or path == ws[-1] for ws in copied), f"{path} not copied"
    assert (ROOT / "examples" / "table2_lod22.json").is_file()


def _env_keys(ins):
    from deploy_files import parse_env

    return parse_env(ins.args).keys()


def test_the_code_puts_numba_cache_where_the_dockerfile_says(final, tmp_path):
    """backend/footprint/core/_jit.py: $XDG_CACHE_HOME/footprint/... unless NUMBA_CACHE_DIR is set."""
    env = final.env()
    child = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_DIR", "FOOTPRINT_NO_JIT")}
    if "NUMBA_CACHE_DIR" in env:
        child["NUMBA_CACHE_DIR"] = str(tmp_path / "numba")
        expected = tmp_path / "numba"
    else:
        child["XDG_CACHE_HOME"] = str(tmp_path)
        expected = tmp_path / "footprint"
    out = subprocess.run(
        [sys.executable, "-c", "import footprint.core._jit, numba; print(numba.config.CACHE_DIR)"],
        env=child,
        capture_output=True,
        text=True,
        check=True,
    ).stdout.strip()
    assert Path(out) == expected or expected in Path(out).parents, out


def test_npm_ci_for_the_page(all_stages):
    if not (ROOT / "frontend" / "package.json").is_file():
        pytest.skip("no frontend/package.json")
    assert (ROOT / "frontend" / "package-lock.json").is_file(), "npm ci needs frontend/package-lock.json"
    node = [s for s in all_stages if s.image.split(":")[0] == "node"]
    assert node, "a node stage runs npm ci"
    assert any(re.search(r"\bnpm ci\b", r.args) for r in node[0].all("RUN"))
    final = all_stages[-1]
    assert any(c.flags.get("from") == node[0].name for c in final.all("COPY")), "the page is copied into the runtime"


def test_copied_files_exist_and_are_in_the_build_context(dockerfile):
    pats = dockerignore_patterns()
    for c in [i for i in dockerfile if i.keyword in ("COPY", "ADD") and "from" not in i.flags]:
        for src in c.words()[:-1]:
            path = ROOT / src
            assert path.exists(), f"line {c.line}: {src} does not exist"
            rel = src.rstrip("/")
            assert not ignored(rel, pats), f"line {c.line}: {src} is excluded by .dockerignore"
            if path.is_dir():
                kept = [p for p in path.rglob("*") if p.is_file() and not ignored(str(p.relative_to(ROOT)), pats)]
                assert kept, f"line {c.line}: everything under {src} is excluded by .dockerignore"


def test_dockerignore_keeps_junk_out():
    pats = dockerignore_patterns()
    for junk in (".git/HEAD", "backend/footprint/__pycache__/x.pyc", "frontend/node_modules/x", "tests/conftest.py"):
        assert ignored(junk, pats), junk
    for needed in ("pyproject.toml", "README.md", "backend/footprint/cli.py", "examples/table2_lod22.json"):
        assert not ignored(needed, pats), needed


def test_cmd_is_a_real_cli_command(final):
    (cmd,) = final.all("CMD")
    words = cmd.words()
    assert cmd.exec_form is not None, "exec form, so the server gets the stop signal"
    assert words[:2] == ["footprint", "serve"]
    assert PYPROJECT["project"]["scripts"]["footprint"] == "footprint.cli:main"
    # the same arguments plus --help: an unknown option would fail before the help is printed
    run = subprocess.run(words + ["--help"], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    assert "--host" in run.stdout and "--port" in run.stdout


def test_env_sets_only_real_settings(final, monkeypatch):
    from footprint.service.settings import Settings

    env = {k: v for k, v in final.env().items() if k.startswith("FOOTPRINT_")}
    assert env, "the image sets the service's settings (database URL, port)"
    assert_real_settings(Settings, env, monkeypatch)


def test_healthcheck_opens_a_real_route_on_the_exposed_port(final, tmp_path):
    from footprint.service.settings import Settings

    (hc,) = final.all("HEALTHCHECK")
    words = hc.words()
    assert words[0] == "CMD"
    for flag in ("interval", "timeout", "retries"):
        assert flag in hc.flags
    url = urllib.parse.urlsplit(health_url(words[1:]))
    assert url.hostname in ("127.0.0.1", "localhost")
    (expose,) = final.all("EXPOSE")
    port = int(expose.args.split("/")[0])
    assert url.port == port
    settings_port = int(final.env().get("FOOTPRINT_PORT", Settings.model_fields["port"].default))
    assert settings_port == port, "the server listens where the health check looks"
    assert url.path in get_routes(tmp_path)
    # the command runs with the image's python (no curl in a slim image)
    assert words[1] in ("python", "python3") or words[1].startswith("/opt/venv/bin/python")


def test_repository_paths_are_set_to_copied_folders(final):
    """The image installs the package into the venv, so a setting whose default is a folder of the source
    tree (the page, the migrations) points nowhere there: the image must set it to a folder it copies."""
    from footprint.service.settings import Settings

    env = final.env()
    copied = {}
    for c in final.all("COPY"):
        words = c.words()
        copied[words[-1].rstrip("/")] = (c.flags.get("from"), words[:-1])
    import footprint

    # the source tree the package is imported from (backend/footprint/__init__.py -> its top), which is this
    # checkout under `pip install -e .` and may be another one when the tests run against another install
    source_root = Path(footprint.__file__).resolve().parents[2]
    repo_paths = [
        name
        for name, f in Settings.model_fields.items()
        if isinstance(f.default, Path) and source_root in f.default.resolve().parents
    ]
    assert repo_paths, "expected the page and migrations folders among the settings"
    for name in repo_paths:
        var = f"FOOTPRINT_{name.upper()}"
        assert var in env, f"{var} must be set: its default {Settings.model_fields[name].default} is not in the image"
        assert env[var].rstrip("/") in copied, f"{var}={env[var]} is not a folder the image copies"
        stage, sources = copied[env[var].rstrip("/")]
        if stage is None:  # copied from the build context: the same folder of the repository
            (src,) = sources
            default = Settings.model_fields[name].default.resolve().relative_to(source_root)
            assert Path(src.rstrip("/")) == default, (var, src, default)
