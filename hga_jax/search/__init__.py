"""The search: random stream, genetic operators, selection, settings and the GA loop (device code)."""
