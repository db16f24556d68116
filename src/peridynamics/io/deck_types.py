"""Number types and the strict base schema shared by every deck section."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field


def _not_bool(v: Any) -> Any:
    if isinstance(v, bool):
        raise ValueError("a number is expected, not true/false")
    return v


_Num = BeforeValidator(_not_bool)
PosFloat = Annotated[float, Field(gt=0, allow_inf_nan=False), _Num]
NonNegFloat = Annotated[float, Field(ge=0, allow_inf_nan=False), _Num]
Finite = Annotated[float, Field(allow_inf_nan=False), _Num]
Component = Literal["x", "y", "z"]


class Strict(BaseModel):
    """Base: unknown keys are errors; values are immutable."""

    model_config = ConfigDict(extra="forbid", frozen=True)
