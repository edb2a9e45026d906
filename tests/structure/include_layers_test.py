#!/usr/bin/env python3
"""No include loop and no include against the layers, anywhere in the repository.

Every `#include "..."` line of every C/C++ file of the repository (`git ls-files`, with the new
files not yet added) is resolved as the compiler resolves it for the target that builds the
file: in the including file's own folder first, then in the include roots of its folder (ROOTS,
as the CMakeLists give them). Angle-bracket includes are the system's and the libraries'.
Then three checks, each failure printed as FILE: #include "NAME": the rule broken:

 (a) No include loop. The loop is looked for between units, not files: a unit is a header with
     its own .cpp (the .cpp of the same name that includes it, also from another folder:
     engine/src/params.cpp is the unit of engine/include/compaction/params.hpp), or a file alone.
     A.hpp -> B.hpp with B.cpp -> A.hpp is a loop of the code, though no file includes itself
     again and the include guards hide it from the compiler.
 (b) No include against the layers. LAYERS names every layer (a folder; a file belongs to the
     deepest one that holds it) with the layers its files may include besides their own; any
     other include is against the layers. The layers themselves must form no loop.
 (c) Every quoted include names a file of the repository: one that resolves to nothing means
     ROOTS is out of step with the CMakeLists (or the include is wrong).

ALLOWED_LOOPS lists the loops known and being removed elsewhere, each with why; a listed loop
that no longer exists fails too, so that the list only shrinks.

The first case runs the checks on a small tree made for it, with one loop, one include against
the layers and one include that names nothing, so the checker is seen to find each; the second
runs them on the repository.
"""
import os
import re
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))

SOURCE = re.compile(r"\.(c|cc|cpp|cxx|h|hh|hpp|hxx|ipp|inl)$")
HEADER = re.compile(r"\.(h|hh|hpp|hxx)$")
INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"')

ENGINE_API = ["engine/include"]  # compaction::api: the public types, their JSON, the bundle I/O
CLI = ["engine/cli"]              # compaction::command_line: every program's grammar

# The rooms of server/, from the ground up, and the rooms each may include besides its own
# (server/CMakeLists.txt says the same above the sources of each). Every room may include the
# engine's public headers and the command-line grammar, never the engine's internals.
SERVER_ROOMS = {
    "input": [],                                  # a client's input checked, ApiError
    "config": ["input"],                          # command-line options, tokens
    "http": ["input", "config"],                  # the HTTP server, endpoint table, guard
    "store": ["input"],                           # SQLite: the only files with SQL
    "plan": ["input", "store"],                   # planning: grids, adaptive, regions, cost
    "views": ["store", "plan"],                   # JSON documents of the records
    "exchange": ["input", "config", "http", "store", "plan", "views"],  # uploads, export, import
    "routes": ["input", "config", "http", "store", "plan", "views", "exchange"],  # REST API
}

# Each layer (a folder) and the layers its files may include besides their own.
LAYERS = {
    # The engine: the public API below its implementation; the classifier reads the public
    # result type only; the programs on top, their grammar below them all.
    "engine/include": [],
    "engine/src": ENGINE_API,
    "engine/classify/include": ENGINE_API,
    "engine/classify/src": ENGINE_API + ["engine/classify/include"],
    "engine/cli": ENGINE_API,
    "engine/apps": ENGINE_API + CLI + ["engine/classify/include"],           # compaction-run
    "engine/classify/apps": ENGINE_API + CLI + ["engine/classify/include"],  # compaction-classify
    # The server and the worker: the engine's public API and the grammar only; never each other.
    **{f"server/{room}": ENGINE_API + CLI + [f"server/{r}" for r in may]
       for room, may in SERVER_ROOMS.items()},
    "server": ENGINE_API + CLI + [f"server/{r}" for r in SERVER_ROOMS],      # main.cpp
    "worker": ENGINE_API + CLI,
    # Tests and benchmarks may include what they test; nothing includes them.
    "tests": ["engine/include", "engine/src", "engine/classify/include", "engine/cli",
              "server", *[f"server/{r}" for r in SERVER_ROOMS], "worker"],
    "bench": ["engine/include", "engine/src", "engine/cli", "worker"],
}

