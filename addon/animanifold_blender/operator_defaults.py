"""Operator properties that default to the panel's settings."""

from __future__ import annotations


def option(op, settings, name: str, settings_name: str | None = None):
    """The operator's property `name` when the caller set it, else the setting
    (`settings_name`, default the same name) the panel shows."""
    if op.properties.is_property_set(name):
        return getattr(op, name)
    return getattr(settings, settings_name or name)
