"""A morph computed in a worker thread (a :class:`~animanifold.core_job.CoreJob`), so that
Blender's interface keeps drawing and Esc can cancel it (the add-on's Morph Selected, run from
the interface). A cancel takes effect at the core's next stage, or within about 0.1 s while
TetGen runs (its `interrupted` check).
"""

from __future__ import annotations

from .core_job import CoreJob
from .morph_pipeline import morph


class MorphJob(CoreJob):
    """`morph(source, target, **options)` in a daemon thread, started at once; its result is
    `manifold`."""

    def __init__(self, source, target, **options):
        super().__init__(morph, source, target, name="animanifold morph", **options)

    @property
    def manifold(self):
        return self.result
