"""Read an LTLMoP project file (``.spec``) as LTLMoP ships it, with LTLMoP's meaning.

The file is LTLMoP's container (``fileMethods.readFromFile``): ``======== SETTINGS ========`` and
``======== SPECIFICATION ========`` parts, each a list of ``Header: # comment`` lines followed by their
data lines. What a specification needs:

SETTINGS
    ``Sensors:`` / ``Actions:``   one ``name, 1`` (enabled) or ``name, 0`` (disabled) per line;
                                  disabled propositions are not part of the spec (as in LTLMoP)
    ``Customs:``                  one name per line: robot propositions kept by the sentences
                                  (``is set on … and reset on …``, ``is toggled on …``)
    ``RegionFile:``               the ``.regions`` map, relative to the project file
    ``CompileOptions:``           ``key: value`` lines; those that change the meaning are read:
                                  ``parser`` (``structured``; ``ltl``: raw LTL; ``slurp`` is refused),
                                  ``decompose`` (the free space inside the boundary becomes regions,
                                  adjacency from shared borders), ``fastslow`` (regions follow the
                                  activation–completion encoding, ``R``/``R_rc``; without it a region
                                  is a robot proposition saying where the robot is, as LTLMoP's
                                  default compilation has it), ``use_region_bit_encoding`` (raw LTL
                                  may name the bits of the robot's region, ``s.bitJ``, and use the
                                  follow macros, see ``_RawLtl``). ``convexify`` only changes how
                                  LTLMoP encodes the same spec.
SPECIFICATION
    ``Spec:``                     the sentences (``parser: structured``, read by
                                  ``structured_english`` with LTLMoP's timing) or the raw LTL
                                  (``parser: ltl``: assumptions, a line of dashes, guarantees; one
                                  conjunct per line in LTLMoP's syntax ``[]``, ``[]<>``, ``next()``,
                                  ``s.``/``e.`` prefixes, region bits and the follow macros, ``_RawLtl``)

Other headers (``CurrentConfigName``, ``RegionMapping``, …) belong to LTLMoP's tools and are ignored.
"""
from __future__ import annotations

import re
from pathlib import Path

from ltl_stack.errors import InputError
from ltl_stack.inputs import read_text
from ltl_stack.spec.errors import SpecError
from ltl_stack.spec.formula import And, Formula, Implies, Not, Or, Var
from ltl_stack.spec.model import SECTIONS, Clause
from ltl_stack.spec.region_map import parse_region_map
from ltl_stack.spec.sections import Line, SpecBuilder
from ltl_stack.spec.structured import NAME_RULE, parse_clause, valid_name
from ltl_stack.spec.structured_english import Declarations, EnglishSpec, add_declaration, compile_sentences

_CONTAINER = re.compile(r"^=+\s*(?P<title>[^=]+?)\s*=+")
_HEADER = re.compile(r"^(?P<key>\w+):\s*(?:#.*)?$")
_TRUE = ("true", "t", "1")
#: LTLMoP's defaults (``project.py``) for the options that change the meaning
DEFAULT_OPTIONS = {"parser": "structured", "decompose": True, "fastslow": False, "use_region_bit_encoding": True}
#: LTLMoP's follow macro (``specCompiler.substituteMacros``): the followed target's region, as sensor
#: bits ``sbitJ``, moves on the map as the robot does
FOLLOW = "FOLLOW_SENSOR_CONSTRAINTS"


