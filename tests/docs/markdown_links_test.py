#!/usr/bin/env python3
"""Every relative link and image in the repository's Markdown files leads somewhere.

For each tracked *.md file (`git ls-files '*.md'`), every inline link or image `[text](target)`,
`![alt](target)`, every reference definition `[id]: target` and every HTML `href`/`src` outside
code is checked: a target with a scheme (http:, https:, mailto:, ...) is skipped; any other must
name a file or folder that exists, relative to the Markdown file (or to the repository's root
when it starts with `/`, as GitHub reads it); a `#anchor`, alone or after a Markdown file, must
be the GitHub slug of one of that file's headings (or an explicit `id`/`name` there). The test
fails listing every broken link as FILE:LINE: TARGET: what is wrong.

The first case runs the checker on a small tree made for it, with one broken link of each kind,
so the checker is seen to find them; the second runs it on the repository.
"""
import os
import re
import subprocess
import tempfile
import unittest
import urllib.parse

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))

FENCE = re.compile(r"^ {0,3}(`{3,}|~{3,})")
INLINE = re.compile(r"!?\[(?:[^\[\]]|\[[^\[\]]*\])*\]\(\s*(<[^>]*>|[^\s()]*(?:\([^\s()]*\)[^\s()]*)*)"
                    r"(?:\s+(?:\"[^\"]*\"|'[^']*'|\([^)]*\)))?\s*\)")
REFERENCE = re.compile(r"^ {0,3}\[[^\]]+\]:\s*(<[^>]*>|\S+)")
HTML = re.compile(r"<(?:a|img)\b[^>]*?\b(?:href|src)\s*=\s*[\"']([^\"']*)[\"']", re.I)
HTML_ANCHOR = re.compile(r"<[a-z][^>]*?\b(?:id|name)\s*=\s*[\"']([^\"']*)[\"']", re.I)
CODE_SPAN = re.compile(r"(`+)(.+?)\1")
SCHEME = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*:")
ATX = re.compile(r"^ {0,3}(#{1,6})[ \t]+(.*?)[ \t]*#*[ \t]*$")


def markdown_files(root):
    """The tracked Markdown files, relative to root (also when the checkout belongs to another
    user than the one running the test, which git otherwise refuses as dubious ownership)."""
    out = subprocess.run(["git", "-c", "safe.directory=*", "-C", root, "ls-files", "-z", "--",
                          "*.md"], check=True, capture_output=True).stdout.decode()
    return sorted(f for f in out.split("\0") if f)


def prose_lines(text):
    """(line number, line, line with its code spans blanked) of the text outside fenced code
    blocks."""
    fence = None
    for number, line in enumerate(text.split("\n"), 1):
        m = FENCE.match(line)
        if fence:
            if m and m.group(1)[0] == fence[0] and len(m.group(1)) >= len(fence):
                fence = None
            continue
        if m:
            fence = m.group(1)
            continue
        yield number, line, CODE_SPAN.sub(lambda c: " " * len(c.group(0)), line)


