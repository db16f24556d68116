"""The keys a deck accepts, read from the schema itself (what ``peridynamics help
deck`` prints): each key with its type and default, nested sections indented."""

from __future__ import annotations

import json
import re
import typing
from typing import Any

from pydantic import BaseModel
from pydantic_core import PydanticUndefined

from peridynamics.deck.schema import Deck


def _type_name(ann: Any) -> str:
    origin, args = typing.get_origin(ann), typing.get_args(ann)
    if origin is typing.Annotated:
        return _type_name(args[0])
    if origin is typing.Literal:
        return " | ".join(str(a).lower() if isinstance(a, bool) else str(a) for a in args)
    if origin in (typing.Union, getattr(__import__("types"), "UnionType", None)):
        names = [_type_name(a) for a in args if a is not type(None)]
        return " or ".join(dict.fromkeys(names))
    if origin in (list, tuple):
        inner = [a for a in args if a is not Ellipsis]
        if origin is tuple and len(inner) > 1:
            return f"[{', '.join(_type_name(a) for a in inner)}]"
        return f"list of {_type_name(inner[0])}" if inner else "list"
    if origin is dict:
        return f"mapping of name -> {_type_name(args[1])}"
    if isinstance(ann, type) and issubclass(ann, BaseModel):
        return "mapping"
    return {float: "number", int: "integer", str: "string", bool: "true/false"}.get(
        ann, getattr(ann, "__name__", str(ann))
    )


def _first_sentence(doc: str) -> str:
    """The first sentence of a docstring's first paragraph, on one line."""
    para = " ".join(doc.strip().split("\n\n")[0].split())
    m = re.search(r"(?<!e\.g)(?<!i\.e)\.(\s|$)", para)
    return para[: m.start() + 1] if m else para


def _sub_models(ann: Any) -> list[Any]:
    if isinstance(ann, type) and issubclass(ann, BaseModel):
        return [ann]
    out: list[Any] = []
    for a in typing.get_args(ann):
        for m in _sub_models(a):
            if m not in out:
                out.append(m)
    return out


def deck_reference(section: str | None = None) -> str:
    """The keys a deck accepts, from the schema itself (what ``peridynamics help deck``
    prints): for each key its type and default, nested sections indented, one block per
    ``type`` / ``model`` where a section has several kinds."""
    lines: list[str] = []
    shown: dict[Any, str] = {}  # section model -> the key path where its keys are listed

    def walk(model: Any, indent: str, where: str) -> None:
        for name, f in model.model_fields.items():
            key = f.alias or name
            path = f"{where}.{key}" if where else key
            if f.is_required():
                default = "required"
            elif f.default is PydanticUndefined or f.default is None:
                default = "optional"
            else:
                d = f.default
                d = d.model_dump(mode="json") if hasattr(d, "model_dump") else d
                default = f"default {json.dumps(d)}"
            lines.append(f"{indent}{key}: {_type_name(f.annotation)} ({default})")
            subs = _sub_models(f.annotation)
            if subs and all(sub in shown for sub in subs):
                lines.append(f"{indent}  (the keys listed under {shown[subs[0]]})")
                continue
            for sub in subs:
                doc = _first_sentence(sub.__doc__ or sub.__name__)
                pad = indent + ("    " if len(subs) > 1 else "  ")
                if len(subs) > 1:
                    lines.append(f"{indent}  - {doc}")
                if sub in shown:
                    lines.append(f"{pad}(the keys listed under {shown[sub]})")
                    continue
                shown[sub] = path
                walk(sub, pad, path)

    fields = Deck.model_fields
    if section is not None:
        if section not in fields:
            raise KeyError(section)
        fields = {section: fields[section]}

    class One:
        model_fields = fields

    walk(One, "", "")
    return "\n".join(lines)
