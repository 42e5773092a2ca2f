#!/usr/bin/env python3
"""Writes the table rows read from stdin into a generated table of a doc, replacing the
rows that are there: the FDIR parameters (trn_mission --fdir-params) into the
"Parameters" table of docs/FDIR.md, or with a section and a header, any other
table whose rows start with "| `" (trn_mission --message-kinds, docs/ARCHITECTURE.md).

    build/trn_mission --fdir-params | tools/build/docs_params.py docs/FDIR.md
    build/trn_mission --message-kinds | tools/build/docs_params.py docs/ARCHITECTURE.md \
        "Message kinds" "kind | tag | channel | from | to | words | fields"
"""
import sys

HEAD = "| name | default | range | unit | meaning |\n|---|---|---|---|---|\n"


def main():
    path = sys.argv[1]
    section = sys.argv[2] if len(sys.argv) > 2 else "Parameters"
    columns = sys.argv[3] if len(sys.argv) > 3 else None
    table_head = HEAD
    if columns is not None:
        table_head = f"| {columns} |\n|" + "---|" * (columns.count("|") + 1) + "\n"
    rows = sys.stdin.read()
    if not rows.startswith("| `"):
        sys.exit("docs_params.py: no table rows on stdin")
    with open(path, encoding="utf-8") as f:
        text = f.read()
    start = text.find(f"## {section}\n")
    head = text.find(table_head, start)
    if start < 0 or head < 0:
        sys.exit(f"docs_params.py: {path} has no \"## {section}\" table")
    body = head + len(table_head)
    end = body
    while text.startswith("| `", end):
        end = text.index("\n", end) + 1
    with open(path, "w", encoding="utf-8") as f:
        f.write(text[:body] + rows + text[end:])
    print(f"docs_params.py: {rows.count(chr(10))} rows written into {path}")


if __name__ == "__main__":
    main()
