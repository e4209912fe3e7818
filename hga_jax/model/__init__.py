"""The model: scenario, geometry, the feasibility rules (collision), tangents, decoding,
fitness, the exact solver and the float64 path."""
