#!/usr/bin/env python3
"""The feature glossary (web/data/feature-glossary.json) covers what the classifier writes, and
docs/classifier.md agrees with it.

The glossary is the one home of the one-line explanation of each feature; the run page groups a
run's features by it, and docs/classifier.md's table "Features at a glance" is generated from it.
Checked here (Python 3 standard library):
- every key the classifier writes into `features` (the `to_json` of
  engine/classify/src/features.cpp, `scores` and `label` of decision.cpp) has an entry, and
  every entry is such a key;
- every feature of schema/summary.schema.json has an entry;
- every entry names a group of the glossary, and its error (`error` / `error_of`) is an entry
  pointing back;
- docs/classifier.md holds the table this file renders from the glossary, byte for byte, and
  names every feature in backticks in its prose too.
`feature_glossary_test.py --write` rewrites the table in docs/classifier.md from the glossary.
"""
import json
import os
import re
import sys
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
GLOSSARY = os.path.join(ROOT, "web", "data", "feature-glossary.json")
DOCS = os.path.join(ROOT, "docs", "classifier.md")
BEGIN = "<!-- feature glossary: generated from web/data/feature-glossary.json by tests/docs/feature_glossary_test.py --write -->"
END = "<!-- end of the feature glossary -->"


def read(*parts):
    with open(os.path.join(ROOT, *parts), encoding="utf-8") as f:
        return f.read()


def glossary():
    with open(GLOSSARY, encoding="utf-8") as f:
        return json.load(f)


def written_keys():
    """The keys the classifier writes into a run's features: the object of
    `nlohmann::json to_json(const Features& f)` and what decision.cpp adds to it."""
    src = read("engine", "classify", "src", "features.cpp")
    body = re.search(r"nlohmann::json to_json\(const Features& f\) \{(.*?)\n\}", src, re.S)
    assert body, "features.cpp: to_json(const Features&) not found"
    keys = re.findall(r'\{"([a-z_0-9]+)",', body.group(1))
    decision = read("engine", "classify", "src", "decision.cpp")
    keys += re.findall(r'feats\["([a-z_0-9]+)"\]', decision)
    keys += re.findall(r'\["features"\]\["([a-z_0-9]+)"\]', decision)
    return keys


def render(g):
    """The Markdown table of the glossary: one line per feature, by group."""
    lines = [BEGIN, "", "| group | feature | what it is |", "|---|---|---|"]
    for group in g["groups"]:
        for key, f in g["features"].items():
            if f["group"] != group["id"]:
                continue
            unit = f" [{f['unit']}]" if f.get("unit") else ""
            band = " (only with a band)" if f.get("band") else ""
            lines.append(f"| {group['title']} | `{key}`{unit} | {f['text']}{band} |")
    lines += ["", f"A run has a band: {g['band_classes']['text']}", "", END]
    return "\n".join(lines)


def docs_block(text):
    start, end = text.find(BEGIN), text.find(END)
    if start < 0 or end < 0:
        return None
    return text[start:end + len(END)]


class FeatureGlossaryTest(unittest.TestCase):
    def setUp(self):
        self.g = glossary()
        self.features = self.g["features"]

    def test_every_written_feature_has_an_entry_and_every_entry_is_written(self):
        written = written_keys()
        self.assertGreater(len(written), 30, written)
        self.assertEqual(sorted(set(written) - set(self.features)), [], "features without a glossary entry")
        self.assertEqual(sorted(set(self.features) - set(written)), [], "glossary entries the classifier does not write")

    def test_every_feature_of_the_summary_schema_has_an_entry(self):
        schema = json.loads(read("schema", "summary.schema.json"))
        props = schema["properties"]["classification"]["properties"]["features"]["properties"]
        self.assertEqual(sorted(set(props) - set(self.features)), [])

    def test_entries_are_complete(self):
        groups = {x["id"] for x in self.g["groups"]}
        for key, f in self.features.items():
            with self.subTest(key=key):
                self.assertIn(f["group"], groups)
                self.assertTrue(f["name"].strip() and f["text"].strip())
                self.assertNotIn("\n", f["text"])
                self.assertNotIn("|", f["text"])
                if "error" in f:
                    self.assertEqual(self.features[f["error"]].get("error_of"), key)
                if "error_of" in f:
                    self.assertEqual(self.features[f["error_of"]].get("error"), key)
        self.assertTrue(set(self.g["band_classes"]["classes"]) <= set("abcdef"))

    def test_the_docs_table_is_the_glossary(self):
        block = docs_block(read("docs", "classifier.md"))
        self.assertIsNotNone(block, "docs/classifier.md has no generated table: run this file with --write")
        self.assertEqual(block, render(self.g), "docs/classifier.md's table differs from the glossary: run this file with --write")

    def test_the_docs_prose_names_every_feature(self):
        text = read("docs", "classifier.md")
        start, end = text.find(BEGIN), text.find(END)
        prose = text[:start] + text[end:]
        missing = [k for k in self.features if f"`{k}`" not in prose]
        self.assertEqual(missing, [], "features docs/classifier.md's prose does not name")


if __name__ == "__main__":
    if sys.argv[1:] == ["--write"]:
        text = read("docs", "classifier.md")
        block = docs_block(text)
        if block is None:
            raise SystemExit(f"docs/classifier.md: add the lines {BEGIN!r} and {END!r} where the table goes")
        with open(DOCS, "w", encoding="utf-8") as f:
            f.write(text.replace(block, render(glossary())))
        print("docs/classifier.md: table written")
    else:
        unittest.main()