# The include roots of the targets that build the files of each folder (a file takes the
# deepest folder listed), as the CMakeLists set them (target_include_directories, with what the
# linked libraries make PUBLIC).
ROOTS = {
    "engine/include": ["engine/include"],
    "engine/src": ["engine/include", "engine/src"],
    "engine/cli": ["engine/cli", "engine/include"],
    "engine/apps": ["engine/include", "engine/classify/include", "engine/cli"],
    "engine/classify": ["engine/classify/include", "engine/include", "engine/cli"],
    "server": ["server", "engine/include", "engine/cli"],
    "worker": ["worker", "engine/include", "engine/cli"],
    "tests/engine": ["engine/src", "engine/include"],
    "tests/classify": ["engine/classify/include", "engine/include"],
    "tests/server": ["server", "engine/include", "engine/cli"],
    "tests/worker": ["tests/server", "worker", "engine/include", "engine/cli"],
    "bench": ["engine/src", "engine/include"],
    "bench/server": ["worker", "engine/include", "engine/cli"],
}

# Loops known and being removed, each a set of units (named by their header, or by the file of a
# unit without one) with the reason it is allowed for now.
ALLOWED_LOOPS = []


def deepest(table, path):
    """The key of `table` that is the deepest folder holding `path`, or None."""
    best = None
    for key in table:
        if path.startswith(key + "/") and (best is None or len(key) > len(best)):
            best = key
    return best


def tracked_sources(root):
    """The repository's C/C++ files, relative to root: tracked ones and new ones not ignored
    (also when the checkout belongs to another user, which git otherwise refuses as dubious)."""
    out = subprocess.run(["git", "-c", "safe.directory=*", "-C", root, "ls-files", "-z",
                          "--cached", "--others", "--exclude-standard"],
                         check=True, capture_output=True).stdout.decode()
    return sorted({f for f in out.split("\0")
                   if SOURCE.search(f) and os.path.isfile(os.path.join(root, f))})


def read_includes(root, files):
    """{file: [(line number, name)]} of the quoted includes."""
    out = {}
    for f in files:
        with open(os.path.join(root, f), encoding="utf-8", errors="replace") as text:
            out[f] = [(n, m.group(1)) for n, line in enumerate(text, 1)
                      if (m := INCLUDE.match(line))]
    return out


def resolve(name, including, files, roots):
    """The file an include names: beside the including file, else under its folder's roots."""
    here = os.path.dirname(including)
    for folder in [here] + roots.get(deepest(roots, including), []):
        path = os.path.normpath(os.path.join(folder, name))
        if path in files:
            return path
    return None


def units_of(files, edges):
    """{file: unit}: a .cpp joins the header of its own name that it includes; others alone."""
    unit = {f: f for f in files}
    for f in files:
        if HEADER.search(f):
            continue
        stem = os.path.splitext(os.path.basename(f))[0]
        own = [t for _, _, t in edges.get(f, [])
               if HEADER.search(t) and os.path.splitext(os.path.basename(t))[0] == stem]
        if own:
            unit[f] = own[0]
    return unit


def loops(graph):
    """The strongly connected components of more than one node, or with a self-edge (Tarjan)."""
    index, low, stack, on_stack, found, counter = {}, {}, [], set(), [], [0]
    sys.setrecursionlimit(max(10000, sys.getrecursionlimit()))

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = set()
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.add(w)
                if w == v:
                    break
            if len(component) > 1 or v in graph.get(v, ()):
                found.append(component)

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def check(root, files, layers=LAYERS, roots=ROOTS, allowed_loops=ALLOWED_LOOPS):
    """The problems of the tree, one line each."""
    problems = []
    file_set = set(files)
    includes = read_includes(root, files)

    # (c) every include resolves; the edges of the file graph
    edges = {}
    for f in files:
        for line, name in includes[f]:
            target = resolve(name, f, file_set, roots)
            if target is None:
                problems.append(f'{f}:{line}: #include "{name}": names no file of the repository '
                                f"beside it or under its include roots {roots.get(deepest(roots, f), [])} "
                                "(ROOTS out of step with the CMakeLists?)")
            else:
                edges.setdefault(f, []).append((line, name, target))

    # (b) the layers: their own order first, then every include
    for loop in loops({layer: set(may) for layer, may in layers.items()}):
        problems.append(f"LAYERS: the layers {sorted(loop)} may include each other: no order")
    for f in files:
        here = deepest(layers, f)
        if here is None:
            problems.append(f"{f}: in no layer of LAYERS (add its folder)")
            continue
        for line, name, target in edges.get(f, []):
            there = deepest(layers, target)
            if there != here and there not in layers[here]:
                problems.append(f'{f}:{line}: #include "{name}" ({target}): against the layers: '
                                f"{here}/ may include {layers[here] or 'nothing'} besides itself, "
                                f"not {there}/")

    # (a) loops of units
    unit = units_of(files, edges)
    graph = {}
    for f in files:
        for _, _, target in edges.get(f, []):
            if unit[target] != unit[f]:
                graph.setdefault(unit[f], set()).add(unit[target])
    allowed = [(frozenset(units), why) for units, why in allowed_loops]
    seen_allowed = set()
    for loop in loops(graph):
        match = [units for units, _ in allowed if units == frozenset(loop)]
        if match:
            seen_allowed.add(match[0])
            continue
        ties = sorted(f'{f} -> "{name}" ({target})' for f in files
                      for _, name, target in edges.get(f, [])
                      if unit[f] in loop and unit[target] in loop and unit[f] != unit[target])
        problems.append(f"include loop of the units {sorted(loop)} (a header with its own .cpp is "
                        "one unit): " + "; ".join(ties))
    for units, why in allowed:
        if units not in seen_allowed:
            problems.append(f"ALLOWED_LOOPS: {sorted(units)} is no loop any more: remove its entry "
                            f"({why})")
    return problems


