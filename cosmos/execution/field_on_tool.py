"""When a link's obstacle field reaches the tool although the task leaves a null space: the log says so.

Where the task leaves a null space (ORIENTATION FREE on the PUMA) the servo
applies the links' field through ``N^T`` only, so the tool keeps its path; a
link dangerously close gets the whole field, which moves the tool
(:mod:`cosmos.runtime.null_space`). This watch turns that into two
``field_on_tool`` events: when it begins (the link, the obstacle, its distance,
the share of the field on the tool) and when it ends (the largest deviation of
the tool from its path meanwhile, as the protective stop measures it).
"""

from __future__ import annotations

from collections.abc import Callable

from cosmos.runtime.null_space import LinkField, NullSpaceTerms

START_SHARE = 0.1
"""An episode begins when this share of the links' field reaches the tool ..."""
END_SHARE = 0.01
"""... and ends when the share falls below this."""


class FieldOnToolWatch:
    """Follows the links' share of the field reaching the tool, one episode at a time."""

    def __init__(self) -> None:
        self._episode: tuple[str, str] | None = None
        self._deviation_m = 0.0

    def update(self, null_space: NullSpaceTerms, field: LinkField, deviation_m: Callable[[], float]) -> str:
        """The event's reason when an episode begins or ends, else "".

        Args:
            null_space: The servo's null-space terms at the last evaluation.
            field: The obstacle field as the servo holds it.
            deviation_m: Measures the tool's distance from its path now, in [m].
        """
        share = null_space.link_share_to_tool
        if self._episode is None:
            if share < START_SHARE:
                return ""
            self._episode = (field.link, field.obstacle)
            self._deviation_m = deviation_m()
            return (
                f"{field.link} is {field.clearance_m * 1e3:.0f} mm from {field.obstacle}: the null space "
                f"cannot keep it clear, {share:.0%} of its field acts on the tool "
                f"(tool {self._deviation_m * 1e3:.1f} mm off its path)"
            )
        self._deviation_m = max(self._deviation_m, deviation_m())
        if share >= END_SHARE:
            return ""
        link, obstacle = self._episode
        self._episode = None
        return (
            f"{link} clear of {obstacle} through the null space again; the field moved the tool "
            f"up to {self._deviation_m * 1e3:.1f} mm off its path"
        )
