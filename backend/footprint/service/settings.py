"""Service settings from FOOTPRINT_* environment variables, validated once at start-up."""

from pathlib import Path

from pydantic import Field, field_validator
from pydantic_settings import BaseSettings, SettingsConfigDict

from footprint.parallel import default_workers

MIGRATIONS_DIR = Path(__file__).resolve().parents[3] / "migrations"  # the repository's top-level migrations/
FRONTEND_DIR = Path(__file__).resolve().parents[3] / "frontend"
MAX_BODY_BYTES = 1_000_000  # 1 MB: the largest request body (docs/api.md)
MAX_HEADER_BYTES = 32 * 1024  # a request's header lines together (431 past it; nginx's large_client_header_buffers)
MAX_URL_BYTES = 8 * 1024  # a request's path and query (414 past it; RFC 9112 3: 8,000 octets at least)


class Settings(BaseSettings):
    """The service's configuration (docs/api.md "Settings")."""

    model_config = SettingsConfigDict(env_prefix="FOOTPRINT_", extra="ignore")

    database_url: str = "sqlite:///footprint.db"
    dask_scheduler: str = ""  # empty: an in-process LocalCluster; "tcp://host:8786": that scheduler
    dask_workers: int = Field(default_factory=default_workers, ge=1, le=256)
    worker_niceness: int = Field(default=10, ge=0, le=19)  # the local cluster's workers' nice(2): the API goes first
    api_token: str = ""  # empty: no authentication
    cors_origins: str = ""  # comma-separated origins
    tile_url: str = ""  # an optional online tile layer for the page
    host: str = "127.0.0.1"
    # Host names besides localhost, 127.0.0.1, [::1] and the bound address that requests may name (comma-separated;
    # "*": any): a page on a name that resolves here (DNS rebinding) is refused (docs/api.md "Hosts")
    allowed_hosts: str = ""
    port: int = Field(default=8000, ge=1, le=65_535)
    frontend_dir: Path = FRONTEND_DIR
    migrations_dir: Path = MIGRATIONS_DIR
    job_threads: int = Field(default=16, ge=1, le=256)  # jobs watched at once by the service process
    # uvicorn processes answering HTTP over the one database; past 1, the process that starts them runs the jobs
    api_processes: int = Field(default=1, ge=1, le=64)
    # a job's wall time from its first task's start; past it the job fails and its workers are restarted
    job_time_limit_s: float = Field(default=3_600.0, ge=1.0, le=7 * 86_400.0)
    # a job fails, with the reason, when no scheduler has answered or it has had no worker this long (an external
    # cluster that is gone; the local one's workers are replaced)
    no_workers_limit_s: float = Field(default=300.0, ge=1.0, le=7 * 86_400.0)
    # a request's line and headers, and then its body, are due within these of their start (408 and closed past them)
    header_timeout_s: float = Field(default=10.0, gt=0.0, le=3_600.0)
    body_timeout_s: float = Field(default=30.0, gt=0.0, le=3_600.0)
    # what a synchronous request (a trajectory, a transform, a reach) may compute in the API process; past it the
    # computation stops at its next flight or guidance prediction and the request is a 422 (docs/api.md)
    sync_time_limit_s: float = Field(default=10.0, gt=0.0, le=3_600.0)
    # uvicorn's line per request on stderr: off by default, its formatting and write were 7 % of the event loop's
    # samples at 200 readers (issue 49, py-spy)
    access_log: bool = False

    @field_validator("dask_scheduler")
    @classmethod
    def _address(cls, v: str) -> str:
        if v and "://" not in v:
            raise ValueError(f"{v!r} is not a scheduler address; give one like tcp://host:8786, or leave it empty")
        return v

    @property
    def cors_origin_list(self) -> list[str]:
        return [o.strip() for o in self.cors_origins.split(",") if o.strip()]

    @property
    def host_names(self) -> frozenset[str]:
        """The names a request's Host may carry (port aside, lower case); "*" among them: any."""
        names = {"localhost", "127.0.0.1", "[::1]"} | {h.strip().lower() for h in self.allowed_hosts.split(",")}
        if self.host not in ("0.0.0.0", "::", ""):  # a wildcard bind is not a name: FOOTPRINT_ALLOWED_HOSTS lists them
            names.add(f"[{self.host}]" if ":" in self.host else self.host.lower())
        return frozenset(names - {""})


def environment(settings: Settings) -> dict[str, str]:
    """The settings as FOOTPRINT_* variables: what a process started by this one reads to get the same."""
    return {f"FOOTPRINT_{name.upper()}": str(value) for name, value in settings.model_dump().items()}


def load_settings(**overrides) -> Settings:
    """Settings from the environment, with keyword overrides (the CLI's options, tests)."""
    return Settings(**{k: v for k, v in overrides.items() if v is not None})
