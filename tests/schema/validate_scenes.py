#!/usr/bin/python3
"""Validates TOML scenes against anamorph's JSON Schema with an independent validator.

Usage: validate_scenes.py SCHEMA.json FILE.toml...   (a FILE of "-" reads one scene from stdin)

Uses Debian's python3-jsonschema (Draft 2020-12) and Python's tomllib, nothing of anamorph's
own code. For each file prints "ok FILE" or "bad FILE: <dotted.path>: <message>" for the error
jsonschema's best_match picks (the deepest, most specific one). Exit code: 0 when every file is
valid, 1 otherwise, 2 on a usage error.
"""
import json
import sys
import tomllib

from jsonschema import Draft202012Validator
from jsonschema.exceptions import best_match


def dotted(path):
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (("." if out else "") + str(p))
    return out or "(top)"


def main(argv):
    if len(argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    with open(argv[1]) as f:
        schema = json.load(f)
    Draft202012Validator.check_schema(schema)
    validator = Draft202012Validator(schema)
    bad = 0
    for name in argv[2:]:
        text = sys.stdin.read() if name == "-" else open(name, encoding="utf-8").read()
        scene = tomllib.loads(text)
        error = best_match(validator.iter_errors(scene))
        if error is None:
            print(f"ok {name}")
            continue
        bad += 1
        print(f"bad {name}: {dotted(error.absolute_path)}: {error.message[:300]}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
