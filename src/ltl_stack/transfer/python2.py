"""Reading Python 2 programs (Indigo-era ROS nodes) with Python 3's ``ast``, for the transfer only.

Python 2 expands a tab in indentation to the next multiple of 8 columns; Python 3 refuses indentation
that mixes tabs and spaces inconsistently. So the text is parsed with its indentation expanded the
Python 2 way, and every line's shift is kept, so spans still point into the original bytes (the output
keeps the program's own tabs). Two Python 2 statements are read by blanking them for the parser only
(same length, so no position moves): ``print`` statements and the ``, name`` of ``except E, name:`` /
``raise E, message``. Other Python 2 syntax is refused in one line naming it.
"""
from __future__ import annotations

import ast
import re
import tokenize
from collections.abc import Callable, Iterator

from ltl_stack.errors import InputError

#: a Python 2 octal literal (0755), one token from Python 3.12 on
OLD_OCTAL = re.compile(r"0[0-9]*[1-9][0-9]*[lL]?")


class Python2Unsupported(InputError):
    """Python 2 syntax this reader does not take, named in one line."""

    def __init__(self, file: str, what: str, line: int):
        super().__init__(file, f"Python 2 syntax this tool does not read: {what}; convert the program (2to3) first",
                         line)


def expand_indentation(text: str) -> tuple[str, list[int]]:
    """The text with each line's leading whitespace expanded as Python 2 does (tabs to multiples of 8),
    and how many columns each line moved (0-based line index)."""
    out, shifts = [], []
    for line in text.split("\n"):
        indent = len(line) - len(line.lstrip(" \t"))
        expanded = line[:indent].expandtabs(8)
        shifts.append(len(expanded) - indent)
        out.append(expanded + line[indent:])
    return "\n".join(out), shifts


def _blank(lines: list[str], start: tuple[int, int], end: tuple[int, int], keep: str = "") -> None:
    """Replace text from ``start`` to ``end`` (token positions) by ``keep`` padded with spaces."""
    (r0, c0), (r1, c1) = start, end
    for row in range(r0, r1 + 1):
        line = lines[row - 1]
        a = c0 if row == r0 else 0
        b = c1 if row == r1 else len(line.rstrip("\n"))
        fill = (keep if row == r0 else "").ljust(b - a)
        lines[row - 1] = line[:a] + fill + line[b:]


def _with_following(tokens: Iterator[tokenize.TokenInfo]) -> Iterator[tuple[tokenize.TokenInfo,
                                                                                tokenize.TokenInfo | None]]:
    """Each token with the one after it (None at the end), read as the tokenizer makes them: the
    whole token list of a large program is some 75 times its size."""
    tok = next(tokens, None)
    while tok is not None:
        following = next(tokens, None)
        yield tok, following
        tok = following


def _ends_print(t: tokenize.TokenInfo) -> bool:
    return t.type in (tokenize.NEWLINE, tokenize.ENDMARKER) or (t.type == tokenize.OP and t.string == ";")


def _ends_line(t: tokenize.TokenInfo) -> bool:
    return t.type in (tokenize.NEWLINE, tokenize.ENDMARKER)


def _ends_except(t: tokenize.TokenInfo) -> bool:
    return t.type in (tokenize.NEWLINE, tokenize.ENDMARKER) or (t.type == tokenize.OP and t.string == ":")


def python2_parse_text(text: str, filename: str) -> tuple[str, list[int]]:
    """Text Python 3's parser reads, with the same positions as the Python 2 program (after the
    indentation shifts returned beside it); InputError naming the line for what it cannot read."""
    expanded, shifts = expand_indentation(text)
    lines = expanded.splitlines(keepends=True)
    del expanded
    try:
        _blank_python2(lines, filename)
    except (tokenize.TokenError, SyntaxError) as err:
        line = err.lineno if isinstance(err, SyntaxError) else err.args[1][0]
        raise InputError(filename, f"not valid Python 2 or 3: {err.args[0]}", line or 0) from None
    return "".join(lines), shifts


def _blank_python2(lines: list[str], filename: str) -> None:
    """Blank the Python 2 statements of ``lines`` in place, one token at a time (a statement's blank
    is made when the token that ends it comes); Python2Unsupported for what cannot be read."""
    logical_start = True
    depth = 0
    statement = None    # 'except' or 'raise' while inside one at bracket depth 0
    open_blanks: list[tuple[tuple[int, int], str, Callable[[tokenize.TokenInfo], bool]]] = []
    for tok, following in _with_following(tokenize.generate_tokens(iter(lines).__next__)):
        if open_blanks:  # a print statement or an ``except E, name`` that ends here
            still = []
            for start, keep, ends in open_blanks:
                if ends(tok):
                    _blank(lines, start, tok.start, keep)
                else:
                    still.append((start, keep, ends))
            open_blanks = still
        if tok.string == "`" and tok.type in (tokenize.OP, tokenize.ERRORTOKEN):
            raise Python2Unsupported(filename, "backquotes (repr)", tok.start[0])
        adjacent = following is not None and following.start == tok.end
        # up to Python 3.11 tokenize splits '<>' into '<' '>' and 0755 into 0 755; 3.12 keeps each one token
        if tok.string == "<>" or (adjacent and tok.string == "<" and following.string == ">"):
            raise Python2Unsupported(filename, "the <> operator", tok.start[0])
        if tok.type == tokenize.NUMBER and OLD_OCTAL.fullmatch(tok.string):
            raise Python2Unsupported(filename, f"the number {tok.string}", tok.start[0])
        if adjacent and tok.type == tokenize.NUMBER and (following.string in ("l", "L") or (
                tok.string == "0" and following.type == tokenize.NUMBER and following.string.isdigit())):
            raise Python2Unsupported(filename, f"the number {tok.string + following.string}", tok.start[0])
        if tok.type in (tokenize.NEWLINE, tokenize.INDENT, tokenize.DEDENT):
            logical_start, statement = True, None
            continue
        if tok.type in (tokenize.NL, tokenize.COMMENT):
            continue
        if tok.type == tokenize.OP and tok.string in "([{":
            depth += 1
        elif tok.type == tokenize.OP and tok.string in ")]}":
            depth -= 1
        elif tok.type == tokenize.OP and tok.string in (":", ";") and depth == 0:
            logical_start, statement = True, None   # a simple statement may follow: if x: print "y"
            continue
        if logical_start and tok.type == tokenize.NAME:
            if tok.string == "exec" and following is not None and following.type == tokenize.STRING:
                raise Python2Unsupported(filename, "the exec statement", tok.start[0])
            if tok.string == "print" and following is not None and not (
                    following.type == tokenize.OP and following.string in ("(", "=", ".", "[")):
                open_blanks.append((tok.start, "pass", _ends_print))
            if tok.string in ("except", "raise"):
                statement = tok.string
        elif statement and depth == 0 and tok.type == tokenize.OP and tok.string == ",":
            open_blanks.append((tok.start, "", _ends_except if statement == "except" else _ends_line))
            statement = None
        logical_start = False


def parse_python2(text: str, filename: str) -> tuple[ast.Module, list[int]]:
    """The syntax tree of a Python 2 program and each line's column shift (see the module docstring)."""
    parse_text, shifts = python2_parse_text(text, filename)
    try:
        tree = ast.parse(parse_text, filename=filename)
    except SyntaxError as err:
        raise InputError(filename, f"not valid Python 2 or 3: {err.msg}", err.lineno or 0) from None
    except (RecursionError, MemoryError):
        raise InputError(filename, "not a program this tool reads: nested too deeply for Python's parser") from None
    return tree, shifts
