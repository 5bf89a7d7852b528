"""The ``.slugsin`` format of the slugs GR(1) synthesis tool: reader and writer.

Each clause is one line in prefix notation over ``! & | ^``, the constants ``0 1``, propositions
and primed propositions ``x'``. ``$ n f0 … f(n-1)`` is a buffer of ``n`` formulas whose value is
the last one; inside it, ``? i`` stands for the (earlier, complete) entry ``i`` of the innermost
buffer. Lines of a section are conjoined (init and safety) or are separate goals (liveness);
an empty section means true. See ``docs/spec_formats.md``.

The parser is iterative (a stack of pending operators), so a chain of thousands of ``&`` costs
no Python stack, and chains of ``&``/``|`` are flattened into one ``And``/``Or``.
"""
from __future__ import annotations

import itertools
import re
from array import array
from collections.abc import Iterator

from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.formula import FALSE, TRUE, And, Const, Formula, Iff, Implies, Not, Or, Var, Xor, children
from ltl_stack.spec.model import SLUGSIN_SECTIONS, Spec
from ltl_stack.spec.ops import Pending, settle
from ltl_stack.spec.sections import Line, Names, read_spec

OPERATORS = {"!": 1, "&": 2, "|": 2, "^": 2}
_TOKEN = re.compile(r"\S+")
_GLUED = re.compile(r"^([$?])(\d+)$")
_NUMBER = re.compile(r"^\d+$")
_COUNT = re.compile(r"^\d{1,18}$")  # a longer count is no real buffer (and int() refuses 4300+ digits)

NAME_RULE = "a slugsin name is one word without a prime that is not an operator or a number"


def valid_name(name: str) -> bool:
    return bool(name) and name not in OPERATORS and name[0] not in "$?#[" and not _NUMBER.match(name) \
        and not any(c.isspace() for c in name)


def parse_slugsin(text: str, file: str = "<string>") -> Spec:
    """Read a ``.slugsin`` spec; raises ``SpecError`` naming file, line and column."""
    return read_spec(text, file, valid_name, NAME_RULE, parse_prefix)


def tokens_of(line: Line) -> list[tuple[str, int]]:
    """Whitespace-separated words of a line with their 1-based columns."""
    return [(m.group(), m.start() + 1) for m in _TOKEN.finditer(line.text)]


#: characters of a line split at a time: a correct line is read in pieces, never held as one list of words
CHUNK = 1 << 16
_SPACE = re.compile(r"\s")


def words_of(text: str) -> Iterator[str]:
    """The words of ``text`` (``str.split()``'s), a piece of the text at a time: an 8 MB line of
    two-letter words would otherwise be a list of millions of strings at once."""
    start, n = 0, len(text)
    while start < n:
        cut = start + CHUNK
        if cut < n:  # cut at whitespace, so that no word is split
            space = _SPACE.search(text, cut)
            cut = space.start() if space else n
        yield from text[start:cut].split()
        start = cut


class _Columns:
    """The 1-based column of word ``token`` of a line (or of the line's end), found by scanning the
    line again: only an error message needs one, so a correct line is split once."""

    __slots__ = ("line",)

    def __init__(self, line: Line):
        self.line = line

    def __getitem__(self, token: int) -> int:
        match = next(itertools.islice(_TOKEN.finditer(self.line.text), token, None), None)
        return match.start() + 1 if match else len(self.line.text) + 1


class _Frames:
    """The operators (and ``$`` buffers) still waiting for operands, as parallel arrays: an open
    operator costs a few machine words, not an object and a list (a line of 4 million ``!`` opens
    4 million of them).

    Chains are merged as they are read, which keeps the frames and the ``Pending`` parts few: an
    ``&`` that is the last operand of an open ``&`` extends that frame (``& a & b c`` is one frame of
    three operands; ``token`` becomes the inner ``&``'s, which messages name), a completed ``&`` hands
    its operands to the open ``&`` it is an operand of (the same for ``|``), and a ``!`` right after
    a ``!`` counts in ``times``."""

    __slots__ = ("op", "token", "need", "base", "times", "args", "buffers")

    def __init__(self) -> None:
        self.op: list[str] = []
        self.token = array("q")  # word index of the (innermost) operator, for messages
        self.need = array("q")  # operands (entries) the frame takes
        self.base = array("q")  # where its operands start in ``args``
        self.times = array("q")  # a ``!`` frame: how many ``!`` in a row
        self.args: list[Formula | Pending] = []  # the operands of every open frame, in order
        self.buffers = array("q")  # the open ``$`` frames, by position

    def have(self) -> int:
        """Operands the innermost frame has."""
        return len(self.args) - self.base[-1]

    def open(self, op: str, token: int, need: int) -> None:
        if self.op and self.op[-1] == op and self.have() == self.need[-1] - 1:
            if op == "!":
                self.times[-1] += 1
                self.token[-1] = token
                return
            if op in _KIND:
                self.need[-1] += 1
                self.token[-1] = token
                return
        if op == "$":
            self.buffers.append(len(self.op))
        self.op.append(op)
        self.token.append(token)
        self.need.append(need)
        self.base.append(len(self.args))
        self.times.append(1)

    def merge_down(self) -> bool:
        """A complete ``&`` (``|``) that is an operand of an open ``&`` (``|``) leaves its operands
        where they are, as that frame's: no copy, whatever the nesting."""
        if len(self.op) < 2 or self.op[-1] not in _KIND or self.op[-2] != self.op[-1]:
            return False
        self.op.pop()
        self.token.pop()
        self.base.pop()
        self.times.pop()
        operands = self.need.pop()
        self.need[-1] += operands - 1
        return True

    def close(self) -> tuple[str, list, int]:
        """Remove the innermost frame: its operator, operands and repeat count."""
        op = self.op.pop()
        self.token.pop()
        self.need.pop()
        start = self.base.pop()
        times = self.times.pop()
        args = self.args[start:]
        del self.args[start:]
        if op == "$":
            self.buffers.pop()
        return op, args, times

    def entries(self, buffer: int) -> tuple[int, int]:
        """Where the complete entries of the ``$`` frame at ``buffer`` are in ``args``: (start, end)."""
        end = self.base[buffer + 1] if buffer + 1 < len(self.base) else len(self.args)
        return self.base[buffer], end


