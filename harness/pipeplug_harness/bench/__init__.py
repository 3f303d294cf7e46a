"""Benchmarks that print ratios measured in one run (``python -m pipeplug_harness.bench.X``)."""
