"""The building blocks of every contract: a strict model (no unknown keys), a bounded number whose error names the
range and its unit, and a model's fields taken over by another."""

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from annotated_types import GroupedMetadata
from pydantic import AfterValidator, BaseModel, BeforeValidator, ConfigDict, Discriminator, Field, Tag


@dataclass(frozen=True)
class Range(GroupedMetadata):
    """A number in [lo, hi], as `Annotated[float, Range(0, 180, "deg")]` (or int): the error names the range and the
    unit; JSON's true and false are not numbers here (pydantic would read false as 0); the OpenAPI document gives
    the minimum and maximum."""

    lo: float
    hi: float
    unit: str = ""

    def check(self, v: float) -> float:
        if not self.lo <= v <= self.hi:
            unit = f" {self.unit}" if self.unit else ""
            raise ValueError(f"{number(v)} is outside the allowed range {number(self.lo)} to {number(self.hi)}{unit}")
        return v

    def __iter__(self) -> Iterator[object]:  # the metadata pydantic applies, in order
        yield BeforeValidator(_not_bool)
        yield AfterValidator(self.check)
        yield Field(json_schema_extra={"minimum": self.lo, "maximum": self.hi})


def number(x: float) -> str:
    """A number as a planner writes it in a message: whole ones with thousands separators ("3,000,000", not
    "3e+06"), others in six significant digits ("0.05", "1.5e+20")."""
    if float(x).is_integer() and abs(x) < 1e15:
        return f"{int(x):,}"
    return f"{x:.6g}"


def _not_bool(v: Any) -> Any:
    if isinstance(v, bool):
        raise ValueError(f"{str(v).lower()} is not a number")
    return v


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


class Settled(Strict):
    """A strict model that never changes once validated (frozen): one instance can be the default of every request
    that leaves it out. pydantic deep-copies a model default at each validation; this one is handed over as it is."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    def __deepcopy__(self, memo: dict[int, Any] | None = None) -> "Settled":
        return self


# A union told apart by the input's JSON shape (a number or a list, a name or an object): its errors name the member the
# input's shape picks, under that member's tag, "(number)", which footprint.contracts.messages leaves out of the
# field's path (a smart union named each member by pydantic's label, "function-after[check(), ...]", and said all)
JSON_SHAPES: dict[str, Any] = {"object": (dict, BaseModel), "array": list, "string": str, "number": (int, float)}


def shape_tag(shape: str) -> Tag:
    """A union member's tag: the JSON shape (a key of JSON_SHAPES) that picks it."""
    return Tag(f"({shape})")


def by_shape(*shapes: str) -> Discriminator:
    """The discriminator of a union whose members are tagged shape_tag(shape): the input's shape picks its member,
    the first when none fits (its error says what was wanted)."""

    def shape(v: Any) -> str:
        fits = (s for s in shapes if isinstance(v, JSON_SHAPES[s]) and not isinstance(v, bool))
        return f"({next(fits, shapes[0])})"

    return Discriminator(shape)


def model_fields(model: type[BaseModel], exclude: tuple[str, ...] = (), **replace: Any) -> dict[str, Any]:
    """A model's fields (type, bounds, default) for create_model, less `exclude`, with some replaced."""
    out = {n: (f.annotation, f) for n, f in model.model_fields.items() if n not in exclude}
    return out | replace
