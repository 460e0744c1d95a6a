"""Controllers: discrete PID and gain-scheduled PID (§temperature-control, §crawler-hardware)."""

__all__ = ["pid", "relay"]
