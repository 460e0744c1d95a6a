"""Controllers: discrete PID and gain-scheduled PID (SPEC.md 2.5, 1.1)."""
