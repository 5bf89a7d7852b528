"""The infix "structured slugs" format, for people who write specs by hand.

Same sections and declarations as ``.slugsin`` (integers ``x:0...7`` included), but each clause
is an infix formula::

    !a | b'                       negation ! ~, and & && /\\, or | || \\/, xor ^
    a -> (b <-> c)                implication -> -->, equivalence <-> <-->
    x' = x + 1                    integer comparisons = != < <= > >= over sums with +
    TRUE  FALSE  1  0             constants

Precedence, tightest first: ``!``, comparisons, ``&``, ``|``, ``^``, ``->`` (right-associative),
``<->`` — as slugs' structured-spec compiler documents it. Integer comparisons are bit-blasted
like slugs does (``ltl_stack.spec.integers``). A clause line that starts with a prefix operator
(``& | ^ $``), or that only parses as prefix, is read as a slugsin clause: slugs' compiler
passes such lines through, and some of its example specs use them.

The parser is an operator-precedence (shunting-yard) loop: no recursion, whatever the nesting.
"""
from __future__ import annotations

import re
from array import array

from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.formula import FALSE, TRUE, And, Formula, Iff, Implies, Not, Or, Xor
from ltl_stack.spec.integers import IntExpr, compare, constant_expr, variable_expr
from ltl_stack.spec.model import Spec
from ltl_stack.spec.ops import Pending, settle
from ltl_stack.spec.sections import Line, Names, read_spec
from ltl_stack.spec.slugsin import parse_prefix

NAME_RULE = "a name is a letter or '_' followed by letters, digits, '_', '@' or '.' (not TRUE or FALSE)"
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_@.]*$")

_TOKEN = re.compile(r"""
    (?P<space>\s+)
  | (?P<op><-->|<->|-->|->|<=|>=|!=|==|&&|\|\||/\\|\\/|[!~&|^()=<>+\-*/])
  | (?P<number>\d+)
  | (?P<name>[A-Za-z_][A-Za-z0-9_@.]*'*)
""", re.VERBOSE)

_SPELLING = {"~": "!", "&&": "&", "/\\": "&", "||": "|", "\\/": "|", "-->": "->", "<-->": "<->", "==": "="}
BINARY = {"&": (5, "left"), "|": (4, "left"), "^": (3, "left"), "->": (2, "right"), "<->": (1, "left")}
COMPARISONS = ("=", "!=", "<", "<=", ">", ">=")
PREFIX_STARTS = ("&", "|", "^", "$")


def valid_name(name: str) -> bool:
    return bool(_NAME.match(name)) and name not in ("TRUE", "FALSE")


def parse_structured(text: str, file: str = "<string>") -> Spec:
    """Read a structured (infix) spec; raises ``SpecError`` naming file, line and column."""
    return read_spec(text, file, valid_name, NAME_RULE, parse_clause)


def parse_clause(line: Line, names: Names) -> Formula:
    """One clause line: infix, or a slugsin prefix line passed through."""
    first = line.text.split()[0]
    if first in PREFIX_STARTS or re.match(r"^\$\d+$", first):
        return parse_prefix(line, names)
    try:
        return parse_infix(line, names)
    except SpecError as infix_error:
        try:
            return parse_prefix(line, names)
        except SpecError:
            raise infix_error from None


class _Token:
    __slots__ = ("kind", "text", "column")

    def __init__(self, kind: str, text: str, column: int):
        self.kind = kind
        self.text = text
        self.column = column


#: digits of a number in a formula or a declaration (integer ranges are far smaller; Python refuses to
#: convert more than 4300 digits)
MAX_NUMBER_DIGITS = 18


_KIND_CODE = {"op": 0, "number": 1, "name": 2}


class _Tokens:
    """The tokens of a line as parallel lists, each name's text stored once: a ``_Token`` object per
    token would cost some 60 times the line (``tokens[i]`` makes one when asked)."""

    __slots__ = ("kinds", "texts", "columns")

    KINDS = ("op", "number", "name")

    def __init__(self) -> None:
        self.kinds = bytearray()  # index in KINDS
        self.texts: list[str] = []
        self.columns = array("i")  # 32 bits: a line of up to 2 GB

    def __len__(self) -> int:
        return len(self.texts)

    def __getitem__(self, i: int) -> _Token:
        return _Token(self.KINDS[self.kinds[i]], self.texts[i], self.columns[i])