def read_project(text: str, file: str, base_dir: Path) -> EnglishSpec:
    """The spec of an LTLMoP project ``text``; one ``SpecError`` naming file and line on bad input."""
    parts = _containers(text, file)
    settings = parts.get("SETTINGS", {})
    options, option_line = _options(settings.get("CompileOptions", []), file)
    parser = options["parser"]
    if parser == "slurp":
        raise SpecError(file, option_line.get("parser", 0), 1,
                        "this project is written for LTLMoP's free-English parser SLURP ('parser: slurp' under "
                        "CompileOptions:), which ltl_stack does not read; write it in Structured English "
                        "('parser: structured')")
    if parser not in ("structured", "ltl"):
        raise SpecError(file, option_line.get("parser", 0), 1,
                        f"unknown parser '{parser}' under CompileOptions:; expected structured or ltl")
    decl = Declarations(regions_are_places=not options["fastslow"])
    for header, kind, word in (("Sensors", "sensors", "sensor"), ("Actions", "actions", "action")):
        for number, entry in settings.get(header, []):
            name, _, flag = entry.partition(",")
            name, flag = name.strip(), flag.strip()
            if flag not in ("", "0", "1"):
                raise SpecError(file, number, 1, f"expected 'name, 1' (enabled) or 'name, 0' (disabled) under "
                                                 f"{header}:, got '{entry}'")
            if flag == "0":
                decl.disabled[name] = word
            else:
                add_declaration(decl, kind, name, number, 1, file)
    for number, entry in settings.get("Customs", []):
        add_declaration(decl, "memory", entry.strip(), number, 1, file)
    spec_lines = parts.get("SPECIFICATION", {}).get("Spec", [])
    derived: dict[str, tuple] = {}
    if options["decompose"] and parser == "structured":
        spec_lines = [(n, _derived_areas(s, derived, file, n)) for n, s in spec_lines]
    region_file = [(n, e) for n, e in settings.get("RegionFile", []) if e.strip() and e.strip() != "None"]
    if region_file:
        _read_map(decl, region_file[0], base_dir, file, options["decompose"], derived)
    sentences = [(n, s) for n, s in spec_lines if s.strip() and not s.lstrip().startswith("#")]
    if parser == "ltl":
        raw = _RawLtl(decl, file, options["use_region_bit_encoding"], option_line)
        english = compile_sentences(decl, [], file, raw.read(spec_lines))
        if raw.numbered:
            english.spec.warnings.append(raw.numbering())
        return english
    return compile_sentences(decl, [(n, _strip_comment(s)) for n, s in sentences if _strip_comment(s).strip()],
                             file)


def _strip_comment(line: str) -> str:
    m = re.search(r"(^|\s)#", line)
    return line[:m.start()] if m else line


def _containers(text: str, file: str) -> dict[str, dict[str, list[tuple[int, str]]]]:
    """``{part: {header: [(line, data), …]}}`` as LTLMoP's ``readFromFile`` splits it."""
    parts: dict[str, dict[str, list[tuple[int, str]]]] = {"": {}}
    title, key = "", None
    for number, raw in enumerate(text.splitlines(), start=1):
        if key != "Spec" and (raw.startswith("#") or not raw.strip()):
            continue
        container = _CONTAINER.match(raw)
        header = _HEADER.match(raw)
        if container:
            title, key = container["title"].strip(), None
            parts[title] = {}
        elif header:
            key = header["key"]
            parts[title][key] = []
        elif key is None:
            raise SpecError(file, number, 1, "data before the first 'Header:' line of an LTLMoP project file")
        else:
            parts[title][key].append((number, raw.strip()))
    return parts


def _options(lines: list[tuple[int, str]], file: str) -> tuple[dict, dict[str, int]]:
    options: dict = dict(DEFAULT_OPTIONS)
    where: dict[str, int] = {}
    for number, entry in lines:
        key, sep, value = entry.partition(":")
        if not sep:
            raise SpecError(file, number, 1, f"expected 'option: value' under CompileOptions:, got '{entry}'")
        key, value = key.strip().lower(), value.strip().lower()
        where[key] = number
        options[key] = value if key == "parser" else value in _TRUE
    return options, where


#: LTLMoP's default distance of 'near R' (``specCompiler``: near$R$50)
NEAR_DISTANCE = 50
_BETWEEN = re.compile(r"\bbetween (\w+) and (\w+)", re.IGNORECASE)
_WITHIN = re.compile(r"\bwithin (\d+) (?:from|of) (\w+)", re.IGNORECASE)
_NEAR = re.compile(r"\bnear (\w+)", re.IGNORECASE)
#: digits of the distance N of ``within N of R`` (map units; a longer number is a typing mistake, and
#: one of more than 4300 digits is more than Python converts)
MAX_DISTANCE_DIGITS = 9


