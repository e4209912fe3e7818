"""Running: many seeded runs in batches and blocks, over devices and processes, within memory."""
