"""The studies: each folder a record of what was measured, its scripts and its results (README.md).

Run a study's script as a module from the repository's root, e.g.
`python3 -m studies.validation.compacted_zone --help`."""