def _derived_areas(sentence: str, derived: dict[str, tuple], file: str = "<string>", line: int = 0) -> str:
    """Name the areas LTLMoP computes from the map (``between A and B``, ``within N of R``, ``near R``)
    as one word each, ``between_A_and_B`` …, and note their geometry in ``derived`` (as LTLMoP's
    ``parseLP`` collects them before it decomposes the map). A distance of more than
    ``MAX_DISTANCE_DIGITS`` digits is a ``SpecError`` at ``file:line``."""
    if sentence.lstrip().startswith("#"):
        return sentence
    for m in _WITHIN.finditer(sentence):
        if len(m[1].lstrip("0")) > MAX_DISTANCE_DIGITS:
            raise SpecError(file, line, m.start(1) + 1, f"'within N of {m[2]}': N has {len(m[1])} digits "
                                                        f"(at most {MAX_DISTANCE_DIGITS})")

    def between(m: re.Match) -> str:
        name = f"between_{m[1]}_and_{m[2]}"
        derived[name] = ("between", m[1], m[2])
        return name

    def within(m: re.Match) -> str:
        name = f"within_{m[1]}_of_{m[2]}"
        derived[name] = ("near", m[2], int(m[1]))
        return name

    def near(m: re.Match) -> str:
        name = f"near_{m[1]}"
        derived[name] = ("near", m[1], NEAR_DISTANCE)
        return name

    return _NEAR.sub(near, _WITHIN.sub(within, _BETWEEN.sub(between, sentence)))


def _read_map(decl: Declarations, entry: tuple[int, str], base_dir: Path, file: str, decompose: bool,
              derived: dict[str, tuple]) -> None:
    number, name = entry
    path = base_dir / name.strip()
    try:
        text = read_text(path, "region map", max_bytes=16 * 1024 * 1024)
    except InputError as e:
        raise SpecError(file, number, 1, f"cannot read the RegionFile: {e}") from None
    try:
        topology = parse_region_map(text, str(path), decompose=decompose, derived=derived)
    except SpecError as e:
        raise SpecError(file, number, 1, f"in the RegionFile: {e}") from None
    for region in topology.regions:
        add_declaration(decl, "regions", region, number, 1, file)
    for area, pieces in topology.areas.items():
        if area not in decl.kind_of:
            decl.kind_of[area] = "regions"
        decl.areas[area] = pieces
    decl.topology = topology
    decl.line_of["map"] = number


_LTL_TOKEN = re.compile(r"\s*(\[\]<>|\[\]|<>|<->|->|next\b|[()!&|]|[A-Za-z_][\w.]*|\S)")
_BIT = re.compile(r"(s?)bit(\d+)")
_LISTED = 12  # regions named in the numbering warning