class IncludeLayersTest(unittest.TestCase):
    def test_checker_finds_a_loop_a_layer_broken_and_an_include_of_nothing(self):
        tree = {
            # b.hpp -> a.hpp, a.cpp -> b.hpp: a loop through a.hpp's own .cpp
            "low/a.hpp": "#pragma once\n",
            "low/a.cpp": '#include "a.hpp"\n#include "low/b.hpp"\n',
            "low/b.hpp": '#include "low/a.hpp"\n',
            # low/ may not include high/
            "low/c.cpp": '#include "high/d.hpp"\n',
            "high/d.hpp": '#include "low/a.hpp"\n',
            # names nothing
            "high/e.cpp": '#include "missing.hpp"\n',
        }
        layers = {"low": [], "high": ["low"]}
        roots = {"low": ["."], "high": ["."]}
        with tempfile.TemporaryDirectory() as root:
            for path, text in tree.items():
                os.makedirs(os.path.join(root, os.path.dirname(path)), exist_ok=True)
                with open(os.path.join(root, path), "w") as f:
                    f.write(text)
            # and an allowed loop that is no loop
            problems = check(root, sorted(tree), layers, roots,
                             [({"high/d.hpp", "high/e.cpp"}, "test")])
        text = "\n".join(problems)
        self.assertEqual(len(problems), 4, text)
        self.assertIn("include loop of the units ['low/a.hpp', 'low/b.hpp']", text)
        self.assertIn('low/a.cpp -> "low/b.hpp"', text)
        self.assertIn('low/c.cpp:1: #include "high/d.hpp" (high/d.hpp): against the layers', text)
        self.assertIn('high/e.cpp:1: #include "missing.hpp": names no file', text)
        self.assertIn("ALLOWED_LOOPS: ['high/d.hpp', 'high/e.cpp'] is no loop any more", text)
        # and layers that include each other have no order
        self.assertTrue(any("no order" in p for p in
                            check(root, [], {"x": ["y"], "y": ["x"]}, roots, [])))

    def test_the_repository_has_no_include_loop_and_none_against_the_layers(self):
        files = tracked_sources(ROOT)
        self.assertGreater(len(files), 100)
        problems = check(ROOT, files)
        self.assertEqual(problems, [], "\n" + "\n".join(problems))

    def test_server_cmakelists_states_the_rooms_order_of_this_script(self):
        with open(os.path.join(ROOT, "server", "CMakeLists.txt")) as f:
            text = f.read()
        stated = {}
        for m in re.finditer(r"#\s+(\w+)/:.*?May include: ([^.]*)\.", text, re.S):
            stated[m.group(1)] = m.group(2)
        for room, may in SERVER_ROOMS.items():
            self.assertIn(room, stated, f"server/CMakeLists.txt says nothing of {room}/")
            words = re.sub(r"\s*#\s*", " ", stated[room]).strip()
            expected = ", ".join(may) if may else "nothing of the server"
            if room == "routes":
                expected = "every room"
            self.assertEqual(words, expected, f"server/CMakeLists.txt on {room}/")
            self.assertTrue(os.path.isdir(os.path.join(ROOT, "server", room)), room)


if __name__ == "__main__":
    unittest.main(verbosity=2)
