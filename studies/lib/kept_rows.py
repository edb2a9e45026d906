"""Rows of a study's committed Markdown table, for runs whose bundles are not on this machine.

A study's bundles live outside the repository (hundreds of MB) and do not outlive a machine;
its report is committed. When a study is made again in parts, on another machine, the rows of
its earlier runs are read back from the committed report: a row whose run has no bundle here
is kept as it was written, and the report says how many rows were kept.
"""
import os


def table_rows(path, header_start):
    """The body rows of the first Markdown table in file `path` whose header line starts with
    `header_start`: a list of rows, each the list of its cells (stripped), in the file's order.
    [] when the file or the table is missing."""
    if not os.path.exists(path):
        return []
    rows, inside = [], False
    with open(path) as f:
        for line in f:
            line = line.rstrip("\n")
            if not inside:
                inside = line.startswith(header_start)
                continue
            if not line.startswith("|"):
                break
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if set("".join(cells)) <= set("-: "):  # the separator line
                continue
            rows.append(cells)
    return rows


def number(cell):
    """The first number of a cell such as "1.883 +- 0.01", "a (0.59)" -> None, "-" -> None."""
    word = cell.split()[0] if cell.split() else ""
    try:
        return float(word)
    except ValueError:
        return None


def plus_minus(cell):
    """(value, uncertainty) of a cell "v +- u"; None for what is not a number."""
    parts = [p.strip() for p in cell.split("+-")]
    return number(parts[0]), number(parts[1]) if len(parts) > 1 else None


def label(cell):
    """(label, confidence) of a cell "b (0.98)"; the confidence None when it is not a number."""
    name, _, rest = cell.partition("(")
    return name.strip(), number(rest.rstrip(")"))
