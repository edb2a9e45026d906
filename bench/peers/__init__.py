"""Peer benchmarks: python3 -m bench.peers.matter_vs_engine --matter SRC (Matter, the authors'
code, built from a checkout given on the command line, against compaction-run on one scene)."""
