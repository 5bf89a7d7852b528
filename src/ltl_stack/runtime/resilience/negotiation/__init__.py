"""Integrative negotiation between two robots without ROS (thesis §4.8, Alg. 4; Def. 4.3.1, Table 4.1).

**Proposition classes.** Which inputs abstract another robot's behaviour (eAP_r, Table 4.1's
pi^r_{prop,r'}) and which are global sensors (Sen_G) is declared in the robot's *mapping* file, under
the top-level key ``negotiation:`` (the mapping already says which topic feeds each input, so it is
where "this input is robot A's openDoor" belongs; the spec stays a plain GR(1) spec)::

    negotiation:
      robot: D                       # this robot's name, as its peers call it
      global_sensors: [ingredientArrived]        # Sen_G: same name for every robot
      peers:
        A:
          service: /kitchen/A/negotiate         # optional (ROS adapter); default <peer ns>/negotiate
          eap: {openDoor_A: openDoor}           # eAP_D about A: my input -> A's proposition
          shares: {road_c: road_c_D}            # my proposition -> A's input that abstracts it

``eap`` and ``shares`` together are the translation table between the two namespaces: a formula
sent to A is renamed with it (Sen_G names unchanged), and A parses it against its own declarations.

**phi^{t(r_env)}_{e,r}** (§4.8): the env-safety clauses of the spec that mention an eAP input about
r_env (``assumptions_about``).

**Alg. 4 for one party** (``Negotiation``), driven by messages (``Message``) in this order, the same
for both robots (the transport decides who sends first; the initiator sends, the responder answers):

1. ``offer()`` (line 3): phi^{t(r_env)}_{e,r} and phi^g_{s,r}, renamed into r_env's names, as
   structured spec text (``[SYS_TRANS]`` / ``[ENV_LIVENESS]`` of the receiver) — the received
   assumptions become system safety and the received goals environment liveness (line 5); a received
   assumption over the receiver's completion sensors only is kept through the activations they
   report (``road_c'`` -> ``road'``) when that rewrite implies it, else as sent (``ownership``):
   a clause the receiver cannot keep makes phi^nego unrealizable (4.8.2/4.8.3), never an adoption;
2. ``receive(offer)`` (lines 4-9): parse it against our propositions (garbled text or an unknown
   name is a fault), phi^nego = init from the current state (lines 6-7: incoming inputs, current
   outputs), original env safety phi^t_e (line 2: the EC disjuncts are dropped), phi*^t_s /\\ received
   assumptions, phi*^g_e /\\ received goals; synthesize;
3. ``status(1)`` / ``receive(status 1)`` (lines 10-17): if phi^nego is realizable it becomes phi*;
   else if the peer's is, phi* is resynthesized with the new init (4.8.2); else both abort (4.8.3);
4. ``status(2)`` / ``receive(status 2)`` (lines 18-21): phi* is adopted only when both phi* are
   realizable; otherwise abort (line 20). With both realizable the responder is *prepared* (bound by
   its status 2, not adopted) and the initiator decides: it adopts and sends ``commit``; the
   responder adopts on it and confirms (commit protocol). Until the confirmation arrives the
   initiator reports ``UNCONFIRMED``, and either robot asks again (``Negotiator.settle``).

Faults — a message out of order, garbled spec text, a peer that sends ``abort``, a timeout or a
vanished peer reported by the transport (``fail``) — end the negotiation as ``FAILED``: nothing is
adopted (no half-adopted spec). The party that started it (its own spec is unrealizable, Alg. 3)
then goes to S.1; the responder keeps the controller it was running, which is still correct for its
own spec. A robot is in one negotiation at a time (``sessions.Negotiator``), so each phi^nego is built
on the spec it runs after every earlier adoption. Messages may be signed (``auth``).
"""

from ltl_stack.runtime.resilience.negotiation.auth import Authenticator
from ltl_stack.runtime.resilience.negotiation.classes import (
    Classes,
    NegotiationError,
    Peer,
    assumptions_about,
    caller_refusal,
    classes_authenticator,
    classes_from_data,
    classes_from_mapping,
    negotiation_classes,
    rename,
)
from ltl_stack.runtime.resilience.negotiation.messages import (
    ABORT,
    BUSY,
    MAX_OFFER_BYTES,
    MAX_OFFER_CLAUSES,
    OFFER,
    OFFER_SECTIONS,
    SIMULTANEOUS,
    STATUS,
    WRITE_FAILED,
    Adoption,
    Message,
    Outcome,
    Phase,
    ProtocolFault,
    offer_refusal,
    report_lines,
)
from ltl_stack.runtime.resilience.negotiation.ownership import Ownership, split_by_ownership
from ltl_stack.runtime.resilience.negotiation.party import Negotiation, answer, drive
from ltl_stack.runtime.resilience.negotiation.sessions import (
    Negotiator,
    Transport,
    count_negotiation,
    violated_clauses,
)
from ltl_stack.runtime.resilience.negotiation.staging import (
    commit_adopted,
    discard_staged,
    stage_adopted,
    write_adopted,
)

__all__ = ["ABORT", "BUSY", "MAX_OFFER_BYTES", "MAX_OFFER_CLAUSES", "OFFER", "OFFER_SECTIONS", "SIMULTANEOUS",
           "STATUS", "WRITE_FAILED", "Adoption", "Authenticator", "Classes", "Message", "Negotiation",
           "NegotiationError", "Negotiator", "Outcome", "Ownership", "Peer", "Phase", "ProtocolFault", "Transport",
           "answer", "assumptions_about", "caller_refusal", "classes_authenticator", "classes_from_data",
           "classes_from_mapping", "commit_adopted", "count_negotiation", "discard_staged", "drive",
           "negotiation_classes", "offer_refusal", "rename", "report_lines", "split_by_ownership", "stage_adopted",
           "violated_clauses", "write_adopted"]
