#!/usr/bin/env python3
"""@file count_tests.py
@brief Counts one GoogleTest XML report test case by test case: passed, failed, skipped.

Usage: count_tests.py REPORT.xml
Prints "PASSED FAILED SKIPPED" on the first line, then the name of every skipped test
(Suite.Name), one a line. A test case that did not run because it is disabled
(status="notrun") is not counted. Each <testcase> is read, not the totals on
<testsuites>: GoogleTest 1.12 writes `skipped` only on each <testsuite>, and totals
cannot be checked against the cases they claim to sum. Exit status 2 on a report
that is not well-formed XML.
"""
import sys
import xml.etree.ElementTree as ET


def main() -> int:
    try:
        root = ET.parse(sys.argv[1]).getroot()
    except (ET.ParseError, OSError) as e:
        print(f"{sys.argv[1]}: {e}", file=sys.stderr)
        return 2
    passed = failed = 0
    skipped = []
    for case in root.iter("testcase"):
        if case.get("status") == "notrun":
            continue
        name = f"{case.get('classname')}.{case.get('name')}"
        if case.find("failure") is not None or case.find("error") is not None:
            failed += 1
        elif case.get("result") == "skipped" or case.find("skipped") is not None:
            skipped.append(name)
        else:
            passed += 1
    print(passed, failed, len(skipped))
    for name in skipped:
        print(name)
    return 0


if __name__ == "__main__":
    sys.exit(main())
