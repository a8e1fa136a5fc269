"""Check: what can be told wrong from a statement alone (clauses and blocks)."""