def tokenize(line: Line, names: Names) -> _Tokens:
    out = _Tokens()
    seen: dict[str, str] = {}
    text = line.text
    position = 0
    while position < len(text):
        m = _TOKEN.match(text, position)
        if not m:
            char = text[position]
            hint = " (a prime must follow a proposition name, as in x')" if char == "'" else ""
            raise names.error(position + 1, f"unexpected character {char!r}{hint}")
        if m.lastgroup != "space":
            word = m.group()
            if m.lastgroup == "number" and len(word) > MAX_NUMBER_DIGITS:
                raise names.error(position + 1, f"a number of {len(word)} digits (at most {MAX_NUMBER_DIGITS})")
            word = _SPELLING.get(word, word)
            out.kinds.append(_KIND_CODE[m.lastgroup])
            out.texts.append(seen.setdefault(word, word))
            out.columns.append(position + 1)
        position = m.end()
    return out


def parse_infix(line: Line, names: Names) -> Formula:
    tokens = tokenize(line, names)
    values: list[Formula] = []
    operators = array("i")  # the tokens '!', '(' and binary operators waiting for operands
    expect_operand = True
    previous: _Token | None = None
    i = 0

    def reduce() -> None:
        op = tokens[operators.pop()]
        if op.text == "!":
            values.append(Not(settle(values.pop())))
            return
        right = values.pop()
        left = values.pop()
        if op.text in ("&", "|"):
            kind = And if op.text == "&" else Or
            if type(left) is Pending and left.kind is kind:  # the chain so far grows (no copy, no new part)
                left.parts.append(settle(right) if type(right) is Pending and right.kind is not kind else right)
                values.append(left)
            else:
                values.append(Pending(kind, left, right))
            return
        left, right = settle(left), settle(right)
        if op.text == "^":
            values.append(Xor(left, right))
        elif op.text == "->":
            values.append(Implies(left, right))
        else:
            values.append(Iff(left, right))

    while i < len(tokens):
        token = tokens[i]
        if expect_operand:
            if token.text in ("!", "("):
                operators.append(i)
                previous = token
                i += 1
            elif token.kind in ("name", "number"):
                value, i = _atom(tokens, i, names)
                values.append(value)
                expect_operand = False
            elif previous is None:
                raise names.error(token.column, f"expected a formula, got '{token.text}'")
            else:
                raise names.error(token.column, f"expected an operand after '{previous.text}', got '{token.text}'")
            continue
        if token.text in BINARY:
            precedence, associativity = BINARY[token.text]
            while operators and tokens.texts[operators[-1]] != "(":
                top = tokens.texts[operators[-1]]
                if top == "!" or BINARY[top][0] > precedence or (
                        BINARY[top][0] == precedence and associativity == "left"):
                    reduce()
                else:
                    break
            operators.append(i)
            previous = token
            expect_operand = True
            i += 1
        elif token.text == ")":
            while operators and tokens.texts[operators[-1]] != "(":
                reduce()
            if not operators:
                raise names.error(token.column, "unexpected ')' without a matching '('")
            operators.pop()
            i += 1
        elif token.text in COMPARISONS or token.text in ("+", "-", "*", "/"):
            raise names.error(token.column, f"'{token.text}' needs integers on both sides "
                                            "(declare them as name:lo...hi)")
        else:
            raise names.error(token.column, f"expected an operator such as '&', '|' or '->' before "
                                            f"'{token.text}'")
    end = len(line.text) + 1
    if expect_operand:
        if previous is None:
            raise names.error(end, "expected a formula")
        raise names.error(end, f"expected an operand after '{previous.text}' at column {previous.column}")
    while operators:
        if tokens.texts[operators[-1]] == "(":
            raise names.error(end, f"expected ')' to close the '(' at column {tokens.columns[operators[-1]]}")
        reduce()
    return settle(values[0])


def _split_prime(token: _Token, names: Names) -> tuple[str, bool]:
    name = token.text
    if name.endswith("''"):
        raise names.error(token.column, f"'{name}' has more than one prime; x' is the next state of x")
    if name.endswith("'"):
        return name[:-1], True
    return name, False


