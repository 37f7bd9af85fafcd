"""A skeleton morph held by the core's test hold, for tests of cancellation that must not
depend on the machine's speed.

The core waits HOLD's seconds where its conforming stage starts (a stand-in child process where
the mesher would run), so a cancel asked for before or during the hold stops the morph there.
A job's `stage` is the last stage that reported its end: if it is still one of
BEFORE_THE_HOLD once the job is done, the cancel took effect before the held stage ended, that
is within the hold, however slow the machine. A cancel that only worked after the hold would
leave "conforming" or a later stage.
"""

HOLD = ("conforming", 30.0)
# The method held: the skeleton method reports each stage as it ends, so its stage names tell a
# cancel within the hold from one after it (the field method names each stage as it starts, and
# "conforming" would stand for both). The hold itself (morph_stages.hpp) is the same for every method.
HELD_METHOD = "skeleton"
# A job's stage before any report, the package's hole-space stage, the core's skeleton stage.
BEFORE_THE_HOLD = ("reading the inputs", "holes", "skeleton")
