#!/usr/bin/env python3
"""Validates JSON documents against a JSON Schema (draft 2020-12) with the `jsonschema` package,
the specification's reference implementation in Python: tests/suite/experiment.rs checks every
report.json it makes against experiments/report.schema.json through this script, with the venv
scripts/exr_reader.sh makes. Prints one line per error (the message, then the instance path)
and exits 1 if there is any.

Usage: check_schema.py SCHEMA.json DOCUMENT.json...
"""
import json
import sys

import jsonschema


def main(schema_path, *documents):
    with open(schema_path) as f:
        schema = json.load(f)
    jsonschema.Draft202012Validator.check_schema(schema)
    validator = jsonschema.Draft202012Validator(schema)
    failed = False
    for path in documents:
        with open(path) as f:
            document = json.load(f)
        for error in sorted(validator.iter_errors(document), key=lambda e: list(e.absolute_path)):
            where = "/" + "/".join(str(p) for p in error.absolute_path)
            print(f"{path}: {error.message} at {where}")
            failed = True
    return 1 if failed else 0


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    sys.exit(main(*sys.argv[1:]))