def slug(heading):
    """GitHub's anchor of a heading: its text as rendered, lower case, punctuation dropped but
    hyphens and underscores, each space a hyphen."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link or image: its text
    text = re.sub(r"<[^>]+>", "", text)                          # HTML tags
    text = text.replace("`", "")
    text = text.lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path):
    """The anchors a Markdown file offers: its headings' slugs (a repeated one gets -1, -2, ...)
    and explicit id or name attributes."""
    with open(path, encoding="utf-8") as f:
        text = f.read()
    found, seen = set(), {}
    for _, line, prose in prose_lines(text):
        m = ATX.match(line)
        if m:
            base = slug(m.group(2))
            n = seen.get(base, 0)
            seen[base] = n + 1
            found.add(base if n == 0 else "%s-%d" % (base, n))
        found.update(HTML_ANCHOR.findall(prose))
    return found


def targets(text):
    """(line number, target) of every link, image, reference definition and HTML href/src."""
    for number, _, line in prose_lines(text):
        for m in INLINE.finditer(line):
            yield number, m.group(1)
        m = REFERENCE.match(line)
        if m:
            yield number, m.group(1)
        for m in HTML.finditer(line):
            yield number, m.group(1)


def broken_links(root, files):
    """Every broken relative link of the files (paths relative to root), as
    'FILE:LINE: TARGET: reason'."""
    problems, anchor_cache = [], {}
    for rel in files:
        path = os.path.join(root, rel)
        with open(path, encoding="utf-8") as f:
            text = f.read()
        for number, target in targets(text):
            target = target.strip()
            if target.startswith("<") and target.endswith(">"):
                target = target[1:-1]
            if not target or SCHEME.match(target):
                continue
            name, _, anchor = target.partition("#")
            name = urllib.parse.unquote(name)
            if not name:
                dest = path
            elif name.startswith("/"):
                dest = os.path.join(root, name.lstrip("/"))
            else:
                dest = os.path.normpath(os.path.join(os.path.dirname(path), name))
            where = "%s:%d: %s" % (rel, number, target)
            if not os.path.exists(dest):
                problems.append("%s: no such file or folder" % where)
                continue
            if anchor and dest.endswith(".md") and os.path.isfile(dest):
                if dest not in anchor_cache:
                    anchor_cache[dest] = anchors(dest)
                if urllib.parse.unquote(anchor) not in anchor_cache[dest]:
                    problems.append("%s: no heading with the anchor #%s in %s"
                                    % (where, anchor, os.path.relpath(dest, root)))
    return problems


class CheckerFindsWhatIsBroken(unittest.TestCase):
    def test_each_kind_of_broken_link_is_listed_and_good_ones_are_not(self):
        with tempfile.TemporaryDirectory() as d:
            os.makedirs(os.path.join(d, "docs", "img"))
            open(os.path.join(d, "docs", "img", "a.png"), "wb").close()
            with open(os.path.join(d, "docs", "guide.md"), "w") as f:
                f.write("# The guide\n\n## Run it: `compaction-run` (one scene)\n\n"
                        "## Run it: `compaction-run` (one scene)\n\n<a id=\"kept\"></a>\n")
            with open(os.path.join(d, "README.md"), "w") as f:
                f.write("\n".join([
                    "# Top",
                    "[guide](docs/guide.md) ![a](docs/img/a.png) [folder](docs/img/)",
                    "[heading](docs/guide.md#run-it-compaction-run-one-scene)",
                    "[second heading](docs/guide.md#run-it-compaction-run-one-scene-1)",
                    "[explicit](docs/guide.md#kept) [self](#top) [web](https://example.org/x)",
                    "[root](/docs/guide.md) [mail](mailto:a@b.c) [ref]: docs/guide.md",
                    "`[in code](missing-in-code.md)`",
                    "```",
                    "[in a fence](missing-in-fence.md)",
                    "```",
                    "[gone](docs/gone.md)",
                    "![gone image](docs/img/b.png)",
                    "[bad anchor](docs/guide.md#no-such-heading)",
                    "[bad self](#nowhere)",
                    "[ref2]: docs/gone-too.md",
                    "<img src=\"docs/img/c.png\">",
                ]) + "\n")
            problems = broken_links(d, ["README.md", "docs/guide.md"])
        self.assertEqual(problems, [
            "README.md:11: docs/gone.md: no such file or folder",
            "README.md:12: docs/img/b.png: no such file or folder",
            "README.md:13: docs/guide.md#no-such-heading: no heading with the anchor "
            "#no-such-heading in docs/guide.md",
            "README.md:14: #nowhere: no heading with the anchor #nowhere in README.md",
            "README.md:15: docs/gone-too.md: no such file or folder",
            "README.md:16: docs/img/c.png: no such file or folder",
        ])

    def test_slugs_are_githubs(self):
        self.assertEqual(slug("Pore contact: one velocity field or two (`pore_contact`)"),
                         "pore-contact-one-velocity-field-or-two-pore_contact")
        self.assertEqual(slug("The 3D column (`geometry = pseudo1d_3d`)"),
                         "the-3d-column-geometry--pseudo1d_3d")
        self.assertEqual(slug("Band speed vs q_y/(rho V^2)"), "band-speed-vs-q_yrho-v2")


class RepositoryLinks(unittest.TestCase):
    def test_every_relative_link_in_the_repository_resolves(self):
        files = markdown_files(ROOT)
        self.assertIn("README.md", files)
        problems = broken_links(ROOT, files)
        self.assertEqual(problems, [], "%d broken links in Markdown files:\n%s"
                         % (len(problems), "\n".join(problems)))


if __name__ == "__main__":
    unittest.main()