_KIND = {"&": And, "|": Or}


def parse_prefix(line: Line, names: Names) -> Formula:
    """One prefix formula that must fill the whole line: time linear in the line's length, memory a
    small multiple of it (the words are split a piece of the line at a time, see ``_Frames``)."""
    words = words_of(line.text)  # the same words as ``tokens_of``: both split at Unicode whitespace
    columns = _Columns(line)
    known = names.known_variables()
    frames = _Frames()
    i = 0  # index of the next word
    while True:
        word = next(words, None)
        if word is None:
            raise _incomplete(frames, names, columns, i)
        token = i
        i += 1
        value = known.get(word)  # a variable this spec's clauses already used
        if value is None:
            need = OPERATORS.get(word)
            if need is not None:
                frames.open(word, token, need)
                continue
            glued = _GLUED.match(word) if word[0] in "$?" else None
            # the count's column: that of word ``count_at`` plus ``count_shift`` (1 when glued, as in $3)
            if glued:
                word, count_word, count_at, count_shift = glued[1], glued[2], token, 1
            elif word in ("$", "?"):
                count_word, count_at, count_shift = next(words, None), i, 0
                if count_word is None:
                    raise names.error(columns[i], f"expected a number after '{word}'")
                i += 1
            if word == "$":
                if not _COUNT.match(count_word) or int(count_word) < 1:
                    raise names.error(columns[count_at] + count_shift,
                                      f"expected a positive number of entries after '$', got '{count_word}'")
                frames.open("$", token, int(count_word))
                continue
            if word == "?":
                value = _recall(frames, count_word, (count_at, count_shift), token, columns, names)
            elif word == "1":
                value = TRUE
            elif word == "0":
                value = FALSE
            else:
                value = known[word] = _variable(word, token, columns, names)
        # Reduce: hand the finished operand to the operators waiting for it.
        while True:
            if not frames.op:
                extra = next(words, None)
                if extra is not None:
                    raise names.error(columns[i], f"unexpected '{extra}' after a complete formula "
                                                  "(a slugsin clause is one prefix formula per line)")
                return settle(value)
            op = frames.op[-1]
            # a ``$`` entry stays a chain until it is used: ``settle`` keeps its result (parsing stays linear)
            if type(value) is Pending and op not in ("&", "|", "$"):
                value = settle(value)
            frames.args.append(value)
            while frames.have() == frames.need[-1] and frames.merge_down():
                pass
            if frames.have() < frames.need[-1]:
                break
            value = _build(*frames.close())


def _build(op: str, args: list, times: int) -> Formula | Pending:
    if op == "!":
        value = settle(args[0])
        for _ in range(times):
            value = Not(value)
        return value
    if op in _KIND:
        return Pending.of(_KIND[op], args)
    if op == "^":
        return Xor(settle(args[0]), settle(args[1]))
    return args[-1]  # a $ buffer is worth its last entry


def _recall(frames: _Frames, index_word: str, index_at: tuple[int, int], token: int, columns: _Columns,
            names: Names) -> Formula:
    """Entry ``index_word`` of the innermost ``$`` buffer; ``index_at`` is (word, shift) of its column."""
    def index_column() -> int:
        return columns[index_at[0]] + index_at[1]

    if not frames.buffers:
        raise names.error(columns[token], "'?' outside a '$' buffer (? i refers to entry i of the enclosing $ n)")
    if not _COUNT.match(index_word):
        raise names.error(index_column(), f"expected an entry number after '?', got '{index_word}'")
    index = int(index_word)
    buffer = frames.buffers[-1]
    start, end = frames.entries(buffer)
    done = end - start
    if index >= done:
        at = columns[frames.token[buffer]]
        raise names.error(index_column(), f"'? {index}' refers to an entry that is not complete yet: the buffer "
                                          f"at column {at} has {done} complete "
                                          f"entr{'y' if done == 1 else 'ies'} (0...{done - 1})"
                          if done else f"'? {index}' used before the buffer at column {at} "
                                       "has any complete entry")
    return frames.args[start + index]


