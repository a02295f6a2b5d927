#!/usr/bin/env python3
"""Validates YAML files against a JSON Schema (draft 2020-12), as an editor's
YAML extension does: `validate_yaml_schema.py SCHEMA FILE...`. Prints one line
per invalid file (FILE: the first error, with its path in the document) and
exits 1 if any is invalid, 2 if the schema itself is not a valid schema."""
import json
import sys

import jsonschema
import yaml


def main(argv):
    if len(argv) < 3:
        print("usage: validate_yaml_schema.py SCHEMA FILE...", file=sys.stderr)
        return 2
    with open(argv[1], encoding="utf-8") as f:
        schema = json.load(f)
    try:
        jsonschema.Draft202012Validator.check_schema(schema)
    except jsonschema.SchemaError as e:
        print(f"{argv[1]}: not a valid draft 2020-12 schema: {e.message}", file=sys.stderr)
        return 2
    validator = jsonschema.Draft202012Validator(schema)
    bad = 0
    for path in argv[2:]:
        with open(path, encoding="utf-8") as f:
            doc = yaml.safe_load(f)
        errors = sorted(validator.iter_errors(doc), key=lambda e: list(e.absolute_path))
        if errors:
            bad += 1
            e = errors[0]
            where = "/".join(str(p) for p in e.absolute_path) or "(top)"
            print(f"{path}: {where}: {e.message}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
