"""The compiled plan: the contract between the language and the executor.

A :class:`Plan` is the program after parsing, checking and compiling: a list of
steps in execution order. A step is a :class:`Segment` (the arm does something
under one fixed control law until a completion or stop condition), a scene
change (:class:`AddObstacle`, :class:`RemoveObstacle`), or a node the executor
decides at run time: a :class:`Branch` (IF), a :class:`Loop` (WHILE), an
:class:`Attempt` (TRY) and its :class:`Retry`, each holding its compiled steps.
Procedures and REPEAT loops are already expanded; each step keeps the span of
the statement it came from.

The types live in the package's modules, in the order a plan is read: :mod:`.targets`
(a segment's kind, target and completion), :mod:`.conditions` (UNTIL and what IF and
WHILE read), :mod:`.segments`, :mod:`.steps` (scene changes, hand actions, decisions,
the :class:`Plan`) and :mod:`.plan_json` (the plan as JSON); every name is imported here.

Conventions, for every field of these types:

- Units are SI: m, s, N, N m, rad, m/s, N/m, N m/rad, N s/m, N m s/rad.
- Vectors and matrices are read-only ``float64`` numpy arrays. A 6-vector is
  ordered (x, y, z, rx, ry, rz): three translations then three rotations.
- ``*_world`` quantities are in the world frame. 6-vectors of a segment
  (``motion_axes``, ``force_setpoint``, ``stiffness``, ``damping``) are in the
  segment's *task frame*, whose orientation is ``frame_rotation``: a 3x3 matrix
  whose columns are the task frame's x, y, z axes in world coordinates (so a
  task-frame vector v is ``frame_rotation @ v`` in the world). The task frame's
  origin is the tool point; only its orientation matters.
- Forces and moments are those the tool applies to the environment
  (docs/language.md, "Sign of forces"): ``CONTACT DOWN FORCE 10 N`` holds a
  setpoint of -10 N on the world z axis.

Statement-level semantics the executor must honour:

- Segments of one statement share ``statement_index`` (CONTACT gives two).
  ``timeout_s`` and the ``DISTANCE`` of ``until`` count from the start of the
  statement's first segment. When ``until`` holds, the statement ends with
  success: skip its remaining segments.
- A relative target or a ``None`` target is resolved against the tool pose
  measured when the segment starts.
"""

from cosmos.plan.conditions import (
    AllOf,
    AnyOf,
    CompareOp,
    Comparison,
    Condition,
    Ending,
    LastOutcome,
    Quantity,
    condition_holds,
)
from cosmos.plan.plan_json import condition_to_json, plan_to_json, segment_to_json, step_to_json
from cosmos.plan.segments import NAMED_POSTURES, JamCheck, Posture, Search, SearchPattern, Segment, ToolEnd
from cosmos.plan.steps import (
    AddObstacle,
    Attempt,
    Branch,
    Decided,
    Diagnostic,
    HandAction,
    HandStep,
    Loop,
    ObstacleShape,
    Plan,
    RemoveObstacle,
    Retry,
    Step,
    all_steps,
    inner_steps,
)
from cosmos.plan.targets import (
    TOUCH_THRESHOLD_N,
    AbsoluteTarget,
    BoolArray,
    Completion,
    CompletionKind,
    ContactTouch,
    DepthReached,
    Elapsed,
    FloatArray,
    ForceSettled,
    GoalReached,
    RelativeTarget,
    SegmentKind,
    Target,
    UntilOnly,
)

__all__ = [
    "AbsoluteTarget",
    "AddObstacle",
    "AllOf",
    "AnyOf",
    "Attempt",
    "BoolArray",
    "Branch",
    "CompareOp",
    "Comparison",
    "Completion",
    "CompletionKind",
    "Condition",
    "ContactTouch",
    "Decided",
    "DepthReached",
    "Diagnostic",
    "Elapsed",
    "Ending",
    "FloatArray",
    "ForceSettled",
    "GoalReached",
    "HandAction",
    "HandStep",
    "JamCheck",
    "LastOutcome",
    "Loop",
    "NAMED_POSTURES",
    "ObstacleShape",
    "Plan",
    "Posture",
    "Quantity",
    "RelativeTarget",
    "RemoveObstacle",
    "Retry",
    "Search",
    "SearchPattern",
    "Segment",
    "SegmentKind",
    "Step",
    "TOUCH_THRESHOLD_N",
    "Target",
    "ToolEnd",
    "UntilOnly",
    "all_steps",
    "condition_holds",
    "condition_to_json",
    "inner_steps",
    "plan_to_json",
    "segment_to_json",
    "step_to_json",
]
