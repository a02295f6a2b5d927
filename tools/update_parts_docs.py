#!/usr/bin/env python3
"""Writes the docs made from the part registry (`make docs-parts`):

- docs/boards.md: the parts table between `<!-- parts-table:begin -->` and
  `<!-- parts-table:end -->`, from `ddmr-hil parts --markdown`;
- docs/schema/board.schema.json: `properties.parts.items`, from
  `ddmr-hil parts --schema` (the rest of the schema is written by hand).

Usage: update_parts_docs.py [DDMR_HIL]   (default: build/ddmr-hil)

tests/tools/parts_command_test.cpp fails while either is out of date. Exit 0
written (or already up to date), 2 an error (one line on stderr)."""
import json
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
BOARDS_MD = ROOT / "docs" / "boards.md"
BOARD_SCHEMA = ROOT / "docs" / "schema" / "board.schema.json"
BEGIN = "<!-- parts-table:begin -->\n"
END = "<!-- parts-table:end -->"


class Refused(Exception):
    pass


def parts(cli, option):
    r = subprocess.run([cli, "parts", option], capture_output=True, text=True, check=False)
    if r.returncode != 0:
        raise Refused(f"{cli} parts {option}: exit {r.returncode}: {r.stderr.strip()}")
    return r.stdout


def with_table(md, table):
    b = md.find(BEGIN)
    e = md.find(END)
    if b < 0 or e < b:
        raise Refused(f"{BOARDS_MD}: no '{BEGIN.strip()}' ... '{END}' markers")
    return md[: b + len(BEGIN)] + "\n" + table + "\n" + md[e:]


def with_items(schema_text, items):
    schema = json.loads(schema_text)
    props = schema.get("properties", {})
    if "parts" not in props:
        raise Refused(f"{BOARD_SCHEMA}: no properties.parts to put the items in")
    props["parts"]["items"] = items
    # As the file is written by hand: two-space indent, UTF-8, final newline.
    return json.dumps(schema, indent=2, ensure_ascii=False) + "\n"


def update(path, make):
    old = path.read_text(encoding="utf-8")
    new = make(old)
    if new == old:
        print(f"{path.relative_to(ROOT)}: up to date")
        return
    path.write_text(new, encoding="utf-8")
    print(f"{path.relative_to(ROOT)}: written")


def main(argv):
    cli = argv[1] if len(argv) > 1 else str(ROOT / "build" / "ddmr-hil")
    try:
        table = parts(cli, "--markdown")
        items = json.loads(parts(cli, "--schema"))
        update(BOARDS_MD, lambda md: with_table(md, table))
        update(BOARD_SCHEMA, lambda text: with_items(text, items))
    except (Refused, OSError, ValueError) as e:
        print(f"update_parts_docs: error: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
