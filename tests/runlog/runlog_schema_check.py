"""Two independent readers of the log's JSON schemas, for tests.

- ``validate``: the JSON Schema keywords the cosmos schemas use (type, properties,
  patternProperties, required, items, minItems, maxItems, enum, minimum,
  maximum, oneOf with const), applied to a message. The ``jsonschema`` package
  is not a dependency, so this small validator stands in for it.
- ``foxglove_fields``: the rules by which Foxglove turns a JSON schema into
  message types (a single string ``type`` per property, arrays of a single item
  type, ``oneOf`` only as numeric constants); raises where Foxglove would fail.
"""

from __future__ import annotations

import re
from typing import Any

_JSON_TYPES = {
    "object": dict,
    "array": list,
    "string": str,
    "boolean": bool,
    "null": type(None),
}


def _is_type(value: Any, name: str) -> bool:
    if name == "number":
        return isinstance(value, int | float) and not isinstance(value, bool)
    if name == "integer":
        return isinstance(value, int) and not isinstance(value, bool)
    return isinstance(value, _JSON_TYPES[name])


def validate(value: Any, schema: dict[str, Any], where: str = "$") -> list[str]:
    """Errors of ``value`` against ``schema`` (empty if valid)."""
    errors: list[str] = []
    types = schema.get("type")
    if types is not None:
        names = [types] if isinstance(types, str) else list(types)
        if not any(_is_type(value, name) for name in names):
            return [f"{where}: {value!r} is not of type {names}"]
    if "enum" in schema and value not in schema["enum"]:
        errors.append(f"{where}: {value!r} not in {schema['enum']}")
    if "oneOf" in schema:
        matches = [alt for alt in schema["oneOf"] if not validate(value, alt, where)]
        if len(matches) != 1:
            errors.append(f"{where}: {value!r} matches {len(matches)} oneOf alternatives")
    if "const" in schema and value != schema["const"]:
        errors.append(f"{where}: {value!r} != {schema['const']!r}")
    if isinstance(value, int | float) and not isinstance(value, bool):
        if "minimum" in schema and value < schema["minimum"]:
            errors.append(f"{where}: {value} < {schema['minimum']}")
        if "maximum" in schema and value > schema["maximum"]:
            errors.append(f"{where}: {value} > {schema['maximum']}")
    if isinstance(value, list):
        if "minItems" in schema and len(value) < schema["minItems"]:
            errors.append(f"{where}: {len(value)} items < {schema['minItems']}")
        if "maxItems" in schema and len(value) > schema["maxItems"]:
            errors.append(f"{where}: {len(value)} items > {schema['maxItems']}")
        if "items" in schema:
            for i, item in enumerate(value):
                errors += validate(item, schema["items"], f"{where}[{i}]")
    if isinstance(value, dict):
        for key in schema.get("required", []):
            if key not in value:
                errors.append(f"{where}: missing required {key!r}")
        for key, item in value.items():
            if key in schema.get("properties", {}):
                errors += validate(item, schema["properties"][key], f"{where}.{key}")
            for pattern, sub in schema.get("patternProperties", {}).items():
                if re.search(pattern, key):
                    errors += validate(item, sub, f"{where}.{key}")
    return errors


_FOXGLOVE_ITEM_TYPES = {"boolean", "string", "number", "integer", "object"}


def foxglove_fields(schema: dict[str, Any], name: str = "root") -> dict[str, str]:
    """Field name -> Foxglove type of an object schema; raises ValueError where Foxglove does."""
    if schema.get("type") != "object":
        raise ValueError(f'{name}: expected "type": "object", got {schema.get("type")!r}')
    fields: dict[str, str] = {}
    for field, sub in schema.get("properties", {}).items():
        path = f"{name}.{field}"
        if "oneOf" in sub:
            if not all(isinstance(alt.get("const"), int | float) for alt in sub["oneOf"]):
                raise ValueError(f"{path}: oneOf alternatives must have number values")
            fields[field] = "uint32"
            continue
        kind = sub.get("type")
        if kind in ("boolean", "string", "number", "integer"):
            fields[field] = kind
        elif kind == "object":
            foxglove_fields(sub, path)
            fields[field] = "object"
        elif kind == "array":
            item_kind = sub["items"].get("type")
            if item_kind not in _FOXGLOVE_ITEM_TYPES:
                raise ValueError(f"{path}: unsupported array item type {item_kind!r}")
            if item_kind == "object":
                foxglove_fields(sub["items"], path)
            fields[field] = f"{item_kind}[]"
        else:
            raise ValueError(f"{path}: unsupported type {kind!r}")
    return fields
