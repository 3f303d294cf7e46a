"""Benchmarks that print ratios measured in one run: ``python -m benchmarks.NAME`` from the
repository root (not part of the installed package; their results are in docs/)."""
