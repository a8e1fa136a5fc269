"""The fast lexer's scanner: every token of a line in one call, kinds by first character.

The lexer's master expression (:attr:`~cosmos.lang.lalr_tables.Tables.lexer`)
names a group per terminal, and reading a token's kind from a match object
(``lastindex``, ``span``) costs more than matching it. The scanner is the same
expression (the same terminal patterns, in the same order, so it matches the
same text) with two groups only: the blanks before a token, and the token.
``findall`` then gives a line's tokens as (blanks, text) pairs, and a token's
column is counted from the lengths.

A token's kind is read from its first character: in this grammar, tokens of
different terminals start with different characters. Characters that start
tokens of more than one kind (``.`` starts a number or is a bad character, a
backslash a continuation or a bad character) and characters outside ASCII have
no entry in :attr:`Scanner.first_kinds`; for those the master expression says
(:meth:`Scanner.kind_at`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

_PROBES = ("", "0", "a", "\n", "=")
"""What follows a character when its tokens' kinds are found (:func:`first_kinds`)."""


def non_capturing(regexp: str) -> str:
    r"""``regexp`` with each capturing group ``(...)`` made non-capturing ``(?:...)``.

    Escapes (``\(``) and character classes (``[(]``) are left alone.
    """
    out: list[str] = []
    index = 0
    in_class = False
    while index < len(regexp):
        char = regexp[index]
        if char == "\\":
            out.append(regexp[index : index + 2])
            index += 2
            continue
        if in_class:
            in_class = char != "]"
        elif char == "[":
            in_class = True
            # a ']' right after '[' or '[^' is a member, not the end
            for member in ("^]", "]"):
                if regexp.startswith(member, index + 1):
                    out.append(char + member)
                    index += 1 + len(member)
                    break
            else:
                out.append(char)
                index += 1
            continue
        elif char == "(" and not regexp.startswith("?", index + 1):
            out.append("(?:")
            index += 1
            continue
        out.append(char)
        index += 1
    return "".join(out)


_CLASS_REPEATED = re.compile(r"\[([^\]^\\]|\\.)([^\]\\]|\\.)*\]\+")
"""A character class repeated: ``[ \t]+`` (no ``]`` inside, not negated)."""


def blanks_pattern(blanks: list[str]) -> str:
    r"""Any run of ``blanks``: ``(?:A|B)*``, or ``[ab]*`` where they are ``[a]+`` and ``[b]+``.

    The two match the same text (and give the same backtracking points), but a
    repeated character class is one step of the regular expression engine where
    a repeated group is a loop of them: a tenth of the scanner's time.
    """
    if blanks and all(_CLASS_REPEATED.fullmatch(blank) for blank in blanks):
        return "[" + "".join(blank[1:-2] for blank in blanks) + "]*"
    return "(?:" + ("|".join(f"(?:{non_capturing(blank)})" for blank in blanks) or "(?!)") + ")*"


@dataclass(frozen=True)
class Scanner:
    """The scanner and what it needs to tell the kinds of its tokens.

    Attributes:
        pattern: The master expression's blanks and terminals, in two groups:
            ``(blanks)(token)``; ``findall`` on a line gives its tokens.
        exact: The master expression (a group per terminal).
        kinds: The terminal name of each of ``exact``'s groups, by number.
        first_kinds: The kind of every token that starts with a character, for
            the characters that start tokens of one kind only.
    """

    pattern: re.Pattern[str]
    exact: re.Pattern[str]
    kinds: tuple[str | None, ...]
    first_kinds: dict[str, str]

    def kind_at(self, line: str, offset: int) -> str:
        """The kind of the token at ``offset`` in ``line``, as the master expression says."""
        return _kind_at(self.exact, self.kinds, line, offset)


def _kind_at(exact: re.Pattern[str], kinds: tuple[str | None, ...], line: str, offset: int) -> str:
    match = exact.match(line, offset)
    assert match is not None  # it matches any character
    return kinds[match.lastindex]  # type: ignore[index,return-value]


def scanner(
    blanks: list[str], terminals: list[str], exact: re.Pattern[str], kinds: tuple[str | None, ...]
) -> Scanner:
    """The scanner of the master expression ``exact``, made of the same patterns.

    Args:
        blanks: The patterns of the blanks matched in front of a token.
        terminals: The terminals' patterns in the master expression's order, its
            catch-all for a bad character last.
        exact: The master expression.
        kinds: The terminal name of each of ``exact``'s groups, by number.
    """
    alternatives = "|".join(f"(?:{non_capturing(terminal)})" for terminal in terminals)
    pattern = re.compile(f"({blanks_pattern(blanks)})({alternatives})")
    if pattern.groups != 2:
        raise ValueError(f"the scanner has {pattern.groups} groups, not 2: {pattern.pattern!r}")
    return Scanner(pattern, exact, kinds, first_kinds(pattern, exact, kinds))


def first_kinds(
    pattern: re.Pattern[str], exact: re.Pattern[str], kinds: tuple[str | None, ...]
) -> dict[str, str]:
    """The kind of the tokens that each ASCII character starts, where there is one kind only.

    Each character is tried in front of a set of continuations (:data:`_PROBES`);
    a character whose tokens come out of more than one kind gets no entry.
    """
    found: dict[str, str] = {}
    for code in range(128):
        char = chr(code)
        seen = set()
        for probe in _PROBES:
            match = pattern.match(char + probe)
            if match is not None and not match.group(1):  # a token that starts at the character
                seen.add(_kind_at(exact, kinds, char + probe, 0))
        if len(seen) == 1:
            found[char] = seen.pop()
    return found