def _operator_hint(tokens: _Tokens, i: int) -> str:
    """A hint for a Boolean operator written as a comparison: ``=>`` (implication is ``->``), ``=``
    or ``==`` between propositions (equivalence is ``<->``), ``>=``/``<=`` for ``->``/``<-``."""
    op = tokens[i]
    after = tokens[i + 1] if i + 1 < len(tokens) else None
    if op.text == "=" and after is not None and after.text == ">" and after.column == op.column + 1:
        return "; for 'implies' write '->' (not '=>')"
    if after is None or after.kind != "name":  # compared with a number: no Boolean operator meant
        return ""
    if op.text == "=":
        return "; for 'if and only if' between propositions write '<->'"
    if op.text == ">=":
        return "; for 'implies' write '->' (not '>=')"
    if op.text == "<=":
        return "; for 'is implied by' swap the sides and write '->' (not '<=')"
    return ""


def _atom(tokens: _Tokens, i: int, names: Names) -> tuple[Formula, int]:
    """A proposition, a constant or a comparison starting at ``tokens[i]``; returns the next index."""
    token = tokens[i]
    nxt = tokens[i + 1].text if i + 1 < len(tokens) else None
    if token.kind == "name":
        name, primed = _split_prime(token, names)
        if name in ("TRUE", "FALSE") and not primed:
            return (TRUE if name == "TRUE" else FALSE), i + 1
        if not names.is_integer(name):
            if nxt in COMPARISONS or nxt == "+":
                if name in names.builder.inputs or name in names.builder.outputs:
                    raise names.error(token.column, f"'{name}' is a Boolean proposition; only integer "
                                                    f"variables (name:lo...hi) can be compared or added"
                                                    f"{_operator_hint(tokens, i + 1)}")
            return names.boolean(name, primed, token.column), i + 1
    elif nxt not in COMPARISONS and nxt != "+":
        if token.text in ("0", "1"):
            return (TRUE if token.text == "1" else FALSE), i + 1
        raise names.error(token.column, f"the number {token.text} is not a formula; compare it with an "
                                        "integer variable, as in x = 3")
    start = i
    left, i = _sum(tokens, i, names)
    if i >= len(tokens) or tokens[i].text not in COMPARISONS:
        if i == start + 1 and token.kind == "name":
            raise names.error(token.column, f"integer variable '{token.text.rstrip(chr(39))}' needs a "
                                            f"comparison, such as {token.text} = 0")
        last = tokens[i - 1]
        where = tokens[i].column if i < len(tokens) else last.column + len(last.text)
        raise names.error(where, "expected a comparison (= != < <= > >=) after the integer expression")
    op = tokens[i].text
    right, i = _sum(tokens, i + 1, names, after=op)
    return compare(op, left, right), i


def _sum(tokens: _Tokens, i: int, names: Names, after: str | None = None) -> tuple[IntExpr, int]:
    """``term (+ term)*`` where a term is a number or an integer variable, possibly primed."""
    total = IntExpr()
    while True:
        if i >= len(tokens):
            last = tokens[-1]
            raise names.error(last.column + len(last.text), f"expected a number or an integer variable "
                                                            f"after '{after or last.text}'")
        token = tokens[i]
        if token.kind == "number":
            total = total.plus(constant_expr(int(token.text)))
        elif token.kind == "name":
            name, primed = _split_prime(token, names)
            if not names.is_integer(name):
                if name in names.builder.inputs or name in names.builder.outputs:
                    raise names.error(token.column, f"'{name}' is a Boolean proposition, not an integer")
                raise names.error(token.column, f"undeclared integer variable '{name}' "
                                                "(declare it as name:lo...hi in [INPUT] or [OUTPUT])")
            names.check_prime(name, primed, token.column)
            total = total.plus(variable_expr(names.integer(name), primed))
        else:
            raise names.error(token.column, f"expected a number or an integer variable, got '{token.text}'")
        i += 1
        if i < len(tokens) and tokens[i].text in ("-", "*", "/"):
            raise names.error(tokens[i].column, f"operator '{tokens[i].text}' is not supported in integer "
                                                "expressions; only '+' is")
        if i < len(tokens) and tokens[i].text == "+":
            after = "+"
            i += 1
            continue
        return total, i
