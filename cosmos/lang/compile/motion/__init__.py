"""Motion statements to plan segments: one module per statement, on a shared base."""
