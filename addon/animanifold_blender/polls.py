"""The poll checks the operators share: Object Mode, and an active object of the right kind
(in Object Mode or in any), each refusal worded for the button's tooltip (poll_message_set)."""

from __future__ import annotations

from typing import Callable


def in_object_mode(cls, context) -> bool:
    """Whether the operator `cls` may run in this mode; otherwise it says to switch."""
    if context.mode != "OBJECT":
        cls.poll_message_set("Switch to Object Mode")
        return False
    return True


def active_object_is(cls, context, accepts: Callable[[object], bool], message: str) -> bool:
    """Whether the operator `cls` may run: Object Mode and an active object that `accepts`;
    otherwise it says what to select (`message`)."""
    return in_object_mode(cls, context) and active_object_in_any_mode_is(cls, context, accepts, message)


def active_object_in_any_mode_is(cls, context, accepts: Callable[[object], bool], message: str) -> bool:
    """Whether the active object is one that `accepts`, in whatever mode (for operators that touch
    only its settings, not its mesh); otherwise the operator `cls` says what to select (`message`)."""
    obj = context.active_object
    if obj is None or not accepts(obj):
        cls.poll_message_set(message)
        return False
    return True
