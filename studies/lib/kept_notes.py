"""The hand-written part of a generated report, kept when its tables are made again.

A study's script writes the report's tables from its runs; what people wrote about the numbers
goes below MARKER, and the script carries it over, as it was, into the report it writes next.
"""
import os

MARKER = "<!-- notes: kept when the tables are made again -->"


def below_marker(path):
    """The text of file `path` from MARKER on (the marker included); the marker alone, with its
    newline, when the file or its marker is missing."""
    if os.path.exists(path):
        with open(path) as f:
            old = f.read()
        if MARKER in old:
            return old[old.index(MARKER):]
    return MARKER + "\n"


def write(path, text):
    """Write the report `path`: `text` (the tables made now), a newline, then what the report
    there now holds from MARKER on (below_marker)."""
    notes = below_marker(path)
    with open(path, "w") as f:
        f.write(text + "\n" + notes)
