# SPDX-License-Identifier: MIT
"""A JSON Schema validator for the subset host_sim/metrics.schema.json uses, standard library only.

Keywords: type, enum, properties, required, additionalProperties (false or a schema),
items, minItems, maxItems, minimum, maximum, $ref to "#/$defs/...", and the annotations
$schema, $id, title, description, $defs. A schema that uses any other keyword is refused,
so nothing in it can be silently ignored.
"""

ANNOTATIONS = {"$schema", "$id", "title", "description", "$defs"}
KEYWORDS = {"type", "enum", "properties", "required", "additionalProperties", "items",
            "minItems", "maxItems", "minimum", "maximum", "$ref"} | ANNOTATIONS
TYPES = {
    "object": lambda v: isinstance(v, dict),
    "array": lambda v: isinstance(v, list),
    "string": lambda v: isinstance(v, str),
    "boolean": lambda v: isinstance(v, bool),
    "null": lambda v: v is None,
    "integer": lambda v: isinstance(v, int) and not isinstance(v, bool),
    "number": lambda v: isinstance(v, (int, float)) and not isinstance(v, bool),
}


class SchemaError(Exception):
    """The schema itself uses something this validator does not know."""


def validate(doc, schema):
    """Every way @p doc breaks @p schema, as 'path: message' strings (empty: valid)."""
    errors = []
    _check(doc, schema, schema, "$", errors)
    return errors


def _resolve(root, ref):
    if not ref.startswith("#/"):
        raise SchemaError("only local references are supported: %s" % ref)
    node = root
    for part in ref[2:].split("/"):
        if not isinstance(node, dict) or part not in node:
            raise SchemaError("unresolved reference %s" % ref)
        node = node[part]
    return node


def _check(v, s, root, path, errors):
    unknown = set(s) - KEYWORDS
    if unknown:
        raise SchemaError("%s: unsupported schema keywords %s" % (path, sorted(unknown)))
    if "$ref" in s:
        _check(v, _resolve(root, s["$ref"]), root, path, errors)
    if "type" in s:
        types = s["type"] if isinstance(s["type"], list) else [s["type"]]
        for t in types:
            if t not in TYPES:
                raise SchemaError("%s: unknown type %r" % (path, t))
        if not any(TYPES[t](v) for t in types):
            errors.append("%s: %r is not %s" % (path, v, " or ".join(types)))
            return
    if "enum" in s and v not in s["enum"]:
        errors.append("%s: %r is not one of %s" % (path, v, s["enum"]))
    number = TYPES["number"](v)
    if number and "minimum" in s and v < s["minimum"]:
        errors.append("%s: %r is below the minimum %r" % (path, v, s["minimum"]))
    if number and "maximum" in s and v > s["maximum"]:
        errors.append("%s: %r is above the maximum %r" % (path, v, s["maximum"]))
    if isinstance(v, dict):
        props = s.get("properties", {})
        for name in s.get("required", []):
            if name not in v:
                errors.append("%s: the field %r is missing" % (path, name))
        extra = s.get("additionalProperties", True)
        for name, value in v.items():
            if name in props:
                _check(value, props[name], root, "%s.%s" % (path, name), errors)
            elif extra is False:
                errors.append("%s: the field %r is not in the schema" % (path, name))
            elif isinstance(extra, dict):
                _check(value, extra, root, "%s.%s" % (path, name), errors)
    if isinstance(v, list):
        if "minItems" in s and len(v) < s["minItems"]:
            errors.append("%s: %d items, fewer than %d" % (path, len(v), s["minItems"]))
        if "maxItems" in s and len(v) > s["maxItems"]:
            errors.append("%s: %d items, more than %d" % (path, len(v), s["maxItems"]))
        if "items" in s:
            for i, item in enumerate(v):
                _check(item, s["items"], root, "%s[%d]" % (path, i), errors)


# A field only an option writes says so first: it may then be left out of 'required'.
OPTIONAL = "Only with --"


def undocumented(schema):
    """Schema nodes that describe a field or definition without a description, objects
    that would accept fields they do not list, and fields not required whose description
    does not start with OPTIONAL."""
    out = []

    def walk(s, path):
        if not isinstance(s, dict):
            return
        if "description" not in s and "$ref" not in s and path != "$":
            out.append("%s: no description" % path)
        if s.get("type") == "object" or "properties" in s:
            if s.get("additionalProperties", True) is not False:
                out.append("%s: additionalProperties is not false" % path)
            props = s.get("properties", {})
            missing = {name for name in set(props) - set(s.get("required", []))
                       if not props[name].get("description", "").startswith(OPTIONAL)}
            if missing:
                out.append("%s: fields not required: %s" % (path, sorted(missing)))
        for name, sub in s.get("properties", {}).items():
            if "description" not in sub:
                out.append("%s.%s: no description" % (path, name))
            walk(sub, "%s.%s" % (path, name))
        for name, sub in s.get("$defs", {}).items():
            walk(sub, "$defs.%s" % name)
        if isinstance(s.get("items"), dict) and "properties" in s["items"]:
            walk(s["items"], path + "[]")

    walk(schema, "$")
    return out
