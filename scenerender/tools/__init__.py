"""Tools around rendering: image comparison for CI, benchmarks."""
