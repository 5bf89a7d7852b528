"""Who keeps a received assumption (thesis §4.8 Alg. 4 line 5, activation-completion §4.3): a clause over
the receiver's completion sensors goes onto its activations only where that implies the literal clause;
otherwise, and for sensors it does not control, the clause stays as sent, and a clause the receiver
cannot keep is a 4.8.2 for it, never an adoption reported as 4.8.1."""
from __future__ import annotations

from ltl_stack.runtime.resilience.negotiation import Classes, Negotiation, Outcome, Peer, answer, drive
from ltl_stack.runtime.resilience.negotiation.ownership import implied_by_rewrite, split_by_ownership
from ltl_stack.spec import parse_structured
from ltl_stack.spec.formula import variables
from ltl_stack.synthesis import synthesize

#: Q heads for road or dig (activations) and senses where it is (completions); ``lag``: a completion
#: may stay after its activation ends (Q can be in road while heading for dig), else it needs it
Q_TEXT = """
[INPUT]
road_c
dig_c
s
[OUTPUT]
road
dig
[ENV_INIT]
!road_c & !dig_c & !s
[SYS_INIT]
!road & !dig
[ENV_TRANS]
{env}
[SYS_TRANS]
!(road' & dig')
"""
LAG = "road_c' -> (road_c | road)\ndig_c' -> (dig_c | dig)"
NO_LAG = "road_c' -> road\ndig_c' -> dig"

# P observes Q's completions and Q's sensor s; P's spec assumes Q is never in both places at once
P_CLASSES = Classes("P", {"Q": Peer("Q", eap={"road_c_Q": "road_c", "dig_c_Q": "dig_c", "s_Q": "s"}, shares={})})
Q_CLASSES = Classes("Q", {"P": Peer("P", eap={}, shares={"road_c": "road_c_Q", "dig_c": "dig_c_Q", "s": "s_Q"})})


def p_text(assumption: str) -> str:
    return f"""
[INPUT]
road_c_Q
dig_c_Q
s_Q
[OUTPUT]
p
[ENV_INIT]
!road_c_Q & !dig_c_Q & !s_Q
[SYS_INIT]
!p
[ENV_TRANS]
{assumption}
"""


def negotiate(assumption: str, env: str):
    p = parse_structured(p_text(assumption), "P.structuredslugs")
    q = parse_structured(Q_TEXT.format(env=env), "Q.structuredslugs")
    a = Negotiation(p, P_CLASSES, "Q", incoming={"road_c_Q": False, "dig_c_Q": False, "s_Q": False},
                    outputs={"p": False}, initiator=True)
    b = Negotiation(q, Q_CLASSES, "P", incoming={"road_c": False, "dig_c": False, "s": False},
                    outputs={"road": False, "dig": False}, initiator=False)
    drive(a, lambda message: answer(b, message))
    return a, b


def sys_texts(spec) -> list[str]:
    return [" ".join(c.text.split()) for c in spec.sys_safety]


def test_a_rewrite_that_does_not_imply_the_literal_clause_is_not_made():
    """With completions that lag their activations, "never heading for both" lets Q be in road and
    arrive in dig at once: the rewrite does not keep the sender's assumption, the literal clause does."""
    q = parse_structured(Q_TEXT.format(env=LAG), "Q")
    position = {"road_c": False, "dig_c": False, "s": False, "road": False, "dig": False}
    clause = parse_structured("[INPUT]\nroad_c\ndig_c\n[SYS_TRANS]\n!(road_c' & dig_c')\n", "P").sys_safety
    owned = split_by_ownership(clause, q, position)
    assert owned.rewritten == [] and [c.text.strip() for c in owned.literal] == ["!(road_c' & dig_c')"]
    a, b = negotiate("!(road_c_Q' & dig_c_Q')", LAG)
    assert b.outcome is Outcome.BOTH_ADOPT, b.reason
    texts = sys_texts(b.adopted.spec)
    assert "!(road_c' & dig_c')" in texts and "!(road' & dig')" in texts  # its own clause, and the literal one
    assert synthesize(b.adopted.spec).realizable


def test_a_rewrite_that_implies_the_literal_clause_goes_onto_the_activations():
    q = parse_structured(Q_TEXT.format(env=NO_LAG), "Q")
    position = {"road_c": False, "dig_c": False, "s": False, "road": False, "dig": False}
    clause = parse_structured("[INPUT]\nroad_c\ndig_c\n[SYS_TRANS]\n!(road_c' & dig_c')\n", "P").sys_safety[0]
    rewrite = parse_structured("[OUTPUT]\nroad\ndig\n[SYS_TRANS]\n!(road' & dig')\n", "R").sys_safety[0]
    assert implied_by_rewrite(clause.formula, rewrite.formula, q, position)
    # not from a position where the literal clause or its rewrite is already false
    assert not implied_by_rewrite(clause.formula, rewrite.formula, q, {**position, "road": True, "dig": True})
    a, b = negotiate("!(road_c_Q' & dig_c_Q')", NO_LAG)
    assert b.outcome is Outcome.BOTH_ADOPT
    assert not any(v.primed and v.name in ("road_c", "dig_c") for c in b.adopted.spec.sys_safety
                   for v in variables(c.formula)), \
        sys_texts(b.adopted.spec)


def test_a_clause_over_a_sensor_the_receiver_does_not_control_is_not_an_adoption():
    """P assumes Q's sensor s stays off; Q cannot keep that (nothing in its assumptions links s to its
    moves): Q's phi^nego is unrealizable, so P incorporates Q's offer and Q keeps its own spec (4.8.2),
    not "both robots adopt" with the clause turned into an assumption of Q."""
    a, b = negotiate("!s_Q'", LAG)
    assert b.outcome is Outcome.KEPT_OWN and a.outcome is Outcome.ADOPTED_PEERS, (a.outcome, b.outcome)
    assert not any("s'" in " ".join(c.text.split()) for c in b.adopted.spec.env_safety + b.adopted.spec.sys_safety)
    assert any("cannot guarantee what it only senses" in line for line in b.log), b.log


def test_a_clause_over_a_sensor_the_receiver_already_assumes_is_kept_as_sent():
    a, b = negotiate("!s_Q'", LAG + "\n!s'")
    assert a.outcome is b.outcome is Outcome.BOTH_ADOPT
    assert sys_texts(b.adopted.spec).count("!s'") == 1
