"""Readers for the deployment files (Dockerfile, .dockerignore, docker-compose.yml) used by tests/deploy/.

The Dockerfile reader is our own, small and strict: one instruction per logical line, backslash
continuations joined, comment lines dropped (also inside a continuation, as Docker does), JSON (exec)
form recognized, leading --flags split off, each instruction tagged with its build stage.
"""

from __future__ import annotations

import fnmatch
import json
import re
import shlex
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DOCKERFILE = ROOT / "Dockerfile"
DOCKERIGNORE = ROOT / ".dockerignore"
COMPOSE = ROOT / "docker-compose.yml"
COMPOSE_SCHEMA = ROOT / "tests" / "authorities" / "compose-spec.json"

KEYWORDS = {
    "FROM",
    "RUN",
    "CMD",
    "LABEL",
    "EXPOSE",
    "ENV",
    "ADD",
    "COPY",
    "ENTRYPOINT",
    "VOLUME",
    "USER",
    "WORKDIR",
    "ARG",
    "ONBUILD",
    "STOPSIGNAL",
    "HEALTHCHECK",
    "SHELL",
    "MAINTAINER",
}


class DockerfileError(ValueError):
    pass


@dataclass
class Instruction:
    keyword: str
    flags: dict[str, str]
    args: str  # the rest of the line after the flags, continuations joined with a space
    line: int  # 1-based line where the instruction starts
    stage: int  # index of the FROM it belongs to
    exec_form: list[str] | None = field(default=None)  # the JSON array, when written in exec form

    def words(self) -> list[str]:
        """The arguments as a list: the exec form as written, else split like a shell would."""
        return list(self.exec_form) if self.exec_form is not None else shlex.split(self.args)


def _split_flags(rest: str) -> tuple[dict[str, str], str]:
    flags = {}
    while True:
        m = re.match(r"--([a-z][a-z0-9-]*)(?:=(\S*))?\s*", rest)
        if not m:
            return flags, rest
        flags[m.group(1)] = m.group(2) if m.group(2) is not None else "true"
        rest = rest[m.end() :]


def parse_dockerfile(text: str) -> list[Instruction]:
    lines = text.splitlines()
    # parser directives: only '# syntax=' (and no other escape character than the backslash) is supported
    for raw in lines:
        m = re.match(r"#\s*([a-zA-Z]+)\s*=\s*(\S+)", raw)
        if not m:
            break
        if m.group(1).lower() == "escape" and m.group(2) != "\\":
            raise DockerfileError("only the default escape character is supported")
    instructions: list[Instruction] = []
    stage = -1
    i = 0
    while i < len(lines):
        raw = lines[i]
        stripped = raw.strip()
        if not stripped or stripped.startswith("#"):
            i += 1
            continue
        start = i + 1
        parts = []
        text_line = raw.rstrip()
        while text_line.endswith("\\"):
            parts.append(text_line[:-1].strip())
            i += 1
            # comment and empty lines inside a continuation are dropped
            while i < len(lines) and (not lines[i].strip() or lines[i].strip().startswith("#")):
                i += 1
            if i == len(lines):
                raise DockerfileError(f"line {start}: continuation runs past the end of the file")
            text_line = lines[i].rstrip()
        parts.append(text_line.strip())
        i += 1
        logical = " ".join(p for p in parts if p)
        m = re.match(r"([A-Za-z]+)(\s+|$)(.*)", logical)
        if not m:
            raise DockerfileError(f"line {start}: not an instruction: {logical!r}")
        keyword = m.group(1).upper()
        if keyword not in KEYWORDS:
            raise DockerfileError(f"line {start}: unknown instruction {m.group(1)!r}")
        rest = m.group(3).strip()
        if keyword == "FROM":
            stage += 1
        elif stage < 0 and keyword != "ARG":
            raise DockerfileError(f"line {start}: {keyword} before the first FROM")
        flags, rest = _split_flags(rest) if keyword in {"FROM", "COPY", "ADD", "RUN", "HEALTHCHECK"} else ({}, rest)
        exec_form = None
        head, body = "", rest
        if keyword == "HEALTHCHECK" and re.match(r"CMD\s", rest, re.IGNORECASE):  # HEALTHCHECK [flags] CMD [...]
            head, body = "CMD", rest[3:].strip()
        if body.startswith("["):
            try:
                value = json.loads(body)
            except json.JSONDecodeError:
                value = None
            if isinstance(value, list) and all(isinstance(v, str) for v in value):
                exec_form = ([head] if head else []) + value
        instructions.append(Instruction(keyword, flags, rest, start, stage, exec_form))
    if stage < 0:
        raise DockerfileError("no FROM instruction")
    return instructions


