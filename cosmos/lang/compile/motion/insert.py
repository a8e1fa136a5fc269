"""INSERT to segments: push along one direction to a depth, compliant across it."""

from __future__ import annotations

from cosmos import plan
from cosmos.errors import ProgramError
from cosmos.lang import ast, units
from cosmos.lang.compile.motion.axes import AXIS_NAMES, NO_FORCES, NO_FREE, held_since
from cosmos.lang.compile.motion.axis_rules import AxisRules
from cosmos.lang.compile.motion.clause_values import ClauseValues
from cosmos.lang.compile.motion.clauses import Clauses, clauses_of
from cosmos.osc.motion import cruise_duration
from cosmos.osc.search import LissajousPath, SpiralPath
from cosmos.rotations import readonly, signed_column

_INSERT = plan.SegmentKind.INSERT
APPROACH_BEYOND_M = 0.002
"""An INSERT's approach aims this far beyond its DEPTH [m] (it ends at DEPTH, or on a touch)."""


class Insert(AxisRules, ClauseValues):
    """The motion builder's INSERT (it keeps the held contact)."""

    __slots__ = ()

    def insert(self, statement: ast.Insert) -> None:
        """INSERT: force along the direction, compliant across it.

        Without a held contact an approach with every axis held comes first, until the tool touches.
        """
        clauses = clauses_of(statement.clauses)
        frame, _, fixture = self._frame(clauses, "INSERT", allow_duration=False)
        axis, sign = self._translation(statement.direction, "INSERT")
        direction_world = signed_column(frame.rotation, axis, sign)[0]
        depth_expr = clauses.exprs.get(ast.ClauseKind.DEPTH)
        assert depth_expr is not None  # the checker requires DEPTH
        depth = self._positive_scalar(depth_expr, units.LENGTH, "DEPTH")
        force = self._force(clauses)
        contact = self.state.contact
        forces = {axis: sign * force}
        contact_axis = None
        if contact is not None:
            contact_axis, contact_sign = self._contact_axis(contact, frame, statement.span)
            if contact_axis != axis:
                forces[contact_axis] = contact_sign * contact.force_n

        def what() -> str:  # for messages only: built when one is given
            return f"INSERT {statement.direction.text}"

        if clauses.comply is not None:
            free = {ref.axis.value for ref in clauses.comply.axes}
            for ref in clauses.comply.axes:
                if ref.axis.value in forces:
                    because = (
                        f"{what()} pushes along it"
                        if ref.axis.value == axis
                        else f"it carries {held_since(contact)}"
                    )
                    raise ProgramError(
                        f"{ref.axis.name} cannot be compliant here: {because}; leave it out of COMPLY",
                        ref.span,
                    )
        else:
            lateral = [i for i in range(3) if i != axis]
            free = {i for i in lateral + [i + 3 for i in lateral] if i != contact_axis}
        self._no_compliance(axis, what, statement.direction.span)
        if contact_axis is not None and contact_axis != axis:
            self._no_compliance(contact_axis, lambda: held_since(contact), statement.span)
        self._warn_away_from_fixture(statement.direction, fixture, "INSERT")
        search_clause = next((c for c in statement.clauses if isinstance(c, ast.SearchClause)), None)
        search = None
        if search_clause is not None:
            search = self._search(search_clause, axis, free, contact_axis)
            self._warn_search_timeout(search, clauses, search_clause)
        speed = self._speed(clauses, self.defaults.insert_speed_mps)
        self._warn_impact(speed, clauses, "INSERT")
        until = None if clauses.until is None else self._until(clauses, frame, force_expected=True)
        if contact is None:
            # No contact yet: approach along the direction with every axis held, as CONTACT
            # does, until the tool touches (or has gone DEPTH). Compliant axes at zero force
            # would let the tool wander on the way: the joints' friction, uncompensated on
            # them, pushed a peg 1.6 mm sideways in 2 mm of fall, off a 1 mm chamfer.
            _, direction = signed_column(frame.rotation, axis, sign)
            self._add(
                plan.SegmentKind.CONTACT_APPROACH,
                statement,
                frame,
                self._axes(NO_FORCES, NO_FREE),
                # Aimed beyond DEPTH: a goal at DEPTH would be neared, never quite reached.
                target=plan.RelativeTarget(
                    readonly(tuple(d * (depth + APPROACH_BEYOND_M) for d in direction))
                ),
                speed=speed,
                completion=plan.DepthReached(
                    direction_world,
                    depth,
                    touch_n=min(self.defaults.touch_threshold_n, 0.5 * force),
                    force_n=force,
                ),
                until=until,
                timeout=self._timeout(clauses),
            )
        self._add(
            _INSERT,
            statement,
            frame,
            self._axes(forces, free),
            target=None,
            speed=speed,
            completion=plan.DepthReached(direction_world, depth),
            until=until,
            timeout=self._timeout(clauses),
            jam_check=self._jam_check,
            search=search,
        )

    def _warn_search_timeout(self, search: plan.Search, clauses: Clauses, clause: ast.SearchClause) -> None:
        """A TIMEOUT that ends the INSERT before its pattern has covered its RADIUS."""
        timeout = self._timeout(clauses)
        if timeout is None:
            return
        if search.pattern is plan.SearchPattern.SPIRAL:
            path: SpiralPath | LissajousPath = SpiralPath(search.radius_m, search.pitch_m)
        else:
            path = LissajousPath.of(search.radius_m, search.pitch_m)
        needed = cruise_duration(path.length_m, search.speed_mps)
        if timeout < needed:
            self.warn(
                f"TIMEOUT {timeout:g} s ends the INSERT before its SEARCH {clause.pattern.value} has "
                f"covered its RADIUS ({needed:.3g} s at {search.speed_mps * 1e3:g} mm/s)",
                clauses.span_of(ast.ClauseKind.TIMEOUT),
            )

    def _search(
        self, clause: ast.SearchClause, axis: int, free: set[int], contact_axis: int | None
    ) -> plan.Search:
        """INSERT's SEARCH: its pattern on the two translations across the insertion axis.

        During the search those axes are motion-controlled and track the pattern (eq. 19),
        so they must be the INSERT's to move: compliant at zero force (its COMPLY axes), not
        a held contact's force axis nor left stiff by the INSERT's COMPLY list.
        """
        keyword = f"SEARCH {clause.pattern.value}"
        lateral = tuple(i for i in range(3) if i != axis)
        names = " and ".join(AXIS_NAMES[i] for i in lateral)
        for i in lateral:
            if i == contact_axis:
                raise ProgramError(
                    f"{keyword} moves {names}, across the insertion, but {AXIS_NAMES[i]} carries "
                    f"{held_since(self.state.contact)}; make the contact along the insertion",
                    clause.span,
                )
            if i not in free:
                raise ProgramError(
                    f"{keyword} moves {names}, across the insertion, but this INSERT keeps "
                    f"{AXIS_NAMES[i]} stiff: a search moves the compliant axes; "
                    f"give COMPLY {' '.join(AXIS_NAMES[j] for j in sorted(free | set(lateral)))}",
                    clause.span,
                )
        exprs = {p.kind: p.value for p in clause.parameters}
        radius_expr, pitch_expr = exprs[ast.ClauseKind.RADIUS], exprs[ast.ClauseKind.PITCH]
        radius = self._positive_scalar(radius_expr, units.LENGTH, "SEARCH RADIUS")
        pitch = self._positive_scalar(pitch_expr, units.LENGTH, "SEARCH PITCH")
        if pitch > radius:
            raise ProgramError(
                f"PITCH {self.text_of(pitch_expr.span)} is larger than RADIUS "
                f"{self.text_of(radius_expr.span)}: the pattern would end before its first turn; "
                "give a PITCH at most the RADIUS",
                pitch_expr.span,
            )
        return plan.Search(
            pattern=plan.SearchPattern[clause.pattern.name],
            radius_m=radius,
            pitch_m=pitch,
            lateral_axes=(lateral[0], lateral[1]),
            speed_mps=self.defaults.search_speed_mps,
            found_depth_m=self.defaults.search_found_depth_m,
        )
