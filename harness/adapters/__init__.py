"""Adapters that put a system behind the `untimely/1` protocol (docs/reference/protocol.md)."""
