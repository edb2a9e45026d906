#!/usr/bin/python3
"""studies/lib/kept_notes.py: a report made again keeps what was written below its marker.

A report is written, text is added below the marker by hand, and the report is made again with
new tables by kept_notes.write, as the study scripts do: the hand-written text must
come through byte for byte and the old tables must not; a report without a marker, or no report
yet, gets the bare marker so that the next hand-written text has its place.
"""
import os
import tempfile
import unittest

from studies.lib import kept_notes


class KeptNotes(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.path = os.path.join(self.dir.name, "report.md")

    def tearDown(self):
        self.dir.cleanup()

    def test_no_report_yet_gets_the_bare_marker(self):
        kept_notes.write(self.path, "| old table |\n")
        with open(self.path) as f:
            self.assertEqual(f.read(), "| old table |\n\n" + kept_notes.MARKER + "\n")

    def test_hand_written_text_survives_new_tables(self):
        kept_notes.write(self.path, "| old table |\n")
        notes = "## What the runs show\n\n- a finding with | pipes | and a trailing space \n"
        with open(self.path, "a") as f:
            f.write(notes)
        kept_notes.write(self.path, "| new table |\n")
        with open(self.path) as f:
            text = f.read()
        self.assertEqual(text, "| new table |\n\n" + kept_notes.MARKER + "\n" + notes)
        self.assertNotIn("old table", text)

    def test_report_without_marker_gets_the_bare_marker(self):
        with open(self.path, "w") as f:
            f.write("| a table made before the marker existed |\n")
        self.assertEqual(kept_notes.below_marker(self.path), kept_notes.MARKER + "\n")


if __name__ == "__main__":
    unittest.main()