class _RawLtl:
    """LTLMoP's ``parser: ltl``: assumptions, a line of dashes, guarantees; each line one conjunct,
    ``[]<>f`` a goal, ``[]f`` a safety formula, anything else an initial condition; ``=`` is an
    equivalence that binds tighter than ``&`` (JTLV's, see ``_tight_iff``).

    With ``use_region_bit_encoding`` (``specCompiler._writeLTLFile``) the robot's region is also
    named by bits: region number i (in the order of ``decl.regions``) is the binary number i on
    ``bit0`` (most significant) … ``bitK-1``, K = ceil(log2 n) (``bitEncoding``). A bit is read as
    the disjunction of the regions whose number has it set, which means what LTLMoP's bits mean
    where exactly one region holds. ``sbitJ`` are sensors encoding a followed target's region the
    same way; ``FOLLOW_SENSOR_CONSTRAINTS`` (a line of its own) stands for LTLMoP's mirror of the
    topology onto them: the target starts in and stays in one of the n numbers, and moves only to a
    neighbour (or stays); ``TARGET_IS_STATIONARY`` for ``sbitJ' <-> sbitJ`` for every J."""

    def __init__(self, decl: Declarations, file: str, bits: bool, option_line: dict[str, int]):
        self.decl, self.file, self.bits, self.option_line = decl, file, bits, option_line
        self.width = (len(decl.regions) - 1).bit_length() if len(decl.regions) > 1 else 0
        self.numbered = False  # a line used the bit numbering of the regions

    def read(self, lines: list[tuple[int, str]]) -> dict[str, list[Clause]]:
        file = self.file
        for number, raw in lines:  # LTLMoP adds the target's bits to the sensors
            if FOLLOW in _strip_comment(raw):
                self._declare_target_bits(number)
        builder = SpecBuilder(file, valid_name, NAME_RULE)
        builder.read_layout("[INPUT]\n" + "".join(n + "\n" for n in self.decl.inputs)
                            + "[OUTPUT]\n" + "".join(n + "\n" for n in self.decl.outputs))
        sections: dict[str, list[Clause]] = {name: [] for name in SECTIONS}
        side = "env"
        dashes = False
        for number, raw in lines:
            text = _strip_comment(raw).strip().rstrip("&").strip()
            if not text:
                continue
            if re.fullmatch(r"-+", text):
                if dashes:
                    raise SpecError(file, number, 1, "a raw LTL spec has one line of dashes (assumptions above it, "
                                                     "guarantees below)")
                side, dashes = "sys", True
                continue
            if FOLLOW in text:
                if text != FOLLOW:
                    raise SpecError(file, number, text.index(FOLLOW) + 1, f"{FOLLOW} stands for several conjuncts "
                                                                          "(initial and []); write it on a line of "
                                                                          "its own")
                for kind, formula, why in self._follow():
                    sections[f"{side}_{kind}"].append(Clause(formula, f"{FOLLOW}: {why}", file, number))
                continue
            kind, infix = self._to_infix(text, number)
            section = f"{side}_{kind}"
            line = Line(number, infix)
            formula = parse_clause(line, builder.names(section, line))
            sections[section].append(Clause(formula, raw.strip(), file, number))
        if not dashes:
            raise SpecError(file, lines[0][0] if lines else 0, 1, "a raw LTL spec ('parser: ltl') has the "
                                                                  "assumptions, a line of dashes, then the guarantees")
        return sections

    def numbering(self) -> str:
        """The warning that says which number (bit pattern) stands for which region."""
        regions = self.decl.regions
        listed = ", ".join(f"{i} {r}" for i, r in enumerate(regions[:_LISTED]))
        if len(regions) > _LISTED:
            listed += f", … {len(regions) - 1} {regions[-1]} (in the map's order)"
        return (f"{self.file}: the region bits (bitJ, sbitJ) number the regions {listed}; LTLMoP numbers its "
                f"decomposed map in an order of its own, so a bit pattern that names one region may name "
                f"another there")

    def _declare_target_bits(self, number: int) -> None:
        if not self.bits:
            raise SpecError(self.file, number, 1, f"LTLMoP expands {FOLLOW} only with use_region_bit_encoding: "
                                                  f"True (line {self.option_line.get('use_region_bit_encoding', 0)}"
                                                  "); without it LTLMoP leaves the word in the formula")
        if self.width == 0:
            raise SpecError(self.file, number, 1, f"{FOLLOW} needs a map with at least two regions (the target's "
                                                  "region is encoded in bits)")
        for j in range(self.width):
            name = f"sbit{j}"
            if self.decl.kind_of.get(name) != "sensors":
                self.decl.disabled.pop(name, None)
                add_declaration(self.decl, "sensors", name, number, 1, self.file)
        self.numbered = True

    def _pattern(self, prefix: str, i: int, primed: bool) -> Formula:
        """Region number ``i`` on the bits ``prefix0`` (most significant) … (``bitEncoding``)."""
        lits = []
        for j in range(self.width):
            var = Var(f"{prefix}{j}", primed)
            lits.append(var if (i >> (self.width - 1 - j)) & 1 else Not(var))
        return And(tuple(lits))

    def _follow(self) -> list[tuple[str, Formula, str]]:
        """LTLMoP's ``FOLLOW_SENSOR_CONSTRAINTS``: its region topology and initial-region fragment
        (``createTopologyFragment``, ``createInitialRegionFragment``) with the robot's bits replaced
        by the target's."""
        regions = self.decl.regions
        topology = self.decl.topology
        index = {r: i for i, r in enumerate(regions)}
        valid = Or(tuple(self._pattern("sbit", i, False) for i in range(len(regions))))
        out = []
        for i, r in enumerate(regions):
            near = sorted(topology.neighbours(r), key=index.__getitem__)
            moves = Or(tuple(self._pattern("sbit", k, True) for k in (i, *(index[n] for n in near))))
            out.append(("safety", Implies(self._pattern("sbit", i, False), moves),
                        f"from {r} the target moves only to a neighbour of it (or stays)"))
        out.append(("safety", valid, "the target is in one of the regions"))
        out.append(("init", valid, "the target starts in one of the regions"))
        return out

    def _bit(self, name: str, primed: bool, number: int, column: int) -> str | None:
        """``bitJ`` (the robot's region) in infix, or None when ``name`` is no region bit."""
        m = _BIT.fullmatch(name)
        if not m or not self.bits or int(m[2]) >= self.width:
            return None
        self.numbered = True
        if m[1]:
            return None  # the target's bit: a sensor
        j = int(m[2])
        if name in self.decl.kind_of:
            raise SpecError(self.file, number, column, f"'{name}' is declared and is also LTLMoP's region bit {j} "
                                                       "(use_region_bit_encoding: True); rename the proposition")
        if not self.decl.regions_are_places:
            raise SpecError(self.file, number, column, f"the region bit '{name}' names where the robot is, which "
                                                       "LTLMoP's region model has (fastslow: False); with fastslow: "
                                                       "True name the regions")
        tick = "'" if primed else ""
        ones = [r + tick for i, r in enumerate(self.decl.regions) if (i >> (self.width - 1 - j)) & 1]
        return "(" + " | ".join(ones) + ")"

    def _to_infix(self, text: str, number: int) -> tuple[str, str]:
        """One LTLMoP conjunct as (init|safety|liveness, the structured format's infix text)."""
        file = self.file
        tokens = _LTL_TOKEN.findall(text)
        kind = "init"
        if tokens and tokens[0] == "[]<>":
            kind, tokens = "liveness", tokens[1:]
        elif tokens and tokens[0] == "[]":
            kind, tokens = "safety", tokens[1:]
        out: list[str] = []
        next_depth: list[int] = []  # paren depths at which a next( opened
        depth = 0
        k = 0
        while k < len(tokens):
            t = tokens[k]
            if t in ("[]", "[]<>", "<>"):
                raise SpecError(file, number, text.find(t) + 1, f"'{t}' inside a formula is not GR(1); write one "
                                                                "conjunct per line, [] or []<> in front")
            if t == "next":
                if k + 1 >= len(tokens) or tokens[k + 1] != "(":
                    raise SpecError(file, number, 1, "expected '(' after next")
                next_depth.append(depth)
                depth += 1
                out.append("(")
                k += 2
                continue
            if t == "(":
                depth += 1
            elif t == ")":
                depth -= 1
                if next_depth and next_depth[-1] == depth:
                    next_depth.pop()
            if t == "STAY_THERE":
                out.append(_stay_there(self.decl))
            elif t == "TARGET_IS_STATIONARY":
                self.numbered = True
                out.append("(" + " & ".join(f"(sbit{j}' <-> sbit{j})" for j in range(self.width)) + ")"
                           if self.width else "TRUE")
            elif re.match(r"[A-Za-z_]", t) and t.upper() not in ("TRUE", "FALSE"):
                name = re.sub(r"^[se]\.", "", t)
                bit = self._bit(name, bool(next_depth), number, text.find(t) + 1)
                out.append(bit if bit is not None else name + ("'" if next_depth else ""))
            else:
                out.append(t)
            k += 1
        return kind, " ".join(_tight_iff(out))