def _variable(word: str, token: int, columns: _Columns, names: Names) -> Var:
    name, primed = word, False
    if word.endswith("'"):
        name, primed = word[:-1], True
        if name.endswith("'"):
            raise names.error(columns[token], f"'{word}' has more than one prime; x' is the next state of x")
    if not name:
        raise names.error(columns[token], "a prime must follow a proposition name, as in x'")
    # the column is only needed for an error (and finding it costs a scan of the line)
    return names.boolean(name, primed, 0 if names.allowed(name, primed) else columns[token])


def _incomplete(frames: _Frames, names: Names, columns: _Columns, token: int) -> SpecError:
    column = columns[token]
    if not frames.op:
        return names.error(column, "expected a formula")
    op, need = frames.op[-1], frames.need[-1]
    at = columns[frames.token[-1]]
    missing = need - frames.have()
    if op == "$":
        return names.error(column, f"expected {missing} more entr{'y' if missing == 1 else 'ies'} "
                                   f"of the '$ {need}' buffer at column {at}")
    if op == "!" or missing > 1:
        return names.error(column, f"expected an operand after '{op}' at column {at}")
    return names.error(column, f"expected a second operand for '{op}' at column {at}")


# -- writer -------------------------------------------------------------------------------------

def write_slugsin(spec: Spec, *, comments: bool = False) -> str:
    """``spec`` as ``.slugsin`` text that slugs reads and ``parse_slugsin`` reads back.

    Integers are written as their bits (slugs' own format has only Boolean propositions); an
    integer with a one-value range has no bits and so is not written. Subformulas that occur more
    than once in a clause (shared objects, as ``? i`` references give) become ``$`` buffer
    entries, so the text stays as small as the formula. With ``comments`` every clause is
    preceded by ``# file:line: text`` of where it came from.
    """
    for name in spec.propositions:
        if not valid_name(name):
            raise ValueError(f"proposition {name!r} cannot be written in slugsin: {NAME_RULE}")
    out = ["[INPUT]", *spec.inputs, "", "[OUTPUT]", *spec.outputs, ""]
    for section, header in SLUGSIN_SECTIONS.items():
        out.append(f"[{header}]")
        for clause in spec.section(section):
            if comments and clause.text:
                text = " ".join(clause.text.split())
                out.append(f"# {clause.file}:{clause.line}: {text}")
            out.append(formula_to_slugsin(clause.formula))
        out.append("")
    return "\n".join(out)


def formula_to_slugsin(f: Formula) -> str:
    """``f`` in slugsin prefix notation on one line (``->`` and ``<->`` expressed with ``! | ^``)."""
    shared = _shared_nodes(f)
    if not shared:
        return " ".join(_prefix_tokens(f, {}))
    index: dict[int, int] = {}
    parts = [f"$ {len(shared) + 1}"]
    for k, node in enumerate(shared):
        parts.extend(_prefix_tokens(node, index))
        index[id(node)] = k
    parts.extend(_prefix_tokens(f, index))
    return " ".join(parts)


def _shared_nodes(f: Formula) -> list[Formula]:
    """Compound nodes reachable along more than one path, children before parents."""
    count: dict[int, int] = {}
    order: list[Formula] = []
    stack: list[tuple[Formula, bool]] = [(f, False)]
    while stack:
        node, done = stack.pop()
        if done:
            order.append(node)
            continue
        key = id(node)
        if key in count:
            count[key] += 1
            continue
        count[key] = 1
        stack.append((node, True))
        stack.extend((k, False) for k in reversed(children(node)))
    return [n for n in order if count[id(n)] > 1 and not isinstance(n, (Var, Const))
            and not (isinstance(n, Not) and isinstance(n.arg, (Var, Const)))]


def _prefix_tokens(f: Formula, index: dict[int, int]) -> list[str]:
    out: list[str] = []
    stack: list[Formula | str] = [f]
    while stack:
        item = stack.pop()
        if isinstance(item, str):
            out.append(item)
            continue
        if item is not f and id(item) in index:
            out.append(f"? {index[id(item)]}")
        elif isinstance(item, Var):
            out.append(item.name + ("'" if item.primed else ""))
        elif isinstance(item, Const):
            out.append("1" if item.value else "0")
        elif isinstance(item, Not):
            out.append("!")
            stack.append(item.arg)
        elif isinstance(item, (And, Or)):
            args = item.args
            if not args:
                out.append("1" if isinstance(item, And) else "0")
                continue
            op = "&" if isinstance(item, And) else "|"
            sequence: list[Formula | str] = []
            for a in args[:-1]:
                sequence += [op, a]
            sequence.append(args[-1])
            stack.extend(reversed(sequence))
        elif isinstance(item, Xor):
            stack.extend([item.right, item.left, "^"])
        elif isinstance(item, Implies):
            stack.extend([item.right, item.left, "!", "|"])
        elif isinstance(item, Iff):
            stack.extend([item.right, item.left, "^", "!"])
    return out
