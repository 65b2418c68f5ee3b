"""Validates a SARIF log (stdin) against the SARIF 2.1.0 JSON schema, formats included.

Prints each violation and exits 1 if there are any. `scripts/test` installs
`jsonschema[format-nongpl]` (whose format checkers include `uri` and `uri-reference`).
"""

import json
import pathlib
import sys

from jsonschema import Draft7Validator

SCHEMA = pathlib.Path(__file__).with_name("sarif-schema-2.1.0.json")


def main() -> int:
    schema = json.loads(SCHEMA.read_text())
    checker = Draft7Validator.FORMAT_CHECKER
    missing = {"uri", "uri-reference"} - set(checker.checkers)
    if missing:
        print(f"format checkers missing: {sorted(missing)}: pip install 'jsonschema[format-nongpl]'")
        return 2
    validator = Draft7Validator(schema, format_checker=checker)
    log = json.load(sys.stdin)
    errors = sorted(validator.iter_errors(log), key=lambda e: list(e.absolute_path))
    for error in errors:
        where = "/".join(str(p) for p in error.absolute_path)
        print(f"{where}: {error.message}")
    print(f"{len(errors)} violation(s)")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
