"""The REPL's own commands, typed with a leading colon: ``:help``, ``:state``, ``:load FILE`` ...

Each command is a function of the engine and the rest of the line; it returns
False to end the session.
"""

from __future__ import annotations

import difflib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from cosmos.errors import UsageError
from cosmos.lang import CompileState
from cosmos.repl.engine import ReplEngine
from cosmos.repl.names import frame_table
from cosmos.repl.output import Tone
from cosmos.repl.status import format_vector
from cosmos.runlog.live import DEFAULT_PORT as LIVE_PORT

AXIS_LABELS = ("X", "Y", "Z", "RX", "RY", "RZ")

KEYS_HELP = (
    "Enter runs the input when it is complete; inside PROC ... END or REPEAT n ... END,\n"
    "or after a line ending in '\\', Enter starts a new line.\n"
    "Esc Enter runs the input as it is. Two empty lines end an unfinished block.\n"
    "Tab completes keywords, frames, obstacles and procedures; Up and Down recall history.\n"
    "Ctrl-C while the arm moves stops it (it holds its pose); at the prompt it clears the line.\n"
    "Ctrl-D on an empty line, or :quit, ends the session."
)

LANGUAGE_HELP = (
    "Statements: MOVE TO p | MOVE BY (dx, dy, dz), CONTACT DOWN FORCE 10 N, SLIDE +X BY 50 mm,\n"
    "INSERT DOWN DEPTH 25 mm FORCE 15 N, COMPLY X Y | COMPLY NONE, WAIT 1 s, SPEED 0.2 m/s,\n"
    "LET name = value, FRAME name = (x, y, z) RPY (r, p, y), OBSTACLE name SPHERE AT p RADIUS r,\n"
    "PROC name ... END, REPEAT n ... END, and a PROC's name alone to call it.\n"
    "Fixtures: table, hole, slope (z into the surface). See docs/language.md and docs/repl.md."
)


@dataclass(frozen=True)
class Command:
    """A REPL command.

    Attributes:
        name: What is typed after the colon.
        usage: How it is typed.
        summary: What it does, in one line.
        run: Does it; returns False to end the session.
    """

    name: str
    usage: str
    summary: str
    run: Callable[[ReplEngine, str], bool]


def _help(engine: ReplEngine, argument: str) -> bool:
    width = max(len(c.usage) for c in COMMANDS.values())
    engine.printer.lines([f"{c.usage:<{width}}  {c.summary}" for c in COMMANDS.values()])
    engine.printer.write("")
    engine.printer.write(KEYS_HELP)
    engine.printer.write("")
    engine.printer.write(LANGUAGE_HELP)
    return True


def settings_lines(state: CompileState) -> list[str]:
    """What the language state holds: held contact, COMPLY, SPEED, obstacles, procedures."""
    lines = []
    contact = state.contact
    if contact is None:
        lines.append("contact  none held")
    else:
        lines.append(
            f"contact  {contact.force_n:g} N along {format_vector(contact.direction_world, digits=2)} "
            f"(task frame {contact.frame.name}; {contact.span.file}:{contact.span.line})"
        )
    complied = [
        f"{label} {c.stiffness:g}" for label, c in zip(AXIS_LABELS, state.compliance, strict=True) if c
    ]
    lines.append("comply   " + (", ".join(complied) + " (stiffness)" if complied else "none"))
    lines.append(f"speed    {state.default_speed_mps * 1000:g} mm/s")
    lines.append("obstacles " + (", ".join(state.obstacles) or "none"))
    procedures = [entry.definition.name.name for entry in state.procedures.values()]
    lines.append("procs    " + (", ".join(procedures) or "none"))
    return lines


def _state(engine: ReplEngine, argument: str) -> bool:
    engine.printer.lines(engine.status().lines())
    engine.printer.lines(settings_lines(engine.state))
    return True


def _frames(engine: ReplEngine, argument: str) -> bool:
    engine.printer.lines(frame_table(engine.state))
    return True


def _load(engine: ReplEngine, argument: str) -> bool:
    text = argument.strip().strip("\"'")
    if not text:
        engine.printer.write("usage: :load FILE", Tone.ERROR)
        return True
    engine.load(Path(text).expanduser())
    return True


def _reset(engine: ReplEngine, argument: str) -> bool:
    engine.reset()
    return True


def _log(engine: ReplEngine, argument: str) -> bool:
    engine.printer.write(f"log: {engine.session.log_path}")
    return True


def _live(engine: ReplEngine, argument: str) -> bool:
    log = engine.session.log
    if log.live_server is None:
        text = argument.strip() or str(LIVE_PORT)
        if not text.isdigit() or not 0 <= int(text) <= 65535:
            engine.printer.write(f"usage: :live [PORT]  (a port 0..65535, default {LIVE_PORT})", Tone.ERROR)
            return True
        try:
            log.pace(1.0, int(text))
        except UsageError as error:
            engine.printer.write(error.render(), Tone.ERROR)
            return True
    assert log.live_server is not None
    engine.printer.write(
        f"live: ws://127.0.0.1:{log.live_server.port} (Foxglove: Open connection); "
        "the arm now moves in real time"
    )
    return True


def _quit(engine: ReplEngine, argument: str) -> bool:
    return False


COMMANDS = {
    command.name: command
    for command in (
        Command("help", ":help", "this help", _help),
        Command(
            "state", ":state", "joint angles, tool pose, wrench, force-controlled axes, settings", _state
        ),
        Command("frames", ":frames", "the known frames and where they are", _frames),
        Command("load", ":load FILE", "run a program file into the session (its names are kept)", _load),
        Command("reset", ":reset", "put the arm back home and forget names, frames and settings", _reset),
        Command("log", ":log", "print the path of the session's log", _log),
        Command("live", ":live [PORT]", "stream the session to Foxglove, in real time", _live),
        Command("quit", ":quit", "end the session (or Ctrl-D)", _quit),
    )
}


def is_command(text: str) -> bool:
    """Whether an input is a REPL command (starts with ``:``)."""
    return text.lstrip().startswith(":")


BARE_COMMANDS = {"help": "help", "exit": "quit", "quit": "quit"}
"""Words typed without their colon that run the command, unless a PROC has the name."""


def bare_command(text: str) -> str:
    """The ``:command`` a bare ``help``, ``exit`` or ``quit`` means ("" for any other input)."""
    return BARE_COMMANDS.get(text.strip().lower(), "")


def command_hint(text: str) -> str:
    """For an input that failed as a statement: the ``:command`` its bare word would be, if any."""
    word = text.strip().lower()
    name = "quit" if word == "exit" else word
    return f"REPL commands start with ':': type :{name}" if name in COMMANDS else ""


def run_command(engine: ReplEngine, text: str) -> bool:
    """Run a ``:command``; returns False to end the session."""
    name, _, argument = text.strip()[1:].partition(" ")
    command = COMMANDS.get(name.lower())
    if command is None:
        close = difflib.get_close_matches(name.lower(), list(COMMANDS), n=1)
        hint = f"; did you mean :{close[0]}?" if close else "; :help lists them"
        engine.printer.write(f"unknown command ':{name}'{hint}", Tone.ERROR)
        return True
    if command.name not in ("load", "reset"):  # those record themselves
        engine.transcript.add_command(text.strip())
    return command.run(engine, argument)
