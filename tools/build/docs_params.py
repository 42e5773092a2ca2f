#!/usr/bin/env python3
"""Writes the FDIR parameter rows read from stdin (trn_mission --fdir-params) into the
"Parameters" table of docs/FDIR.md, replacing the rows that are there.

    build/trn_mission --fdir-params | tools/build/docs_params.py docs/FDIR.md
"""
import sys

HEAD = "| name | default | range | unit | meaning |\n|---|---|---|---|---|\n"


def main():
    path = sys.argv[1]
    rows = sys.stdin.read()
    if not rows.startswith("| `"):
        sys.exit("docs_params.py: no parameter rows on stdin")
    with open(path, encoding="utf-8") as f:
        text = f.read()
    start = text.find("## Parameters\n")
    head = text.find(HEAD, start)
    if start < 0 or head < 0:
        sys.exit(f"docs_params.py: {path} has no \"## Parameters\" table")
    body = head + len(HEAD)
    end = body
    while text.startswith("| `", end):
        end = text.index("\n", end) + 1
    with open(path, "w", encoding="utf-8") as f:
        f.write(text[:body] + rows + text[end:])
    print(f"docs_params.py: {rows.count(chr(10))} rows written into {path}")


if __name__ == "__main__":
    main()
