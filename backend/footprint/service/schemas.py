"""Request and response models of the REST API (docs/api.md). Cases and studies are not redefined here: a
job's study, a trajectory's case, a transform or a reach request are parsed by their contract modules
(footprint.contracts.case, .footprint, .optimization, .sweep, .transform, .reach); landing sites reuse
footprint.contracts.reach.Site."""

from typing import Annotated, Any, Literal, Union

from pydantic import AfterValidator, BaseModel, ConfigDict, Field, StringConstraints, WrapValidator, create_model

from footprint import contracts
from footprint.contracts.bounds import FOOTPRINT_NAME_CHARS, JOB_NAME_CHARS, VEHICLE_ID_CHARS
from footprint.contracts.doors import computable
from footprint.contracts.fields import model_fields
from footprint.contracts.reach import Site
from footprint.contracts.vehicle import VehicleCase


def _job_kind(kind: str) -> str:
    """A kind the registry runs as a job (looked up at each request: a kind registered later is one too)."""
    kinds = contracts.job_kinds()
    if kind not in kinds:
        raise ValueError(f"{kind!r} is not a kind of job; allowed: {', '.join(kinds)}")
    return kind


def _kinds_schema(schema: dict) -> None:
    schema["enum"] = list(contracts.job_kinds())  # the document's kinds: those registered when it is made


JobKind = Annotated[
    str, StringConstraints(max_length=40), AfterValidator(_job_kind), Field(json_schema_extra=_kinds_schema)
]
JobStatus = Literal["queued", "running", "succeeded", "failed", "cancelled"]
VEHICLE_ID_PATTERN = rf"^[A-Za-z0-9][A-Za-z0-9_.-]{{0,{VEHICLE_ID_CHARS - 1}}}$"
# a job's or a footprint's id, as db.queries makes them (str(uuid.uuid4())): anything else is a 422, never a lookup
# (or a read-cache key: 2,000 ids of 90,000 characters kept 177 MB, issue 24 item 4)
StoredId = Annotated[
    str, StringConstraints(max_length=36, pattern=r"^[0-9a-fA-F]{8}(-[0-9a-fA-F]{4}){3}-[0-9a-fA-F]{12}$")
]


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


def _typed_job(kind: str) -> type[BaseModel]:
    return create_model(
        f"{kind.capitalize()}Job",
        __base__=_Strict,
        kind=(Literal[kind], ...),
        study=(Annotated[contracts.module(kind).REQUEST, WrapValidator(computable)], ...),
        name=(str | None, Field(default=None, max_length=JOB_NAME_CHARS)),
    )


def job_create() -> Any:
    """POST /api/jobs's body: one typed study per kind of job registered now, discriminated on "kind"."""
    models = tuple(_typed_job(k) for k in contracts.job_kinds())
    return Annotated[Union[models], Field(discriminator="kind")]  # noqa: UP007 (a union of a computed tuple)


# POST /api/footprints/{id}/transform: a transform request less what the stored footprint gives (its points, its
# entry as "from", its study)
FootprintTransform = create_model(
    "FootprintTransform",
    __base__=_Strict,
    **model_fields(contracts.module("transform").REQUEST, exclude=("points", "from_", "study")),
)


class FootprintRename(_Strict):
    name: str = Field(
        min_length=1, max_length=FOOTPRINT_NAME_CHARS, pattern=r"^[^\x00-\x1f]*[^\s\x00-\x1f][^\x00-\x1f]*$"
    )  # printable, not blank


class JobCreated(BaseModel):
    id: str
    name: str | None  # given, or made from what the study is (vehicle, method, entry): the page's label for it
    status: JobStatus
    url: str  # the job (GET to poll, DELETE to cancel); also the response's Location header
    events: str  # its server-sent progress events


class JobSummary(BaseModel):
    id: str
    kind: str
    name: str | None
    status: JobStatus
    progress: float
    progress_note: str | None = None  # what a running job is doing: "solve 3 of 27: IPOPT iteration 12"
    error: str | None
    created_at: str
    started_at: str | None
    finished_at: str | None


class QueuedJob(JobSummary):
    ahead: int  # jobs not yet finished that came before it
    ends_in_s: float | None  # about when it ends: the measured work to it over the workers; None: a kind unmeasured


class Queue(BaseModel):
    workers: int
    jobs: list[QueuedJob]  # queued and running, oldest first
    costs: dict[str, dict[str, float]]  # kind -> {median_s, jobs}: its last succeeded jobs' median run time


class JobRead(JobSummary):
    study: dict[str, Any]
    result: dict[str, Any] | None


class JobList(BaseModel):
    items: list[JobSummary]
    total: int


class VehicleCreate(_Strict):
    id: str = Field(pattern=VEHICLE_ID_PATTERN)
    description: str = Field(default="", max_length=4_000)
    vehicle: VehicleCase  # a case's vehicle: its definition, checked (and packed) as it is read