@dataclass
class Stage:
    index: int
    image: str
    name: str | None
    instructions: list[Instruction]

    def all(self, keyword: str) -> list[Instruction]:
        return [ins for ins in self.instructions if ins.keyword == keyword]

    def env(self) -> dict[str, str]:
        """Every ENV of the stage, later ones winning (inherited ENV of another stage not included)."""
        out = {}
        for ins in self.all("ENV"):
            out.update(parse_env(ins.args))
        return out


def stages(instructions: list[Instruction]) -> list[Stage]:
    out = []
    for ins in instructions:
        if ins.keyword == "FROM":
            words = ins.args.split()
            name = words[2] if len(words) == 3 and words[1].upper() == "AS" else None
            if len(words) not in (1, 3) or (len(words) == 3 and name is None):
                raise DockerfileError(f"line {ins.line}: FROM image [AS name], got {ins.args!r}")
            out.append(Stage(ins.stage, words[0], name, [ins]))
        elif ins.stage >= 0:
            out[ins.stage].instructions.append(ins)
    return out


def parse_env(args: str) -> dict[str, str]:
    words = shlex.split(args)
    if words and "=" not in words[0]:  # legacy form: ENV KEY value with spaces
        return {words[0]: " ".join(words[1:])}
    env = {}
    for w in words:
        if "=" not in w:
            raise DockerfileError(f"ENV: {w!r} is not KEY=value")
        k, v = w.split("=", 1)
        env[k] = v
    return env


def dockerignore_patterns() -> list[str]:
    return [ln.strip() for ln in DOCKERIGNORE.read_text().splitlines() if ln.strip() and not ln.strip().startswith("#")]


def ignored(rel_path: str, patterns: list[str]) -> bool:
    """Whether .dockerignore keeps `rel_path` (or a folder above it) out of the build context."""
    parts = rel_path.strip("/").split("/")
    result = False
    for pat in patterns:
        negate = pat.startswith("!")
        pat = pat.lstrip("!").strip("/")
        for n in range(1, len(parts) + 1):
            prefix = "/".join(parts[:n])
            if _match(pat, prefix):
                result = not negate
                break
    return result


def _match(pattern: str, path: str) -> bool:
    if pattern.startswith("**/"):
        tail = pattern[3:]
        segs = path.split("/")
        return any(fnmatch.fnmatchcase("/".join(segs[k:]), tail) for k in range(len(segs)))
    return fnmatch.fnmatchcase(path, pattern) and path.count("/") == pattern.count("/")


def health_url(test: list[str] | str) -> str:
    """The http URL a health check command opens."""
    text = test if isinstance(test, str) else " ".join(test)
    m = re.search(r"https?://[^\s'\"]+", text)
    if not m:
        raise AssertionError(f"no URL in health check {test!r}")
    return m.group(0)


def package_environ_reads() -> set[str]:
    """FOOTPRINT_* variables that the package reads straight from os.environ (outside the Settings class)."""
    pattern = re.compile(r"""(?:environ\.get\(|environ\[|getenv\()\s*["'](FOOTPRINT_[A-Z0-9_]+)["']""")
    names = set()
    for source in (ROOT / "backend" / "footprint").rglob("*.py"):
        names.update(pattern.findall(source.read_text()))
    return names


def assert_real_settings(Settings, env, monkeypatch):
    """Every FOOTPRINT_* variable in `env` is a field of the service's Settings (and reads back as set), or
    one the package reads from os.environ itself (outside Settings)."""
    prefix = Settings.model_config.get("env_prefix", "")
    assert prefix.upper() == "FOOTPRINT_"
    for k, v in env.items():
        monkeypatch.setenv(k, v)
    settings = Settings()
    direct = package_environ_reads()
    for k, v in env.items():
        name = k[len(prefix) :].lower()
        if k in direct and name not in Settings.model_fields:
            continue
        assert name in Settings.model_fields, f"{k} is not a setting of footprint.service.settings.Settings"
        assert str(getattr(settings, name)) == v, f"{k}={v!r} read as {getattr(settings, name)!r}"


def get_routes(tmp_path):
    from footprint.service.app import create_app
    from footprint.service.settings import Settings

    """The GET routes of the app: its OpenAPI paths (routers included under /api) and its plain routes."""
    app = create_app(Settings(database_url=f"sqlite:///{tmp_path / 'routes.db'}"))
    paths = {path for path, methods in app.openapi()["paths"].items() if "get" in methods}
    paths |= {r.path for r in app.routes if "GET" in (getattr(r, "methods", None) or ())}
    return paths
