"""What the study scripts share: running compaction-run and reading its bundles (runs), the
paper's examples (examples), number formats (cells), statistics (spread), movie.bin (movie) and
the hand-written parts of a generated report (kept_notes, kept_rows)."""