class VehicleItem(BaseModel):
    id: str
    builtin: bool
    description: str
    wing_loading_psf: float
    ld_max: float | None  # at Mach 20, 200,000 ft
    alpha_ld_max_deg: float | None
    reported_ld_max: float | None
    limits: dict[str, float | None]  # contracts.vehicle.VehicleLimits: what each flight is checked against (None: none)


class AeroSummary(BaseModel):
    altitude_ft: float
    mach: list[float]
    ld_max: list[float | None]
    alpha_ld_max_deg: list[float | None]
    cl_max: list[float | None]


class VehicleDetail(VehicleItem):
    definition: dict[str, Any] | None  # a custom vehicle's stored definition
    aero: AeroSummary


class SiteRead(Site):
    id: int
    last_reach: dict[str, Any] | None = None  # {"reachable", "windows", "first_deorbit_time_s", "best_margin_nmi",
    # "footprint", "orbit", "checked_at"}: the last reach stored for it


class SitesCreated(BaseModel):
    created: int  # new names
    updated: int  # names already stored: moved to the upload's place


class SitesDeleted(BaseModel):
    deleted: int


class Entry(BaseModel):
    latitude_deg: float
    longitude_deg: float
    heading_deg: float
    velocity_fps: float
    gamma_deg: float
    altitude_ft: float


class FootprintSummary(BaseModel):
    id: str
    name: str
    job_id: str
    vehicle: str
    method: str
    entry: Entry
    area_nmi2: float
    max_crossrange_nmi: float
    max_downrange_nmi: float
    min_downrange_nmi: float
    trajectories: int
    created_at: str


class FootprintList(BaseModel):
    items: list[FootprintSummary]
    total: int


class PointRead(BaseModel):
    downrange_nmi: float
    crossrange_nmi: float
    flight_time_s: float
    latitude_deg: float
    longitude_deg: float
    heading_deg: float
    side: str
    parameter: dict[str, Any]
    stop_reason: str
    mirrored: bool


class TrackPoint(BaseModel):
    latitude_deg: float
    longitude_deg: float
    time_s: float | None  # a moved track without flight times has none


class OutlineRead(BaseModel):
    """The boundary on the cylindrical map (core.outline): its line in latitude and continuous longitude (deg), the
    footprint on its left; its area within -180..180 deg as polygons of [longitude, latitude] rings (outer ring
    counter-clockwise, holes clockwise, as a GeoJSON MultiPolygon's coordinates); the poles it holds."""

    latitude_deg: list[float]
    longitude_deg: list[float]
    area: list[list[list[tuple[float, float]]]]
    pole: Literal["north", "south", "both"] | None


class FootprintRead(FootprintSummary):
    points: list[PointRead]
    interior: list[PointRead]
    ground_track: list[TrackPoint]
    outline: OutlineRead


class TrajectoryRead(BaseModel):
    summary: dict[str, Any]  # footprint.core.trajectory's summary: downrange_nmi, crossrange_nmi, flight_time_s, ...
    history: dict[str, list[float | None]]  # time_s, altitude_ft, ... (at most 2,000 rows)


class MovedPoint(BaseModel):
    latitude_deg: float
    longitude_deg: float
    flight_time_s: float | None = None
    downrange_nmi: float
    crossrange_nmi: float
    mirrored: bool
    side: str | None = None  # "exact": the flown point's side and control, and whether it bounds the footprint
    parameter: dict[str, Any] | None = None
    on_boundary: bool | None = None


class PlaceRead(BaseModel):
    """The destination's initial point and heading after the step: the origin of the moved ranges."""

    latitude_deg: float
    longitude_deg: float
    heading_deg: float
    inclination_deg: float


class TransformRead(BaseModel):
    points: list[MovedPoint]
    reference: PlaceRead
    earth_rotation: Literal["none", "approximate", "exact"]
    points_in: int


class FootprintTransformRead(TransformRead):
    outline: OutlineRead
    geojson: dict[str, Any]  # the moved footprint as the stored one's GeoJSON FeatureCollection
    ground_track: list[TrackPoint] = []
    approximate_error_nmi: dict[str, float | int | None] | None = None  # "exact": max, mean, points


class SiteVerdict(BaseModel):
    name: str
    latitude_deg: float
    longitude_deg: float
    reachable: bool
    passes: int  # windows joined across the node
    windows: int
    revolutions: list[int]
    coverage_u_deg: float
    best_margin_nmi: float | None  # negative: how far short the nearest placement falls
    first_deorbit_time_s: float | None


class ReachRead(BaseModel):
    orbit: dict[str, Any]
    footprint: dict[str, Any]
    analysis: dict[str, Any]
    sites: list[SiteVerdict]
    windows: list[dict[str, Any]]  # site, revolution, u_start_deg, u_end_deg, ..., deorbit_points
    notes: list[str]


class Health(BaseModel):
    status: Literal["ok", "degraded", "starting"]
    version: str
    starting: str | None = None  # while starting: the step under way
    database: dict[str, Any]
    cluster: dict[str, Any]


class PageConfig(BaseModel):
    tile_url: str | None  # the optional online tile layer (FOOTPRINT_TILE_URL); null: none
    version: str