def _tight_iff(out: list[str]) -> list[str]:
    """JTLV's ``=`` (what LTLMoP's verdicts come from) binds tighter than ``&``, as in SMV: ``a = b & c``
    is ``(a <-> b) & c``. Each ``=`` becomes ``<->`` around its two operands: a name, a parenthesised
    group or one of them after ``!``s; a chain groups from the left."""
    out = list(out)
    k = 0
    while k < len(out):
        if out[k] != "=":
            k += 1
            continue
        start = _operand_end(out, k - 1, -1)
        while start > 0 and out[start - 1] == "!":
            start -= 1
        end = k + 1
        while end < len(out) - 1 and out[end] == "!":
            end += 1
        end = _operand_end(out, end, 1)
        out[k] = "<->"
        out[start:end + 1] = ["(", *out[start:end + 1], ")"]
        k += 2
    return out


def _operand_end(out: list[str], at: int, step: int) -> int:
    """Where the operand at ``out[at]`` ends, walking in direction ``step`` over a parenthesised group."""
    opening, closing = ("(", ")") if step == 1 else (")", "(")
    if not 0 <= at < len(out) or out[at] != opening:
        return at
    depth = 0
    while 0 <= at < len(out):
        depth += (out[at] == opening) - (out[at] == closing)
        if depth == 0:
            return at
        at += step
    return at - step


def _stay_there(decl: Declarations) -> str:
    """LTLMoP's STAY_THERE macro (``createStayFormula``) in infix: the robot's region does not change."""
    if not decl.regions:
        return "TRUE"
    if decl.regions_are_places:
        return "(" + " & ".join(f"({r} <-> {r}')" for r in decl.regions) + ")"
    return "(" + " & ".join(f"({r}_rc | !{r}')" for r in decl.regions) + ")"
